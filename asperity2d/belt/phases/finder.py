"""Locating the next switch of a phase: grid screen, then roots to machine precision.

The event functions g (:mod:`.phases.events`) are scanned on a grid of ``step`` (1/16
of the fastest period) in chunks that double in length, so a long phase
without switches costs a few vectorised calls. An interval is examined
closely only where g may come within ``SWITCH_TOL`` of zero: it changes sign,
or the lower bound

    min(g_a, g_b) - 4/27·h·(|g'_a| + |g'_b|) - h⁴/384·max|g''''|

of g over the interval (the cubic Hermite interpolant's minimum minus its
error bound) is below the tolerance. For closed-form phases max|g''''| is
bounded rigorously from the modal form, so no contact is missed; for
integrated phases it is estimated as 1e-3 of the local magnitudes.

Each contact is then classified by the depth of its dip -- the **touch rule**:

* the lowest value of g in the dip is below -SWITCH_TOL: a *crossing*; the
  switch is at the first zero, located by safeguarded Newton steps;
* the lowest value is within ±SWITCH_TOL of zero: a *touch*, at the dip's
  minimum (a simple zero of g', located to machine precision). For a
  slipping mass the phase ends there and :func:`.chain.modes.resolve_modes`
  decides between stick and touch-and-go (a graze); for a stuck mass whose
  static force touches its limit the stick condition still holds, so the
  scan goes on.

Round-off therefore never decides whether a tangential contact happened:
the tolerance does, and the same way every time. Nor does it decide what a
phase that opens at a zero does next: the opening zero is known (the state
there is exact), and the row's next contact is searched after it has left
that zero, whether the closed form gives +1e-16 or -1e-16 there.
"""

from __future__ import annotations

import math
from functools import partial

import numpy as np

from ..limits import SWITCH_TOL  # noqa: F401 -- relative tolerance that declares an event function zero

_EPS = float(np.finfo(float).eps)  # (a plain float: the scalar root search does its arithmetic in floats)
#: subdivisions of one interval for one row before it is declared free of contact
_SUBDIVISIONS = 64


def find_event(events, horizon: float, step: float, chunk: int = 16, clock=None):
    """(tau, touching masses, contradicted masses) of the first switch or velocity touch in (0, horizon] (s).

    ``clock(tau)``, when given, is called before each chunk of the scan with the time reached (s
    from the phase start): a long phase of a stiff chain is scanned in thousands of chunks, so the
    run's wall-clock budget is watched inside the scan, not only between phases.

    None when nothing happens before ``horizon``. Contradicted masses left the zero of
    their event function the wrong way at once (:func:`.chain.modes.resolve_modes` reverses them).

    Rows that start within SWITCH_TOL of zero (the switch that opened this phase) start at
    a known zero, whatever the sign of the rounding leftover their closed form gives at 0:
    their next contact is looked for after they have left it (:func:`_after_opening`).
    """
    if len(events) == 0 or horizon <= 0:
        return None
    step = min(step, horizon)
    if not events.pointwise:
        g, d = events.values(np.array([0.0]))
        opening = np.abs(g[:, 0]) <= SWITCH_TOL
        g_prev, d_prev = g[:, 0], d[:, 0]
    t_prev, first = 0.0, True
    while t_prev < horizon:
        if clock is not None:
            clock(t_prev)
        # the chunk's grid from its start (t_prev + 0·step is t_prev itself, below the horizon)
        tg = t_prev + step * np.arange(chunk + 1)
        # (the grid increases: the times below the limit are its first ones, as many as searchsorted counts)
        tg = tg[: tg.searchsorted(horizon * (1 - 4 * _EPS))]
        if tg.size <= chunk:
            tg = np.concatenate((tg, [horizon]))
        if events.pointwise:  # the chunk with its start, in one evaluation (the start's values again, to the bit)
            G, D = events.values(tg)
            if first:
                opening = np.abs(G[:, 0]) <= SWITCH_TOL
        else:
            g, d = events.values(tg[1:])
            G, D = np.concatenate((g_prev[:, None], g), axis=1), np.concatenate((d_prev[:, None], d), axis=1)
        flagged = _screen(G, D, (tg[1:] - tg[:-1])[None, :], events.bound4)
        if first:
            # the first interval's opening rows count as positive at its start and only a crossing
            # counts (`_flags` with ``opening``); the other rows' flags stand as screened
            flagged[:, 0] = np.where(opening, G[:, 1] <= 0, flagged[:, 0])
        for k in np.logical_or.reduce(flagged, axis=0).nonzero()[0]:
            found = _earliest(events, flagged[:, k].nonzero()[0], tg[k], tg[k + 1], G[:, k], G[:, k + 1], D[:, k],
                          D[:, k + 1], opening if first and k == 0 else None, horizon)
            if found is not None:
                return found
        t_prev, g_prev, d_prev, first = tg[-1], G[:, -1], D[:, -1], False
        chunk = min(2 * chunk, 4096)
    return None


