"""Sums of exponentials: the closed form of everything a phase of the exact solver follows.

Between two switches every quantity of a chain at constant belt speed --
positions, velocities, accelerations, event functions, powers -- is a
:class:`ModalForm`

    r(tau) = Re(B · exp(lam·tau)) + c0 + c1·tau

with ``lam`` the modes of the slipping segments (:mod:`.phases.segment`). Linear maps
and time derivatives of a ModalForm are ModalForms, integrals and integrals of
squares are closed form: event functions and their derivatives come exactly,
and many times are evaluated with one ``exp``/``cos``/``sin`` and two real
matrix products. Long chains store ``B`` as a sparse matrix (block structure:
each row touches one or two segments).
"""

from __future__ import annotations

import numpy as np

#: above this many exponentials, forms are stored as sparse matrices (cost ~ non-zeros, not R·S)
SPARSE_ABOVE = 64
#: linear maps wider than this many state rows are stored as sparse matrices
DENSE_MAP_WIDTH = 48


class ModalForm:
    """Rows ``r(tau) = Re(B @ exp(lam * tau)) + c0 + c1 * tau`` (``B`` complex, dense or scipy CSR).

    ``lam`` holds one eigenvalue of each complex-conjugate pair (Im >= 0) with the
    pair's weight 2 folded into ``B``: real outputs need only half the exponentials,
    evaluated in real arithmetic (``exp``, ``cos``, ``sin`` and two real matrix products,
    which NumPy does far faster than one complex product).
    """

    __slots__ = ("lam", "B", "Br", "Bi", "c0", "c1", "damped", "_offset")

    def __init__(self, lam, B, c0, c1, damped=None):
        """``damped``: :func:`damped` of ``lam`` (found from ``lam`` when None; the solvers pass
        it from the mode pattern, which knows it once for all its phases)."""
        self.lam, self.B, self.c0, self.c1 = lam, B, c0, c1
        self.Br, self.Bi = B.real, B.imag
        self.damped = damped
        self._offset = None  # (see :meth:`at`)

    def growth(self, tau):
        """(Re, Im) of exp(lam·tau), each (S, T), at times ``tau`` (s, (T,)), and the angles Im lam·tau.

        (Outer products here and below are broadcast products, the same numbers as
        ``np.multiply.outer`` without its Python-level cost: these run several times a phase.)
        """
        angle = self.lam.imag[:, None] * tau
        cos, sin = np.cos(angle), np.sin(angle)
        if self.damped is None:
            self.damped = damped(self.lam)
        if self.damped:
            amp = np.exp(self.lam.real[:, None] * tau)
            cos *= amp
            sin *= amp
        return cos, sin, angle

    def at(self, tau, growth=None) -> np.ndarray:
        """Values (R, T) at times ``tau`` (s, (T,), >= 0 as every time from a phase start);
        ``growth`` reuses :meth:`growth` of the same times."""
        cos, sin, _ = self.growth(tau) if growth is None else growth
        # in place, in the order of Br@cos - Bi@sin + c0 + c1·tau (the same rounding): a long scan
        # evaluates thousands of times at once, and each fresh (R, T) temporary costs page faults
        out = self.Br @ cos
        out -= self.Bi @ sin
        if self._offset is None:
            # rows without a ramp (every c1 a signed zero: an all-slipping phase): c1·tau is c1
            # itself for tau >= +0, and (y + c0) + z = y + (c0 + z) for a signed zero z, so one
            # addition of c0 + c1 gives the same numbers
            self._offset = False if np.count_nonzero(self.c1) else (self.c0 + self.c1)[:, None]
        if self._offset is False:
            out += self.c0[:, None]
            out += self.c1[:, None] * tau
        else:
            out += self._offset
        return out

    def integral(self, tau, growth=None) -> np.ndarray:
        """Integrals from 0 to ``tau`` (R, T) in closed form (every lam non-zero).

        (exp(lam·tau) - 1)/lam is formed from expm1 and 2·sin²(omega·tau/2), never as a
        difference of nearly equal numbers: short phases keep their relative accuracy.
        ``growth``: :meth:`growth` of the same times by a form with the same ``lam`` (its
        angles, and its sin, exp(Re lam·tau)·sin(Im lam·tau) = Im exp(lam·tau): the same
        numbers, not evaluated again).
        """
        tau = np.asarray(tau, dtype=float)
        w = self.lam.imag[:, None] * tau if growth is None else growth[2]
        # in place, in the order of the formulas in the comments (the same rounding)
        half = np.sin(0.5 * w)
        np.square(half, out=half)
        half *= 2.0
        if self.damped is None:
            self.damped = damped(self.lam)
        if self.damped:
            a = self.lam.real[:, None] * tau
            re = np.expm1(a)  # Re(exp(lam tau) - 1) = expm1(a)·cos(w) - 2·sin²(w/2)
            re *= np.cos(w)
            re -= half
            if growth is None:
                im = np.exp(a)  # Im(exp(lam tau)) = exp(a)·sin(w) (growth's sin: sin(w)·exp(a), the same product)
                im *= np.sin(w)
        else:
            # Re lam = +0: a = +0·tau = +0 (tau >= 0), expm1(a)·cos(w) = ±0 and exp(a) = 1, so the
            # same numbers are 0.0 - 2·sin²(w/2) (±0 - x = -x for x > 0; x = 0 only at w = 0,
            # where cos = 1 and both give +0) and sin(w): no cos, exp or expm1 to evaluate
            re = np.subtract(0.0, half, out=half)
            if growth is None:
                im = np.sin(w)  # (growth's sin: sin(w) itself, undamped)
        if growth is not None:
            im = growth[1]
        Bl = scale_columns(self.B, 1.0 / self.lam)
        out = Bl.real @ re  # Bl.real @ re - Bl.imag @ im + c0·tau + c1·tau²/2
        out -= Bl.imag @ im
        out += self.c0[:, None] * tau
        half_c1 = 0.5 * self.c1
        if np.count_nonzero(half_c1):  # (cheaper than .any() on a few rows)
            out += half_c1[:, None] * np.square(tau)
        else:  # signed zeros times tau² >= +0: themselves (no (R, T) product to form)
            out += half_c1[:, None]
        return out

    def derivative(self) -> "ModalForm":
        """d/dtau of every row."""
        return ModalForm(self.lam, scale_columns(self.B, self.lam), self.c1, np.zeros_like(self.c1))

    def compose(self, L, offset) -> "ModalForm":
        """The rows ``L @ r(tau) + offset`` (L real, dense or sparse like ``B``)."""
        B = L @ self.Br + 1j * (L @ self.Bi) if isinstance(self.B, np.ndarray) else L @ self.B
        return ModalForm(self.lam, B, L @ self.c0 + offset, L @ self.c1)

    def scalar(self, r: int) -> tuple:
        """(lam, b, c0, c1) of row ``r`` with only its non-zero exponentials, for root finding."""
        if isinstance(self.B, np.ndarray):
            b = self.B[r]
            keep = b != 0
            if np.count_nonzero(keep) == keep.size:  # every exponential present: the same numbers, uncopied
                return self.lam, b, float(self.c0[r]), float(self.c1[r])
            return self.lam[keep], b[keep], float(self.c0[r]), float(self.c1[r])
        lo, hi = self.B.indptr[r], self.B.indptr[r + 1]  # CSR row r, without fancy indexing
        return self.lam[self.B.indices[lo:hi]], self.B.data[lo:hi], float(self.c0[r]), float(self.c1[r])


