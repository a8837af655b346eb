"""What a user would otherwise write for a belt chain: two independent reference solvers.

None uses asperity2d's solver code; each takes the keyword arguments of
``simulate_chain`` (a preset) and returns ``(t, x, n_switches, ...)`` with ``x`` (n, T)
at the requested sample times (the ``solve_ivp`` ones also each mass's stick intervals).

* :func:`ivp_events` -- ``scipy.integrate.solve_ivp`` (DOP853, rtol 1e-10, atol 1e-12) on
  the piecewise-smooth system: slipping masses feel -s·mu_k·N, stuck masses ride the belt;
  terminal events on s·(v_i - V) (slipping) and on mu_s·N ∓ F_req,i (stuck), restarted at
  each event. The fastest version we could write (one matrix product per right-hand side,
  one event function per phase): the baseline the exact solver is measured against.
  :func:`ivp_plain` is the same method written straightforwardly (a lambda per guard).
* :func:`expm_stepper` -- a plain matrix-exponential stepper: the augmented state
  z = [x, v, 1] advanced by P = expm(Â·h) (cached per mode pattern) with h = 1/16 of
  the fastest period; a sign change of an event function over a step is located with
  ``brentq`` on expm(Â·tau)·z; samples from batched expm.

Both decide modes by the same rule: a mass reaching belt speed sticks if the static
force it needs is below mu_s·N, otherwise it slips (or reverses) with the net force; a
stuck mass whose needed force reaches the bound slips. Tangential touches without a
sign change are not events for them (they keep slipping, as the exact solver's grazes).
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg import expm
from scipy.optimize import brentq


class Chain:
    """Arrays of a chain given as ``simulate_chain`` keyword arguments (SI)."""

    def __init__(self, kw):
        self.m = np.asarray(kw["masses"], float)
        self.n = n = self.m.size
        k, c = np.asarray(kw["springs"], float), np.asarray(kw["dampers"], float)
        self.K, self.C = _tridiag(k), _tridiag(c)
        normal = self.m * kw.get("g", 9.81)
        mu_s = kw["mu_s"]
        mu_k = kw.get("mu_k") if kw.get("mu_k") is not None else mu_s
        self.fs, self.fk = mu_s * normal, mu_k * normal
        self.V = float(kw["v_belt"])
        self.x0, self.v0 = np.asarray(kw["x0"], float), np.asarray(kw["v0"], float)
        self.t_end = float(kw["t_end"])
        A = np.block([[np.zeros((n, n)), np.eye(n)], [-self.K / self.m[:, None], -self.C / self.m[:, None]]])
        self.rate = float(np.max(np.abs(np.linalg.eigvals(A))))
        omega = np.sqrt(np.max(k[:-1] + k[1:]) / np.min(self.m))
        self.vscale = max(abs(self.V), np.max(np.abs(self.v0)), np.max(self.fs / self.m) / omega)
        self.lscale = max(np.max(np.abs(self.x0)), self.vscale / omega)

    def f_req(self, x, v):
        """Static force (N) each mass needs to ride the belt."""
        return self.K @ x + self.C @ v

    def initial_modes(self):
        """Slip direction off belt speed; at belt speed stick if the static force suffices, else slip with it."""
        rel = self.v0 - self.V
        modes = np.where(rel >= 0, 1, -1)
        at = np.abs(rel) <= 1e-9 * self.vscale
        f = self.f_req(self.x0, np.where(at, self.V, self.v0))
        modes[at] = np.where(np.abs(f[at]) < self.fs[at], 0, -np.sign(f[at])).astype(int)
        return modes

    def after(self, modes, i, x, v):
        """Modes after mass ``i``'s event at state (x, v)."""
        new = modes.copy()
        f = self.f_req(x, np.where(modes == 0, self.V, v))[i]
        if modes[i] == 0:
            new[i] = -int(np.sign(f))  # the static bound was reached: slip with the net force
        else:
            new[i] = 0 if abs(f) < self.fs[i] * (1 - 1e-9) else -int(np.sign(f))
        return new

    def event_values(self, modes, x, v):
        """Event functions, positive while the modes hold: (rows,), with the mass of each row."""
        f = self.f_req(x, v)
        g, who = [], []
        for i in range(self.n):
            if modes[i] == 0:
                g += [(self.fs[i] - f[i]) / self.fs[i], (self.fs[i] + f[i]) / self.fs[i]]
                who += [i, i]
            else:
                g.append(modes[i] * (v[i] - self.V) / self.vscale)
                who.append(i)
        return np.array(g), who


