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
    ``intervals`` the slowed (padded, merged) intervals as ``(start, end, S)``
    (S: the interval's base factor; where the slider moves fast a frame's own
    ``slow`` is larger). With positions given (``x``, ``pitch``): ``jumps`` (F,)
    the slider's displacement since the previous frame in pitches, ``jump_limit``
    the most a frame inside a slow interval was planned to move (pitches), and
    ``coarse_reason`` why some frame moves more than a pitch ("" if none does);
    ``rates`` the playback rate piece by piece inside the slowed intervals,
    ``(start, end, S)`` with equal neighbours merged (a player's slow motion).
    """

    index: np.ndarray
    time: np.ndarray
    slow: np.ndarray
    normal_step: float
    intervals: tuple
    jumps: np.ndarray | None = None
    jump_limit: float | None = None
    coarse_reason: str = ""
    rates: tuple = ()

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
             slip_share: float = 0.4, min_frames: int = 4, pad: float = 0.25, x=None,
             pitch: float | None = None, jump: float = 0.6) -> Schedule:
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
    x, pitch : array (T,), float, optional
        The slider's positions (m) and the surface's pitch (m): inside a slowed
        interval, playback slows further wherever the slider moves fast, so
        that no frame moves it more than ``jump`` pitches (a tip is seen to
        climb a flank, not teleport past asperities). The frames this takes
        come out of the normal-speed ones; when the slips' travel would need
        more than 70 % of all frames, the bound is relaxed (``coarse_reason``).
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
    moving = x is not None and pitch is not None and pitch > 0 and bool(merged)
    if not moving:
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
    return _moving(t, np.asarray(x, dtype=float), float(pitch), frames, merged, rates, jump)


def nice_up(value: float) -> float:
    """The smallest whole number >= ``value`` with two significant digits from 100 up (>= 1)."""
    if value <= 1 or not np.isfinite(value):
        return 1.0
    e = max(0.0, np.floor(np.log10(value)) - 1)
    return float(np.ceil(value / 10.0**e - 1e-9) * 10.0**e)


def _moving(t, x, pitch, frames, merged, rates, jump) -> Schedule:
    """Frames whose playback slows, inside the slowed intervals, where the slider moves fast.

    Between recorded samples i and i+1 inside interval j the playback rate is
    rho_i = max(S_j, K |dx_i| / dt_i) (rounded up to a :func:`nice_up` whole
    number: the "×N slow" a frame shows is the rate it was played at), so a
    frame step of playback time tau_f moves the slider at most tau_f / K.
    K = tau_f / (jump * pitch) and tau_f = tau(K) / (frames - 1) are solved
    together (bisection: tau grows with K at most as the slips' travel does).
    """
    t0, t1 = float(t[0]), float(t[-1])
    pieces = []  # (start, end, rate_floor, dt array, |dx| array, knot times)
    for (a, b), r in zip(merged, rates):
        ia = int(np.searchsorted(t, a, side="left"))
        ib = int(np.searchsorted(t, b, side="right"))
        knots = np.unique(np.r_[a, t[ia:ib], b])
        xk = np.interp(knots, t, x)
        pieces.append((a, b, float(r), np.diff(knots), np.abs(np.diff(xk)), knots))
    outside = (t1 - t0) - sum(b - a for a, b, *_ in pieces)
    travel = float(sum(d.sum() for *_, d, _k in pieces))

    def tau_of(K):
        return outside + sum(float(np.sum(np.maximum(r * dt, K * dx))) for _a, _b, r, dt, dx, _k in pieces)

    # the slips' travel may take at most 70 % of the frames
    limit = max(jump, travel / (0.7 * max(frames - 1, 1) * pitch)) if travel > 0 else jump
    scale = (frames - 1) * limit * pitch
    lo = tau_of(0.0) / scale
    hi = lo
    while tau_of(hi) / scale > hi:
        hi *= 2.0
    for _ in range(80):  # g(K) = tau(K) / scale - K is convex, >= 0 at lo, <= 0 at hi
        mid = 0.5 * (lo + hi)
        if tau_of(mid) / scale > mid:
            lo = mid
        else:
            hi = mid
    K = hi
    knots_t, knots_tau, knot_rate, tau = [t0], [0.0], [1.0], 0.0
    last = t0
    rates_out: list[list[float]] = []
    for a, b, r, dt, dx, knots in pieces:
        tau += a - last
        with np.errstate(divide="ignore", invalid="ignore"):
            rho = np.where(dt > 0, np.maximum(r, K * dx / np.where(dt > 0, dt, 1.0)), r)
        rho = np.array([nice_up(v) for v in rho])
        for k, v in enumerate(rho):
            if rates_out and rates_out[-1][2] == v and rates_out[-1][1] == knots[k]:
                rates_out[-1][1] = float(knots[k + 1])
            else:
                rates_out.append([float(knots[k]), float(knots[k + 1]), float(v)])
        cum = tau + np.r_[0.0, np.cumsum(rho * dt)]
        knots_t += knots.tolist()
        knots_tau += cum.tolist()
        knot_rate += [rho[0]] + rho.tolist()
        tau = float(cum[-1])
        last = b
    tau += t1 - last
    knots_t.append(t1), knots_tau.append(tau), knot_rate.append(1.0)
    knots_t, knots_tau = np.asarray(knots_t), np.asarray(knots_tau)
    grid = np.linspace(0.0, tau, frames)
    wanted = np.interp(grid, knots_tau, knots_t)
    # each frame's rate: that of the stretch of playback time it sits in (1 outside the intervals)
    seg = np.clip(np.searchsorted(knots_tau, grid, side="right") - 1, 0, len(knots_tau) - 1)
    slow = np.asarray(knot_rate, dtype=float)[seg]
    inside = np.zeros(frames, dtype=bool)
    for a, b, *_ in pieces:
        inside |= (wanted >= a) & (wanted <= b)
    slow = np.where(inside, slow, 1.0)
    intervals = tuple((a, b, float(r)) for a, b, r, *_ in pieces if r > 1 or np.any(slow[(wanted >= a) & (wanted <= b)] > 1))
    plan = _finish(t, wanted, slow, tau / (frames - 1), intervals)
    jumps = np.r_[0.0, np.abs(np.diff(x[plan.index]))] / pitch
    reason = ""
    if np.any(jumps > 1.0):
        step = float(np.max(np.abs(np.diff(x)))) / pitch if len(x) > 1 else 0.0
        if limit > jump:
            reason = f"{frames} frames are too few for the slips' travel ({travel / pitch:.0f} pitches)"
        elif step > 1.0:
            reason = f"the record's own samples are up to {step:.1f} pitches apart"
        else:
            reason = "a frame's nearest recorded sample"
    return Schedule(index=plan.index, time=plan.time, slow=plan.slow, normal_step=plan.normal_step,
                    intervals=plan.intervals, jumps=jumps, jump_limit=float(limit), coarse_reason=reason,
                    rates=tuple(tuple(piece) for piece in rates_out))


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


__all__ = ["Schedule", "TIMINGS", "chain_slips", "nearest", "nice_factor", "nice_up", "schedule",
           "slip_intervals"]