def damped(lam) -> bool:
    """False only when every ``lam`` has real part +0.0 exactly (so that exp(lam·tau) = cos + i·sin
    with no rounding of its own): a -0.0 counts as damped, which costs time, never bits."""
    real = np.asarray(lam).real
    return bool(np.count_nonzero(real) or np.count_nonzero(np.signbit(real)))


def scale_columns(B, w):
    """B·diag(w) for dense or sparse B."""
    return B * w if isinstance(B, np.ndarray) else B @ _sparse().diags_array(w)


def square_integral(form: ModalForm, weights, tau) -> np.ndarray:
    """∫_0^tau Σ_j w_j·r_j(s)² ds (T,) in closed form, for rows without a ramp (c1 = 0).

    With r_j = Re(z_j) + e_j, z_j = d_j·exp(lam·s): Re(z)² = ½Re(z²) + ½|z|², so the
    integral is a sum over pairs of exponentials exp((lam_a + lam_b)s) and
    exp((lam_a + conj lam_b)s), each integrated by :func:`phi`.
    """
    tau = np.asarray(tau, dtype=float)
    w = np.asarray(weights, dtype=float)
    d, e = form.B, form.c0
    dw = _scale_rows(d, w)
    out = float(w @ e**2) * tau
    lin = (e * w) @ d if isinstance(d, np.ndarray) else np.asarray(d.T @ (e * w)).ravel()
    out += 2 * (phi(np.multiply.outer(form.lam, tau)) * np.multiply.outer(lin, tau)).real.sum(axis=0)
    for other, conj in ((d, False), (d.conj(), True)):
        Q = cmatmul(dw.T, other) if isinstance(d, np.ndarray) else (dw.T @ other).tocoo()
        a, b, q = (np.nonzero(Q) + (Q[np.nonzero(Q)],)) if isinstance(Q, np.ndarray) else (Q.row, Q.col, Q.data)
        lam_b = form.lam[b].conj() if conj else form.lam[b]
        mu = form.lam[a] + lam_b
        out += 0.5 * (q[:, None] * phi(np.multiply.outer(mu, tau)) * tau[None, :]).real.sum(axis=0)
    return out


