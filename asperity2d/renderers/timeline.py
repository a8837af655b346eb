"""Which sample each frame shows: event-aware frame times, slow motion through slips.

A stick–slip run at the asperity scale sticks for 10–100 ns and slips in a
few ns at km/s: frames spaced evenly in time jump over the slips, the one
event the picture exists to show. :func:`schedule` plays the run at a
*normal* rate (simulated time per frame) and each fast interval (a slip,
padded by a quarter of its length on both sides so the onset shows) slower
by its own factor S, so that the slips get about ``slip_share`` of the
frames between them (shared as the square root of their lengths, at least
``min_frames`` each); the factor is a whole number (two significant digits
from 100 up) (the label "×S slow" is the rate used) and never makes
frames closer than the record's own samples. ``timing="uniform"`` gives
evenly spaced frames.

Frames are evenly spaced in *playback* time tau, with dtau/dt = 1 at normal
speed and S inside a slowed interval; each frame shows the recorded sample
nearest its time, so a frame's time is always a recorded sample's (the
picture and the meters' cursor agree exactly).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SceneError

TIMINGS = ("events", "uniform")


@dataclass(frozen=True)
class Schedule:
    """Frame times of an animation.

    ``index`` (F,) recorded sample shown in each frame; ``time`` (F,) its time (s);
    ``slow`` (F,) the frame's slow-motion factor (1: normal speed, S: S times
    slower); ``normal_step`` (s) simulated time per frame at normal speed;
    ``intervals`` the slowed (padded, merged) intervals as ``(start, end, S)``.
    """

    index: np.ndarray
    time: np.ndarray
    slow: np.ndarray
    normal_step: float
    intervals: tuple

    def __len__(self) -> int:
        return len(self.index)


def nice_factor(value: float) -> float:
    """``value`` as a whole number, rounded to two significant digits from 100 up."""
    if value <= 0 or not np.isfinite(value):
        return 1.0
    e = max(0.0, np.floor(np.log10(value)) - 1)
    return float(max(1.0, np.round(value / 10.0**e) * 10.0**e))


def _merge(intervals, t0: float, t1: float, pad: float) -> list[list[float]]:
    out: list[list[float]] = []
    for a, b in sorted((float(a), float(b)) for a, b in intervals):
        if not b > a:
            continue
        a, b = max(t0, a - pad * (b - a)), min(t1, b + pad * (b - a))
        if b <= a:
            continue
        if out and a <= out[-1][1]:
            out[-1][1] = max(out[-1][1], b)
        else:
            out.append([a, b])
    return out


def schedule(t, fast_intervals=(), frames: int = 120, *, timing: str = "events",
             slip_share: float = 0.4, min_frames: int = 4, pad: float = 0.25) -> Schedule:
    """Frame times for ``frames`` frames over the samples ``t`` (s), slowed through ``fast_intervals``.

    Parameters
    ----------
    t : array (T,)
        Recorded sample times (s), non-decreasing.
    fast_intervals : sequence of (start, end)
        Intervals to play in slow motion (s), e.g. the slips.
    frames : int
        Number of frames (>= 1).
    timing : {"events", "uniform"}
        Event-aware (default) or evenly spaced frames.
    slip_share : float
        Fraction of the frames the slowed intervals get together (at least
        ``min_frames`` each) when evenly spaced frames would give them less.
    """
    if timing not in TIMINGS:
        raise SceneError(f"`timing` must be one of {', '.join(map(repr, TIMINGS))}, got {timing!r}")
    t = np.asarray(t, dtype=float)
    if t.size == 0:
        raise SceneError("`result` has no samples to draw")
    t0, t1 = float(t[0]), float(t[-1])
    span = t1 - t0
    if frames == 1 or span <= 0:
        wanted = np.full(frames, t0) if span <= 0 else np.array([t0])
        return _finish(t, wanted, np.ones(frames), span / max(frames - 1, 1), ())
    merged = _merge(fast_intervals, t0, t1, pad) if timing == "events" else []
    lengths = np.array([b - a for a, b in merged])
    total = float(lengths.sum()) if merged else 0.0
    rates = np.ones(len(merged))
    if merged and total < span:
        # Frames each interval gets: a share of slip_share * frames growing as the square
        # root of its length (a 3 ns slip is as much an event as a 30 ns one), at least
        # min_frames, never fewer than evenly spaced frames would give it; together at
        # most 3/4 of all.
        uniform = frames * lengths / span
        weight = np.sqrt(lengths) / np.sqrt(lengths).sum()
        want = np.maximum(np.maximum(min_frames, slip_share * frames * weight), uniform)
        if want.sum() > 0.75 * frames:
            want = np.maximum(uniform, want * 0.75 * frames / want.sum())
        normal_frames = frames - want.sum()
        normal_step = (span - total) / max(normal_frames, 1e-9)
        finest = float(np.min(np.diff(t)[np.diff(t) > 0])) if t.size > 1 else normal_step
        for j, (n_j, length) in enumerate(zip(want, lengths)):
            # never slower than one recorded sample per frame
            rate = min(normal_step * n_j / length, normal_step / finest)
            rates[j] = nice_factor(rate) if rate >= 1.5 else 1.0
    # playback time tau(t): slope 1 outside, rates[j] inside interval j
    knots_t, knots_tau, tau = [t0], [0.0], 0.0
    last = t0
    for (a, b), r in zip(merged, rates):
        tau += a - last
        knots_t.append(a), knots_tau.append(tau)
        tau += r * (b - a)
        knots_t.append(b), knots_tau.append(tau)
        last = b
    tau += t1 - last
    knots_t.append(t1), knots_tau.append(tau)
    grid = np.linspace(0.0, tau, frames)
    wanted = np.interp(grid, knots_tau, knots_t)
    slow = np.ones(frames)
    for (a, b), r in zip(merged, rates):
        slow[(wanted >= a) & (wanted <= b)] = r
    intervals = tuple((a, b, float(r)) for (a, b), r in zip(merged, rates) if r > 1)
    return _finish(t, wanted, slow, tau / (frames - 1), intervals)


def _finish(t, wanted, slow, normal_step, intervals) -> Schedule:
    index = nearest(t, wanted)
    return Schedule(index=index, time=t[index], slow=np.asarray(slow, dtype=float),
                    normal_step=float(normal_step), intervals=intervals)


def nearest(t: np.ndarray, wanted) -> np.ndarray:
    """Index of the sample of ``t`` nearest each of ``wanted`` (ties to the earlier one)."""
    wanted = np.asarray(wanted, dtype=float)
    right = np.clip(np.searchsorted(t, wanted), 0, len(t) - 1)
    left = np.clip(right - 1, 0, len(t) - 1)
    take_left = np.abs(wanted - t[left]) <= np.abs(t[right] - wanted)
    return np.where(take_left, left, right).astype(np.int64)


def slip_intervals(result) -> list[tuple[float, float]]:
    """The fast intervals of a run, ``(start, end)`` in s.

    An asperity run with a spring drive: its stick–slip events' slips
    (:func:`~asperity2d.analysis.stick_slip_events`, ``t_slip`` to ``t_end``);
    with a constant-force drive, none. A belt chain: the times when any mass
    slips (the complement of the intersection of the masses' stick intervals).
    """
    if hasattr(result, "chain") and hasattr(result, "stick_intervals"):
        return chain_slips(result)
    from ..analysis import stick_slip_events
    from ..scene import SpringDrive

    if not isinstance(result.scene.drive, SpringDrive):
        return []
    return [(e.t_slip, e.t_end) for e in stick_slip_events(result)]


def chain_slips(result) -> list[tuple[float, float]]:
    """Intervals (s) in which at least one mass of a belt chain is not stuck."""
    state = np.asarray(result.state)
    moving = np.any(state != 0, axis=0)
    t = np.asarray(result.t, dtype=float)
    if not moving.any():
        return []
    edges = np.flatnonzero(np.diff(moving.astype(np.int8))) + 1
    starts = np.concatenate(([0], edges))
    stops = np.concatenate((edges, [len(t)]))
    return [(float(t[a]), float(t[min(b, len(t) - 1)])) for a, b in zip(starts, stops) if moving[a]]


__all__ = ["Schedule", "TIMINGS", "chain_slips", "nearest", "nice_factor", "schedule",
           "slip_intervals"]
