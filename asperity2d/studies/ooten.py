"""Ooten's studies: the two slider set-ups, scene sizes and the sweep run functions.

The ``scenes/ooten_*`` scripts compare scene variants over seeds with
:func:`asperity2d.compare` (its standard measures: critical force from rest
and with a run-up, first breakaway, peak and mean stick force over a pass)
and these sweep run functions, ``run(*, seed, **params) -> dict[str, float]``
(``params`` are :func:`asperity2d.make_scene` arguments), top-level so they
run in worker processes and on Dask. Their claims are records of
:func:`asperity2d.experiments.verdicts.claim`.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..analysis import event_statistics, stick_slip_events
from ..builders import make_scene
from ..critical import critical_force, critical_force_bracket, settled_run
from ..scene import ConstantForce
from ..run import default_dt, default_duration, default_stops, simulate
from ..sweep.runner import BatchedRun

#: Scene size of the Ooten studies (lower / upper asperities) and the quick (test) size.
STUDY_SIZE = {"lower_count": 10, "upper_count": 3}
QUICK_SIZE = {"lower_count": 4, "upper_count": 2}
#: The two slider set-ups. ``fixed``: Ooten's Working Model set-up (the
#: package default), a horizontal track at fixed height with the upper tips a
#: quarter of a 45° full triangle's height (0.125 µm) below the lower tips'
#: rest height, the same for full and half triangles so only the shape
#: changes. ``free``: the slider rides on the asperities under a 10 mN load.
SETUPS = {"fixed": {"track": "fixed", "interference": 0.125e-6}, "free": {"track": "free"}}


def critical_force_run(*, seed: int = 0, start: str = "rest", **params) -> dict:
    """Sweep run: the critical constant force of one scene.

    Parameters
    ----------
    seed : int, default 0
        The scene's seed.
    start : {"rest", "entry", "run-up"}, default "rest"
        Where the force starts (:func:`asperity2d.critical_force`).
    **params
        :func:`asperity2d.make_scene` arguments (``drive`` is ``"force"``).

    Returns
    -------
    dict
        ``critical_force_N``: the critical force (N).
    """
    scene = make_scene(seed=seed, drive="force", **params)
    return {"critical_force_N": critical_force(scene, start=start)}


def measures_run(*, seed: int = 0, passes: int = 5, starts: tuple = ("rest", "run-up"),
                 quasi_static: bool = True, **params) -> dict:
    """Sweep run: the named measures of one scene, each with what it reports about itself.

    The measures of :mod:`asperity2d.experiments.measures`, taken on
    ``make_scene(seed=seed, drive="force", **params)``: one job per scene, so a study of many
    measures builds each scene once. The critical forces equal those :func:`asperity2d.compare`
    gives for the same measure, scene and seed.

    Parameters
    ----------
    seed : int, default 0
        The scene's seed.
    passes : int, default 5
        Spring-driven passes for the stick forces (0: none).
    starts : tuple of str, default ("rest", "run-up")
        Starts of the critical force (:func:`asperity2d.critical_force_bracket`).
    quasi_static : bool, default True
        Also the quasi-static breakaway (a slowly ramped force; slow).
    **params
        :func:`asperity2d.make_scene` arguments.

    Returns
    -------
    dict
        ``critical_<start>_N`` for each of ``starts`` (N), its non-monotone band
        (``critical_<start>_band_low_N`` / ``_high_N``, NaN when monotone), run count and step;
        ``quasi_static_N`` and its ``quasi_static_rate_change`` (the ramp's convergence); over
        the passes (:func:`asperity2d.experiments.measures.stick_forces`) ``peak_stick_N`` and
        ``mean_stick_N`` (ensemble means), every pass's values (``peak_stick_passes_N``,
        ``mean_stick_passes_N``, lists) and ``first_breakaway_N`` of the pass at the nominal
        drive speed (the middle one).
    """
    from ..critical import critical_force_bracket
    from ..experiments.measures import quasi_static_breakaway, stick_forces

    scene = make_scene(seed=seed, drive="force", **params)
    out: dict = {}
    for start in starts:
        key = "critical_" + start.replace("-", "_")
        bracket = critical_force_bracket(scene, start=start)
        low, high = bracket.band if bracket.band else (math.nan, math.nan)
        out.update({f"{key}_N": bracket.value, f"{key}_band_low_N": low, f"{key}_band_high_N": high,
                    f"{key}_runs": float(bracket.runs), f"{key}_dt_s": bracket.dt})
    if quasi_static:
        q = quasi_static_breakaway(scene)
        out.update(quasi_static_N=q.force, quasi_static_rate_change=q.rate_change, quasi_static_dt_s=q.dt)
    if passes:
        sf = stick_forces(scene, passes=passes)
        out.update(peak_stick_N=sf.average("peak"), mean_stick_N=sf.average("mean"),
                   peak_stick_passes_N=list(sf.peak), mean_stick_passes_N=list(sf.mean),
                   first_breakaway_N=sf.first_breakaway[len(sf.first_breakaway) // 2],
                   events=list(map(float, sf.events)), stick_dt_s=sf.dt)
    return out


def travel_run(*, seed: int = 0, force: float, start: str = "run-up", **params) -> dict:
    """Sweep run: Ooten's figure 10, how far a constant force carries the slider.

    Parameters
    ----------
    seed : int, default 0
        The scene's seed.
    force : float
        The constant force (N).
    start : {"rest", "entry", "run-up"}, default "run-up"
        Where the force starts (as for :func:`asperity2d.critical_force`).
    **params
        :func:`asperity2d.make_scene` arguments (``drive`` is ``"force"``).

    Returns
    -------
    dict
        ``travel_m`` (m), ``passed`` and ``stuck`` (1/0), ``force_N`` and ``dt_s``, the step
        (the step policy's for the critical force from ``start``).
    """
    from ..experiments.measures import measure_step, travel_under_force

    scene = make_scene(seed=seed, drive="force", **params)
    dt = measure_step("travel", scene, start=start)
    travel, status = travel_under_force(scene, force=force, start=start, dt=dt)
    return {"travel_m": travel, "passed": float(status == "passed"), "stuck": float(status == "stuck"),
            "force_N": force, "dt_s": dt}


def pushed(scene, force: float, *, start: str = "rest", dt: float | None = None):
    """A constant force applied to a scene from a start, as :func:`asperity2d.critical_force`
    begins each of its runs.

    Parameters
    ----------
    scene : asperity2d.Scene
        The scene (its drive is replaced by the constant force).
    force : float
        The force (N).
    start : {"rest", "entry", "run-up"}, default "rest"
        ``"rest"``: at rest on the surface, every tip against its flank; ``"run-up"``: from the
        builder's position.
    dt : float, optional
        The step (s); default the scene's default step.

    Returns
    -------
    asperity2d.Result
        The run, ended by the default stops (passed, stuck or the time limit).
    """
    pushed_scene = scene.replace(drive=ConstantForce(force=force))
    run = settled_run(scene, start=start, dt=dt)
    run.set_drive_force(force)
    run.advance(default_duration(pushed_scene), stop=default_stops(pushed_scene))
    return dataclasses.replace(run.result(), scene=pushed_scene)


def spring_pass(scene, *, contact_work: bool = False, dt: float | None = None):
    """One spring-driven pass of a scene (:func:`asperity2d.simulate` with the default stops).

    Parameters
    ----------
    scene : asperity2d.Scene
        A scene with a spring drive.
    contact_work : bool, default False
        Also keep the contact-work books (``result.meta["contact_work"]``).
    dt : float, optional
        The step (s); default the step policy's for stick forces
        (:func:`asperity2d.experiments.measures.measure_step`).

    Returns
    -------
    tuple
        ``(result, books)``: the :class:`asperity2d.Result` and the contact-work books (a
        mapping of J) or None.
    """
    from ..experiments.measures import measure_step

    dt = measure_step("peak-stick", scene) if dt is None else dt
    result = simulate(scene, contact_work=contact_work, dt=dt)
    return result, result.meta.get("contact_work")


def spring_pass_run(*, seed: int = 0, contact_work: bool = False, **params) -> dict:
    """Sweep run: one full spring-driven pass of ``make_scene(seed=seed, drive="spring", **params)``.

    Parameters
    ----------
    seed : int, default 0
        The scene's seed.
    contact_work : bool, default False
        Also the contact-work books of the pass.
    **params
        :func:`asperity2d.make_scene` arguments.

    Returns
    -------
    dict
        (N, m, J): ``first_breakaway_N`` (first stick-to-slip; on the
    fixed track the front tip entering alone), ``peak_stick_force_N``
    (largest) and ``mean_stick_force_N`` (mean force at the stick-to-slip
    transitions); from the first breakaway on, ``mean_drive_force_N`` (time
    average) and ``keep_moving_force_N`` (the displacement-weighted average,
    work / distance: the mean force needed to keep the slider moving at the
    drive speed); the stick-slip statistics of :func:`asperity2d.event_statistics`
    (``events``, ``force_drop_mean_N``, ``force_drop_std_N``,
    ``slip_distance_mean_m``, ``regularity``); ``travel_m`` (whole pass).
    With ``contact_work``: the contact-work books of the whole pass,
    ``contact_work_pushing_J``, ``contact_work_rebound_J``,
    ``contact_work_resisting_J`` and ``floor_work_J``, and
    ``pushing_force_mean_N`` (pushing work per metre of travel).
    """
    result, books = spring_pass(make_scene(seed=seed, drive="spring", **params), contact_work=contact_work)
    return _pass_quantities(result, books)


def _pass_quantities(result, books) -> dict:
    """:func:`spring_pass_run`'s quantities of one pass (and its contact-work books, or None)."""
    events = stick_slip_events(result)
    stats = event_statistics(events)
    t, x, f = result.t, result.x, result.drive_force
    start = int(np.searchsorted(t, events[0].t_slip)) if events else 0
    dx = np.diff(x[start:])
    force = 0.5 * (f[start:-1] + f[start + 1:])
    nan = math.nan
    travel = float(x[-1] - x[0])
    out = {
        "first_breakaway_N": events[0].force_peak if events else nan,
        "peak_stick_force_N": max((e.force_peak for e in events), default=nan),
        "mean_stick_force_N": float(np.mean([e.force_peak for e in events])) if events else nan,
        "mean_drive_force_N": float(f[start:].mean()),
        "keep_moving_force_N": float(np.sum(force * dx) / np.sum(dx)) if np.sum(dx) > 0 else nan,
        "events": float(stats["count"]), "force_drop_mean_N": stats["force_drop_mean"],
        "force_drop_std_N": stats["force_drop_std"], "slip_distance_mean_m": stats["slip_distance_mean"],
        "regularity": stats["regularity"], "travel_m": travel,
        "passed": float(result.status == "passed"), "dt_s": float(result.meta["dt"]),
    }
    if books is not None:
        out.update(contact_work_pushing_J=books["pushing_J"], contact_work_rebound_J=books["rebound_J"],
                   contact_work_resisting_J=books["resisting_J"], floor_work_J=books["floor_J"],
                   pushing_force_mean_N=books["pushing_J"] / travel if travel > 0 else nan)
    return out


def _pass_scene(params: dict, seed: int):
    """The scene of ``spring_pass_run(**params, seed=seed)``; None with ``contact_work`` (the
    books are the reference's)."""
    params = dict(params)
    if params.pop("contact_work", False):
        return None
    return make_scene(seed=seed, drive="spring", **params)


def _pass_runs(calls, engine: str) -> list:
    """:func:`spring_pass_run` of every ``(params, seed)`` of ``calls`` on ``engine``, the passes
    in one batch per step (each at the step policy's step, as :func:`spring_pass` takes it): per
    call its quantities, or the error that stopped that pass alone."""
    from ..experiments.measures import measure_step
    from ..run import simulate_many

    scenes = [_pass_scene(params, seed) for params, seed in calls]
    steps = [measure_step("peak-stick", scene) for scene in scenes]
    out: list = [None] * len(scenes)
    for dt in sorted(set(steps)):
        chosen = [j for j, step in enumerate(steps) if step == dt]
        for j, result in zip(chosen, simulate_many([scenes[j] for j in chosen], dt=dt, engine=engine)):
            out[j] = result if isinstance(result, Exception) else _pass_quantities(result, None)
    return out


spring_pass_run.batched = BatchedRun(scene=_pass_scene, runs=_pass_runs)


#: Energy channels :func:`damping_travel_run` reports for each run (J, see
#: ``asperity2d.engine.energy``); ``numerical`` sums the method's channels.
DAMPING_CHANNELS = ("drive_work", "stored_energy_change", "friction_work", "normal_work", "damper_work",
                    "stop_work", "numerical")


def damping_travel_run(*, seed: int = 0, factor: float = 0.9, **params) -> dict:
    """Sweep run, Ooten's figure 12: a constant force, ``factor`` x the damped critical force,
    on damped and undamped scenes.

    The critical force is bisected on the damped scene (``params`` as given);
    the same force then pushes three scenes: ``damped`` (as given),
    ``undamped`` (track dampers off, ``damping_ratio=0``) and ``elastic``
    (dampers off and contact ``restitution=1``: no impact loss either).
    Returns the force (N), each slider's final travel from its start and the
    farthest it got (``travel_<label>_m``, ``reach_<label>_m``, m), whether
    it passed or came to rest (``passed_<label>``, ``stuck_<label>``, 1/0;
    neither: the time limit) and its energy books (``<label>_<channel>_J``
    for ``DAMPING_CHANNELS``), also over the damped slider's travel only
    (``<label>_same_<channel>_J``: the books when it first got as far as the
    damped one stopped; NaN if it never did), which compares the channels
    over one path.

    Parameters
    ----------
    seed : int, default 0
        The scenes' seed.
    factor : float, default 0.9
        The force as a fraction of the damped scene's critical force with a run-up.
    **params
        :func:`asperity2d.make_scene` arguments (``damping`` is ignored).

    Returns
    -------
    dict
        ``critical_force_N`` and ``force_N`` (N), and per scene (``damped``, ``undamped``,
        ``elastic``) the travel, reach, status and energy books described above.
    """
    params = {k: v for k, v in params.items() if k != "damping"}
    damped = make_scene(seed=seed, drive="force", **params)
    # the pushes below start where the builder puts the slider: so does this threshold, and it is
    # taken at their step (the default: travel is converged there; the run-up threshold itself
    # reads ~4 % low at it, the same for the threshold and the pushes)
    critical = critical_force_bracket(damped, start="run-up", dt=default_dt(damped)).value
    force = factor * critical
    out = {"critical_force_N": critical, "force_N": force}
    undamped = {**params, "damping_ratio": 0.0}
    scenes = {"damped": damped, "undamped": make_scene(seed=seed, drive="force", **undamped),
              "elastic": make_scene(seed=seed, drive="force", **{**undamped, "restitution": 1.0})}
    for label, scene in scenes.items():
        scene = scene.replace(drive=ConstantForce(force=force))
        same = {}
        reach = out.get("travel_damped_m", 0.0) if label != "damped" else 0.0

        def watch(probe, same=same, reach=reach):  # the books where it first got as far
            if reach > 0 and not same and abs(probe.x - probe.x_start) >= reach:
                same.update(probe.energy())

        result = simulate(scene, energy=True, observers=[watch])
        books = result.meta["energy"]
        same = books if label == "damped" else same
        out[f"travel_{label}_m"] = float(result.x[-1] - result.x[0])
        out[f"reach_{label}_m"] = float(result.x.max() - result.x[0])
        out[f"passed_{label}"] = float(result.status == "passed")
        out[f"stuck_{label}"] = float(result.status == "stuck")
        for k in DAMPING_CHANNELS:
            out[f"{label}_{k}_J"] = float(books[f"{k}_J"])
            out[f"{label}_same_{k}_J"] = float(same.get(f"{k}_J", math.nan))
    return out


def plot_positions(results, labels, path):
    """Slider travel against time for several runs on one axis (Ooten's figure 10 style): plateaus
    are where a slider stopped on a flank.

    Parameters
    ----------
    results : sequence of asperity2d.Result
        The runs.
    labels : sequence of str
        One legend entry per run.
    path : str or os.PathLike
        The image file (``.png``, ``.svg``, ``.pdf``).

    Returns
    -------
    pathlib.Path
        The file written.
    """
    from ..renderers.plots import plot_positions as draw

    return draw(results, labels, path)


def plot_position_velocity(result, path, *, title: str = ""):
    """Ooten's figure 17: slider position (µm) and velocity (m/s) against time (µs); the velocity
    panel shows the collision spikes where the slider hits a lower flank.

    Parameters
    ----------
    result : asperity2d.Result
        The run.
    path : str or os.PathLike
        The image file (``.png``, ``.svg``, ``.pdf``).
    title : str, default ""
        The figure's title.

    Returns
    -------
    pathlib.Path
        The file written.
    """
    from ..renderers.plots import plot_position_velocity as draw

    return draw(result, path, title=title)
