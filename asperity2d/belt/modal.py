"""Sums of exponentials: the closed form of a linear chain segment between two switches.

A segment of L slipping masses with constant kinetic forces obeys

    y' = A·y + p/m + q/m·tau,   y = [x; v],   A = [[0, I], [-M⁻¹K, -M⁻¹C]]

(p, q the constant and ramp forces from the kinetic friction and from stuck
neighbours that ride the belt). With A = W·diag(lam)·W⁻¹ and the particular
solution x_p = alpha + beta·tau (K·beta = q, K·alpha = p - C·beta),

    y(tau) = Re(W · (coef · exp(lam·tau))) + [alpha; beta] + [beta; 0]·tau.

Every quantity the exact solver follows through a phase -- positions,
velocities, accelerations, event functions -- is therefore a
:class:`ModalForm`, ``Re(B·exp(lam·tau)) + c0 + c1·tau``, and linear maps and
time derivatives of a ModalForm are ModalForms: event functions and their
derivatives come in closed form, evaluated on many times with one ``exp`` and
one matrix product. Segments whose K is singular (no spring anchors them) or
whose A is defective have no such form; :class:`Segment` then propagates the
augmented system [y, tau, 1] with ``scipy.linalg.expm``.
"""

from __future__ import annotations

import numpy as np

#: above this many exponentials, forms are stored as sparse matrices (cost ~ non-zeros, not R·S)
SPARSE_ABOVE = 64


class ModalForm:
    """Rows ``r(tau) = Re(B @ exp(lam * tau)) + c0 + c1 * tau``; ``B`` dense or scipy CSR."""

    __slots__ = ("lam", "B", "c0", "c1")

    def __init__(self, lam, B, c0, c1):
        self.lam, self.B, self.c0, self.c1 = lam, B, c0, c1

    def at(self, tau) -> np.ndarray:
        """Values (R, T) at times ``tau`` (s, (T,))."""
        growth = np.exp(np.multiply.outer(self.lam, tau))
        return (self.B @ growth).real + self.c0[:, None] + np.multiply.outer(self.c1, tau)

    def derivative(self) -> "ModalForm":
        """d/dtau of every row."""
        if isinstance(self.B, np.ndarray):
            B = self.B * self.lam
        else:
            B = self.B @ _sparse().diags_array(self.lam)
        return ModalForm(self.lam, B, self.c1, np.zeros_like(self.c1))

    def compose(self, L, offset) -> "ModalForm":
        """The rows ``L @ r(tau) + offset`` (L dense or sparse, matching ``B``)."""
        return ModalForm(self.lam, L @ self.B, L @ self.c0 + offset, L @ self.c1)

    def scalar(self, r: int) -> tuple:
        """(lam, b, c0, c1) of row ``r`` with only its non-zero exponentials, for root finding."""
        if isinstance(self.B, np.ndarray):
            b = self.B[r]
            keep = b != 0
            return self.lam[keep], b[keep], float(self.c0[r]), float(self.c1[r])
        row = self.B[[r]].tocoo()
        return self.lam[row.col], row.data, float(self.c0[r]), float(self.c1[r])


def block_matrix(blocks, shape):
    """Dense or CSR complex matrix of ``shape`` from (rows, cols, values) blocks."""
    if shape[1] <= SPARSE_ABOVE:
        out = np.zeros(shape, dtype=complex)
        for rows, cols, values in blocks:
            out[np.ix_(rows, cols)] = values
        return out
    sp = _sparse()
    if not blocks:
        return sp.csr_array(shape, dtype=complex)
    r = np.concatenate([np.repeat(rows, len(cols)) for rows, cols, _ in blocks])
    c = np.concatenate([np.tile(cols, len(rows)) for rows, cols, _ in blocks])
    v = np.concatenate([np.ravel(values) for _, _, values in blocks])
    return sp.csr_array((v, (r, c)), shape=shape)


def linear_map(shape, sparse, entries):
    """A real (R, C) matrix, dense or CSR, from (row, col, value) triples (duplicates add up)."""
    r, c, v = (np.asarray(a) for a in entries)
    if not sparse:
        out = np.zeros(shape)
        np.add.at(out, (r.astype(int), c.astype(int)), v)
        return out
    return _sparse().csr_array((v.astype(float), (r.astype(int), c.astype(int))), shape=shape)


def _sparse():
    import scipy.sparse  # lazily: only long chains need it, and start-up stays light

    return scipy.sparse