def _screen(G, D, h, bound4):
    """:func:`_flags` of every interval of a chunk's grid (values ``G``, slopes ``D``: rows x times).

    With a fourth-derivative bound: the same operations in the same order as :func:`_lower`,
    with the slopes' magnitudes taken once for both ends and the bound formed in place.
    """
    ga, gb = G[:, :-1], G[:, 1:]
    if bound4 is None:
        return _flags(ga, gb, D[:, :-1], D[:, 1:], h, bound4)
    slopes = np.abs(D)
    low = np.minimum(ga, gb)
    low -= 4 / 27 * h * (slopes[:, :-1] + slopes[:, 1:])
    low -= h**4 / 384 * bound4[:, None]
    flagged = gb <= 0
    flagged |= low <= SWITCH_TOL
    flagged &= ga > 0
    return flagged


def _flags(ga, gb, da, db, h, bound4, opening=None):
    """Rows (or rows x intervals) where g may come within SWITCH_TOL of zero on [a, b].

    ``opening`` rows started at zero: they count as positive at ``a`` and only a crossing counts.
    """
    if opening is None:
        return (ga > 0) & ((gb <= 0) | (_lower(ga, gb, da, db, h, bound4) <= SWITCH_TOL))
    # an opening row (|ga| within the tolerance) is flagged by a crossing only
    return np.where(opening, gb <= 0, (ga > 0) & ((gb <= 0) | (_lower(ga, gb, da, db, h, bound4) <= SWITCH_TOL)))


def _earliest(events, rows, a, b, ga, gb, da, db, opening, horizon, depth=0):
    """Earliest switch among ``rows`` on [a, b]; ``ga`` ... ``db`` hold every row's end values.

    Many flagged rows (long chains) are narrowed down by bisecting the interval with one
    vectorised evaluation per halving, so that few rows need a root search. A half that
    separates no row from the others is searched row by row at once: the bisection only
    descends while it sorts rows, so its cost stays bounded when rows hover near zero.
    """
    if rows.size <= 2 or depth >= 20:
        return _rows_event(events, rows, a, b, ga, gb, da, db, opening, horizon)
    mid = 0.5 * (a + b)
    g, d = events.values(np.array([mid]))
    gm, dm = g[:, 0], d[:, 0]
    b4 = None if events.bound4 is None else events.bound4[rows]
    # only the half that starts at the phase's start holds the opening zeros: in the other half an
    # opening row is an ordinary row (its touches count)
    for lo, hi, g0, g1, d0, d1, op in ((a, mid, ga, gm, da, dm, opening), (mid, b, gm, gb, dm, db, None)):
        sub = rows[_flags(g0[rows], g1[rows], d0[rows], d1[rows], hi - lo, b4, None if op is None else op[rows])]
        if not sub.size:
            continue
        search = _rows_event if sub.size == rows.size else partial(_earliest, depth=depth + 1)
        if found := search(events, sub, lo, hi, g0, g1, d0, d1, op, horizon):
            return found
    return None


def _rows_event(events, rows, a, b, ga, gb, da, db, opening, horizon):
    """(time, touching masses, contradicted masses) of the earliest of ``rows``' events on [a, b], or None."""
    # plain floats and ints: the root search is scalar, and each NumPy scalar operation costs
    # several times a float's (the same IEEE operations: the same numbers)
    a, b = float(a), float(b)
    found = [(out, events.mass[r]) for r in rows.tolist()
             if (out := _row_event(events, r, a, b, float(ga[r]), float(gb[r]), float(da[r]), float(db[r]),
                                   opening is not None and bool(opening[r]), horizon)) is not None]
    if not found:
        return None
    t = min(out[0] for out, _ in found)
    at_t = [(kind, int(m)) for (t_r, kind), m in found if t_r <= t + 4 * _EPS * abs(t)]
    return t, tuple(m for kind, m in at_t if kind == "touch"), tuple(m for kind, m in at_t if kind == "now")


