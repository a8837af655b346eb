"""Closed-form motion of one segment of slipping masses between two switches.

A segment of L slipping masses (joined by springs or dampers, with stuck
neighbours or walls at its ends) obeys, with constant kinetic forces,

    M·x'' + C·x' + K·x = p + q·tau

(p, q in N and N/s: the kinetic friction plus stuck neighbours that move as
x_s0 + V·tau). The particular solution is x_p = alpha + beta·tau with
K·beta = q, K·alpha = p - C·beta; the rest is a sum of modes:

* undamped segments (C = 0): the symmetric tridiagonal problem
  M^-1/2·K·M^-1/2 = Q·diag(omega²)·Qᵀ gives mass-normalised shapes
  Phi = M^-1/2·Q and x = x_p + Phi·(a·cos(omega·tau) + b·sin(omega·tau)) with
  a = Phiᵀ·M·(x0 - alpha), b = Phiᵀ·M·(v0 - beta)/omega: O(L²) per switch, no
  inverse, no defective cases;
* damped segments: the eigendecomposition A = W·diag(lam)·W⁻¹ of
  A = [[0, I], [-M⁻¹K, -M⁻¹C]] and y = Re(W·(coef·exp(lam·tau))) + y_p.

Both are stored over the half spectrum (one eigenvalue of each conjugate
pair, weight 2) as the (2L, S) block of a :class:`~.phases.modal.ModalForm`. A
segment no spring anchors (singular K) or with a defective A has no such
form: the augmented system [y, tau, 1] is propagated by :class:`TaylorGrid`.
"""

from __future__ import annotations

from functools import cached_property

import numpy as np

from ..backend import watch
from .modal import cmatmul, damped


#: largest condition number of the eigenvector matrix of a damped segment solved in modal form:
#: the coefficients then carry at most ~2e-11 relative error
MAX_CONDITION = 1e5


