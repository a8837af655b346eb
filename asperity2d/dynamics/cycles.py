"""Limit-cycle detection on Poincaré sections, and steady-state (transient) detection.

**Limit cycles** are found on the Poincaré section points P_k
(:mod:`.sections`): the run is periodic with multiplicity n (a period-n
orbit, n crossings per period) if ``|P_{k+n} - P_k| <= rtol`` times a scale
for the last ``min_repeats·n`` k, with n the smallest such number up to
``max_multiplicity``. The scale of each coordinate is the size of the motion
over the last quarter of the run (its peak-to-peak; for a bare sequence,
its largest magnitude), so a decay towards rest never counts as periodic.
The period is the mean of ``T_{k+n} - T_k`` over those k. Otherwise the answer is *not periodic within
the run*, which covers chaos, quasi-periodic motion and transients longer
than the run alike; the message says which test failed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._inputs import check_tolerance
from ..errors import SceneError
from .sections import chain_section, crossings, opening_section, poincare_section
from .signals import check_series


@dataclass(frozen=True)
class Cycle:
    """Outcome of limit-cycle detection.

    ``periodic``; ``period`` (s, NaN if not periodic); ``multiplicity`` n
    (section crossings per period, 0 if not periodic); ``amplitude`` (half the
    peak-to-peak of the signal over the last period, or over the last half of
    the run when not periodic; unit of the signal); ``t_start`` (s, first
    section crossing from which the repetition holds); ``repeats`` (periods
    observed from ``t_start``); ``mismatch`` (largest relative distance
    abs(P_{k+n} - P_k) checked, or the smallest over n when not periodic);
    ``crossings`` (section points used); ``section`` (what the plane was);
    ``message``.

    See Also
    --------
    asperity2d.dynamics.chain_cycle, asperity2d.dynamics.limit_cycle : find one.

    Examples
    --------
    >>> from asperity2d import belt, dynamics
    >>> chain = dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...             v_belt=0.1, x0=[0.0], v0=[0.1], t_end=20.0)
    >>> result = belt.simulate_chain(**chain)  # one mass, stick-slip on the belt
    >>> cycle = dynamics.chain_cycle(result)
    >>> cycle.periodic, cycle.multiplicity, round(cycle.period, 4)
    (True, 1, 0.6694)
    >>> cycle.message
    'period-1 cycle, period 0.669357062 s, repeating from t = 0.865557 s'
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


def detect_period(points, times=None, *, scale=None, rtol: float = 1e-4, max_multiplicity: int = 8,
                  min_repeats: int = 3) -> tuple:
    """``(n, period, k_start, mismatch)`` of a sequence of section points, or ``(0, nan, -1, best)``.

    See the module docstring.

    Parameters
    ----------
    points : array_like, (K, d) or (K,)
        The section points in order.
    times : array_like, (K,), optional
        The section times (s; default: the index, so the period of a sequence is counted in steps).
    scale : array_like, (d,), optional
        The size each coordinate's differences are measured against (default: its largest
        magnitude over the points).
    rtol : float
        Relative mismatch within which a point repeats (of ``scale``).
    max_multiplicity : int
        Most points per period.
    min_repeats : int
        How many times the cycle must repeat.

    Returns
    -------
    tuple
        ``(multiplicity, period, first index, mismatch)``.

    See Also
    --------
    asperity2d.dynamics.limit_cycle, asperity2d.dynamics.chain_cycle : on a series or a belt run.

    Examples
    --------
    >>> from asperity2d import dynamics
    >>> dynamics.detect_period([1.0, 2.0, 1.0, 2.0, 1.0, 2.0, 1.0, 2.0])  # period 2 steps
    (2, 2.0, 0, 0.0)
    """
    _check_detect(rtol, max_multiplicity, min_repeats)
    P = np.asarray(points, dtype=float)
    P = P[:, None] if P.ndim == 1 else P.reshape(P.shape[0], int(np.prod(P.shape[1:])))
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
    check_tolerance("rtol", rtol)
    for name, val in (("max_multiplicity", max_multiplicity), ("min_repeats", min_repeats)):
        if isinstance(val, bool) or not isinstance(val, (int, np.integer)) or val < 1:
            raise SceneError(f"`{name}` must be an integer >= 1, got {val!r}")


