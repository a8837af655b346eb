"""Poincaré sections, limit-cycle detection and steady-state (transient) detection.

A **Poincaré section** is where a trajectory crosses a plane ``s(t) = 0`` in a
chosen direction. For belt chains the natural plane is a mass's velocity
equal to the belt speed, crossed from below: on the exact solver's output
that is the stick onset itself, sampled exactly (the solver records a sample
at every switching instant, with v = V to the last bit in a stick), so the
section times are exact. Elsewhere a crossing is located by a cubic through
the four samples around it (linear where a cubic does not bracket it), and
the other coordinates are interpolated linearly at that time.

**Limit cycles** are found on the sequence of section points P_k: the run is
periodic with multiplicity n (a period-n orbit, n crossings per period) if
``|P_{k+n} - P_k| <= rtol`` (each coordinate relative to its largest
magnitude over the section) for the last ``min_repeats·n`` k, with n the
smallest such number up to ``max_multiplicity``. The period is the mean of
``T_{k+n} - T_k`` over those k. Otherwise the answer is *not periodic within
the run*, which covers chaos, quasi-periodic motion and transients longer
than the run alike; the message says which test failed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SceneError
from .signals import belt_speed, check_series, is_belt


@dataclass(frozen=True)
class Section:
    """Crossings of a Poincaré plane: ``t`` (K,) s, ``points`` (K, d) SI, ``names`` of the d coordinates."""

    t: np.ndarray
    points: np.ndarray
    names: tuple
    description: str


@dataclass(frozen=True)
class Cycle:
    """Outcome of limit-cycle detection.

    ``periodic``; ``period`` (s, NaN if not periodic); ``multiplicity`` n
    (section crossings per period, 0 if not periodic); ``amplitude`` (half the
    peak-to-peak of the signal over the last period, or over the last half of
    the run when not periodic; unit of the signal); ``t_start`` (s, first
    section crossing from which the repetition holds); ``repeats`` (periods
    observed from ``t_start``); ``mismatch`` (largest relative distance
    |P_{k+n} - P_k| checked, or the smallest over n when not periodic);
    ``crossings`` (section points used); ``section`` (what the plane was);
    ``message``.
    """

    periodic: bool
    period: float
    multiplicity: int
    amplitude: float
    t_start: float
    repeats: int
    mismatch: float
    crossings: int
    section: str
    message: str

    def to_dict(self) -> dict:
        return dict(self.__dict__)


def crossings(t, s, *, direction: int = 1) -> np.ndarray:
    """Times (s) where ``s`` crosses zero upward (``direction=1``), downward (-1) or either (0).

    An upward crossing is a sample with s >= 0 after one with s < 0; a
    sample exactly at zero is the crossing time itself.
    """
    t, s = np.asarray(t, dtype=float), np.asarray(s, dtype=float)
    if direction not in (-1, 0, 1):
        raise SceneError(f"`direction` must be -1, 0 or 1, got {direction!r}")
    sg = np.sign(s)
    up = (sg[:-1] < 0) & (sg[1:] >= 0)
    down = (sg[:-1] > 0) & (sg[1:] <= 0)
    mask = up if direction == 1 else down if direction == -1 else (up | down)
    return np.array([_root(t, s, k) for k in np.flatnonzero(mask) + 1])


def _root(t, s, k) -> float:
    """Zero of s between samples k-1 and k: exact sample, cubic through k-2..k+1, or linear."""
    if s[k] == 0:
        return float(t[k])
    a, b = t[k - 1], t[k]
    linear = a + (b - a) * s[k - 1] / (s[k - 1] - s[k])
    if k < 2 or k + 1 >= t.size or b <= a:
        return float(linear)
    tt, ss = t[k - 2:k + 2], s[k - 2:k + 2]
    if np.any(np.diff(tt) <= 0) or np.any(ss == 0):
        return float(linear)
    u = (tt - a) / (b - a)
    roots = np.roots(np.polyfit(u, ss, 3))
    real = roots[np.abs(roots.imag) < 1e-9].real
    real = real[(real >= 0) & (real <= 1)]
    if real.size != 1:
        return float(linear)
    return float(a + real[0] * (b - a))


def poincare_section(t, states, *, plane: int = 0, level: float = 0.0, direction: int = 1,
                     names=None) -> Section:
    """Crossings of ``states[plane] = level`` by the trajectory ``states`` (d, T) sampled at ``t``."""
    states = np.atleast_2d(np.asarray(states, dtype=float))
    t, _ = check_series(t, states[0], minimum=2)
    if states.shape[1] != t.size:
        raise SceneError(f"`states` must have {t.size} columns (one per time), got shape {states.shape}")
    if not 0 <= plane < states.shape[0]:
        raise SceneError(f"`plane` must be a row index 0..{states.shape[0] - 1}, got {plane!r}")
    names = tuple(names) if names is not None else tuple(f"y{i}" for i in range(states.shape[0]))
    times = crossings(t, states[plane] - level, direction=direction)
    points = np.array([np.interp(times, t, row) for row in states]).T.reshape(times.size, states.shape[0])
    points[:, plane] = level
    return Section(times, points, names, f"{names[plane]} = {level:g} ({_dir(direction)})")


def chain_section(result, *, mass: int = 0, direction: int = 1) -> Section:
    """Section of a belt run where mass ``mass`` (0-based) reaches the belt speed (stick onsets for +1).

    Points are the full state (x_1..x_n in m, v_1..v_n in m/s) at the crossing.
    """
    if not is_belt(result):
        raise SceneError("`result` must be a belt-chain result (BeltResult)")
    if isinstance(mass, bool) or not isinstance(mass, (int, np.integer)) or not 0 <= mass < result.n:
        raise SceneError(f"`mass` must be an index 0..{result.n - 1}, got {mass!r}")
    t = result.t
    slip = result.v[mass] - belt_speed(result, t)
    times = crossings(t, slip, direction=direction)
    states = np.vstack([result.x, result.v])
    idx = np.searchsorted(t, times)
    exact = (idx < t.size) & (t[np.minimum(idx, t.size - 1)] == times)
    points = np.array([np.interp(times, t, row) for row in states]).T.reshape(times.size, states.shape[0])
    # a crossing on a sample (the stick onset) takes that sample itself, not an interpolation
    points[exact] = states[:, idx[exact]].T
    names = tuple(f"x{i + 1}" for i in range(result.n)) + tuple(f"v{i + 1}" for i in range(result.n))
    return Section(times, points, names, f"v{mass + 1} = belt speed ({_dir(direction)})")


def _dir(direction):
    return {1: "upward", -1: "downward", 0: "both ways"}[direction]


def detect_period(points, times=None, *, scale=None, rtol: float = 1e-4, max_multiplicity: int = 8,
                  min_repeats: int = 3) -> tuple:
    """``(n, period, k_start, mismatch)`` of a sequence of section points, or ``(0, nan, -1, best)``.

    ``points`` (K, d) or (K,); ``times`` (K,) the section times (default: the
    index, so the period of a sequence is counted in steps); ``scale`` (d,)
    the size each coordinate's differences are measured against (default:
    its largest magnitude over the points). See the module docstring.
    """
    _check_detect(rtol, max_multiplicity, min_repeats)
    P = np.asarray(points, dtype=float)
    P = P.reshape(P.shape[0], -1)
    K = P.shape[0]
    T = np.arange(K, dtype=float) if times is None else np.asarray(times, dtype=float)
    if scale is None:
        scale = np.max(np.abs(P), axis=0) if K else np.ones(P.shape[1])
    scale = np.array(scale, dtype=float).reshape(-1)
    scale[~(scale > 0)] = 1.0
    best = np.inf
    for n in range(1, max_multiplicity + 1):
        pairs = K - n
        need = min_repeats * n
        if pairs < need:
            break
        dist = np.max(np.abs(P[n:] - P[:-n]) / scale, axis=1)  # (K - n,)
        tail = dist[pairs - need:]
        worst = float(tail.max())
        if worst <= rtol:
            bad = np.flatnonzero(dist > rtol)
            k0 = int(bad[-1] + 1) if bad.size else 0
            period = float(np.mean(T[n:][pairs - need:] - T[:-n][pairs - need:]))
            return n, period, k0, worst
        best = min(best, worst)
    return 0, float("nan"), -1, float(best)


def _check_detect(rtol, max_multiplicity, min_repeats):
    if not np.isfinite(rtol) or rtol <= 0:
        raise SceneError(f"`rtol` must be > 0, got {rtol!r}")
    for name, val in (("max_multiplicity", max_multiplicity), ("min_repeats", min_repeats)):
        if isinstance(val, bool) or not isinstance(val, (int, np.integer)) or val < 1:
            raise SceneError(f"`{name}` must be an integer >= 1, got {val!r}")


def _cycle(n, period, k0, mismatch, times, signal_t, signal_y, count, description, rtol, max_n, why=None):
    if n:
        last = signal_t >= signal_t[-1] - period
        amp = 0.5 * float(np.ptp(signal_y[last]))
        t_start = float(times[k0])
        repeats = int(np.floor((times[-1] - t_start) / period + 1e-9))
        msg = f"period-{n} cycle, period {period:.9g} s, repeating from t = {t_start:.6g} s"
        return Cycle(True, period, n, amp, t_start, repeats, mismatch, count, description, msg)
    half = signal_t >= 0.5 * (signal_t[0] + signal_t[-1])
    amp = 0.5 * float(np.ptp(signal_y[half]))
    if why is None:
        why = (f"only {count} section crossings" if not np.isfinite(mismatch) else
               f"no repeat within rtol = {rtol:g} for n <= {max_n} (closest: {mismatch:.3g})")
    return Cycle(False, float("nan"), 0, amp, float("nan"), 0, mismatch, count, description,
                 f"not periodic within the run: {why}")


def limit_cycle(t, y, *, level: float | None = None, rtol: float = 1e-4, max_multiplicity: int = 8,
                min_repeats: int = 3) -> Cycle:
    """Limit cycle of a scalar series ``y(t)`` (SI).

    The section is the upward crossings of ``level`` (default: the mean of the
    last half of the run); its points are (interval since the previous
    crossing, max y, min y between them), so a period-2 orbit shows as
    alternating peaks.
    """
    t, y = check_series(t, y)
    _check_detect(rtol, max_multiplicity, min_repeats)
    if level is None:
        level = float(np.mean(y[t >= 0.5 * (t[0] + t[-1])]))
    times = crossings(t, y - level, direction=1)
    idx = np.searchsorted(t, times)
    feats = [(times[j + 1] - times[j], _extreme(y, idx[j], idx[j + 1], 1, level),
              _extreme(y, idx[j], idx[j + 1], -1, level)) for j in range(times.size - 1)]
    points = np.array(feats).reshape(-1, 3)
    swing = float(np.ptp(y[t >= t[0] + 0.75 * (t[-1] - t[0])]))
    if swing <= 1e-12 * max(float(np.max(np.abs(y))), 1e-300):
        return _cycle(0, np.nan, -1, np.nan, times, t, y, 0, "none", rtol, max_multiplicity,
                      why="the signal is constant over its last quarter (at rest)")
    scale = [np.mean(points[:, 0]) if points.size else 1.0, swing, swing]
    n, period, k0, mis = detect_period(points, times[1:], scale=scale, rtol=rtol,
                                       max_multiplicity=max_multiplicity, min_repeats=min_repeats)
    return _cycle(n, period, k0, mis, times[1:], t, y, len(feats), f"y = {level:.6g} (upward)", rtol,
                  max_multiplicity)


def _extreme(y, lo, hi, sign, default) -> float:
    """Largest (sign 1) or smallest (-1) of y[lo:hi], refined by a parabola through its neighbours.

    The refinement assumes locally uniform sampling; it cuts the sampling error
    of a smooth peak from O(dt²) to O(dt³), so the peaks of a periodic signal
    repeat to well within ``rtol`` even when the period is not a multiple of dt.
    """
    if hi <= lo:
        return float(default)
    k = lo + int(np.argmax(sign * y[lo:hi]))
    if k == 0 or k + 1 >= y.size:
        return float(y[k])
    a, b, c = y[k - 1], y[k], y[k + 1]
    curv = a - 2 * b + c
    if sign * curv >= 0:  # not a smooth extremum (a kink or a plateau): keep the sample
        return float(b)
    return float(b - (a - c) ** 2 / (8 * curv))


def chain_cycle(result, *, mass: int | None = None, rtol: float = 1e-6, max_multiplicity: int = 8,
                min_repeats: int = 3) -> Cycle:
    """Limit cycle of a belt run, on the exact stick-onset section of mass ``mass``.

    ``mass=None`` takes the mass with the most stick onsets in the last half
    of the run; if no mass reaches the belt speed there (pure slip) the
    section is the upward crossings of mass 1's velocity through its
    last-half mean. Points are the full state. ``amplitude`` is that of the
    section mass's position (m). The default ``rtol`` suits the exact solver,
    whose cycles repeat to round-off once settled.
    """
    _check_detect(rtol, max_multiplicity, min_repeats)
    t = result.t
    half = t >= 0.5 * (t[0] + t[-1])
    if mass is None:
        counts = [int(np.sum(chain_section(result, mass=i).t >= t[half][0])) for i in range(result.n)]
        mass = int(np.argmax(counts)) if max(counts) > 0 else None
    if mass is not None:
        sec = chain_section(result, mass=mass)
        ref = mass
    else:
        ref = 0
        v = result.v[0]
        states = np.vstack([result.x, result.v])
        names = tuple(f"x{i + 1}" for i in range(result.n)) + tuple(f"v{i + 1}" for i in range(result.n))
        sec = poincare_section(t, states, plane=result.n, level=float(np.mean(v[half])), names=names)
    # differences are measured against the size of the motion over the last quarter of the run
    # (not against the offsets of the positions), so a decay towards rest is never "periodic"
    tail = t >= t[0] + 0.75 * (t[-1] - t[0])
    swing_x = np.ptp(result.x[:, tail], axis=1)
    swing_v = np.ptp(result.v[:, tail], axis=1)
    size = max(float(swing_v.max()), 1e-300)
    if size <= 1e-12 * max(float(np.max(np.abs(result.v))), 1e-300):
        return _cycle(0, np.nan, -1, np.nan, sec.t, t, result.x[ref], sec.t.size, sec.description, rtol,
                      max_multiplicity, why="every mass moves steadily over the last quarter (at rest)")
    scale = np.concatenate([np.where(swing_x > 0, swing_x, swing_x.max()), np.where(swing_v > 0, swing_v, size)])
    n, period, k0, mis = detect_period(sec.points, sec.t, scale=scale, rtol=rtol,
                                       max_multiplicity=max_multiplicity, min_repeats=min_repeats)
    return _cycle(n, period, k0, mis, sec.t, t, result.x[ref], sec.t.size, sec.description, rtol,
                  max_multiplicity)


@dataclass(frozen=True)
class SteadyState:
    """Transient cut-off: ``t_start`` (s) from which the signal's envelope stays within ``rtol`` of its final one.

    ``settled`` is False when that happens only in the last half of the run
    (the run is mostly transient); ``low``/``high`` are the final envelope.
    """

    t_start: float
    settled: bool
    low: float
    high: float


def steady_state(t, y, *, windows: int | None = None, rtol: float = 0.05) -> SteadyState:
    """Where the transient ends: the run is cut into ``windows`` equal windows.

    The reference envelope is the min and max over the last quarter of the
    run; a window agrees if its own min and max lie within ``rtol`` times the
    reference range (plus 1e-12 of the signal's magnitude, for a signal at
    rest) of the reference ones. ``t_start`` is the start of the first window
    after which all agree. Each window must span a few periods of the slowest
    oscillation for the envelope test to ignore phase: ``windows=None`` makes
    them 3 periods of the dominant frequency of the last half (at least 1/40
    of the run, at most 4 windows per run). A heuristic: a quasi-periodic or
    chaotic signal counts as settled once its envelope is.
    """
    t, y = check_series(t, y)
    if windows is None:
        windows = _auto_windows(t, y)
    if isinstance(windows, bool) or not isinstance(windows, (int, np.integer)) or not 4 <= windows <= t.size // 2:
        raise SceneError(f"`windows` must be an integer from 4 to {t.size // 2}, got {windows!r}")
    if not np.isfinite(rtol) or rtol <= 0:
        raise SceneError(f"`rtol` must be > 0, got {rtol!r}")
    edges = np.linspace(t[0], t[-1], windows + 1)
    ref = t >= t[0] + 0.75 * (t[-1] - t[0])
    lo, hi = float(y[ref].min()), float(y[ref].max())
    tol = rtol * (hi - lo) + 1e-12 * float(np.max(np.abs(y)))
    agree = []
    for a, b in zip(edges[:-1], edges[1:]):
        w = (t >= a) & (t <= b)
        agree.append(bool(w.any()) and abs(y[w].min() - lo) <= tol and abs(y[w].max() - hi) <= tol)
    bad = np.flatnonzero(~np.array(agree))
    first = int(bad[-1] + 1) if bad.size else 0
    t_start = float(edges[min(first, windows - 1)])
    return SteadyState(t_start, bool(t_start < t[0] + 0.5 * (t[-1] - t[0])), lo, hi)


def _auto_windows(t, y) -> int:
    from .spectrum import spectrum

    span = t[-1] - t[0]
    half = t >= t[0] + 0.5 * span
    try:
        f0 = spectrum(t[half], y[half], method="periodogram").dominant
    except SceneError:  # too few samples in the last half for a spectrum
        return max(4, min(40, t.size // 2))
    length = max(span / 40.0, 3.0 / f0) if f0 > 0 else span / 4.0
    return int(np.clip(np.floor(span / length), 4, min(40, t.size // 2)))
