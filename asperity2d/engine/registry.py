"""The asperity engines: the contract every engine keeps, and the table of them (:data:`ENGINES`).

Part of :mod:`asperity2d.engine`. An engine steps asperity scenes; it is an :class:`EngineEntry`
listed under its name in :data:`ENGINES`, as the belt lists its back ends in
``asperity2d.belt.METHODS``. :func:`asperity2d.simulate`, the named stick-force measures,
:func:`asperity2d.compare` and the command line (``--engine``) take an engine by name; the
default is always ``"pymunk"``. The contract:

1. **In:** validated :class:`~asperity2d.scene.Scene` objects and the run options the run loop
   resolved (per scene its step ``dt`` (s) and duration (s), ``record_every``, ``iterations``,
   whether the default stop -- the slider has passed the surface -- ends it, the
   :class:`~asperity2d.Stuck` stop's ``(speed, dwell)`` or None, and how long it may settle
   first (s) or None).
2. **Out:** per scene, the record of a :class:`~asperity2d.Result` of the kind the reference
   makes, ``(arrays, meta)`` (the slider's SI columns; ``meta["engine"]`` names the engine that
   made it; :func:`asperity2d.run.simulate_many` makes the Result), or the
   :class:`~asperity2d.errors.SimulationError` that stopped that scene alone: a scene that
   diverges never stops the others of its batch.
3. **Must check** before anything runs what the reference checks (the scales, a step longer
   than the contact it must resolve, a load the springs cannot carry: the same messages), and
   that the batch fits in memory (refused up front, naming the batch size).
4. **May refuse** a scene option it does not implement, in one
   :class:`~asperity2d.errors.SceneError` line naming the option and saying ``engine="pymunk"``
   runs it (:attr:`EngineEntry.refusal`, asked before anything runs); and, when its optional
   dependency is missing, one line saying how to install it (:attr:`EngineEntry.unavailable`).
5. Same scenes and options, same numbers, bit for bit; a scene's result does not depend on
   what else is in its batch. An engine never prints and never writes files.

``"pymunk"`` is the reference: every scene option, the energy books, the lower asperities'
records, stop conditions of the user's own, pictures and the workbench; its runs are
:class:`asperity2d.Run`.
``"batched"`` (:mod:`.batched`) steps many scenes of the model's common case at once.

Who asks which engine: a single run, a picture and the workbench's live run take the reference
unless told otherwise; an ensemble (``compare(seeds="auto")``, a sweep, the main job's
comparisons) may pass ``engine="auto"``, and :func:`choose_engine` -- the one place that
decides -- gives it ``"batched"`` when Numba is installed and the engine runs every one of its
scenes, else ``"pymunk"``; :func:`engine_label` is how output names the engine it used
(``engine: batched (Numba)``).

Examples
--------
>>> from asperity2d.engine import ENGINES
>>> list(ENGINES)
['pymunk', 'batched']
>>> ENGINES["pymunk"].unavailable() is None  # the reference is always there
True
>>> from asperity2d import make_scene
>>> choose_engine("auto", [make_scene(contact_law="viscous")])  # a law of slip speed: only the reference runs it
'pymunk'
>>> engine_label("pymunk")
'pymunk'
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from .._registry import Registry
from ..errors import SceneError
from . import batched

#: The engine every run uses unless told otherwise.
DEFAULT = "pymunk"
#: The engine name that leaves the choice to :func:`choose_engine` (ensembles only).
AUTO = "auto"
#: The engine :func:`choose_engine` prefers for an ensemble, where it is installed and covers it.
ENSEMBLE = "batched"


@dataclass(frozen=True)
class EngineEntry:
    """One asperity engine (the module's contract): ``unavailable()`` says why it cannot run
    here (None: it can), ``refusal(scene, settle)`` names a scene option it does not implement
    (None: it runs the scene), ``run(scenes, dts, durations, record_every=, iterations=,
    passed=, stuck=, settle=)`` returns one record ``(arrays, meta)`` or SimulationError per scene (None for the reference, whose
    run loop is :class:`asperity2d.Run`); ``dependency`` names the optional package it runs on,
    for output (:func:`engine_label`)."""

    name: str
    description: str
    unavailable: Callable[[], str | None]
    refusal: Callable[..., str | None]
    run: Callable | None = None
    dependency: str | None = None


def _always() -> None:
    return None


def _everything(scene, *, settle: bool = False) -> None:
    return None


def _check_entry(entry) -> EngineEntry:
    if not isinstance(entry, EngineEntry):
        raise SceneError(f"`engine` must be an EngineEntry, got {type(entry).__name__}")
    return entry


#: Name -> engine, the reference first (a ``Registry`` (``asperity2d._registry``): an installed
#: package adds one through the entry-point group ``asperity2d.engines``).
ENGINES: Registry = Registry("engine", "asperity2d.engines", key=lambda e: e.name, check=_check_entry,
                             param="engine")
ENGINES.register(EngineEntry("pymunk", "pymunk (Chipmunk 2D), one scene at a time: the reference; every "
                             "scene option", _always, _everything))
ENGINES.register(EngineEntry("batched", "the model's own compiled loop (Numba), many scenes in lockstep: "
                             "convex asperities of every profile on spring tracks, the floor and a substrate; no lattice links",
                             batched.unavailable, batched.refusal, batched.run, dependency="Numba"))


def check_engine(engine) -> str:
    """``engine`` as a known, usable name; a ``SceneError`` line otherwise (an unknown name, with
    the nearest ones, or an engine whose optional dependency is missing, saying how to install it)."""
    if not isinstance(engine, str):
        raise SceneError(f"`engine` must be one of {', '.join(ENGINES)}, got {type(engine).__name__}")
    entry = ENGINES.lookup(engine, "engine")
    why = entry.unavailable()
    if why is not None:
        raise SceneError(why)
    return entry.name


def refuse(engine: str, scene, *, settle: bool = False) -> None:
    """Raise the ``SceneError`` line of a scene option ``engine`` does not implement, if any."""
    why = ENGINES[engine].refusal(scene, settle=settle)
    if why is not None:
        raise SceneError(why)


def choose_engine(engine, scenes, *, settle: bool | None = None) -> str:
    """The engine that runs the ensemble ``scenes``: ``engine`` itself (checked, as
    :func:`check_engine`) unless it is ``"auto"``; then :data:`ENSEMBLE` (``"batched"``) when its
    optional dependency is installed and it implements every scene (its ``refusal`` is None for
    each, ``settle`` as :func:`asperity2d.simulate` decides it: None settles a free slider), else
    the reference. Nothing else decides it: the ensembles that take ``engine="auto"`` ask here.

    Examples
    --------
    >>> from asperity2d import make_scene
    >>> choose_engine("pymunk", [make_scene()])
    'pymunk'
    >>> choose_engine("auto", [make_scene(contact_law="viscous")])  # a law of slip speed: only the reference
    'pymunk'
    """
    if engine != AUTO:
        return check_engine(engine)
    entry = ENGINES[ENSEMBLE]
    if entry.unavailable() is not None:
        return DEFAULT
    for scene in scenes:
        settles = scene.slider.track == "free" if settle is None else bool(settle)
        if entry.refusal(scene, settle=settles) is not None:
            return DEFAULT
    return entry.name


def engine_label(engine: str) -> str:
    """How output names ``engine``: its name, and the package it runs on when that is optional
    (``"batched (Numba)"``).

    Examples
    --------
    >>> engine_label("batched")
    'batched (Numba)'
    """
    entry = ENGINES.lookup(engine, "engine")
    return f"{entry.name} ({entry.dependency})" if entry.dependency else entry.name
