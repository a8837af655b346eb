"""asperity2d: friction at the asperity scale, in 2D, on pymunk.

Public names (see README):

* :func:`make_scene`, :class:`Scene` and its parts — scene specification (SI);
* :func:`simulate` -> :class:`Result`, :func:`load`;
* :func:`critical_force`, :func:`breakaway_force`, :func:`stick_slip_events`;
* :mod:`asperity2d.belt` — masses on a moving belt with exact stick/slip;
* :class:`SceneError`, :class:`SimulationError`.

Every public name is imported on first use (PEP 562), so ``import asperity2d``
and the command line start without NumPy, pymunk, SciPy or matplotlib.
"""

import sys
import types

from ._lazy import exports
from .errors import SceneError, SimulationError

#: Public name -> the module that defines it, imported when the name is first used.
_LAZY = {
    "Profile": "geometry", "RandomSpacing": "geometry", "RegularSpacing": "geometry",
    "ConstantForce": "scene", "Contact": "scene", "LowerSurface": "scene", "Scene": "scene",
    "Slider": "scene", "SpringDrive": "scene",
    "make_scene": "builders",
    "Result": "result", "load": "result",
    "Passed": "simulate", "Stuck": "simulate", "Travelled": "simulate", "simulate": "simulate",
    "Run": "simulate",
    "CriticalForce": "critical", "critical_force": "critical", "critical_force_bracket": "critical",
    "Event": "analysis", "breakaway_force": "analysis", "event_statistics": "analysis",
    "friction_traces": "analysis", "stick_slip_events": "analysis", "peak_stick_force": "analysis",
    "mean_stick_force": "analysis",
    "Comparison": "compare", "compare": "compare",
    "render": "render",
    "__version__": "_version",
}
_SUBPACKAGES = ("belt", "friction", "sweep", "tribometer", "fitting", "quasistatic", "studies", "stats",
                "surface", "dynamics")


__getattr__, __dir__ = exports(__name__, globals(), _LAZY, _SUBPACKAGES)


class _Package(types.ModuleType):
    """The package module: the functions ``simulate``, ``compare`` and ``render`` keep their names.

    Importing a submodule binds it on its package (``asperity2d.simulate`` =
    the module). Where a public function has its module's name, the function
    wins, as it did when these names were imported eagerly: the binding is
    skipped and the name resolves lazily to the function.
    """

    def __setattr__(self, name, value):
        if isinstance(value, types.ModuleType) and _LAZY.get(name) == name:
            return
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package

__all__ = [
    "__version__", "SceneError", "SimulationError", "Profile", "RegularSpacing",
    "RandomSpacing", "ConstantForce", "Contact", "LowerSurface", "Scene", "Slider",
    "SpringDrive", "make_scene", "Result", "load", "simulate", "Run", "Passed", "Stuck", "Travelled",
    "CriticalForce", "critical_force", "critical_force_bracket", "Event", "breakaway_force",
    "peak_stick_force", "mean_stick_force", "event_statistics", "friction_traces", "stick_slip_events",
    "Comparison", "compare", "render",
]
