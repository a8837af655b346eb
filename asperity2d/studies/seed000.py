"""Seed 000's studies: the two slider set-ups, scene sizes and the sweep run functions.

The ``scenes/seed000_*`` scripts compare scene variants over seeds with
:func:`asperity2d.compare` (its standard measures: critical force from rest
and with a run-up, first breakaway, peak and mean stick force over a pass)
and these sweep run functions, ``run(*, seed, **params) -> dict[str, float]``
(``params`` are :func:`asperity2d.make_scene` arguments), top-level so they
run in worker processes and on Dask. Their claims are records of
:mod:`asperity2d.studies.claims`.
"""

from __future__ import annotations

import math

import numpy as np

from ..analysis import event_statistics, stick_slip_events
from ..builders import make_scene
from ..critical import critical_force
from ..scene import ConstantForce
from ..simulate import simulate

#: Scene size of the seed-000 studies (lower / upper asperities) and the quick (test) size.
STUDY_SIZE = {"lower_count": 10, "upper_count": 3}
QUICK_SIZE = {"lower_count": 4, "upper_count": 2}
#: The two slider set-ups. ``fixed``: seed 000's Working Model set-up (the
#: package default), a horizontal track at fixed height with the upper tips a
#: quarter of a 45° full triangle's height (0.125 µm) below the lower tips'
#: rest height, the same for full and half triangles so only the shape
#: changes. ``free``: the slider rides on the asperities under a 10 mN load.
SETUPS = {"fixed": {"track": "fixed", "interference": 0.125e-6}, "free": {"track": "free"}}


def critical_force_run(*, seed: int = 0, start: str = "rest", **params) -> dict:
    """Sweep run: critical constant force (N) of ``make_scene(seed=seed, drive="force", **params)``
    from ``start`` (see :func:`asperity2d.critical_force`)."""
    scene = make_scene(seed=seed, drive="force", **params)
    return {"critical_force_N": critical_force(scene, start=start)}


def spring_pass_run(*, seed: int = 0, **params) -> dict:
    """One full spring-driven pass of ``make_scene(seed=seed, drive="spring", **params)``.

    Returns (N, m, J): ``first_breakaway_N`` (first stick-to-slip),
    ``peak_stick_force_N`` (largest) and ``mean_stick_force_N`` (mean force at
    the stick-to-slip transitions); from the first breakaway on,
    ``mean_drive_force_N`` (time average) and ``keep_moving_force_N`` (the
    displacement-weighted average, work / distance: the mean force needed to
    keep the slider moving at the drive speed); the stick-slip statistics of
    :func:`event_statistics` (``events``, ``force_drop_mean_N``,
    ``force_drop_std_N``, ``regularity``); and the work of the net horizontal
    contact force on the slider split by sign: ``front_flank_work_J`` (resisting,
    tips climbing front flanks) and ``back_flank_work_J`` (pushing forward,
    back flanks sliding down lower flanks as the lower springs recover).
    """
    result = simulate(make_scene(seed=seed, drive="spring", **params))
    events = stick_slip_events(result)
    stats = event_statistics(events)
    t, x, f = result.t, result.x, result.drive_force
    start = int(np.searchsorted(t, events[0].t_slip)) if events else 0
    dx = np.diff(x[start:])
    force = 0.5 * (f[start:-1] + f[start + 1:])
    resist = result.friction_force[start + 1:]
    forward = np.clip(dx, 0.0, None)
    nan = math.nan
    return {
        "first_breakaway_N": events[0].force_peak if events else nan,
        "peak_stick_force_N": max((e.force_peak for e in events), default=nan),
        "mean_stick_force_N": float(np.mean([e.force_peak for e in events])) if events else nan,
        "mean_drive_force_N": float(f[start:].mean()),
        "keep_moving_force_N": float(np.sum(force * dx) / np.sum(dx)) if np.sum(dx) > 0 else nan,
        "events": float(stats["count"]), "force_drop_mean_N": stats["force_drop_mean"],
        "force_drop_std_N": stats["force_drop_std"], "regularity": stats["regularity"],
        "front_flank_work_J": float(np.sum(np.clip(resist, 0.0, None) * forward)),
        "back_flank_work_J": float(np.sum(np.clip(-resist, 0.0, None) * forward)),
        "passed": float(result.status == "passed"),
    }


def damping_travel_run(*, seed: int = 0, factor: float = 0.9, **params) -> dict:
    """Seed 000 figure 12: constant force ``factor`` x the damped critical force, damped vs undamped.

    The critical force is bisected on the damped scene (``params`` as given);
    the same force then pushes the damped scene and the scene with undamped
    lower asperities (``damping_ratio=0``). Returns the force (N), each
    slider's final travel from its start (m) and whether it passed (1/0).
    """
    params = {k: v for k, v in params.items() if k != "damping"}
    damped = make_scene(seed=seed, drive="force", **params)
    # the pushes below start where the builder puts the slider: so does this threshold
    critical = critical_force(damped, start="run-up")
    force = factor * critical
    out = {"critical_force_N": critical, "force_N": force}
    undamped = make_scene(seed=seed, drive="force", **{**params, "damping_ratio": 0.0})
    for label, scene in (("damped", damped), ("undamped", undamped)):
        result = simulate(scene.replace(drive=ConstantForce(force=force)))
        out[f"travel_{label}_m"] = float(result.x[-1] - result.x[0])
        out[f"passed_{label}"] = float(result.status == "passed")
    return out


