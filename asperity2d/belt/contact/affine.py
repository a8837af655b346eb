"""Closed form of a general linear phase z' = A·z + b0 + b1·tau (A real, not symmetric).

A chain with a normal degree of freedom and friction mu·N has, in a sliding phase,
a stiffness that is *not* symmetric (the friction on x_i follows N_i, which follows
y_i or x_i, but nothing acts back the same way): the symmetric modal solution of
:mod:`.phases.segment` does not apply. The first-order system is solved instead:

    z(tau) = exp(A·tau)·(z0 - alpha) + alpha + beta·tau,   A·beta = -b1,  A·alpha = beta - b0,

(substituting: z' = A·exp(A·tau)·(z0 - alpha) + beta and A·z + b0 + b1·tau = the same),
with exp(A·tau) = W·diag(exp(lam·tau))·W⁻¹ from the eigendecomposition of A. A is
real, so its complex eigenvalues come in conjugate pairs with conjugate
eigenvectors: the real motion needs one of each pair (weight 2) and the real
eigenvalues (weight 1), stored as a :class:`~.phases.modal.ModalForm` -- the form every
event function, force and power of a phase is composed from.

Where that form does not exist -- A singular (a free flight with no normal spring
is a parabola; a mass no spring holds drifts) or nearly defective (two eigenvalues
coalescing: the flutter onset itself, where cond(W) grows without bound) -- the
augmented system [z, tau, 1] is propagated by :class:`~.phases.segment.TaylorGrid`
(exp(A·h) on a grid, a degree-16 Taylor series in between: exact to rounding) and
the event functions are sampled from it.
"""

from __future__ import annotations

import numpy as np

from ..phases.modal import ModalForm
from ..phases.segment import MAX_CONDITION, TaylorGrid

#: |lambda| below this fraction of the largest counts as a zero eigenvalue (A singular)
SINGULAR = 1e-10


class AffineModes:
    """What the motion under ``A`` (d, d) needs that does not depend on the state (cached per phase pattern).

    ``lam`` (S,) the half spectrum, ``shapes`` (d, S) its eigenvectors, ``rate`` = max |lam| (1/s),
    ``growth`` = max Re lam (1/s); ``exact`` False when A is singular or ill-conditioned (then
    only ``A`` is used, through :class:`TaylorGrid`).
    """

    def __init__(self, A):
        self.A = A = np.asarray(A, dtype=float)
        d = self.d = A.shape[0]
        if d == 0:
            self.rate = self.growth = 0.0
            self.exact = True
            self.lam, self.shapes = np.zeros(0, complex), np.zeros((0, 0), complex)
            return
        lam, W = np.linalg.eig(A)
        self.rate = float(np.max(np.abs(lam)))
        self.growth = float(np.max(lam.real))
        self.exact = bool(np.min(np.abs(lam)) > SINGULAR * self.rate and np.linalg.cond(W) < MAX_CONDITION)
        if self.exact:
            self.W_inv = np.linalg.inv(W.astype(complex))
            self.half = np.flatnonzero(lam.imag >= 0)
            self.weight = np.where(lam.imag[self.half] > 0, 2.0, 1.0)
            self.lam = lam[self.half].astype(complex)
            self.shapes = W[:, self.half].astype(complex)

    def particular(self, b0, b1):
        """(alpha, beta) of the particular solution alpha + beta·tau (A invertible)."""
        beta = -np.linalg.solve(self.A, b1) if np.any(b1) else np.zeros(self.d)
        alpha = np.linalg.solve(self.A, beta - b0)
        return alpha, beta

    def form(self, z0, b0, b1) -> ModalForm:
        """The motion from ``z0`` under z' = A·z + b0 + b1·tau as a ModalForm (exact A only)."""
        if self.d == 0:
            return ModalForm(self.lam, np.zeros((0, 0), complex), np.zeros(0), np.zeros(0))
        alpha, beta = self.particular(b0, b1)
        coef = (self.W_inv @ (z0 - alpha))[self.half] * self.weight
        return ModalForm(self.lam, self.shapes * coef, alpha, beta)

    def taylor(self, z0, b0, b1) -> "BalancedTaylor":
        """The motion from ``z0`` as a Taylor grid on [z, tau, 1] (any A); its ``at`` returns (d + 2, T)."""
        d = self.d
        aug = np.zeros((d + 2, d + 2))
        aug[:d, :d] = self.A
        aug[:d, d] = b1
        aug[:d, d + 1] = b0
        aug[d, d + 1] = 1.0
        return BalancedTaylor(aug, np.concatenate([z0, [0.0, 1.0]]))


class BalancedTaylor:
    """:class:`TaylorGrid` of T⁻¹·aug·T, T the diagonal power-of-two balancing of ``aug`` (exact in
    floating point). A stiff second-order system has ||A||_1 ~ k/m while its rates are ~sqrt(k/m): the
    grid step 0.5/||A||_1 would be that much too fine; balanced, the norm is ~ the largest rate."""

    def __init__(self, aug, z0):
        from scipy.linalg import matrix_balance  # lazily: keeps `import asperity2d.belt` free of SciPy

        B, T = matrix_balance(aug, permute=False, separate=True)
        self.scale = T[0]
        self.grid = TaylorGrid(B, z0 / self.scale)

    def at(self, tau) -> np.ndarray:
        return self.grid.at(tau) * self.scale[:, None]
