"""Closed-form motion of a chain between two switching events (constant belt speed).

Between events every mass is either stuck (x = x_s0 + V·tau, v = V exactly)
or slipping under a constant kinetic force. The slipping masses split into
independent *segments* -- maximal runs joined by a spring or damper -- since
a stuck mass acts on its neighbours as a wall moving at V. Each segment obeys

    y' = A·y + p + q·tau,   y = [x; v],   A = [[0, I], [-M⁻¹K, -M⁻¹C]]

whose exact solution is the matrix exponential: with the particular solution
x_p = alpha + beta·tau (K·beta = M·q, K·alpha = M·p - C·beta, with
M·p, M·q the constant and ramp forces) and
A = W·diag(lam)·W⁻¹, y(tau) = Re(W·(c·exp(lam·tau))) + y_p(tau). When K is
singular or A is defective, the augmented system [y, tau, 1] is propagated
with ``scipy.linalg.expm`` instead. Cost: O(L³) to set up a segment of L
masses, O(L²) per evaluation time.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

from .spec import link_force


class Modal:
    """What a segment of masses lo..hi needs that does not depend on the state: A, K, C, eig(A).

    Cached per (lo, hi) by :class:`LinearPhase` so that an event costs O(L²), not O(L³).
    """

    def __init__(self, spec, lo, hi):
        m = spec.m[lo : hi + 1]
        k, c = spec.k, spec.c
        L = hi - lo + 1
        K = np.diag(k[lo : hi + 1] + k[lo + 1 : hi + 2])
        C = np.diag(c[lo : hi + 1] + c[lo + 1 : hi + 2])
        off = np.arange(L - 1)
        K[off, off + 1] = K[off + 1, off] = -k[lo + 1 : hi + 1]
        C[off, off + 1] = C[off + 1, off] = -c[lo + 1 : hi + 1]
        minv = 1.0 / m
        A = np.zeros((2 * L, 2 * L))
        A[:L, L:] = np.eye(L)
        A[L:, :L] = -minv[:, None] * K
        A[L:, L:] = -minv[:, None] * C
        self.L, self.m, self.K, self.C, self.A = L, m, K, C, A
        lam, W = np.linalg.eig(A)
        self.rate = float(np.max(np.abs(lam)))
        self.exact = _well_posed(K, lam, W)
        if self.exact:
            self.lam, self.W = lam, W
            self.K_lu = sla.lu_factor(K)
            self.W_lu = sla.lu_factor(W)


class Segment:
    """Exact trajectory of slipping masses lo..hi, time measured from the phase start."""

    def __init__(self, modal, lo, hi, spec, x0, v0, fric, left, right, V):
        self.idx = np.arange(lo, hi + 1)
        self.L = L = modal.L
        k, c = spec.k, spec.c
        # forcing from the neighbours: stuck masses move as x_s0 + V·tau, walls stay at 0
        p = np.array(fric, dtype=float)
        q = np.zeros(L)
        if left is not None:
            p[0] += k[lo] * left + c[lo] * V
            q[0] += k[lo] * V
        if right is not None:
            p[-1] += k[hi + 1] * right + c[hi + 1] * V
            q[-1] += k[hi + 1] * V
        y0 = np.concatenate([x0, v0])
        self.rate = modal.rate
        self.exact = modal.exact
        if not modal.exact:
            # singular K or defective A: propagate the augmented system [y, tau, 1] with expm
            aug = np.zeros((2 * L + 2, 2 * L + 2))
            aug[: 2 * L, : 2 * L] = modal.A
            aug[L : 2 * L, 2 * L] = q / modal.m
            aug[L : 2 * L, 2 * L + 1] = p / modal.m
            aug[2 * L, 2 * L + 1] = 1.0
            self.aug = aug
            self.z0 = np.concatenate([y0, [0.0, 1.0]])
            return
        # p, q are forces (N, N/s): K·beta = q, K·alpha = p - C·beta
        beta = sla.lu_solve(modal.K_lu, q)
        alpha = sla.lu_solve(modal.K_lu, p - modal.C @ beta)
        self.alpha = np.concatenate([alpha, beta])
        self.beta = np.concatenate([beta, np.zeros(L)])
        self.lam, self.W = modal.lam, modal.W
        self.coef = sla.lu_solve(modal.W_lu, (y0 - self.alpha).astype(complex))

    def evaluate(self, tau: np.ndarray) -> np.ndarray:
        """State y = [x; v] (2L, len(tau)) at times ``tau`` (s) after the phase start."""
        tau = np.atleast_1d(np.asarray(tau, dtype=float))
        if not self.exact:
            return np.column_stack([(sla.expm(self.aug * s) @ self.z0)[: 2 * self.L] for s in tau])
        growth = np.exp(np.outer(self.lam, tau)) * self.coef[:, None]
        return (self.W @ growth).real + self.alpha[:, None] + self.beta[:, None] * tau[None, :]


class LinearPhase:
    """The whole chain between two events: stuck masses ride the belt, segments move exactly."""

    def __init__(self, spec, modes, x0, v0, V, cache=None):
        self.spec = spec
        cache = {} if cache is None else cache
        self.modes = np.asarray(modes)
        self.x0 = np.asarray(x0, dtype=float)
        self.v0 = np.asarray(v0, dtype=float)
        self.V = float(V)
        n = spec.n
        stuck = self.modes == 0
        self.stuck = stuck
        # kinetic force on each slipping mass: opposes the relative velocity
        self.fric_slip = -self.modes * spec.law.kinetic_coefficient * spec.normal
        link = (spec.k[1:n] != 0) | (spec.c[1:n] != 0)
        self.segments = []
        i = 0
        while i < n:
            if stuck[i]:
                i += 1
                continue
            j = i
            while j + 1 < n and not stuck[j + 1] and link[j]:
                j += 1
            # a neighbour outside the segment is stuck (moves with the belt) or unlinked (its
            # link coefficients are zero, so its value does not matter); walls are None
            left = self.x0[i - 1] if i > 0 else None
            right = self.x0[j + 1] if j + 1 < n else None
            modal = cache.get((i, j))
            if modal is None:
                modal = cache[(i, j)] = Modal(spec, i, j)
                if len(cache) > 512:  # bounded memory on long chains
                    cache.pop(next(iter(cache)))
            sl = slice(i, j + 1)
            self.segments.append(
                Segment(modal, i, j, spec, self.x0[sl], self.v0[sl], self.fric_slip[sl], left, right, self.V)
            )
            i = j + 1
        rate = max([s.rate for s in self.segments], default=0.0)
        #: scan step (s): 1/16 of the fastest period, or the whole horizon for all-stuck chains
        self.step = 0.4 / rate if rate > 0 else np.inf

    def evaluate(self, tau, masses=None):
        """Positions, velocities, accelerations (each (n, len(tau))) at ``tau`` (s) after the phase start.

        With ``masses`` (indices), only the segments holding them are computed: rows of other
        slipping masses are then meaningless (used by the root finder, which reads one row).
        """
        tau = np.atleast_1d(np.asarray(tau, dtype=float))
        n = self.spec.n
        x = self.x0[:, None] + self.V * tau[None, :] * np.ones((n, 1))
        v = np.full((n, tau.size), self.V)
        for seg in self.segments:
            if masses is not None and not np.any((masses >= seg.idx[0]) & (masses <= seg.idx[-1])):
                continue
            y = seg.evaluate(tau)
            x[seg.idx] = y[: seg.L]
            v[seg.idx] = y[seg.L :]
        a = self.acceleration(x, v)
        return x, v, a

    def belt_velocity(self, tau):
        return np.full(np.size(tau), self.V)

    def belt_acceleration(self, tau):
        return np.zeros(np.size(tau))

    def friction_force(self, x, v, a, tau):
        """Friction force on each mass (N): kinetic while slipping, the required static force while stuck."""
        f = np.repeat(self.fric_slip[:, None], np.size(tau), axis=1)
        f[self.stuck] = -self.spring_damper_force(x, v)[self.stuck]
        return f

    def spring_damper_force(self, x, v):
        return link_force(self.spec.k, x) + link_force(self.spec.c, v)

    def acceleration(self, x, v):
        a = (self.spring_damper_force(x, v) + self.fric_slip[:, None]) / self.spec.m[:, None]
        a[self.stuck] = 0.0
        return a


def _well_posed(K, lam, W) -> bool:
    """True when K is invertible and eig(A) is safely diagonalisable (cheap checks first).

    K (symmetric, positive semi-definite) is singular when the segment is anchored by no
    spring; A is defective only when eigenvalues coincide, so well-separated eigenvalues
    skip the O(L³) condition number of W.
    """
    w_min = sla.eigvalsh_tridiagonal(np.diag(K).copy(), np.diag(K, 1).copy(), select="i", select_range=(0, 0))[0] \
        if K.shape[0] > 1 else K[0, 0]
    if w_min <= 1e-10 * np.max(np.abs(K)):
        return False
    scale = np.max(np.abs(lam))
    gaps = np.abs(lam[:, None] - lam[None, :]) + np.eye(lam.size) * scale
    if gaps.min() > 1e-6 * scale:
        return True
    return np.linalg.cond(W) < 1e8