def cmatmul(a, b):
    """Dense complex matrix product through real products (NumPy's complex matmul is far slower)."""
    return a.real @ b.real - a.imag @ b.imag + 1j * (a.real @ b.imag + a.imag @ b.real)


def _scale_rows(B, w):
    return B * w[:, None] if isinstance(B, np.ndarray) else _sparse().diags_array(w) @ B


def phi(z):
    """(exp(z) - 1)/z elementwise, accurate near z = 0 (series for |z| < 0.5, 1 at 0)."""
    z = np.asarray(z, dtype=complex)
    small = np.abs(z) < 0.5
    out = np.empty_like(z)
    zs = z[small]
    term, acc = np.ones_like(zs), np.ones_like(zs)
    for k in range(2, 20):  # |z|^17/18! < 1e-20 for |z| < 0.5
        term = term * zs / k
        acc = acc + term
    out[small] = acc
    big = z[~small]
    out[~small] = (np.exp(big) - 1.0) / big
    return out


def block_matrix(blocks, shape):
    """Dense or CSR complex matrix of ``shape`` from (rows, cols, values) blocks.

    ``rows`` and ``cols`` of each block are runs of consecutive indices (``range(lo, lo + L)``).
    """
    if shape[1] <= SPARSE_ABOVE:
        out = np.zeros(shape, dtype=complex)
        for rows, cols, values in blocks:  # slices: consecutive indices (np.ix_ costs 5x more)
            out[rows[0] : rows[-1] + 1, cols[0] : cols[-1] + 1] = values
        return out
    sp = _sparse()
    if not blocks:
        return sp.csr_array(shape, dtype=complex)
    r = np.concatenate([np.repeat(rows, len(cols)) for rows, cols, _ in blocks])
    c = np.concatenate([np.tile(cols, len(rows)) for rows, cols, _ in blocks])
    v = np.concatenate([np.ravel(values) for _, _, values in blocks])
    return sp.csr_array((v, (r, c)), shape=shape)


def linear_map(shape, entries):
    """A real (R, C) matrix from (row, col, value) triples (duplicates add up).

    CSR beyond ``DENSE_MAP_WIDTH`` columns: the maps of a phase (event functions,
    powers) have a handful of non-zeros per row, so a dense product would cost R·C·S.
    """
    if shape[1] <= DENSE_MAP_WIDTH:
        out = np.zeros(shape)
        if len(entries[2]) <= 64:  # a few entries: in Python, summed in order from 0.0 as np.add.at does
            total: dict = {}
            for i, j, value in zip(*entries):
                key = (int(i), int(j))
                total[key] = total.get(key, 0.0) + float(value)
            for key, value in total.items():
                out[key] = value
            return out
        np.add.at(out, tuple(np.asarray(a).astype(int) for a in entries[:2]), np.asarray(entries[2]))
        return out
    r, c, v = (np.asarray(a) for a in entries)
    return _sparse().csr_array((v.astype(float), (r.astype(int), c.astype(int))), shape=shape)


def stack_rows(a, b):
    """The rows of ``a`` then ``b`` (both dense or both sparse)."""
    return np.concatenate((a, b)) if isinstance(a, np.ndarray) else _sparse().vstack([a, b], format="csr")


def _sparse():
    import scipy.sparse  # lazily: only long chains need it, and start-up stays light

    return scipy.sparse
