"""The pymunk adapter: the only place that imports pymunk.

* :mod:`.asperity` — asperity scenes (:class:`Engine`: stepping, drive, settling),
  with its mixins :mod:`.build` (the space) and :mod:`.contacts` (stick/slip
  switching, read-outs);
* :mod:`.energy` — per-step energy accounting (:class:`~.energy.EnergyMeter`);
* :mod:`.belt` — masses on a moving belt, for cross-checks of the exact solver.
"""

from .asperity import PYMUNK_VERSION, Engine

__all__ = ["Engine", "PYMUNK_VERSION"]