class SegmentModes:
    """What a segment of masses lo..hi needs that does not depend on the state (cached per run).

    ``rate`` = max |lam| (1/s); ``lam`` the half spectrum; ``exact`` is False when K
    is singular or A defective (then only ``A`` is used).
    """

    def __init__(self, spec, lo: int, hi: int):
        L = self.L = hi - lo + 1
        m = self.m = spec.m[lo : hi + 1]
        k, c = self._k, self._c = spec.k[lo : hi + 2], spec.c[lo : hi + 2]
        k_diag, k_off = k[:-1] + k[1:], -k[1:-1]
        self.undamped = not np.count_nonzero(c)
        if self.undamped:
            root = np.sqrt(m)
            w2, Q = _symmetric_tridiagonal_eig(k_diag / m, k_off / (root[:-1] * root[1:]))
            self.rate = float(np.sqrt(max(w2[-1], 0.0)))
            self.exact = bool(w2[-1] > 0 and w2[0] > 1e-10 * w2[-1])
            if self.exact:
                self.omega = np.sqrt(w2)
                self.omega2 = self.omega**2
                self.Phi = Q / root[:, None]  # mass-normalised: Phiᵀ M Phi = I
                self.lam = 1j * self.omega
                self.shapes = np.concatenate((self.Phi, self.Phi * self.lam))  # (complex: promoted)
                self.damped = damped(self.lam)
            return
        lam, W = np.linalg.eig(self.A)
        self.rate = float(np.max(np.abs(lam)))
        self.exact = _well_posed(self.K, lam, W)
        if self.exact:
            self.W_inv = np.linalg.inv(W.astype(complex))
            self.K_inv = np.linalg.inv(self.K)
            # A is real: conjugate pairs have conjugate eigenvectors, so the real motion needs
            # one of each pair (weight 2) plus the real eigenvalues (weight 1)
            self.half = np.flatnonzero(lam.imag >= 0)
            self.half_weight = np.where(lam.imag[self.half] > 0, 2.0, 1.0)
            self.lam = lam[self.half].astype(complex)
            self.shapes = W[:, self.half].astype(complex)
            #: :func:`~.phases.modal.damped` of ``lam`` (exact segments)
            self.damped = damped(self.lam)

    @cached_property
    def K(self) -> np.ndarray:
        """Stiffness matrix (N/m) of the segment, built when used (an undamped anchored segment is
        solved from its symmetric eigenproblem without it)."""
        k = self._k
        return _tridiagonal(k[:-1] + k[1:], -k[1:-1])

    @cached_property
    def C(self) -> np.ndarray:
        """Damping matrix (N·s/m) of the segment, built when used."""
        c = self._c
        return _tridiagonal(c[:-1] + c[1:], -c[1:-1])

    @cached_property
    def A(self) -> np.ndarray:
        """[[0, I], [-M⁻¹K, -M⁻¹C]] (1/s², 1/s), built when used: damped, unanchored or defective
        segments (an undamped anchored one is solved from its symmetric eigenproblem)."""
        L, m = self.L, self.m
        A = np.zeros((2 * L, 2 * L))  # (np.block costs 10x more)
        A[:L, L:] = np.eye(L)
        A[L:, :L] = -self.K / m[:, None]
        A[L:, L:] = -self.C / m[:, None]
        return A

    def solve(self, y0, p, q):
        """(c0, c1, coef) of the motion from ``y0`` = [x0; v0] under forces p + q·tau (N, N/s).

        [x; v](tau) = Re(shapes·(coef·exp(lam·tau))) + c0 + c1·tau with c0 = [alpha; beta],
        c1 = [beta; 0] the particular solution and ``coef`` (S,) the modal amplitudes
        (complex; for the undamped case a - i·b).
        """
        L = self.L
        if self.undamped:
            Phi, omega = self.Phi, self.omega
            beta = Phi @ ((Phi.T @ q) / self.omega2)  # K⁻¹ = Phi·diag(1/omega²)·Phiᵀ
            alpha = Phi @ ((Phi.T @ p) / self.omega2)
            a = Phi.T @ (self.m * (y0[:L] - alpha))
            b = Phi.T @ (self.m * (y0[L:] - beta)) / omega
            coef = a - 1j * b
        else:
            beta = self.K_inv @ q
            alpha = self.K_inv @ (p - self.C @ beta)
            coef = (self.W_inv @ (y0 - np.concatenate([alpha, beta])))[self.half] * self.half_weight
        c1 = np.zeros(2 * L)
        c1[:L] = beta
        return np.concatenate([alpha, beta]), c1, coef


class Segment:
    """Motion of the slipping masses lo..hi from the phase start (tau = 0).

    ``p``, ``q`` (N, N/s): constant and ramp forces on each mass; ``y0`` = [x0; v0].
    """

    def __init__(self, modes: SegmentModes, lo: int, y0, p, q):
        self.modes, self.lo, self.L = modes, lo, modes.L
        if modes.exact:
            self.c0, self.c1, self.coef = modes.solve(y0, p, q)
            return
        L = self.L  # singular K or defective A: the augmented system [y, tau, 1]
        aug = np.zeros((2 * L + 2, 2 * L + 2))
        aug[: 2 * L, : 2 * L] = modes.A
        aug[L : 2 * L, 2 * L] = q / modes.m
        aug[L : 2 * L, 2 * L + 1] = p / modes.m
        aug[2 * L, 2 * L + 1] = 1.0
        self.taylor = TaylorGrid(aug, np.concatenate([y0, [0.0, 1.0]]))

    def evaluate(self, tau) -> np.ndarray:
        """State [x; v] (2L, T) at times ``tau`` (s)."""
        tau = np.asarray(tau, dtype=float)
        if self.modes.exact:
            growth = np.exp(np.multiply.outer(self.modes.lam, tau))
            return cmatmul(self.modes.shapes * self.coef, growth).real + self.c0[:, None] + np.multiply.outer(self.c1, tau)
        return self.taylor.at(tau)[: 2 * self.L]


