"""Measures and sweep run functions for seed-000 style studies.

Top-level, picklable functions so they run in worker processes (compare's
process pool, the sweep executors, Dask):

* ``measure(scene) -> float`` for :func:`asperity2d.compare`;
* ``run(*, seed, **params) -> dict[str, float]`` for :mod:`asperity2d.sweep`
  (``params`` are :func:`make_scene` arguments).

The seed-000 study scripts (``scenes/seed000_*.py``) share the set-ups, the
parallel map :func:`run_many` and the claim / statistics helpers below.
"""

from __future__ import annotations

import math
from concurrent.futures import ProcessPoolExecutor
from typing import Callable

import numpy as np

from .analysis import breakaway_force, event_statistics, stick_slip_events
from .critical import critical_force
from .errors import SceneError
from .builders import make_scene
from .scene import ConstantForce, Scene, SpringDrive
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


#: Scene size of the seed-000 studies (lower / upper asperities) and the quick (test) size.
STUDY_SIZE = {"lower_count": 10, "upper_count": 3}
QUICK_SIZE = {"lower_count": 4, "upper_count": 2}
#: The two slider set-ups. ``free``: the slider rides on the asperities under a
#: 10 mN normal load (the package default). ``fixed``: seed 000's Working Model
#: set-up, a horizontal track at fixed height with the upper tips 0.125 µm
#: (a quarter of a 45° full triangle's height) below the lower tips' rest
#: height, the same for full and half triangles so only the shape changes.
SETUPS = {"free": {"track": "free"}, "fixed": {"track": "fixed", "interference": 0.125e-6}}


def peak_spring_force_of(scene: Scene) -> float:
    """Largest drive force (N) at a stick-to-slip transition over a full spring-driven pass.

    On the fixed track the first breakaway happens while only the front tip
    has entered the surface; the peak over the pass is the force needed to
    break the fully engaged slider loose at its worst position.
    """
    if not isinstance(scene.drive, SpringDrive):
        scene = scene.replace(drive=SpringDrive())
    events = stick_slip_events(simulate(scene))
    return max((e.force_peak for e in events), default=math.nan)


