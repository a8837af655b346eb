"""Initial-condition scans of asperity runs: the long-run stick-slip over the drive preload.

The scene builder places the slider relative to the first lower asperity
(a tenth of a base before it on the fixed track), so shifting the lower
surface's spacing ``offset`` moves the whole scene rigidly and changes
nothing. The initial condition the public API does vary is the drive
spring's initial force ``drive_preload`` (N): the drive point starts
preload / k_drive ahead of the slider, so the slider meets the surface with
a different speed and spring force. :func:`asperity_basins` runs one scene
per preload (and per spacing seed) through the sweep machinery and
classifies each run with :func:`classify_asperity`, into the classes of
:data:`asperity2d.dynamics.basins.LABELS`.
"""

from __future__ import annotations

import json

import numpy as np

from ..errors import SceneError
from .basins import BasinMap, _axis, _run
from .cycles import detect_period

RUN = "asperity2d.dynamics.asperity_basins:asperity_basin_run"
KEYS = ("label", "multiplicity", "period", "events", "pitches_per_cycle", "amplitude")
#: part of the run analysed (fractions of its duration): the slider is over the surface, past its entry
ASPERITY_WINDOW = (0.15, 0.9)


def classify_asperity(result, *, rtol: float = 0.05, max_multiplicity: int = 12) -> dict:
    """Class of a spring-driven asperity run, from its stick-slip events in the window :data:`ASPERITY_WINDOW`.

    ``rest``: the run ended stuck (status "stuck"); ``pure slip``: no
    stick-slip event in the window (:func:`asperity2d.stick_slip_events`);
    ``stick-slip``: the slips repeat -- the section is the slip onsets, its
    points (time since the previous slip, peak force, force drop) must repeat
    within ``rtol`` (of the mean interval and of the drive force's
    peak-to-peak: the pymunk contact solver repeats to about 1 %, not to
    round-off) twice over, with at most ``max_multiplicity`` slips per
    period; ``irregular`` otherwise. (The drive force itself is a poor
    section: the drive spring rings after every slip and crosses any level
    many times.) ``pitches_per_cycle`` is the drive's advance per period
    over the mean pitch of the lower surface; ``amplitude`` is half the
    peak-to-peak drive force in the window (N).

    Parameters
    ----------
    result : Result
        A spring-driven asperity run (``drive="spring"``).
    rtol : float
        Relative tolerance within which the section points must repeat (of the mean interval
        between slips and of the drive force's peak-to-peak).
    max_multiplicity : int
        Most slips per period of a repeating cycle.

    Returns
    -------
    dict
        ``label`` (an index into :data:`BASIN_LABELS`, as a float), ``events``, ``multiplicity``,
        ``period`` (s), ``pitches_per_cycle`` and ``amplitude`` (N).

    See Also
    --------
    asperity_basins : the class over a scan of the drive preload.

    Examples
    --------
    Two stick-slip events in the window of a short surface are too few to show a repeating
    cycle, so the run is "irregular":

    >>> import asperity2d as a
    >>> from asperity2d.dynamics import BASIN_LABELS, classify_asperity
    >>> c = classify_asperity(a.simulate(a.make_scene(lower_count=8, upper_count=2)))
    >>> BASIN_LABELS[int(c["label"])], c["events"]
    ('irregular', 2.0)
    """
    from ..analysis import stick_slip_events

    t = result.t
    a, b = t[0] + ASPERITY_WINDOW[0] * (t[-1] - t[0]), t[0] + ASPERITY_WINDOW[1] * (t[-1] - t[0])
    w = (t >= a) & (t <= b)
    force = result.drive_force[w]
    out = {"multiplicity": 0.0, "period": float("nan"), "pitches_per_cycle": float("nan"),
           "amplitude": 0.5 * float(np.ptp(force)) if force.size else 0.0}
    if result.status == "stuck":
        return {"label": 0.0, "events": 0.0, **out}
    events = [e for e in stick_slip_events(result) if a <= e.t_slip <= b]
    out["events"] = float(len(events))
    if not events:
        return {"label": 1.0, **out}
    slips = np.array([e.t_slip for e in events])
    points = np.column_stack([np.diff(slips), [e.force_peak for e in events[1:]], [e.force_drop for e in events[1:]]])
    swing = float(np.ptp(force))
    scale = [float(np.mean(points[:, 0])) if len(points) else 1.0, swing, swing]
    n, period, _, _ = detect_period(points, slips[1:], scale=scale, rtol=rtol, max_multiplicity=max_multiplicity,
                                    min_repeats=2)
    if not n:
        return {"label": 3.0, **out}
    pitch = result.scene.lower.spacing.mean_pitch
    return {"label": 2.0, **out, "multiplicity": float(n), "period": period,
            "pitches_per_cycle": period * result.scene.drive.velocity / pitch}


