"""Switching logic shared by the exact and the integrator-based belt solvers.

Event functions are written so that they are positive while the current mode
holds and reach zero at a switch:

* slipping mass i, direction s = ±1:  g = s·(v_i - V) / v_scale     (relative velocity reaches 0)
* stuck mass i: g± = (mu_s·N_i ∓ F_req,i) / (mu_s·N_i)              (static force reaches its limit)

with F_req,i = m_i·dV/dt - F_springs+dampers,i the friction force needed to
keep the mass on the belt. The first zero is bracketed on a grid of 1/16 of
the fastest period (plus a check of every interior minimum through the
derivative, so a graze between grid points is not missed) and located to
machine precision with ``scipy.optimize.brentq`` on the exact trajectory.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from .spec import link_force

#: relative tolerance that declares two numbers equal at a switching instant
SWITCH_TOL = 1e-9


def event_rows(spec, modes):
    """(kind, mass) pairs of the active event functions; frictionless masses have none."""
    mu_s_n = spec.law.static_coefficient * spec.normal
    mu_k_n = spec.law.kinetic_coefficient * spec.normal
    rows = []
    for i, mode in enumerate(modes):
        if mu_s_n[i] == 0 and mu_k_n[i] == 0:
            continue
        if mode == 0:
            rows += [(1, i), (-1, i)]
        else:
            rows.append((0, i))
    return rows


class EventFunctions:
    """Vectorised event functions g (rows, T) and their time derivatives for one phase."""

    def __init__(self, phase, rows, v_scale):
        self.phase = phase
        self.kind = np.array([r[0] for r in rows], dtype=int)
        self.mass = np.array([r[1] for r in rows], dtype=int)
        spec = phase.spec
        self.limit = spec.law.static_coefficient * spec.normal
        self.v_scale = v_scale
        self.f_scale = np.where(self.limit > 0, self.limit, 1.0)

    def __call__(self, tau, row=None):
        """(g, dg) for all rows, or -- with ``row`` -- correct in that row only (cheaper)."""
        ph = self.phase
        if row is not None and hasattr(ph, "segments"):
            i = self.mass[row]
            x, v, a = ph.evaluate(tau, masses=np.array([i - 1, i, i + 1]))
        else:
            x, v, a = ph.evaluate(tau)
        tau = np.atleast_1d(tau)
        spec = ph.spec
        a_belt = ph.belt_acceleration(tau)
        V = ph.belt_velocity(tau)
        f_req = spec.m[:, None] * a_belt[None, :] - (link_force(spec.k, x) + link_force(spec.c, v))
        df_req = -(link_force(spec.k, v) + link_force(spec.c, a))  # d(a_belt)/dt neglected
        i, kind = self.mass, self.kind
        s = ph.modes[i][:, None]
        slip = kind == 0
        g = np.empty((len(i), tau.size))
        dg = np.empty_like(g)
        g[slip] = s[slip] * (v[i[slip]] - V[None, :]) / self.v_scale
        dg[slip] = s[slip] * (a[i[slip]] - a_belt[None, :]) / self.v_scale
        st = ~slip
        lim = (self.limit[i[st]] / self.f_scale[i[st]])[:, None]
        sign = kind[st][:, None]
        g[st] = lim - sign * f_req[i[st]] / self.f_scale[i[st]][:, None]
        dg[st] = -sign * df_req[i[st]] / self.f_scale[i[st]][:, None]
        return g, dg


def find_event(events: EventFunctions, horizon: float, step: float, chunk: int = 32):
    """First tau in (0, horizon] where an event function reaches zero, or None.

    Rows that start at zero (the switch that opened this phase) count as
    positive; the mode choice guarantees they move away from zero.
    """
    if len(events.kind) == 0:
        return None
    step = min(step, horizon)
    g0, dg0 = events(np.array([0.0]))
    just = np.abs(g0[:, 0]) <= 1e-9
    t_prev, g_prev, dg_prev = 0.0, g0[:, 0], dg0[:, 0]
    first = True
    while t_prev < horizon:
        taus = t_prev + step * np.arange(1, chunk + 1)
        taus = taus[taus < horizon * (1 - 1e-15)]
        taus = np.append(taus, horizon) if taus.size < chunk else taus
        g, dg = events(taus)
        tg = np.concatenate([[t_prev], taus])
        G = np.column_stack([g_prev, g])
        D = np.column_stack([dg_prev, dg])
        pos = G[:, :-1] > 0
        if first:
            pos[just, 0] = True
        cross = pos & (G[:, 1:] <= 0)
        dip = pos & ~cross & (D[:, :-1] < 0) & (D[:, 1:] > 0)
        if dip.any():
            dip &= _hermite_may_reach_zero(G, D, np.diff(tg))
        flagged = np.flatnonzero((cross | dip).any(axis=0))
        for k in flagged:
            roots = []
            for r in np.flatnonzero(cross[:, k] | dip[:, k]):
                root = _root_in(events, r, tg[k], tg[k + 1], bool(cross[r, k]), just[r] and first and k == 0)
                if root is not None:
                    roots.append(root)
            if roots:
                return min(roots)
        t_prev, g_prev, dg_prev = tg[-1], G[:, -1], D[:, -1]
        first = False
    return None


_S = np.linspace(0.0, 1.0, 33)
_H = np.stack([2 * _S**3 - 3 * _S**2 + 1, _S**3 - 2 * _S**2 + _S, -2 * _S**3 + 3 * _S**2, _S**3 - _S**2])


def _hermite_may_reach_zero(G, D, h):
    """Screen interior minima with the cubic Hermite interpolant of (g, g') at the grid points.

    On a step of 1/16 of the fastest period the interpolation error is below ~1e-4 of the
    oscillation amplitude; a minimum whose estimate stays above 1e-3 of that scale cannot
    reach zero, and is skipped without root finding.
    """
    g0, g1, d0, d1 = G[:, :-1], G[:, 1:], D[:, :-1] * h, D[:, 1:] * h
    est = np.einsum("k,...->...k", _H[0], g0) + np.einsum("k,...->...k", _H[1], d0) \
        + np.einsum("k,...->...k", _H[2], g1) + np.einsum("k,...->...k", _H[3], d1)
    margin = 1e-3 * (np.abs(g0) + np.abs(g1) + np.abs(d0) + np.abs(d1))
    return est.min(axis=-1) <= margin


def _root_in(events, row, a, b, crossing, started_at_zero):
    f = lambda t: events(np.array([t]), row)[0][row, 0]  # noqa: E731
    if not crossing:
        df = lambda t: events(np.array([t]), row)[1][row, 0]  # noqa: E731
        try:
            t_min = brentq(df, a, b, xtol=1e-300, rtol=8.9e-16, maxiter=200)
        except ValueError:  # derivative from an integrator's dense output: fall back to sampling
            grid = np.linspace(a, b, 65)
            t_min = grid[int(np.argmin(events(grid, row)[0][row]))]
        if f(t_min) > (-1e-12 if started_at_zero else 0.0):
            return None
        b = t_min
    if started_at_zero and f(a) <= 0:
        # the row left zero in the wrong direction: switch again at once
        return a
    if f(b) == 0:
        return b
    return brentq(f, a, b, xtol=1e-300, rtol=8.9e-16, maxiter=200)


def resolve_modes(spec, x, v, V, a_belt, previous, v_scale):
    """New modes (0 stick, ±1 slip) at a switching instant; returns (modes, v) with stuck v = V exactly.

    A mass at belt speed sticks if the static force it needs is below
    mu_s·N; otherwise it slips in the direction of the net force (which also
    covers a slip reversal). At the limit itself, the rate of change of the
    required force decides.
    """
    v = np.array(v, dtype=float)
    modes = np.array(previous, dtype=int)
    limit = spec.law.static_coefficient * spec.normal
    kinetic = spec.law.kinetic_coefficient * spec.normal
    frictional = (limit > 0) | (kinetic > 0)
    v_tol = SWITCH_TOL * v_scale
    at_belt = frictional & (np.abs(v - V) <= v_tol)
    v[at_belt] = V
    modes[~at_belt] = np.sign(v[~at_belt] - V).astype(int)
    f_sd = link_force(spec.k, x) + link_force(spec.c, v)
    f_req = spec.m * a_belt - f_sd
    tol = SWITCH_TOL * np.maximum(limit, 1e-300)
    border = []
    for i in np.flatnonzero(at_belt):
        if abs(f_req[i]) < limit[i] - tol[i]:
            modes[i] = 0
        elif abs(f_req[i]) > limit[i] + tol[i]:
            modes[i] = -int(np.sign(f_req[i]))
        else:
            modes[i] = 0
            border.append(i)
    if border:
        # at the static limit: compare the trend of the required force with the tentative modes
        fric = -modes * kinetic
        a = (f_sd + fric) / spec.m
        a[modes == 0] = a_belt
        df_req = -(link_force(spec.k, v) + link_force(spec.c, a))
        for i in border:
            if np.sign(f_req[i]) * df_req[i] > 0 or (f_req[i] == 0 and df_req[i] != 0):
                modes[i] = -int(np.sign(f_req[i] if f_req[i] != 0 else df_req[i]))
    return modes, v
