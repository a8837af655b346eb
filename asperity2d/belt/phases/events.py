"""Event functions of one phase: positive while the current mode holds, zero at a switch.

* slipping mass i, direction s = ±1:  g = s·(v_i - V) / v_scale      (relative velocity reaches 0)
* stuck mass i, bound kappa = ±1:     g = (mu_s·N_i - kappa·F_req,i) / (mu_s·N_i)
                                                                       (static force reaches its limit)

with F_req,i = m_i·dV/dt - F_springs+dampers,i the friction force needed to
keep the mass on the belt. Two implementations share one interface:

* :class:`ModalEvents` for closed-form phases: each g is a
  :class:`~.phases.modal.ModalForm`, so values and derivatives on a whole grid cost
  one ``exp`` and one matrix product, a point costs one small ``exp``, and
  ``bound4`` bounds |g''''| rigorously (sum of |b|·|lam|⁴) for the grid screen;
* :class:`SampledEvents` for integrated phases (and closed-form phases with an
  unanchored or critically damped segment), from ``phase.evaluate``.
"""

from __future__ import annotations

import numpy as np

from .modal import ModalForm, linear_map, scale_columns, stack_rows
from ..spec import force_row, link_force


def event_rows(spec, modes):
    """(kind, mass) arrays of the active event functions: kind 0 slip, ±1 stick bounds.

    Frictionless masses have none (they never stick).
    """
    kind, mass = [], []
    modes = np.asarray(modes).tolist()  # (plain ints: a new mode pattern's rows are built in Python)
    for i in spec.frictional_masses:
        if modes[i] == 0:
            kind += [1, -1]
            mass += [i, i]
        else:
            kind.append(0)
            mass.append(i)
    return np.array(kind, dtype=int), np.array(mass, dtype=int)


def event_map(spec, modes, V):
    """(kind, mass, map, offset): g = map @ [x; v; a] + offset for a constant belt speed ``V`` (m/s)."""
    kind, mass = event_rows(spec, modes)
    n, v_scale = spec.n, spec.velocity_scale
    # (plain floats: the same divisions and products as on NumPy's scalars, at a fraction of the cost)
    f_scale, limit = spec.limit_scale.tolist(), spec.static_limit.tolist()
    rows, cols, vals = [], [], []
    offset = [0.0] * kind.size
    modes = np.asarray(modes).tolist()
    for r, (k, i) in enumerate(zip(kind.tolist(), mass.tolist())):
        if k == 0:  # s·(v_i - V)/v_scale
            s = modes[i] / v_scale
            rows.append(r), cols.append(n + i), vals.append(s)
            offset[r] = -s * V
            continue
        cols_i, coefs_i = force_row(spec, i)  # (limit + kappa·F_sd,i)/f_scale
        rows += [r] * len(cols_i)
        cols += cols_i
        vals += [k / f_scale[i] * coef for coef in coefs_i]
        offset[r] = limit[i] / f_scale[i]
    return kind, mass, linear_map((kind.size, 3 * n), (rows, cols, vals)), np.array(offset)


class ModalEvents:
    """Event functions of a closed-form phase as modal forms (maps cached in the phase's template)."""

    #: the value at each time is computed on its own, the same numbers alone or among other times
    #: (elementwise exp/cos/sin, and products of a strided B.real / B.imag or a CSR matrix, which
    #: NumPy and SciPy sum term by term in order, never blocked by BLAS)
    pointwise = True

    def __init__(self, phase):
        t = phase.template
        self.kind, self.mass = t.kind, t.mass
        self.g = phase.form(t.event_shapes, t.event_map, t.event_offset)
        lam = self.g.lam
        dB = scale_columns(self.g.B, lam)
        B = stack_rows(self.g.B, dB)
        R = self.kind.size
        c1 = np.zeros(2 * R)
        c1[:R] = self.g.c1
        self._both = ModalForm(lam, B, np.concatenate([self.g.c0, self.g.c1]), c1, self.g.damped)
        #: rigorous bound on |d⁴g/dtau⁴| per row: sum of |b|·|lam|⁴
        self.bound4 = t.event_shapes_abs @ (np.abs(phase.coef) * t.lam_abs4)
        self._points = {}  # row -> its closed form at one time (the root search asks repeatedly)

    def __len__(self):
        return self.kind.size

    def values(self, tau):
        """(g, dg), each (rows, T), at times ``tau`` (s)."""
        both = self._both.at(tau)
        R = self.kind.size
        return both[:R], both[R:]

    def point(self, r):
        """``f(t) -> (g, dg, d2g)`` of row ``r`` at one time, in closed form."""
        f = self._points.get(r)
        if f is None:
            f = self._points[r] = self._point(r)
        return f

    def _point(self, r):
        lam, b, c0, c1 = self.g.scalar(r)
        M = np.array([b, b * lam, b * lam * lam])
        # the root search asks again for times it has just evaluated (the zero it returns is the
        # dip search's start): the same numbers, kept; t = 0 is left out (a -0.0 would share its key)
        seen = {}

        def f(t):
            out = seen.get(t)
            if out is None:
                d0, d1, d2 = (M @ np.exp(lam * t)).real.tolist()  # (plain floats: the search is scalar)
                out = d0 + c0 + c1 * t, d1 + c1, d2
                if t:
                    seen[t] = out
            return out

        return f


class SampledEvents:
    """Event functions evaluated from ``phase.evaluate`` (integrated or expm-propagated phases)."""

    bound4 = None
    #: (integrators' dense output may evaluate many times as one matrix product)
    pointwise = False

    def __init__(self, phase):
        self.phase, self.spec = phase, phase.spec
        self.kind, self.mass = event_rows(phase.spec, phase.modes)
        self.v_scale = phase.spec.velocity_scale
        self.f_scale = phase.spec.limit_scale

    def __len__(self):
        return self.kind.size

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

