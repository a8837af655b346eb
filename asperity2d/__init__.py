"""asperity2d: friction at the asperity scale, in 2D, on pymunk.

Public names (see README):

* :func:`make_scene`, :class:`Scene` and its parts — scene specification (SI);
* :func:`simulate` -> :class:`Result`, :func:`load`;
* :func:`critical_force`, :func:`breakaway_force`, :func:`stick_slip_events`;
* :mod:`asperity2d.belt` — masses on a moving belt with exact stick/slip;
* :class:`SceneError`, :class:`SimulationError`.
"""

__version__ = "0.1.0"

from .errors import SceneError, SimulationError
from .geometry import Profile, RandomSpacing, RegularSpacing
from .scene import ConstantForce, Contact, LowerSurface, Scene, Slider, SpringDrive
from .builders import make_scene
from .result import Result, load
from .simulate import Passed, Stuck, Travelled, simulate
from .critical import CriticalForce, critical_force, critical_force_bracket
from .analysis import (Event, breakaway_force, event_statistics, friction_traces, mean_stick_force,
                       peak_stick_force, stick_slip_events)
from .compare import Comparison, compare
from .render import render

_SUBPACKAGES = ("belt", "friction", "sweep", "tribometer", "fitting", "quasistatic", "studies")


def __getattr__(name):
    """Subpackages load on first use (``asperity2d.belt.simulate_chain``), keeping import light."""
    if name in _SUBPACKAGES:
        import importlib

        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "__version__", "SceneError", "SimulationError", "Profile", "RegularSpacing",
    "RandomSpacing", "ConstantForce", "Contact", "LowerSurface", "Scene", "Slider",
    "SpringDrive", "make_scene", "Result", "load", "simulate", "Passed", "Stuck", "Travelled",
    "CriticalForce", "critical_force", "critical_force_bracket", "Event", "breakaway_force",
    "peak_stick_force", "mean_stick_force", "event_statistics", "friction_traces", "stick_slip_events", "Comparison", "compare", "render",
]
