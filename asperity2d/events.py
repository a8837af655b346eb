"""Stick–slip events: a run cut into stick–slip cycles (:func:`stick_slip_events`, one frozen
:class:`Event` each), their summary (:func:`event_statistics`) and table (:func:`events_table`),
and :func:`synthetic_stick_slip`, a seeded series whose true events are known (in the spirit of
ruptures' ``pw_constant``), used to test the detector. ``asperity2d.analysis`` re-exports
every name here.

Segmentation (Ooten's stick–slip: the slider stops, the drive spring loads
it, it breaks away and slips): a sample is *stick* when the slider is nearly at
rest, ``|v| < stick_speed``, and *slip* when it moves clearly faster than the
drive, ``v > slip_speed``; in between the previous state holds (hysteresis).
The slip speed follows the scene (``slip_speed_threshold``): a block that
loses no friction swings on the drive spring from rest to exactly 2 V, and a
real slip peaks above that by an amount the closed form of a spring-driven
block gives (:func:`spring_block_slip`), so the threshold sits between the two.
Slips shorter than ``min_slip`` or moving the slider less than
``min_slip_distance`` are noise (micro-slips of one contact); sticks in which
the slider is slow for less than ``min_stick`` inside a slip are bounces off
asperities, not re-sticking. Both rules look at time and distance, not at
sample counts, so the events do not depend on how often the run was recorded.
The distance rule follows the scene's own scale (``slip_scale``): a tenth
of the smallest of the asperity base, the lower surface's mean pitch and the
drive spring's stretch over one slip, so a flat block's 30 nm slips count
while an asperity's nanometre micro-slips do not.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .builders import make_scene
from .errors import SceneError
from .result import Result
from .scene import SpringDrive
from .slip_thresholds import (MIN_SLIP_FRACTION, MIN_SLIP_PERIODS, STICK_SPEED_FRACTION, _min_stick,
                              slip_scale, slip_speed_threshold)


@dataclass(frozen=True)
class Event:
    """One stick–slip cycle (SI units).

    ``t_stick`` (s): start of the stick phase; ``t_slip`` (s): stick-to-slip
    transition (the sample where the drive force peaks, just before the slider
    overtakes the drive); ``t_end`` (s): end of the slip (re-stick, or the end
    of the run when ``complete`` is False); ``force_peak`` (N): drive force at
    ``t_slip``; ``force_drop`` (N): peak minus the lowest drive force during
    the slip; ``slip_distance`` (m): slider travel from ``t_slip`` to ``t_end``;
    ``stick_duration`` (s) = ``t_slip - t_stick``.

    Attributes
    ----------
    t_stick, t_slip, t_end : float
        Start of the stick, the stick-to-slip transition, end of the slip (s).
    force_peak, force_drop : float
        Drive force at ``t_slip`` and its fall during the slip (N).
    slip_distance : float
        Slider travel during the slip (m).
    stick_duration : float
        ``t_slip - t_stick`` (s).
    complete : bool, default True
        False when the run ended during the slip.

    See Also
    --------
    asperity2d.stick_slip_events : the events of a run.

    Examples
    --------
    >>> import asperity2d as a
    >>> result = a.simulate(a.make_scene(lower_count=4, upper_count=2))
    >>> event = a.stick_slip_events(result)[0]
    >>> event.complete, f"{event.force_drop * 1e3:.3g} mN"
    (True, '9.21 mN')
    """

    t_stick: float
    t_slip: float
    t_end: float
    force_peak: float
    force_drop: float
    slip_distance: float
    stick_duration: float
    complete: bool = True


#: the columns of :func:`events_table`, in order: :class:`Event`'s fields
EVENT_COLUMNS = ("t_stick", "t_slip", "t_end", "force_peak", "force_drop", "slip_distance", "stick_duration",
                 "complete")


def events_table(events, path=None) -> dict:
    """Events as a table: column name -> array, one row per event; written as CSV to ``path`` if given.

    No pandas needed; with pandas, ``pandas.DataFrame(events_table(events))`` is the data frame.

    Parameters
    ----------
    events : sequence of Event
        Events of a run (:func:`stick_slip_events`).
    path : str or os.PathLike, optional
        A ``.csv`` file to write (atomically): a header line of ``EVENT_COLUMNS``, SI units,
        ``complete`` as 1 or 0.

    Returns
    -------
    dict
        ``EVENT_COLUMNS`` -> NumPy array (float64; ``complete`` bool), each with one entry per event.

    Examples
    --------
    >>> import asperity2d as a
    >>> events = a.stick_slip_events(a.simulate(a.make_scene(lower_count=4, upper_count=2)))
    >>> table = a.events_table(events, "events.csv")
    >>> [f"{f * 1e3:.3g} mN" for f in table["force_drop"]], table["complete"].tolist()
    (['9.21 mN', '11.7 mN'], [True, False])
    >>> open("events.csv").readline().strip()
    't_stick,t_slip,t_end,force_peak,force_drop,slip_distance,stick_duration,complete'
    """
    from ._io import atomic_write

    rows = list(events)
    if not all(isinstance(e, Event) for e in rows):
        raise SceneError("`events` must be a sequence of Event (stick_slip_events(result))")
    table = {name: np.array([getattr(e, name) for e in rows], dtype=bool if name == "complete" else float)
             for name in EVENT_COLUMNS}
    if path is not None:
        if not str(path).lower().endswith(".csv"):
            raise SceneError(f"`path` must end in .csv, got {str(path)!r}")
        columns = np.column_stack([table[n].astype(float) for n in EVENT_COLUMNS]) if rows else np.zeros((0, 8))

        def write(fh):
            np.savetxt(fh, columns, delimiter=",", header=",".join(EVENT_COLUMNS), comments="", fmt="%.17g")

        atomic_write(path, write)
    return table


def _asperity_run(result) -> None:
    """Raise SceneError unless ``result`` is an asperity run (a Result, or a record read lazily)."""
    if getattr(result, "kind", "asperity") != "asperity" or getattr(result, "scene", None) is None:
        what = "a belt chain" if getattr(result, "kind", None) == "belt" else type(result).__name__
        hint = ("; a chain's sticks and slips are its `stick_intervals` and `events` (asperity2d.belt)"
                if what == "a belt chain" else "")
        raise SceneError(f"`result` must be an asperity run (asperity2d.simulate), got {what}{hint}")


def _drive_scales(result) -> tuple[float | None, float | None]:
    """(drive velocity m/s, slider period on the drive spring s), or Nones."""
    _asperity_run(result)
    drive = result.scene.drive
    if not isinstance(drive, SpringDrive):
        return None, None
    return drive.velocity, 2.0 * math.pi * math.sqrt(result.scene.slider.mass / drive.stiffness)


def _runs(state: np.ndarray) -> list[list[int]]:
    """Runs of equal values as [value, start, stop) lists."""
    if len(state) == 0:
        return []
    cuts = np.flatnonzero(np.diff(state)) + 1
    starts = np.concatenate(([0], cuts))
    stops = np.concatenate((cuts, [len(state)]))
    return [[int(state[a]), int(a), int(b)] for a, b in zip(starts, stops)]


def _merge(runs: list[list[int]]) -> list[list[int]]:
    out: list[list[int]] = []
    for run in runs:
        if out and out[-1][0] == run[0]:
            out[-1][2] = run[2]
        else:
            out.append(list(run))
    return out


def _thresholds(result, stick_speed, slip_speed, min_stick, min_slip, min_slip_distance) -> dict:
    """The detector's thresholds (SI): the given ones, the scene's defaults for the rest."""
    speed, period = _drive_scales(result)
    defaults = {"stick_speed": (stick_speed, STICK_SPEED_FRACTION, speed),
                "slip_speed": (slip_speed, 1.0, slip_speed_threshold(result.scene)),
                "min_stick": (min_stick, 1.0, _min_stick(result.scene, period)),
                "min_slip": (min_slip, MIN_SLIP_PERIODS, period),
                "min_slip_distance": (min_slip_distance, MIN_SLIP_FRACTION, slip_scale(result.scene))}
    values = {}
    for name, (given, fraction, scale) in defaults.items():
        if given is None:
            if scale is None:
                raise SceneError(f"`{name}` must be given for a run without a spring drive")
            given = fraction * scale
        if not math.isfinite(given) or given < 0:
            raise SceneError(f"`{name}` must be a finite number >= 0, got {given!r}")
        values[name] = float(given)
    if values["slip_speed"] <= values["stick_speed"]:
        raise SceneError(f"`slip_speed` ({values['slip_speed']!r}) must be > "
                         f"`stick_speed` ({values['stick_speed']!r})")
    return values


def stick_slip_events(result, *, stick_speed: float | None = None, slip_speed: float | None = None,
                      min_stick: float | None = None, min_slip: float | None = None,
                      min_slip_distance: float | None = None) -> list[Event]:
    """Segment the slider's motion into stick–slip events.

    Parameters
    ----------
    result : Result
        A run (spring drive for the defaults; any drive with explicit values).
    stick_speed : float, optional
        abs(v) below this (m/s) is stick. Default: 0.5 x the drive velocity.
    slip_speed : float, optional
        v above this (m/s) is slip. Default: ``slip_speed_threshold``, from
        the scene's own scales: halfway between 2 V (a slider that loses no
        friction, released from rest on the drive spring, peaks at exactly
        2 V) and the closed-form peak speed of the scene's slips, between
        2.25 V and 3 V.
    min_stick : float, optional
        A stick shorter than this (s) between two slips is a bounce, merged
        into the slip. Default: half the slider's period on the drive spring,
        or half the closed-form stick (``scene_slip``) if shorter.
    min_slip : float, optional
        A slip shorter than this (s) is ignored. Default: 0.1 of that period.
    min_slip_distance : float, optional
        A slip moving the slider less than this (m) is ignored. Default: 0.1
        of ``slip_scale`` (the asperity base on Ooten's scenes, the drive
        spring's stretch over a slip on a flat block).

    Returns
    -------
    list of Event
        In time order. The last one has ``complete=False`` when the run ended
        during its slip. A slip needs a stick before it: motion before the
        first stick is not an event.

    Raises
    ------
    SceneError
        A threshold is negative or not finite, ``slip_speed`` is not above
        ``stick_speed``, or a default is needed for a run without a spring drive.

    See Also
    --------
    asperity2d.breakaway_force : one force out of these events.
    asperity2d.peak_stick_force
    asperity2d.mean_stick_force
    asperity2d.event_statistics : their counts, means and regularity.

    Examples
    --------
    >>> import asperity2d as a
    >>> result = a.simulate(a.make_scene(lower_count=4, upper_count=2))
    >>> events = a.stick_slip_events(result)
    >>> len(events)
    2
    >>> first = events[0]
    >>> print(f"slips at {first.t_slip:.3g} s under {first.force_peak * 1e3:.3g} mN, "
    ...       f"moves {first.slip_distance * 1e6:.3g} um")
    slips at 1.39e-07 s under 6.33 mN, moves 2.43 um
    """
    values = _thresholds(result, stick_speed, slip_speed, min_stick, min_slip, min_slip_distance)
    speed, _ = _drive_scales(result)
    t, v, x, force = (np.asarray(a, dtype=float) for a in (result.t, result.v, result.x,
                                                             result.drive_force))
    if len(t) < 2:
        return []
    # +1 slip, -1 stick, 0 dead band (keeps the previous state); leading 0: unknown.
    label = np.where(v > values["slip_speed"], 1, np.where(np.abs(v) < values["stick_speed"], -1, 0))
    idx = np.where(label != 0, np.arange(len(v)), 0)
    np.maximum.accumulate(idx, out=idx)
    state = np.where(label[idx] != 0, label[idx], 0)
    runs = _runs(state)
    edge = np.append(t, t[-1] + (t[-1] - t[-2]))  # run [a, b) lasts edge[b] - edge[a]

    def noise(r):  # a slip too short in time or in distance (from the sample before it)
        moved = x[min(r[2], len(x) - 1)] - x[max(r[1] - 1, 0)]
        return edge[r[2]] - edge[r[1]] < values["min_slip"] or moved < values["min_slip_distance"]

    runs = _merge([[-1 if (r[0] == 1 and noise(r)) else r[0], r[1], r[2]] for r in runs])
    # A stick is judged by the time the slider is really slow in it, not by the run's length:
    # the hysteresis holds "stick" through the dead band, so a slider swinging freely on the
    # drive spring after a slip (no contact, v from -1.4 V to 3.4 V, measured) would otherwise
    # log a "stick" every drive period (events 110 nm = V x period apart at 0.2-0.8 mN).
    slow_time = np.concatenate(([0.0], np.cumsum(np.diff(edge) * (np.abs(v) < values["stick_speed"]))))
    for i, r in enumerate(runs):
        if r[0] == -1 and i > 0 and runs[i - 1][0] == 1 and slow_time[r[2]] - slow_time[r[1]] < values["min_stick"]:
            r[0] = 1  # a bounce inside a slip (or a stop too short to trust at the end)
    runs = _merge(runs)

    drive_velocity = speed if speed is not None else 0.0
    events = []
    for i in range(1, len(runs)):
        (prev, s0, _), (kind, a, b) = runs[i - 1], runs[i]
        if kind != 1 or prev != -1:
            continue
        # Onset: the drive force peaks where the slider overtakes the drive; search the
        # samples from the last one not yet faster than the drive to the first fast one.
        slow = np.flatnonzero(v[s0:a] <= max(drive_velocity, values["stick_speed"]))
        lo = s0 + (int(slow[-1]) if len(slow) else a - s0 - 1)
        onset = lo + int(np.argmax(force[lo:a + 1]))
        complete = b < len(t)
        end = b if complete else len(t) - 1
        peak = float(force[onset])
        events.append(Event(
            t_stick=float(t[s0]), t_slip=float(t[onset]), t_end=float(t[end]),
            force_peak=peak, force_drop=peak - float(np.min(force[onset:end + 1])),
            slip_distance=float(x[end] - x[onset]), stick_duration=float(t[onset] - t[s0]),
            complete=complete))
    return events


def event_statistics(events: list[Event]) -> dict:
    """Summary of stick–slip events.

    Returns a dict: ``count``; ``force_drop_mean`` / ``force_drop_std`` (N)
    and ``slip_distance_mean`` (m) over complete events (an unfinished last
    slip has a truncated drop); ``stick_duration_mean`` / ``_std`` (s) over all
    events; ``interval_mean`` (s) and ``regularity``: the coefficient of
    variation (std / mean) of the intervals between successive ``t_slip``
    (0 for perfectly periodic stick–slip). Standard deviations use ddof=1;
    quantities with too few events are NaN.

    Parameters
    ----------
    events : list of Event
        The events of one run, in time order (:func:`~asperity2d.stick_slip_events`).

    Returns
    -------
    dict
        The keys above, each a float (``count``: an int); SI units.

    See Also
    --------
    asperity2d.stick_slip_events : the events.

    Examples
    --------
    >>> import asperity2d as a
    >>> result = a.simulate(a.make_scene(lower_count=4, upper_count=2))
    >>> stats = a.event_statistics(a.stick_slip_events(result))
    >>> stats["count"], f"{stats['force_drop_mean'] * 1e3:.3g} mN"
    (2, '9.21 mN')
    >>> stats["regularity"]  # two events make one interval: no spread to measure
    nan
    """
    def mean_std(values):
        a = np.asarray(values, dtype=float)
        mean = float(a.mean()) if len(a) else math.nan
        return mean, (float(a.std(ddof=1)) if len(a) > 1 else math.nan)

    complete = [e for e in events if e.complete]
    drop_mean, drop_std = mean_std([e.force_drop for e in complete])
    stick_mean, stick_std = mean_std([e.stick_duration for e in events])
    intervals = np.diff([e.t_slip for e in events])
    interval_mean, interval_std = mean_std(intervals)
    return {
        "count": len(events),
        "force_drop_mean": drop_mean, "force_drop_std": drop_std,
        "slip_distance_mean": mean_std([e.slip_distance for e in complete])[0],
        "stick_duration_mean": stick_mean, "stick_duration_std": stick_std,
        "interval_mean": interval_mean,
        "regularity": interval_std / interval_mean if interval_mean > 0 else math.nan,
    }


def synthetic_stick_slip(*, n_events: int = 8, seed: int = 0, noise: float = 0.0,
                         samples_per_stick: tuple[int, int] = (80, 160), samples_per_slip: int = 20,
                         scene=None):
    """A spring-driven stick–slip series with known events (ground truth).

    The slider creeps at 3 % of the drive velocity V while stuck; each slip is
    a half-sine velocity pulse peaking at 40 V for ``samples_per_slip``
    samples, so slip onsets are exact sample indices; the drive force is the
    spring force k (x_drive - x). ``noise`` adds Gaussian noise of that many V
    to v and of that many "force rises per sample" to the force. Stick lengths
    are drawn with ``numpy.random.default_rng(seed)``.

    Returns ``(result, truth)`` where ``truth`` holds the onset sample
    indices ``slip_index`` and the re-stick indices ``end_index``.
    """
    scene = make_scene(lower_count=2, upper_count=1) if scene is None else scene
    V, k = scene.drive.velocity, scene.drive.stiffness
    dt = 1e-3 * scene.base / V
    rng = np.random.default_rng(seed)
    pieces, slip_index, end_index, n = [], [], [], 0
    for _ in range(n_events):
        stick = int(rng.integers(samples_per_stick[0], samples_per_stick[1] + 1))
        pieces.append(np.full(stick, 0.03 * V))
        slip_index.append(n + stick - 1)  # last stick sample: the force peak
        pulse = 40.0 * V * np.sin(np.pi * np.arange(1, samples_per_slip + 1) / (samples_per_slip + 1))
        pieces.append(pulse)
        n += stick + samples_per_slip
        end_index.append(n)  # first sample of the next stick
    pieces.append(np.full(samples_per_stick[0], 0.03 * V))
    v = np.concatenate(pieces)
    t = dt * np.arange(len(v))
    x = np.concatenate(([0.0], np.cumsum(v[1:] * dt)))
    drive_x = V * t
    force = k * (drive_x - x) + rng.normal(0.0, noise * k * V * dt, len(v))
    v = v + rng.normal(0.0, noise * V, len(v))
    zeros, lower = np.zeros_like(t), np.zeros((scene.lower.count, len(t)))
    result = Result(t=t, x=x, v=v, y=zeros, vy=zeros, drive_x=drive_x, drive_force=force,
                    normal_force=zeros, friction_force=force, tangential_force=zeros,
                    contact_count=zeros, lower_dx=lower, lower_dy=lower, lower_contact=lower > 0,
                    scene=scene, meta={"dt": dt, "record_every": 1, "status": "synthetic"})
    return result, {"slip_index": np.array(slip_index), "end_index": np.array(end_index)}
