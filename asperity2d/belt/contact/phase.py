"""One phase of a chain with a normal degree of freedom: the motion between two switches.

A phase is fixed by the *mode* of every mass: stuck (0), slipping (±1, the sign of
v_i - V) or separated (2, :data:`~.normal.SEPARATED`). Over the full state
Z = [q; q'] with q = [x; y] (4n rows) the motion then obeys

    M·q'' + C_e·q' + K_e·q = g_e

with the effective matrices of the mode pattern (:class:`ContactTemplate`):

* a compliant contact in contact adds k_c on y_i: N_i = -k_c·y_i;
* a rigid contact in contact fixes y_i = y_i' = 0 and its force is the constraint
  force N_i = W_i + K_s[y_i]·q + C_s[y_i]·q';
* the friction on a slipping mass, F_i = -s_i·mu_k·N_i, moves s_i·mu_k·(row of N_i) into
  row x_i of K_e and C_e: this is what makes K_e non-symmetric (mode coupling);
* a stuck mass rides the belt, x_i = x_i(0) + V·tau, and needs the friction force
  F_i = (K_s·q + C_s·q')_x_i.

The free coordinates obey z' = A·z + b0 + b1·tau (the constrained ones enter as
known ramps), solved in closed form by :mod:`.contact.affine` (a
:class:`~.phases.modal.ModalForm` of all 4n rows) or, when A is singular or nearly
defective, by its Taylor grid.

Event functions (positive while the mode holds, zero at a switch; :mod:`.phases.finder`
locates them) per mass:

* separated:          y_i / gap_scales[i]                          ("gap": closing)
* in contact:         N_i / normal_scales[i]                       ("normal": opening)
* slipping, s = ±1:   s·(v_i - V) / v_scale                        ("slip")
* stuck, kappa = ±1:  (mu_s·N_i - kappa·F_i) / (mu_s·W_i)          ("stick")

A *touch* of a gap, normal or slip row (its dip's lowest value within
``SWITCH_TOL`` of zero) ends the phase and is a graze when the mode holds; a
touch of a stick row does not (the static force touched its limit and stays
within it), exactly as in :mod:`.phases.finder`.
"""

from __future__ import annotations

import math

import numpy as np

from .affine import AffineModes
from ..phases.events import ModalEvents
from ..phases.finder import SWITCH_TOL  # noqa: F401 -- the tolerance the docstring refers to
from ..phases.modal import ModalForm
from ..normal import SEPARATED

#: event-row roles (column ``role`` of a template's rows)
GAP, NORMAL, SLIP, STICK = "gap", "normal", "slip", "stick"
_GL_X, _GL_W = np.polynomial.legendre.leggauss(10)
#: quadrature pieces span at most this many scan steps (1/16 of the fastest period each)
PIECE_STEPS = 4