def _tridiag(links):
    n = links.size - 1
    out = np.diag(links[:-1] + links[1:])
    i = np.arange(n - 1)
    out[i, i + 1] = out[i + 1, i] = -links[1:-1]
    return out


def _stick_intervals(log, n, t_end):
    """Per mass, the (start, end) of each stick from a log of (t, modes) switches."""
    out, start = [[] for _ in range(n)], [None] * n
    for t, modes in log:
        for i in range(n):
            if modes[i] == 0 and start[i] is None:
                start[i] = t
            elif modes[i] != 0 and start[i] is not None:
                out[i].append((start[i], t))
                start[i] = None
    for i in range(n):
        if start[i] is not None:
            out[i].append((start[i], t_end))
    return out


def ivp_events(kw, samples, *, rtol=1e-10, atol=1e-12, method="DOP853"):
    """The fastest honest ``solve_ivp`` with events: returns (t, x, switches, stick intervals).

    What a careful user writes once they see where ``solve_ivp``'s time goes (its own Python
    per step, and every event function called at every step): in each mode the motion is
    linear, y' = A y + b with y = [x, v], so the right-hand side is one precomputed matrix
    product; every guard of the mode is linear too (G y + h >= 0 while the mode holds), so
    the events are ONE function, min(G y + h), whose crossing ``solve_ivp`` locates on its
    dense output (brentq to 4 eps) -- the guard at its minimum there is the one that fired.
    DOP853, ``rtol`` 1e-10 and ``atol`` 1e-12 as the issue's reference; restarted at each
    event with the last step size (no new initial-step search).
    """
    ch = Chain(kw)
    n = ch.n
    modes, y, t = ch.initial_modes(), np.concatenate([ch.x0, ch.v0]), 0.0
    y[n:][modes == 0] = ch.V
    ts, xs, switches, log = [], [], 0, [(0.0, modes.copy())]
    first_step = None
    while True:
        stuck = modes == 0
        A = np.zeros((2 * n, 2 * n))
        A[:n, n:] = np.eye(n)
        A[n:][~stuck] = np.hstack([-ch.K, -ch.C])[~stuck] / ch.m[~stuck, None]
        b = np.zeros(2 * n)
        b[n:][~stuck] = -modes[~stuck] * ch.fk[~stuck] / ch.m[~stuck]
        G, h, who = [], [], []
        for i in range(n):  # rows of (G, h), each positive while the mode holds
            if stuck[i]:
                for sgn in (1, -1):  # fs - sgn * (K x + C v)_i >= 0
                    G.append(-sgn * np.concatenate([ch.K[i], ch.C[i]]) / ch.fs[i])
                    h.append(1.0)
                    who.append(i)
            else:  # s (v_i - V) >= 0
                row = np.zeros(2 * n)
                row[n + i] = modes[i] / ch.vscale
                G.append(row)
                h.append(-modes[i] * ch.V / ch.vscale)
                who.append(i)
        G, h = np.array(G), np.array(h)

        def rhs(_t, y, A=A, b=b):
            return A @ y + b

        def guard(_t, y, G=G, h=h):
            return (G @ y + h).min()

        guard.terminal, guard.direction = True, -1
        sol = solve_ivp(rhs, (t, ch.t_end), y, method=method, rtol=rtol, atol=atol, first_step=first_step,
                        t_eval=samples[(samples >= t) & (samples <= ch.t_end)], events=guard)
        if len(sol.t):
            ts.append(sol.t)
            xs.append(sol.y[:n])
        if sol.status != 1:
            break
        t, y = float(sol.t_events[0][0]), sol.y_events[0][0].copy()
        i = who[int(np.argmin(G @ y + h))]
        modes = ch.after(modes, i, y[:n], y[n:])
        y[n:][modes == 0] = ch.V
        switches += 1
        log.append((t, modes.copy()))
        if len(sol.t) >= 2:
            first_step = min(float(sol.t[-1] - sol.t[-2]), 0.5 * (ch.t_end - t)) or None
    return np.concatenate(ts), np.concatenate(xs, axis=1), switches, _stick_intervals(log, n, ch.t_end)