def _lower(ga, gb, da, db, h, bound4):
    """Lower bound of g on intervals of width h from the end values and slopes (see module doc)."""
    if not isinstance(ga, np.ndarray):  # one row and interval (the root search): plain floats,
        # the same IEEE operations as NumPy's, without its per-call cost
        if bound4 is None:
            error = 1e-3 * (abs(ga) + abs(gb) + h * (abs(da) + abs(db)))
        else:
            error = h**4 / 384 * bound4
        return min(ga, gb) - 4 / 27 * h * (abs(da) + abs(db)) - error
    if ga.size <= 1024:  # few intervals: fewer NumPy calls win
        if bound4 is None:
            error = 1e-3 * (np.abs(ga) + np.abs(gb) + h * (np.abs(da) + np.abs(db)))
        else:
            error = h**4 / 384 * (bound4[:, None] if ga.ndim == 2 else bound4)
        return np.minimum(ga, gb) - 4 / 27 * h * (np.abs(da) + np.abs(db)) - error
    # many: in place, each operation in the order of the formula above (the same rounding): a long
    # phase screens thousands of intervals at once, and fresh temporaries cost page faults
    slopes = np.abs(da)
    slopes += np.abs(db)
    if bound4 is None:
        error = np.abs(ga)
        error += np.abs(gb)
        error += h * slopes
        error *= 1e-3
    else:
        error = h**4 / 384 * (bound4[:, None] if ga.ndim == 2 else bound4)
    slopes *= 4 / 27 * h
    out = np.minimum(ga, gb)
    out -= slopes
    out -= error
    return out


def _row_event(events, r, a, b, ga, gb, da, db, opening, horizon):
    """(switch time, "cross" | "touch" | "now") of row r in [a, b] under the touch rule, or None."""
    f = events.point(r)
    if opening or ga <= 0:
        return _after_opening(f, a, b, gb, da, db, events.bound4, r, events.kind[r])
    found = _first_contact(f, a, b, ga, gb, da, db, events.bound4, r, [_SUBDIVISIONS])
    if found is None or found[1] > horizon:
        return None
    what, t = found
    if what == "touch" and events.kind[r] != 0:
        return None  # a static force touching its limit: no switch
    return t, what


def _after_opening(f, a, b, gb, da, db, bound4, r, kind):
    """The first switch of a row that opened its phase at ``a`` (g(a) within the tolerance of zero), on [a, b].

    The opening zero is known: it is a, whatever the sign of the leftover (~1e-16) the closed
    form gives there, so the row's value at ``a`` is not looked at. What counts is its next
    contact with zero *after it has left it*:

    * the row ends the interval deeper than the tolerance (``gb < -SWITCH_TOL``): if it rose
      above zero first, the crossing where it came back; else it never left: "now" (the mode
      contradicted at once, below the resolution of the resolver's tests);
    * it ends above zero: nothing on [a, b] (the next intervals are screened as usual);
    * it ends within the tolerance at or below zero: if it rose above the tolerance on the way
      (a hop that lands at the interval's end), its contact after the rise; else it hovered
      within the tolerance all along, and the modes are decided again at ``b`` (a "cross"
      there) -- left alone, a row at or below zero would never be screened again.
    """
    if gb > 0:
        return None
    if gb >= -SWITCH_TOL:
        ts, gs = _samples(f, a, b, da, db)
        up = np.flatnonzero(gs > SWITCH_TOL)
        if up.size:
            t_up, g_up = float(ts[up[0]]), float(gs[up[0]])
            found = _first_contact(f, t_up, b, g_up, gb, f(t_up)[1], db, bound4, r, [_SUBDIVISIONS])
            if found is not None:
                what, t = found
                return None if what == "touch" and kind != 0 else (t, what)
        return None if kind != 0 else (b, "cross")
    # did it leave zero the right way (even to second order, g' = 0 at a border) and
    # cross back within this interval? then the crossing is the switch; else switch at once
    ts, gs = _samples(f, a, b, da, db)
    up = np.flatnonzero(gs > 0)
    if up.size:
        down = np.flatnonzero(gs[up[0]:] <= 0)  # the first return to zero after leaving it
        i = up[0] + (down[0] if down.size else ts.size - up[0]) - 1
        t_hi, g_hi = (ts[i + 1], gs[i + 1]) if i + 1 < ts.size else (b, gb)
        return _zero(lambda t: f(t)[:2], ts[i], t_hi, gs[i], g_hi), "cross"
    return a, "now"  # the motion contradicts the mode at once (below the resolution of g)