def _cycle(n, period, k0, mismatch, times, signal_t, signal_y, count, description, rtol, max_n, why=None):
    if n:
        i0 = int(np.searchsorted(signal_t, signal_t[-1] - period))
        end = signal_t.size
        amp = 0.5 * (_extreme(signal_t, signal_y, i0, end, 1, 0.0) - _extreme(signal_t, signal_y, i0, end, -1, 0.0))
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
                min_repeats: int = 3, hysteresis: float = 0.1) -> Cycle:
    """Limit cycle of a scalar series ``y(t)`` (SI).

    The section is the upward crossings of ``level`` (default: the mean of the
    last half of the run), counted only after y dipped ``hysteresis`` times
    its last-quarter peak-to-peak below the level (so noise on a measured or
    pymunk signal does not add crossings); its points are (interval since
    the previous crossing, max y, min y between them), so a period-2 orbit
    shows as alternating peaks.

    Parameters
    ----------
    t, y : array_like
        Times (s) and the series.
    level : float, optional
        The section's level (unit of ``y``).
    rtol : float, default 1e-4
        Relative mismatch within which two section points are the same.
    max_multiplicity : int, default 8
        Most crossings per period tried.
    min_repeats : int, default 3
        Periods the cycle must repeat.
    hysteresis : float, default 0.1
        Dip before a crossing counts, relative to the peak-to-peak.

    Returns
    -------
    Cycle

    See Also
    --------
    asperity2d.dynamics.chain_cycle : exact, for belt runs.

    Examples
    --------
    >>> from asperity2d import belt, dynamics
    >>> chain = dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...             v_belt=0.1, x0=[0.0], v0=[0.1], t_end=20.0)
    >>> result = belt.simulate_chain(**chain)  # one mass, stick-slip on the belt
    >>> t, v = dynamics.signal(result, 'v')
    >>> cycle = dynamics.limit_cycle(t, v)
    >>> cycle.periodic, round(cycle.period, 4)
    (True, 0.6694)
    """
    t, y = check_series(t, y)
    _check_detect(rtol, max_multiplicity, min_repeats)
    if not np.isfinite(hysteresis) or not 0 <= hysteresis < 0.5:
        raise SceneError(f"`hysteresis` must be in [0, 0.5), got {hysteresis!r}")
    if level is None:
        level = float(np.mean(y[t >= 0.5 * (t[0] + t[-1])]))
    swing = float(np.ptp(y[t >= t[0] + 0.75 * (t[-1] - t[0])]))  # size of the motion at the end
    times = crossings(t, y - level, direction=1, hysteresis=hysteresis * swing)
    idx = np.searchsorted(t, times)
    feats = [(times[j + 1] - times[j], _extreme(t, y, idx[j], idx[j + 1], 1, level),
              _extreme(t, y, idx[j], idx[j + 1], -1, level)) for j in range(times.size - 1)]
    points = np.array(feats).reshape(-1, 3)
    if swing <= 1e-12 * max(float(np.max(np.abs(y))), 1e-300):
        return _cycle(0, np.nan, -1, np.nan, times, t, y, 0, "none", rtol, max_multiplicity,
                      why="the signal is constant over its last quarter (at rest)")
    scale = [np.mean(points[:, 0]) if points.size else 1.0, swing, swing]
    n, period, k0, mis = detect_period(points, times[1:], scale=scale, rtol=rtol,
                                       max_multiplicity=max_multiplicity, min_repeats=min_repeats)
    return _cycle(n, period, k0, mis, times[1:], t, y, len(feats), f"y = {level:.6g} (upward)", rtol,
                  max_multiplicity)


def _extreme(t, y, lo, hi, sign, default) -> float:
    """Largest (sign 1) or smallest (-1) of y[lo:hi], refined by the parabola through its neighbours.

    The refinement cuts the sampling error of a smooth peak from O(dt²) to
    O(dt³), so the peaks of a periodic signal repeat to well within ``rtol``
    even when the period is not a multiple of dt. A sample whose neighbours do
    not both lie strictly below it (a plateau, e.g. a stick at the belt speed)
    is kept as it is.
    """
    if hi <= lo:
        return float(default)
    k = lo + int(np.argmax(sign * y[lo:hi]))
    if k == 0 or k + 1 >= y.size:
        return float(y[k])
    (t0, t1, t2), (a, b, c) = t[k - 1:k + 2], y[k - 1:k + 2]
    if not (sign * (b - a) > 0 and sign * (b - c) > 0 and t0 < t1 < t2):
        return float(b)
    # vertex of the Lagrange parabola through the three samples
    d1, d2 = (b - a) / (t1 - t0), (c - b) / (t2 - t1)
    curv = (d2 - d1) / (t2 - t0)  # half the second derivative
    t_star = 0.5 * (t0 + t1) - d1 / (2 * curv)
    if not t0 <= t_star <= t2:
        return float(b)
    return float(b + d1 * (t_star - t1) + curv * (t_star - t0) * (t_star - t1))