class SegmentModes:
    """What a segment of masses lo..hi needs that does not depend on the state (cached per run).

    ``K``, ``C`` (N/m, N·s/m) restricted to the segment; ``lam``, ``W``, ``W_inv``
    the eigendecomposition of A; ``K_inv``; ``rate`` = max |lam| (1/s);
    ``exact`` is False when K is singular or A defective (then only ``A`` is used).
    """

    def __init__(self, spec, lo: int, hi: int):
        L = hi - lo + 1
        m = spec.m[lo : hi + 1]
        k, c = spec.k, spec.c
        off = np.arange(L - 1)
        K = np.diag(k[lo : hi + 1] + k[lo + 1 : hi + 2])
        C = np.diag(c[lo : hi + 1] + c[lo + 1 : hi + 2])
        K[off, off + 1] = K[off + 1, off] = -k[lo + 1 : hi + 1]
        C[off, off + 1] = C[off + 1, off] = -c[lo + 1 : hi + 1]
        A = np.zeros((2 * L, 2 * L))
        A[:L, L:] = np.eye(L)
        A[L:, :L] = -K / m[:, None]
        A[L:, L:] = -C / m[:, None]
        self.L, self.m, self.K, self.C, self.A = L, m, K, C, A
        lam, W = np.linalg.eig(A)
        self.rate = float(np.max(np.abs(lam)))
        self.exact = _well_posed(K, lam, W)
        if self.exact:
            self.lam, self.W = lam.astype(complex), W.astype(complex)
            self.W_inv = np.linalg.inv(self.W)
            self.K_inv = np.linalg.inv(K)


class Segment:
    """Motion of the slipping masses lo..hi from the phase start (tau = 0).

    ``p``, ``q`` (N, N/s): constant and ramp forces on each mass (kinetic
    friction plus stuck neighbours moving as x_s0 + V·tau); ``y0`` = [x0; v0].
    """

    def __init__(self, modes: SegmentModes, lo: int, y0, p, q):
        self.modes, self.lo, self.L = modes, lo, modes.L
        if modes.exact:
            beta = modes.K_inv @ q
            alpha = modes.K_inv @ (p - modes.C @ beta)
            self.c0 = np.concatenate([alpha, beta])
            self.c1 = np.concatenate([beta, np.zeros(self.L)])
            self.coef = modes.W_inv @ (y0 - self.c0)
            return
        L = self.L  # singular K or defective A: the augmented system [y, tau, 1]
        aug = np.zeros((2 * L + 2, 2 * L + 2))
        aug[: 2 * L, : 2 * L] = modes.A
        aug[L : 2 * L, 2 * L] = q / modes.m
        aug[L : 2 * L, 2 * L + 1] = p / modes.m
        aug[2 * L, 2 * L + 1] = 1.0
        self.aug, self.z0 = aug, np.concatenate([y0, [0.0, 1.0]])

    def block(self, n: int, col: int):
        """(rows, cols, values) of this segment in a phase's state form of 2n rows."""
        idx = self.lo + np.arange(self.L)
        rows = np.concatenate([idx, n + idx])
        return rows, col + np.arange(2 * self.L), self.modes.W * self.coef

    def evaluate(self, tau) -> np.ndarray:
        """State [x; v] (2L, T) at times ``tau`` (s)."""
        if self.modes.exact:
            growth = np.exp(np.multiply.outer(self.modes.lam, tau)) * self.coef[:, None]
            return (self.modes.W @ growth).real + self.c0[:, None] + np.multiply.outer(self.c1, tau)
        from scipy.linalg import expm  # lazily: rare (unanchored or critically damped segments)

        props = expm(self.aug[None] * np.asarray(tau, dtype=float)[:, None, None])
        return (props @ self.z0)[:, : 2 * self.L].T


def _well_posed(K, lam, W) -> bool:
    """True when K is invertible and A safely diagonalisable (cheap checks first).

    K (symmetric, positive semi-definite) is singular when no spring anchors the
    segment; A is defective only where eigenvalues coincide, so well-separated
    eigenvalues skip the condition number of W.
    """
    if np.linalg.eigvalsh(K)[0] <= 1e-10 * np.max(np.abs(K)):
        return False
    scale = np.max(np.abs(lam))
    gaps = np.abs(lam[:, None] - lam[None, :]) + np.eye(lam.size) * scale
    return bool(gaps.min() > 1e-6 * scale or np.linalg.cond(W) < 1e8)
