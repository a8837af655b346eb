"""Non-linear time-series analysis for both models (the multi-DOF belt thesis' aims).

* :mod:`.signals`  -- a named series out of a ``Result`` / ``BeltResult``; uniform resampling
* :mod:`.spectrum` -- power spectrum (Welch / periodogram), dominant frequency, harmonics, THD
* :mod:`.sections` -- Poincaré sections (exact stick onsets for belt chains)
* :mod:`.cycles`   -- limit cycles (period, multiplicity, "not periodic"), steady state
* :mod:`.lyapunov` -- largest Lyapunov exponent: Rosenstein from a series, Benettin for chains
* :mod:`.floquet`  -- monodromy (Floquet) multipliers of belt-chain limit cycles
* :mod:`.basins`   -- initial-condition basin maps (belt chains through the sweep machinery;
  asperity runs over the drive preload: :func:`asperity_basins`, :func:`classify_asperity`, the
  classes :data:`BASIN_LABELS`, the part of a run classified :data:`ASPERITY_WINDOW`)
"""

from .asperity_basins import ASPERITY_WINDOW, asperity_basins, classify_asperity
from .basins import LABELS as BASIN_LABELS
from .cycles import Cycle, SteadyState, chain_cycle, detect_period, limit_cycle, steady_state
from .floquet import Floquet, floquet, flow_map, monodromy
from .lyapunov import Lyapunov, chain_lyapunov, lyapunov_series
from .sections import Section, chain_section, crossings, opening_section, poincare_section
from .signals import resample, signal
from .spectrum import Peak, Spectrum, spectrum

__all__ = [
    "ASPERITY_WINDOW", "BASIN_LABELS", "asperity_basins", "classify_asperity",
    "Cycle", "Floquet", "Lyapunov", "Peak", "Section", "Spectrum", "SteadyState", "chain_cycle",
    "chain_lyapunov", "chain_section", "crossings", "detect_period", "floquet", "flow_map", "limit_cycle",
    "lyapunov_series", "monodromy", "opening_section", "poincare_section", "resample", "signal", "spectrum", "steady_state",
]