class TaylorGrid:
    """exp(A·tau)·z0 for any tau >= 0, to rounding, for any A (defective or singular included).

    States on a grid of step h = 0.5/||A||_1 are propagated with P = exp(A·h), and any tau
    is reached from the grid point below it by the Taylor series of exp(A·s), s < h, to
    degree 16 (remainder below 0.5^17/17! = 2e-20): a few matrix products, vectorised over
    many times, where ``scipy.linalg.expm`` per time costs a scaling-and-squaring each.
    """

    DEGREE = 16

    def __init__(self, A, z0):
        self.A = A
        norm = float(np.max(np.abs(A).sum(axis=0)))
        self.h = 0.5 / norm if norm > 0 else np.inf
        eye = np.eye(A.shape[0])
        self.P = eye
        if norm > 0:
            for j in range(self.DEGREE, 0, -1):  # Horner: I + Ah(I + Ah/2(I + ...))
                self.P = eye + (self.h / j) * (A @ self.P)
        self.grid = np.asarray(z0, dtype=float)[:, None]
        self.filled = 1

    def at(self, tau) -> np.ndarray:
        """(d, T) states at times ``tau`` (s, >= 0)."""
        tau = np.atleast_1d(np.asarray(tau, dtype=float))
        if np.isinf(self.h):
            k, s = np.zeros(tau.size, dtype=int), tau
        else:
            k = np.floor(tau / self.h).astype(int)
            s = tau - k * self.h
        need = int(k.max(initial=0)) + 1
        if need > self.filled:
            if need > self.grid.shape[1]:  # grow geometrically: appending is amortised O(1)
                grown = np.empty((self.grid.shape[0], max(need, 2 * self.grid.shape[1])))
                grown[:, : self.filled] = self.grid[:, : self.filled]
                self.grid = grown
            for i in range(self.filled, need):
                self.grid[:, i] = self.P @ self.grid[:, i - 1]
                if not i % 4096:  # a stiff chain's grid step can be 1e-11 s: millions of steps
                    watch()
            self.filled = need
        base = self.grid[:, k]
        out = base
        for j in range(self.DEGREE, 0, -1):
            out = base + (s / j) * (self.A @ out)
        return out


def _symmetric_tridiagonal_eig(d, e):
    """Eigenvalues (ascending) and orthonormal eigenvectors of the symmetric tridiagonal (d, e).

    LAPACK's MRRR driver costs O(L²); below 64 masses the dense solver wins on call overhead.
    A single mass needs no solver: LAPACK returns its one entry and the eigenvector 1 too.
    """
    if d.size == 1:
        return d.copy(), np.ones((1, 1))
    if d.size <= 64:
        # the dense matrix np.diag(d) + np.diag(e, 1) + np.diag(e, -1), built in place: adding +0.0
        # turns a -0.0 into +0.0 as those sums do and leaves every other number as it is
        dense = _tridiagonal(d, e)
        dense += 0.0
        return np.linalg.eigh(dense)
    from scipy.linalg import eigh_tridiagonal  # lazily: keeps `import asperity2d.belt` free of SciPy

    return eigh_tridiagonal(d, e, lapack_driver="stemr")


def _tridiagonal(diagonal, off):
    """The symmetric (L, L) matrix with ``diagonal`` and ``off`` (L - 1) beside it, zeros elsewhere
    (what np.diag and two index assignments give, in fewer NumPy calls: built once per segment)."""
    L = diagonal.size
    out = np.zeros((L, L))
    out.flat[:: L + 1] = diagonal
    out.flat[1 :: L + 1] = off
    out.flat[L :: L + 1] = off
    return out


def _well_posed(K, lam, W) -> bool:
    """True when K is invertible and W well conditioned (cond(W) < ``MAX_CONDITION``).

    K (symmetric, positive semi-definite) is singular when no spring anchors the
    segment. The modal coefficients W⁻¹·y lose cond(W)·eps of relative accuracy, and
    cond(W) grows without bound near a defective A -- also for eigenvalues that are not
    close in absolute terms (a cluster 1e-4 wide gave cond(W) = 8e11) -- so it is computed,
    never guessed from eigenvalue gaps. Worse segments go to :class:`TaylorGrid`.
    """
    if np.linalg.eigvalsh(K)[0] <= 1e-10 * np.max(np.abs(K)):
        return False
    return bool(np.linalg.cond(W) < MAX_CONDITION)