class ContactTemplate:
    """What a phase needs that depends only on the chain and its mode pattern (cached per run).

    ``modes`` (n,) ints; ``free`` the indices of the free coordinates in q; ``A`` and its
    :class:`~.contact.affine.AffineModes`; ``N_map`` (n, 4n), ``N_offset`` (n,): the normal
    forces; ``F_map``, ``F_offset``: the friction forces; the event rows ``ev_map``,
    ``ev_offset`` with their ``role``, ``owner`` (mass) and ``kappa`` (stick bound).
    """

    def __init__(self, spec, modes):
        n, D = spec.n, 2 * spec.n
        self.spec, self.n, self.D = spec, n, D
        self.modes = modes = np.asarray(modes, dtype=int)
        self.V = V = float(spec.chain.v_belt)
        nc = spec.normal
        law = spec.chain.law
        mu_s, mu_k = law.static_coefficient, law.kinetic_coefficient
        Ks, Cs = spec.stiffness_matrix, spec.damping_matrix
        K, C, g = Ks.copy(), Cs.copy(), spec.constant_force.copy()
        contact = modes != SEPARATED
        self.contact, self.stuck = contact, modes == 0
        N_map, N_off = np.zeros((n, 2 * D)), np.zeros(n)
        for i in np.flatnonzero(contact):
            if nc.rigid:
                N_map[i, :D], N_map[i, D:] = Ks[n + i], Cs[n + i]
                N_off[i] = spec.load[i]
            else:
                K[n + i, n + i] += nc.contact_stiffness
                N_map[i, n + i] = -nc.contact_stiffness
        F_map, F_off = np.zeros((n, 2 * D)), np.zeros(n)
        for i in np.flatnonzero(contact & ~self.stuck):
            s = modes[i]
            K[i] += s * mu_k * N_map[i, :D]
            C[i] += s * mu_k * N_map[i, D:]
            g[i] -= s * mu_k * N_off[i]
            F_map[i], F_off[i] = -s * mu_k * N_map[i], -s * mu_k * N_off[i]
        for i in np.flatnonzero(self.stuck):  # the static force that keeps x_i'' = 0
            F_map[i, :D], F_map[i, D:] = Ks[i], Cs[i]
        self.N_map, self.N_offset, self.F_map, self.F_offset = N_map, N_off, F_map, F_off
        held = np.zeros(D, dtype=bool)
        held[np.flatnonzero(self.stuck)] = True
        if nc.rigid:
            held[n + np.flatnonzero(contact)] = True
        self.held, self.free = held, np.flatnonzero(~held)
        #: ramp of each held coordinate (m/s): V for stuck x, 0 for a rigid contact's y
        self.rate = np.where(np.arange(D) < n, V, 0.0) * held
        f, h = self.free, np.flatnonzero(held)
        d = f.size
        m = spec.mass_vector[f]
        self.K_fh, self.C_fh, self.g_f, self.m_f = K[np.ix_(f, h)], C[np.ix_(f, h)], g[f], m
        A = np.zeros((2 * d, 2 * d))
        A[:d, d:] = np.eye(d)
        A[d:, :d] = -K[np.ix_(f, f)] / m[:, None]
        A[d:, d:] = -C[np.ix_(f, f)] / m[:, None]
        self.affine = AffineModes(A)
        self.step = 2 * math.pi / (16 * self.affine.rate) if self.affine.rate > 0 else math.inf
        #: embedding of the free state z = [q_f; q_f'] in Z = [q; q']
        E = np.zeros((2 * D, 2 * d))
        E[f, np.arange(d)] = 1.0
        E[D + f, d + np.arange(d)] = 1.0
        self.E = E
        self._events(spec, mu_s)

    def _events(self, spec, mu_s):
        n, D = self.n, self.D
        rows, offs, role, owner, kappa = [], [], [], [], []
        v_scale = spec.velocity_scale
        law = spec.chain.law  # friction follows the actual N: a mass is frictional by its coefficients alone
        frictional = np.full(n, law.static_coefficient > 0 or law.kinetic_coefficient > 0)
        for i in range(n):
            if self.modes[i] == SEPARATED:
                r = np.zeros(2 * D)
                r[n + i] = 1.0 / spec.gap_scales[i]  # each mass on its own scale
                rows.append(r), offs.append(0.0), role.append(GAP), owner.append(i), kappa.append(0)
                continue
            rows.append(self.N_map[i] / spec.normal_scales[i])
            offs.append(self.N_offset[i] / spec.normal_scales[i])
            role.append(NORMAL), owner.append(i), kappa.append(0)
            if not frictional[i]:
                continue
            if self.modes[i] == 0:
                lim = spec.limit_scale[i]
                for kap in (1, -1):
                    rows.append((mu_s * self.N_map[i] - kap * self.F_map[i]) / lim)
                    offs.append((mu_s * self.N_offset[i] - kap * self.F_offset[i]) / lim)
                    role.append(STICK), owner.append(i), kappa.append(kap)
            else:
                s = self.modes[i]
                r = np.zeros(2 * D)
                r[D + i] = s / v_scale
                rows.append(r), offs.append(-s * self.V / v_scale), role.append(SLIP), owner.append(i), kappa.append(0)
        self.ev_map = np.array(rows).reshape(len(rows), 2 * D)
        self.ev_offset = np.array(offs, dtype=float)
        self.role, self.owner, self.kappa = role, np.array(owner, dtype=int), np.array(kappa, dtype=int)
        #: finder's ``kind``: 0 for rows whose touch ends the phase (gap, normal, slip), ±1 for stick rows
        self.kind = self.kappa.copy()