def asperity_basin_run(*, scene: str, drive_preload: float, duration: float | None = None, rtol: float = 0.05,
                       seed: int = 0) -> dict:
    """Sweep run function: ``scene`` is the JSON of make_scene keyword arguments; ``seed`` its spacing seed."""
    from ..builders import make_scene
    from ..run import simulate

    kwargs = json.loads(scene)
    return classify_asperity(simulate(make_scene(**kwargs, seed=seed, drive_preload=drive_preload), duration),
                             rtol=rtol)


def asperity_basins(scene: dict, preloads, *, seeds=(0,), duration: float | None = None, rtol: float = 0.05,
                    store=None, workers: int | None = None, scheduler: str | None = None,
                    progress: bool = True) -> BasinMap:
    """Classes of spring-driven runs of ``make_scene(**scene)`` over ``preloads`` (N) and spacing ``seeds``.

    The map's x axis is ``drive_preload``, its y axis ``seed``.

    Parameters
    ----------
    scene : dict
        ``make_scene`` arguments; must not set ``drive_preload`` or ``seed`` (they are the axes)
        and must use ``drive="spring"``.
    preloads : sequence of float
        Drive preloads (N), the map's x axis.
    seeds : sequence of int
        Spacing seeds, the map's y axis.
    duration : float, optional
        Run length (s) as in ``simulate`` (None: until the slider has crossed the surface).
    rtol : float
        Relative tolerance of a repeating cycle, as in :func:`classify_asperity`.
    store : str or os.PathLike, optional
        A resumable store, as in the belt chains' basin maps (``asperity2d belt basins``).
    workers : int, optional
        Worker processes (None: decided from the cost of a run).
    scheduler : str, optional
        A Dask scheduler address.
    progress : bool
        Show a progress bar.

    Returns
    -------
    BasinMap
        ``values[key][i, j]`` for preload ``i`` and seed ``j``, ``key`` one of ``label`` (an
        index into :data:`BASIN_LABELS`), ``events``, ``multiplicity``, ``period``,
        ``pitches_per_cycle``, ``amplitude``.

    See Also
    --------
    classify_asperity : the class of one run.

    Examples
    --------
    >>> from asperity2d.dynamics import BASIN_LABELS, asperity_basins
    >>> m = asperity_basins(dict(lower_count=6, upper_count=2), (0.0, 0.01), workers=1, progress=False)
    >>> [BASIN_LABELS[int(c)] for c in m.values["label"][:, 0]], m.values["events"][:, 0].tolist()
    (['irregular', 'irregular'], [1.0, 1.0])
    """
    from ..builders import make_scene
    from ..sweep import Study

    scene = dict(scene)
    for name in ("drive_preload", "seed"):
        if name in scene:
            raise SceneError(f"`scene` must not set `{name}`: it is an axis of the scan")
    if scene.get("drive", "spring") != "spring":
        raise SceneError(f"`drive` must be 'spring' for a preload scan, got {scene.get('drive')!r}")
    _, ps = _axis(("drive_preload", preloads), "preloads")
    make_scene(**scene, drive_preload=ps[0])  # validate once here, with a clear error, not in every worker
    try:
        text = json.dumps(scene, sort_keys=True)
    except TypeError as exc:
        raise SceneError(f"`scene` must hold JSON values only: {exc}") from None
    if duration is not None and (not np.isfinite(duration) or duration <= 0):
        raise SceneError(f"`duration` must be > 0, got {duration!r}")
    study = Study(name="asperity-basins", run=RUN, grid={"drive_preload": ps}, seeds=tuple(seeds),
                  fixed={"scene": text, "duration": duration, "rtol": float(rtol)})
    where, col = {p: i for i, p in enumerate(ps)}, {s: j for j, s in enumerate(study.seeds)}
    values, failed, wall = _run(study, store, workers, scheduler, progress, (len(ps), len(study.seeds)), KEYS,
                                lambda spec: (where[spec.params["drive_preload"]], col[spec.seed]))
    return BasinMap("drive_preload", np.array(ps), "seed", np.array(study.seeds, dtype=float), values,
                    float("nan") if duration is None else float(duration), failed, wall)