def _samples(f, a, b, da, db):
    """(times, values) of a row at 31 interior points of [a, b], and at its top when it has one there."""
    ts = np.linspace(a, b, 33)[1:-1]
    if da > 0 > db:
        # a short excursion (g' > 0 at the start, the return within one sample spacing)
        # can fall between the samples: its top, where g' = 0, is sampled too (fuzz: a
        # mass pushed 4e-4 over the Coulomb limit flipped between +/-1 at one instant)
        ts = np.sort(np.append(ts, _zero(lambda t: f(t)[1:], a, b, da, db)))
    return ts, np.array([f(t)[0] for t in ts])


def _first_contact(f, a, b, ga, gb, da, db, bound4, r, budget):
    """First contact of g with zero on [a, b] (g(a) > 0): None, ("cross", t_zero) or ("touch", t_min).

    ``budget`` is a one-element list: subdivisions left for this row and interval.
    """
    if gb <= 0:
        end, g_end = b, gb
        if da < 0 < db:  # the dip bottoms out inside: its first zero lies before the bottom
            t_min = _zero(lambda t: f(t)[1:], a, b, da, db)
            if (g_min := f(t_min)[0]) <= 0:
                end, g_end = t_min, g_min
        t_zero = _zero(lambda t: f(t)[:2], a, end, ga, g_end)
        t_min, g_min = _dip_after(f, t_zero, b, b - a)
        return ("cross", t_zero) if g_min < -SWITCH_TOL else ("touch", t_min)
    low = _lower(ga, gb, da, db, b - a, None if bound4 is None else float(bound4[r]))
    if low > SWITCH_TOL:
        return None
    if da < 0 < db:  # one interior minimum
        t_min = _zero(lambda t: f(t)[1:], a, b, da, db)
        g_min = f(t_min)[0]
        if g_min > SWITCH_TOL:
            return None
        if g_min >= -SWITCH_TOL:
            return ("touch", t_min)
        return ("cross", _zero(lambda t: f(t)[:2], a, t_min, ga, g_min))
    budget[0] -= 1
    if budget[0] < 0 or (ga <= SWITCH_TOL and gb <= SWITCH_TOL and low >= -SWITCH_TOL):
        # subdivided enough (the bound shrinks 16x per halving: nothing can hide after a few);
        # and a row hovering within the tolerance of zero at both ends (a mass at belt speed
        # under negligible forces) can only switch by going deeper, which the bound excludes
        return None
    mid = 0.5 * (a + b)
    gm, dm, _ = f(mid)
    return _first_contact(f, a, mid, ga, gm, da, dm, bound4, r, budget) or (
        _first_contact(f, mid, b, gm, gb, dm, db, bound4, r, budget) if gm > 0 else None)


def _dip_after(f, t_zero, b, width):
    """(t, g) at the lowest point of the dip that starts at the zero ``t_zero`` (or once deeper than the tolerance)."""
    g0, d0, _ = f(t_zero)
    if d0 >= 0:
        return t_zero, g0
    lo, d_lo, hi = t_zero, d0, b
    for _ in range(32):
        g_hi, d_hi, _ = f(hi)
        if g_hi < -SWITCH_TOL:
            return hi, g_hi
        if d_hi > 0:
            t = _zero(lambda t: f(t)[1:], lo, hi, d_lo, d_hi)
            return t, f(t)[0]
        lo, d_lo, hi = hi, d_hi, hi + width
    return hi, g_hi


def _zero(fn, a, b, fa, fb, max_iter: int = 200):
    """A zero of ``fn`` in [a, b] (fa, fb of opposite signs or fb == 0) to machine precision.

    ``fn(t) -> (value, slope or None)``. Newton steps (regula falsi without a slope) are
    taken while they stay inside the bracket and shrink it; bisection otherwise. Returns
    the bracket end on the far side of the zero (where the sign has changed).
    """
    if fb == 0:
        return b
    t, ft, slope = (a, fa, None)
    width = b - a
    for i in range(max_iter):
        if b - a <= 4 * _EPS * max(abs(a), abs(b), 1e-300):
            break
        cand = None
        if slope:
            delta = ft / slope
            cand = t - delta - math.copysign(2 * _EPS * max(abs(t), 1e-300), delta)  # land beyond the zero
        elif i % 3 != 2:
            cand = a - fa * (b - a) / (fb - fa)
        if cand is None or not a < cand < b or (i % 3 == 2 and b - a > 0.5 * width):
            cand = 0.5 * (a + b)
        if i % 3 == 2:
            width = b - a
        val, slope = fn(cand)
        if val == 0:
            return cand
        if (val > 0) == (fa > 0):
            a, fa = cand, val
        else:
            b, fb = cand, val
        t, ft = cand, val
    return b