class ContactPhase:
    """The chain from one switch to the next, from the full state ``Z0`` (4n,) at its start."""

    def __init__(self, template: ContactTemplate, Z0):
        self.template = t = template
        self.spec, self.modes, self.step = t.spec, t.modes, t.step
        Z0 = np.asarray(Z0, dtype=float)
        D = t.D
        q0 = Z0[:D]
        held = np.flatnonzero(t.held)
        f = t.free
        # held coordinates: q_h = q_h(0) + rate·tau (a rigid contact's y is 0), q_h' = rate
        q_h0, r_h = np.where(held < t.n, q0[held], 0.0), t.rate[held]
        self.const0 = np.zeros(2 * D)
        self.const1 = np.zeros(2 * D)
        self.const0[held], self.const0[D + held], self.const1[held] = q_h0, r_h, r_h
        d = f.size
        b0, b1 = np.zeros(2 * d), np.zeros(2 * d)
        b0[d:] = (t.g_f - t.K_fh @ q_h0 - t.C_fh @ r_h) / t.m_f
        b1[d:] = -(t.K_fh @ r_h) / t.m_f
        self.b0, self.b1 = b0, b1
        z0 = np.concatenate([Z0[f], Z0[D + f]])
        aff = t.affine
        self.motion = self.taylor = self._rate = None
        if aff.exact:
            zf = aff.form(z0, b0, b1)
            self.motion = ModalForm(zf.lam, t.E @ zf.B if zf.B.size else np.zeros((2 * D, 0), complex),
                                    t.E @ zf.c0 + self.const0, t.E @ zf.c1 + self.const1)
        else:
            self.taylor = aff.taylor(z0, b0, b1)
        #: the longest time (s) a phase runs before it is restarted from its end state: the
        #: event screen's bound on g'''' holds while no mode grows more than 2x
        self.cap = math.log(2.0) / aff.growth if aff.exact and aff.growth > 0 else math.inf

    # -- the motion ---------------------------------------------------------
    def evaluate(self, tau):
        """Full state Z and its derivative Z' (each (4n, T)) at ``tau`` (s) after the phase start."""
        tau = np.atleast_1d(np.asarray(tau, dtype=float))
        if self.motion is not None:
            if self._rate is None:
                self._rate = self.motion.derivative()
            return self.motion.at(tau), self._rate.at(tau)
        t = self.template
        d = t.free.size
        z = self.taylor.at(tau)[: 2 * d]
        dz = t.affine.A @ z + self.b0[:, None] + np.multiply.outer(self.b1, tau)
        Z = t.E @ z + self.const0[:, None] + np.multiply.outer(self.const1, tau)
        dZ = t.E @ dz + self.const1[:, None]
        return Z, dZ

    def forces(self, Z):
        """(friction F, normal force N), each (n, T) in N, on the states Z (4n, T)."""
        t = self.template
        return t.F_map @ Z + t.F_offset[:, None], t.N_map @ Z + t.N_offset[:, None]

    def events(self):
        return ModalRows(self) if self.motion is not None else SampledRows(self)

    def sample(self, tau):
        """Z (4n, T), F and N (n, T) and the work integrals (3, T: belt, friction, dampers; J) at ``tau``."""
        tau = np.asarray(tau, dtype=float)
        Z, _ = self.evaluate(tau)
        F, N = self.forces(Z)
        return Z, F, N, self.work(tau)

    def power(self, nodes):
        """(3, T) belt power V·ΣF, friction loss ΣF·(V - v), damper loss q'ᵀC_s q' (W) at ``nodes``."""
        t, spec = self.template, self.spec
        Z, _ = self.evaluate(nodes)
        D, n = t.D, t.n
        F, _ = self.forces(Z)
        qd = Z[D:]
        V = t.V
        return np.vstack([V * F.sum(axis=0), (F * (V - qd[:n])).sum(axis=0),
                          np.einsum("it,ij,jt->t", qd, spec.damping_matrix, qd)])

    def work(self, taus):
        """(3, T) work integrals from the phase start to ``taus`` (s, increasing), by 10-point
        Gauss-Legendre quadrature of the closed form on pieces of at most 1/4 of the fastest
        period: the integrands are sums of exponentials and low-degree polynomials, whose
        quadrature error on such pieces is below 1e-19 of their scale."""
        marks = np.concatenate([[0.0], np.asarray(taus, dtype=float)])
        gaps = np.diff(marks)
        piece = PIECE_STEPS * self.step
        pieces = np.maximum(1, np.ceil(gaps / piece)).astype(int) if np.isfinite(piece) else np.ones(gaps.size, int)
        pieces[gaps <= 0] = 0
        if not pieces.sum():
            return np.zeros((3, gaps.size))
        widths = np.repeat(np.where(pieces > 0, gaps / np.maximum(pieces, 1), 0.0), pieces)
        within = np.arange(widths.size) - np.repeat(np.cumsum(pieces) - pieces, pieces)
        starts = np.repeat(marks[:-1], pieces) + within * widths
        nodes = (starts[:, None] + 0.5 * widths[:, None] * (_GL_X[None, :] + 1)).ravel()
        power = self.power(nodes)
        piece_int = (power.reshape(3, -1, _GL_X.size) @ _GL_W) * 0.5 * widths
        cum = np.column_stack([np.zeros(3), np.cumsum(piece_int, axis=1)])
        return cum[:, np.cumsum(pieces)]


