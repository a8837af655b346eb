"""Event functions of one phase: positive while the current mode holds, zero at a switch.

* slipping mass i, direction s = ±1:  g = s·(v_i - V) / v_scale      (relative velocity reaches 0)
* stuck mass i, bound kappa = ±1:     g = (mu_s·N_i - kappa·F_req,i) / (mu_s·N_i)
                                                                       (static force reaches its limit)

with F_req,i = m_i·dV/dt - F_springs+dampers,i the friction force needed to
keep the mass on the belt. Two implementations share one interface:

* :class:`ModalEvents` for closed-form phases: each g is a
  :class:`~.modal.ModalForm`, so values and derivatives on a whole grid cost
  one ``exp`` and one matrix product, a point costs one small ``exp``, and
  ``bound4`` bounds |g''''| rigorously (sum of |b|·|lam|⁴) for the grid screen;
* :class:`SampledEvents` for integrated phases (and closed-form phases with an
  unanchored or critically damped segment), from ``phase.evaluate``.
"""

from __future__ import annotations

import numpy as np

from .modal import linear_map
from .spec import link_force


def event_rows(spec, modes):
    """(kind, mass) arrays of the active event functions: kind 0 slip, ±1 stick bounds.

    Frictionless masses have none (they never stick).
    """
    kind, mass = [], []
    for i in np.flatnonzero(spec.frictional):
        if modes[i] == 0:
            kind += [1, -1]
            mass += [i, i]
        else:
            kind.append(0)
            mass.append(i)
    return np.array(kind, dtype=int), np.array(mass, dtype=int)


class _Rows:
    def __init__(self, phase, v_scale):
        self.phase, self.spec = phase, phase.spec
        self.kind, self.mass = event_rows(phase.spec, phase.modes)
        self.v_scale = v_scale
        limit = self.spec.static_limit
        self.f_scale = np.where(limit > 0, limit, 1.0)

    def __len__(self):
        return self.kind.size


class ModalEvents(_Rows):
    """Event functions of a closed-form phase as modal forms (see :mod:`.modal`)."""

    def __init__(self, phase, v_scale):
        super().__init__(phase, v_scale)
        spec, n, R = self.spec, self.spec.n, len(self.kind)
        rows, cols, vals = [], [], []
        offset = np.empty(R)
        for r, (kind, i) in enumerate(zip(self.kind, self.mass)):
            if kind == 0:  # s·(v_i - V)/v_scale
                s = phase.modes[i] / v_scale
                rows.append(r), cols.append(n + i), vals.append(s)
                offset[r] = -s * phase.V
                continue
            # (limit + kappa·F_sd,i)/f_scale, F_sd,i = k_i x_i-1 - (k_i + k_i+1) x_i + k_i+1 x_i+1 (+ c, v)
            w = kind / self.f_scale[i]
            for base, links in ((0, spec.k), (n, spec.c)):
                for j, coef in ((i - 1, links[i]), (i, -(links[i] + links[i + 1])), (i + 1, links[i + 1])):
                    if 0 <= j < n and coef != 0:
                        rows.append(r), cols.append(base + j), vals.append(w * coef)
            offset[r] = spec.static_limit[i] / self.f_scale[i]
        motion = phase.motion
        sparse = not isinstance(motion.B, np.ndarray)
        self.g = motion.compose(linear_map((R, 3 * n), sparse, (rows, cols, vals)), offset)
        self.dg = self.g.derivative()
        B = np.vstack([self.g.B, self.dg.B]) if not sparse else _vstack(self.g.B, self.dg.B)
        self._both = type(motion)(motion.lam, B, np.concatenate([self.g.c0, self.dg.c0]),
                                  np.concatenate([self.g.c1, self.dg.c1]))
        lam4 = np.abs(motion.lam) ** 4
        #: rigorous bound on |d⁴g/dtau⁴| per row
        self.bound4 = np.abs(self.g.B) @ lam4 if not sparse else abs(self.g.B) @ lam4

    def values(self, tau):
        """(g, dg), each (rows, T), at times ``tau`` (s)."""
        both = self._both.at(tau)
        R = len(self.kind)
        return both[:R], both[R:]

    def point(self, r):
        """``f(t) -> (g, dg, d2g)`` of row ``r`` at one time, in closed form."""
        lam, b, c0, c1 = self.g.scalar(r)
        b1, b2 = b * lam, b * lam * lam

        def f(t):
            e = np.exp(lam * t)
            return float((b @ e).real) + c0 + c1 * t, float((b1 @ e).real) + c1, float((b2 @ e).real)

        return f


def _vstack(a, b):
    import scipy.sparse  # lazily: only long chains use sparse forms

    return scipy.sparse.vstack([a, b], format="csr")


class SampledEvents(_Rows):
    """Event functions evaluated from ``phase.evaluate`` (integrated or expm-propagated phases)."""

    bound4 = None

    def values(self, tau):
        ph, spec = self.phase, self.spec
        tau = np.atleast_1d(np.asarray(tau, dtype=float))
        x, v, a = ph.evaluate(tau)
        a_belt = ph.belt_acceleration(tau)
        V = ph.belt_velocity(tau)
        k, c = spec.k, spec.c
        f_req = spec.m[:, None] * a_belt[None, :] - (link_force(k, x) + link_force(c, v))
        df_req = -(link_force(k, v) + link_force(c, a))  # d(a_belt)/dt neglected
        i, kind = self.mass, self.kind
        slip = kind == 0
        g, dg = np.empty((i.size, tau.size)), np.empty((i.size, tau.size))
        s = ph.modes[i[slip]][:, None] / self.v_scale
        g[slip] = s * (v[i[slip]] - V[None, :])
        dg[slip] = s * (a[i[slip]] - a_belt[None, :])
        st = ~slip
        w = (kind[st] / self.f_scale[i[st]])[:, None]
        g[st] = (spec.static_limit[i[st]] / self.f_scale[i[st]])[:, None] - w * f_req[i[st]]
        dg[st] = -w * df_req[i[st]]
        return g, dg

    def point(self, r):
        """``f(t) -> (g, dg, None)`` of row ``r`` at one time."""

        def f(t):
            g, dg = self.values(np.array([t]))
            return float(g[r, 0]), float(dg[r, 0]), None

        return f