def chain_cycle(result, *, mass: int | None = None, rtol: float = 1e-6, max_multiplicity: int = 8,
                min_repeats: int = 3) -> Cycle:
    """Limit cycle of a belt run, on the exact stick-onset section of mass ``mass``.

    ``mass=None`` takes the mass with the most stick onsets in the last half
    of the run; if no mass reaches the belt speed there (pure slip) the
    section is the upward crossings of mass 1's velocity through its
    last-half mean. Points are the full state. ``amplitude`` is that of the
    section mass's position (m). The default ``rtol`` suits the exact solver,
    whose cycles repeat to round-off once settled.

    Parameters
    ----------
    result : BeltResult
        A belt run long enough to repeat ``min_repeats`` times.
    mass : int, optional
        The mass (0-based) whose stick onsets make the section.
    rtol : float, default 1e-6
        Relative mismatch within which two section points are the same.
    max_multiplicity : int, default 8
        Most crossings per period tried.
    min_repeats : int, default 3
        Periods the cycle must repeat.

    Returns
    -------
    Cycle

    See Also
    --------
    asperity2d.dynamics.limit_cycle : of any series.
    asperity2d.dynamics.floquet : the stability of the cycle.

    Examples
    --------
    >>> from asperity2d import belt, dynamics
    >>> chain = dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...             v_belt=0.1, x0=[0.0], v0=[0.1], t_end=20.0)
    >>> result = belt.simulate_chain(**chain)  # one mass, stick-slip on the belt
    >>> cycle = dynamics.chain_cycle(result)
    >>> cycle.periodic, round(cycle.period, 4), cycle.repeats
    (True, 0.6694, 28)
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
    elif hasattr(result, "separation_intervals") and any(
            a >= t[half][0] for per in result.separation_intervals for a, _ in per):
        # a contact chain that slides and separates but never sticks: its exact section is the
        # instant a contact opens (a sample), not an interpolated velocity crossing
        opens = [sum(a >= t[half][0] for a, _ in per) for per in result.separation_intervals]
        ref = int(np.argmax(opens))
        sec = opening_section(result, mass=ref)
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
    if sec.points.shape[1:] == (4 * result.n,):  # the opening section holds (x, y, v, vy)
        swing_y, swing_vy = np.ptp(result.y[:, tail], axis=1), np.ptp(result.vy[:, tail], axis=1)
        scale = np.concatenate([scale[:result.n], np.where(swing_y > 0, swing_y, max(swing_y.max(), 1e-300)),
                                scale[result.n:], np.where(swing_vy > 0, swing_vy, max(swing_vy.max(), 1e-300))])
    n, period, k0, mis = detect_period(sec.points, sec.t, scale=scale, rtol=rtol,
                                       max_multiplicity=max_multiplicity, min_repeats=min_repeats)
    return _cycle(n, period, k0, mis, sec.t, t, result.x[ref], sec.t.size, sec.description, rtol,
                  max_multiplicity)


@dataclass(frozen=True)
class SteadyState:
    """Transient cut-off: ``t_start`` (s) from which the signal's envelope stays within ``rtol`` of its final one.

    ``settled`` is False when that happens only in the last half of the run
    (the run is mostly transient); ``low``/``high`` are the final envelope.

    See Also
    --------
    asperity2d.dynamics.steady_state : computes one.

    Examples
    --------
    >>> from asperity2d import belt, dynamics
    >>> chain = dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...             v_belt=0.1, x0=[0.0], v0=[0.1], t_end=20.0)
    >>> result = belt.simulate_chain(**chain)  # one mass, stick-slip on the belt
    >>> t, v = dynamics.signal(result, 'v')
    >>> state = dynamics.steady_state(t, v)
    >>> state.settled, state.t_start  # stick-slip from the first stick: no transient
    (True, 0.0)
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
    them 3 periods of the dominant frequency of the last half long, and at
    least 1/40 of the run (between 4 and 40 windows). A heuristic: a
    quasi-periodic or chaotic signal counts as settled once its envelope is.

    Parameters
    ----------
    t, y : array_like
        Times (s) and the series.
    windows : int, optional
        Number of windows.
    rtol : float, default 0.05
        Relative tolerance on the envelope.

    Returns
    -------
    SteadyState

    See Also
    --------
    asperity2d.dynamics.limit_cycle : the cycle after it.

    Examples
    --------
    >>> from asperity2d import belt, dynamics
    >>> chain = dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...             v_belt=0.1, x0=[0.0], v0=[0.1], t_end=20.0)
    >>> result = belt.simulate_chain(**chain)  # one mass, stick-slip on the belt
    >>> t, v = dynamics.signal(result, 'v')
    >>> dynamics.steady_state(t, v).settled
    True
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