class ModalRows(ModalEvents):
    """Event rows of a closed-form phase (the interface :func:`.phases.finder.find_event` reads; values
    and points as :class:`~.phases.events.ModalEvents`).

    ``mass`` holds *row* numbers, so that the finder's touching / contradicted lists name
    rows (a mass has up to three); ``bound4`` bounds |g''''| over the phase's run
    (``cap``): sum |b|·|lam|⁴·exp(max(Re lam, 0)·cap) <= 2·sum |b|·|lam|⁴ for growing modes.
    """

    def __init__(self, phase):
        t = phase.template
        self.kind = t.kind
        self.mass = np.arange(t.kind.size)
        self.g = phase.motion.compose(t.ev_map, t.ev_offset)
        lam = self.g.lam
        grow = np.exp(np.maximum(lam.real, 0.0) * phase.cap) if np.isfinite(phase.cap) else np.ones(lam.size)
        self.bound4 = np.abs(self.g.B) @ (np.abs(lam) ** 4 * grow) if lam.size else np.zeros(len(self))
        d = self.g.derivative()
        self._both = ModalForm(lam, np.vstack([self.g.B, d.B]), np.concatenate([self.g.c0, d.c0]),
                               np.concatenate([self.g.c1, d.c1]))
        self._points = {}  # row -> its closed form at one time (ModalEvents.point's cache)


class SampledRows:
    """Event rows of a phase propagated on its Taylor grid (no modal form): g = L·Z + o, g' = L·Z'."""

    bound4 = None
    pointwise = False  # (:attr:`~.phases.events.ModalEvents.pointwise`: dense products over many times)

    def __init__(self, phase):
        t = phase.template
        self.phase, self.kind, self.mass = phase, t.kind, np.arange(t.kind.size)
        self.L, self.o = t.ev_map, t.ev_offset

    def __len__(self):
        return self.kind.size

    def values(self, tau):
        Z, dZ = self.phase.evaluate(tau)
        return self.L @ Z + self.o[:, None], self.L @ dZ

    def point(self, r):
        def f(t):
            g, dg = self.values(np.array([t]))
            return float(g[r, 0]), float(dg[r, 0]), None

        return f