def ivp_plain(kw, samples, *, rtol=1e-10, atol=1e-12, method="DOP853"):
    """The straightforward ``solve_ivp`` with events (the issue's reference): one event function
    per guard (each a Python lambda that recomputes the spring forces), the right-hand side
    from the force law, restarted at each event. Returns (t, x, switches, stick intervals)."""
    ch = Chain(kw)
    n = ch.n
    modes, y, t = ch.initial_modes(), np.concatenate([ch.x0, ch.v0]), 0.0
    y[n:][modes == 0] = ch.V
    ts, xs, switches, log = [], [], 0, [(0.0, modes.copy())]
    while True:
        stuck, fric = modes == 0, -modes * ch.fk

        def rhs(_t, y, stuck=stuck, fric=fric):
            a = (fric - ch.f_req(y[:n], y[n:])) / ch.m
            a[stuck] = 0.0
            return np.concatenate([y[n:], a])

        events = []
        for i in range(n):
            if stuck[i]:
                for sgn in (1, -1):
                    events.append(lambda _t, y, i=i, sgn=sgn: ch.fs[i] - sgn * ch.f_req(y[:n], y[n:])[i])
            else:
                events.append(lambda _t, y, i=i, s=modes[i]: s * (y[n + i] - ch.V))
        for e in events:
            e.terminal, e.direction = True, -1
        sol = solve_ivp(rhs, (t, ch.t_end), y, method=method, rtol=rtol, atol=atol,
                        t_eval=samples[(samples >= t) & (samples <= ch.t_end)], events=events)
        if len(sol.t):  # (an empty t_eval gives empty lists)
            ts.append(sol.t)
            xs.append(sol.y[:n])
        if sol.status != 1:
            break
        j = min((k for k in range(len(events)) if sol.t_events[k].size), key=lambda k: sol.t_events[k][0])
        t, y = float(sol.t_events[j][0]), sol.y_events[j][0].copy()
        i = [i for i in range(n) for _ in range(2 if stuck[i] else 1)][j]
        modes = ch.after(modes, i, y[:n], y[n:])
        y[n:][modes == 0] = ch.V
        switches += 1
        log.append((t, modes.copy()))
    return np.concatenate(ts), np.concatenate(xs, axis=1), switches, _stick_intervals(log, n, ch.t_end)


def expm_stepper(kw, samples):
    """Plain matrix-exponential stepper with bracketed event location; returns (t, x, switches).

    Steps of h <= 1/16 of the fastest period on a grid that contains the (uniform)
    sample times, so samples cost nothing; after a switch one partial step (its own
    expm) returns to the grid.
    """
    ch = Chain(kw)
    n = ch.n
    spacing = samples[1] - samples[0]
    h = spacing / np.ceil(spacing * 16 * ch.rate / (2 * np.pi))
    cache = {}

    def system(modes):
        key = tuple(modes)
        if key not in cache:
            A = np.zeros((2 * n + 1, 2 * n + 1))
            A[:n, n : 2 * n] = np.eye(n)
            slip = modes != 0
            A[n:2 * n][slip, :n] = -ch.K[slip] / ch.m[slip, None]
            A[n:2 * n][slip, n:2 * n] = -ch.C[slip] / ch.m[slip, None]
            A[n:2 * n][slip, 2 * n] = -modes[slip] * ch.fk[slip] / ch.m[slip]
            cache[key] = (A, expm(A * h))
        return cache[key]

    modes = ch.initial_modes()
    z = np.concatenate([ch.x0, np.where(modes == 0, ch.V, ch.v0), [1.0]])
    A, P = system(modes)
    k, t, switches = 0, 0.0, 0  # t = k·h on the grid
    xs, ts = [z[:n].copy()], [0.0]
    per_sample = int(round(spacing / h))
    g0, who = ch.event_values(modes, z[:n], z[n:2 * n])
    while t < ch.t_end * (1 - 1e-12):
        t_next = (k + 1) * h
        z1 = P @ z if t == k * h else expm(A * (t_next - t)) @ z
        g1, _ = ch.event_values(modes, z1[:n], z1[n:2 * n])
        hit = np.flatnonzero((g0 > 0) & (g1 <= 0))
        if hit.size:
            def g_at(s, r, z=z, A=A, modes=modes):
                zs = expm(A * s) @ z
                return ch.event_values(modes, zs[:n], zs[n:2 * n])[0][r]

            roots = [brentq(g_at, 0.0, t_next - t, args=(r,), xtol=1e-15, rtol=8.9e-16) for r in hit]
            tau, r = min(zip(roots, hit))
            z = expm(A * tau) @ z
            t += tau
            modes = ch.after(modes, who[r], z[:n], z[n:2 * n])
            z[n:2 * n][modes == 0] = ch.V
            A, P = system(modes)
            switches += 1
        else:
            z, t, k = z1, t_next, k + 1
            if k % per_sample == 0:
                xs.append(z[:n].copy())
                ts.append(t)
        g0, who = ch.event_values(modes, z[:n], z[n:2 * n])
    return np.array(ts), np.array(xs).T, switches
