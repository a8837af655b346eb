"""Measures and sweep run functions for seed-000 style studies.

Top-level, picklable functions so they run in worker processes (compare's
process pool, the sweep executors, Dask):

* ``measure(scene) -> float`` for :func:`asperity2d.compare`;
* ``run(*, seed, **params) -> dict[str, float]`` for :mod:`asperity2d.sweep`
  (``params`` are :func:`make_scene` arguments).
"""

from __future__ import annotations

import math

from .analysis import breakaway_force, event_statistics, stick_slip_events
from .critical import critical_force
from .errors import SceneError
from .scene import ConstantForce, Scene, SpringDrive, make_scene
from .simulate import Travelled, simulate


def critical_force_of(scene: Scene) -> float:
    """Critical constant drive force (N), 1 % bisection."""
    return critical_force(scene)


def breakaway_force_of(scene: Scene) -> float:
    """Drive force (N) at the first stick-to-slip transition of a spring-driven run.

    The run stops once the slider has slipped a full mean pitch, which always
    follows the first breakaway, so only the first stick-slip cycle is simulated.
    """
    if not isinstance(scene.drive, SpringDrive):
        scene = scene.replace(drive=SpringDrive())
    result = simulate(scene, stop=Travelled(scene.lower.spacing.mean_pitch))
    try:
        return breakaway_force(result)
    except SceneError:
        return math.nan


def critical_force_run(*, seed: int = 0, **params) -> dict:
    """Sweep run: critical constant force of ``make_scene(seed=seed, drive="force", **params)``."""
    scene = make_scene(seed=seed, drive="force", **params)
    return {"critical_force_N": critical_force(scene)}


def stick_slip_run(*, seed: int = 0, **params) -> dict:
    """Sweep run: a full spring-driven pass; breakaway force and event statistics."""
    scene = make_scene(seed=seed, drive="spring", **params)
    result = simulate(scene)
    events = stick_slip_events(result)
    stats = event_statistics(events)
    try:
        breakaway = breakaway_force(result)
    except SceneError:
        breakaway = math.nan
    return {"breakaway_force_N": breakaway, "events": float(stats["count"]),
            "force_drop_mean_N": stats["force_drop_mean"], "force_drop_std_N": stats["force_drop_std"],
            "mean_drive_force_N": float(result.drive_force.mean())}


def constant_force_travel_run(*, seed: int = 0, force: float, **params) -> dict:
    """Sweep run: how far a constant ``force`` (N) carries the slider before it stops."""
    scene = make_scene(seed=seed, drive="force", drive_force=force, **params)
    result = simulate(scene)
    return {"travel_m": float(result.x[-1] - result.x[0]), "passed": float(result.status == "passed")}


__all__ = ["critical_force_of", "breakaway_force_of", "critical_force_run", "stick_slip_run",
           "constant_force_travel_run", "ConstantForce"]