def spring_pass_run(*, seed: int = 0, **params) -> dict:
    """One full spring-driven pass of ``make_scene(seed=seed, drive="spring", **params)``.

    Returns (N, m, J): ``breakaway_force_N`` (first stick-to-slip) and
    ``peak_force_N`` (largest); from the first breakaway on,
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
        "breakaway_force_N": events[0].force_peak if events else nan,
        "peak_force_N": max((e.force_peak for e in events), default=nan),
        "mean_drive_force_N": float(f[start:].mean()),
        "keep_moving_force_N": float(np.sum(force * dx) / np.sum(dx)) if np.sum(dx) > 0 else nan,
        "events": float(stats["count"]), "force_drop_mean_N": stats["force_drop_mean"],
        "force_drop_std_N": stats["force_drop_std"], "regularity": stats["regularity"],
        "front_flank_work_J": float(np.sum(np.clip(resist, 0.0, None) * forward)),
        "back_flank_work_J": float(np.sum(np.clip(-resist, 0.0, None) * forward)),
        "passed": float(result.status == "passed"),
    }


#: Energy channels :func:`damping_travel_run` reports for each run (J, see
#: :mod:`asperity2d.engine.energy`); ``numerical`` sums the method's channels.
DAMPING_CHANNELS = ("drive_work", "stored_energy_change", "friction_work", "normal_work", "damper_work",
                    "stop_work", "numerical")


def damping_travel_run(*, seed: int = 0, factor: float = 0.9, **params) -> dict:
    """Seed 000 figure 12: constant force ``factor`` x the damped critical force, damped vs undamped.

    The critical force is bisected on the damped scene (``params`` as given);
    the same force then pushes three scenes: ``damped`` (as given),
    ``undamped`` (track dampers off, ``damping_ratio=0``) and ``elastic``
    (dampers off and contact ``restitution=1``: no impact loss either).
    Returns the force (N), each slider's final travel from its start and the
    farthest it got (``travel_<label>_m``, ``reach_<label>_m``, m), whether
    it passed or came to rest (``passed_<label>``, ``stuck_<label>``, 1/0;
    neither: the time limit) and its energy books (``<label>_<channel>_J``
    for :data:`DAMPING_CHANNELS`), also over the damped slider's travel only
    (``<label>_same_<channel>_J``: the books when it first got as far as the
    damped one stopped; NaN if it never did), which compares the channels
    over one path.
    """
    from .engine.energy import EnergyMeter
    from .simulate import Run, default_duration, default_stops

    params = {k: v for k, v in params.items() if k != "damping"}
    damped = make_scene(seed=seed, drive="force", **params)
    critical = critical_force(damped)
    force = factor * critical
    out = {"critical_force_N": critical, "force_N": force}
    undamped = {**params, "damping_ratio": 0.0}
    scenes = {"damped": damped, "undamped": make_scene(seed=seed, drive="force", **undamped),
              "elastic": make_scene(seed=seed, drive="force", **{**undamped, "restitution": 1.0})}
    for label, scene in scenes.items():
        scene = scene.replace(drive=ConstantForce(force=force))
        run = Run(scene)  # as simulate() runs it, metered, with a look at the damped travel
        if scene.slider.track == "free":
            run.settle()
        meter = EnergyMeter(run.engine)
        stops, duration = default_stops(scene), default_duration(scene)
        same = {}
        if label != "damped" and out["travel_damped_m"] > 0:
            if run.advance(duration, stop=[*stops, Travelled(out["travel_damped_m"])]) == "travelled":
                same = meter.report()
                run.advance(duration - run.time, stop=stops)
        else:
            run.advance(duration, stop=stops)
        books, result = meter.report(), run.result()
        same = books if label == "damped" else same
        out[f"travel_{label}_m"] = float(result.x[-1] - result.x[0])
        out[f"reach_{label}_m"] = float(result.x.max() - result.x[0])
        out[f"passed_{label}"] = float(run.status == "passed")
        out[f"stuck_{label}"] = float(run.status == "stuck")
        for k in DAMPING_CHANNELS:
            out[f"{label}_{k}_J"] = float(books[f"{k}_J"])
            out[f"{label}_same_{k}_J"] = float(same.get(f"{k}_J", math.nan))
    return out


def run_many(fn: Callable[..., dict], kwargs_list: list[dict], *, workers: int = 1) -> list[dict]:
    """``[fn(**kw) for kw in kwargs_list]``, in that order, on ``workers`` processes.

    ``fn`` must be a module-level function when ``workers > 1``. The results do
    not depend on ``workers`` (single-threaded stepping is deterministic).
    """
    if workers <= 1 or len(kwargs_list) <= 1:
        return [fn(**kw) for kw in kwargs_list]
    with ProcessPoolExecutor(max_workers=workers) as pool:
        futures = [pool.submit(fn, **kw) for kw in kwargs_list]
        return [f.result() for f in futures]


def mean_ci(values, *, level: float = 0.95) -> dict:
    """Mean, sample std and the t confidence interval of the mean of the finite ``values``."""
    from scipy import stats

    a = np.asarray(values, dtype=float)
    a = a[np.isfinite(a)]
    if len(a) < 2:
        m = float(a.mean()) if len(a) else math.nan
        return {"n": len(a), "mean": m, "std": math.nan, "ci_low": math.nan, "ci_high": math.nan}
    half = stats.t.ppf(0.5 + level / 2.0, len(a) - 1) * a.std(ddof=1) / math.sqrt(len(a))
    return {"n": int(len(a)), "mean": float(a.mean()), "std": float(a.std(ddof=1)),
            "ci_low": float(a.mean() - half), "ci_high": float(a.mean() + half)}


def versus_reference(values, reference: float, *, alternative: str = "less") -> dict:
    """One-sample Wilcoxon signed-rank test of ``values`` against a deterministic ``reference``.

    Returns the statistics of :func:`mean_ci` plus ``reference``, the
    effect size as ``difference`` (mean - reference, same unit),
    ``relative_difference`` (fraction) and ``effect_size_d`` ((mean -
    reference) / std, Cohen's d for one sample), and ``p_wilcoxon`` (one-sided
    in the direction ``alternative`` of values relative to reference) and
    ``p_wilcoxon_two_sided``.
    """
    from scipy import stats

    out = mean_ci(values)
    a = np.asarray(values, dtype=float)
    d = a[np.isfinite(a)] - float(reference)
    diff = out["mean"] - reference
    out.update(reference=float(reference), difference=diff, relative_difference=diff / reference,
               effect_size_d=diff / out["std"] if out["std"] and out["std"] > 0 else math.nan)
    if len(d) < 2 or not np.any(d):
        out["p_wilcoxon"] = out["p_wilcoxon_two_sided"] = 1.0
    else:
        out["p_wilcoxon"] = float(stats.wilcoxon(d, alternative=alternative).pvalue)
        out["p_wilcoxon_two_sided"] = float(stats.wilcoxon(d).pvalue)
    return out


def claim(text: str, holds: bool, numbers: dict, test: str, *, setup: str | None = None) -> dict:
    """A claim record for a study's summary.json: text, verdict, numbers, test (and set-up)."""
    out = {"claim": text, "verdict": "holds" if holds else "does not hold", "numbers": numbers,
           "test": test}
    if setup is not None:
        out["setup"] = setup
    return out


__all__ = ["critical_force_of", "breakaway_force_of", "peak_spring_force_of", "critical_force_run",
           "spring_pass_run", "damping_travel_run",
           "run_many", "mean_ci", "versus_reference", "claim", "STUDY_SIZE", "QUICK_SIZE", "SETUPS",
           "belt_chain_run"]


def belt_chain_run(*, seed: int = 0, preset_name: str = "table2-3dof", ic_spread: float = 0.0,
                   **overrides) -> dict:
    """Sweep run for a seed-001 belt chain: regime and stick-slip measures.

    ``preset_name`` is a :mod:`asperity2d.belt.presets` name; ``overrides``
    replace its ``simulate_chain`` arguments (``v_belt``, ``mu_s``, ...). With
    ``ic_spread`` > 0 the initial displacements get seeded uniform noise of
    that half-width (m): a Monte-Carlo over initial conditions.
    """
    from .belt import presets, regime, simulate_chain
    from .belt.studies import amplitude, total_stick

    kwargs = presets.preset(preset_name, **overrides)
    if ic_spread > 0:
        rng = np.random.default_rng(seed)
        x0 = np.asarray(kwargs["x0"], dtype=float)
        kwargs["x0"] = list(x0 + rng.uniform(-ic_spread, ic_spread, len(x0)))
    result = simulate_chain(**kwargs)
    label = regime.classify(result)
    return {"stick_slip": float(label == "stick-slip"), "quasi_harmonic": float(label == "quasi-harmonic"),
            "total_stick_s": float(sum(total_stick(result))), "amplitude_m": float(max(amplitude(result))),
            "energy_balance_error": float(result.energy_balance_error())}
