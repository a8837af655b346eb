"""asperity2d: friction at the asperity scale, in 2D, on pymunk.

Public names (see README):

* :func:`make_scene`, :class:`Scene` and its parts — scene specification (SI);
* :func:`simulate` -> :class:`Result`, :func:`load` (an asperity or a belt result);
* :func:`critical_force`, :func:`breakaway_force`, :func:`stick_slip_events`;
* :mod:`asperity2d.belt` — masses on a moving belt with exact stick/slip;
* :func:`explore` — the workbench as a notebook widget (``asperity2d explore`` in the browser);
* :class:`SceneError`, :class:`SimulationError`.

Every public name is imported on first use (PEP 562), so ``import asperity2d``
and the command line start without NumPy, pymunk, SciPy or matplotlib.
"""

from ._lazy import exports
from .errors import SceneError, SimulationError

#: Public name -> the module that defines it, imported when the name is first used.
_LAZY = {
    "Profile": "geometry", "RandomSpacing": "geometry", "RegularSpacing": "geometry",
    "ConstantForce": "scene_parts", "Contact": "scene_parts", "LowerSurface": "scene_parts", "Scene": "scene",
    "Slider": "scene_parts", "SpringDrive": "scene_parts",
    "make_scene": "builders",
    "Result": "result", "load": "saved",
    "Passed": "stops", "Stuck": "stops", "Travelled": "stops", "simulate": "run", "Run": "run_loop",
    "CriticalForce": "critical", "critical_force": "critical", "critical_force_bracket": "critical",
    "critical_force_brackets": "critical",
    "Event": "events", "breakaway_force": "forces", "event_statistics": "events",
    "friction_traces": "forces", "stick_slip_events": "events", "peak_stick_force": "forces",
    "mean_stick_force": "forces", "events_table": "events",
    "Comparison": "experiments.compare", "compare": "experiments.compare",
    "render": "renderers",
    "explore": "app",
    "__version__": "_version",
}
_SUBPACKAGES = ("belt", "friction", "sweep", "experiments", "studies", "stats", "surface", "dynamics",
                "renderers", "engine", "cli", "app")


__getattr__, __dir__ = exports(__name__, globals(), _LAZY, _SUBPACKAGES)


__all__ = [
    "__version__", "SceneError", "SimulationError", "Profile", "RegularSpacing",
    "RandomSpacing", "ConstantForce", "Contact", "LowerSurface", "Scene", "Slider",
    "SpringDrive", "make_scene", "Result", "load", "simulate", "Run", "Passed", "Stuck", "Travelled",
    "CriticalForce", "critical_force", "critical_force_bracket", "critical_force_brackets", "Event", "breakaway_force",
    "peak_stick_force", "mean_stick_force", "event_statistics", "friction_traces", "stick_slip_events",
    "events_table", "Comparison", "compare", "render", "explore",
]
