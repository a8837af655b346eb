"""Energy flows of one phase, integrated from its start (J).

* belt work      W_b = ∫ Σ F_i·V dt         (power the belt delivers through the contacts)
* friction loss  D_f = ∫ Σ F_i·(V - v_i) dt  (>= 0; zero on stuck masses)
* damper loss    D_c = ∫ Σ c_j·(Δv_j)² dt   (Δv_j the extension rate of link j)

so that the stored energy E = Σ ½ m v² + Σ ½ k Δx² obeys E - E(0) = W_b - D_f - D_c.

Closed-form phases integrate exactly: with constant belt speed, the belt and
friction powers are linear in the state (kinetic forces are constant, stuck
masses have v = V and need F = -F_springs+dampers), so they are modal forms
whose integrals are closed form; the damper power is a sum of squares of modal
forms (:func:`~.phases.modal.square_integral`). The books then close to rounding while
the stored energy is computed separately from the sampled x and v -- an
independent check of the solution. Closed-form phases without a modal form
(unanchored or critically damped segments) use 10-point Gauss-Legendre
quadrature on pieces no longer than 1/4 of the fastest period (error below
1e-19 of the integrand's scale for the exponentials and low-degree polynomials
present); integrated phases carry the integrals as ODE states (:mod:`.chain.hybrid`).
"""

from __future__ import annotations

import numpy as np

from ..phases.modal import linear_map, square_integral
from ..spec import force_row

_GL_X, _GL_W = np.polynomial.legendre.leggauss(10)
#: quadrature pieces span at most this many scan steps (1/16 period each)
PIECE_STEPS = 4


def power_maps(spec, stuck, fric_slip, V):
    """(power map (2, 3n), its offset, link-rate map (n+1, 3n)) on the rows [x; v; a].

    Belt power V·Σ F_i: a stuck mass needs F_i = -F_sd,i, a slipping one has the
    constant ``fric_slip`` (N); friction power Σ F_i·(V - v_i) is zero on stuck masses.
    The link-rate map (for the damper loss) is None on a chain without dampers.
    """
    n = spec.n
    rows, cols, vals = [], [], []
    for i in stuck.nonzero()[0].tolist():
        cols_i, coefs_i = force_row(spec, i)
        rows += [0] * len(cols_i)
        cols += cols_i
        vals += [-V * c for c in coefs_i]
    slip = (~stuck).nonzero()[0]
    rows += [1] * slip.size
    cols += (n + slip).tolist()
    vals += (-fric_slip[slip]).tolist()
    fric = float(fric_slip[slip].sum())
    rates = None
    if spec.damped:
        j = np.arange(n)
        rates = linear_map((n + 1, 3 * n), (np.concatenate([j, j + 1]), np.concatenate([n + j, n + j]),
                                            np.concatenate([np.ones(n), -np.ones(n)])))
    return linear_map((2, 3 * n), (rows, cols, vals)), np.array([V * fric, V * fric]), rates


def modal_work(phase, taus, growth=None):
    """(3, T) work integrals of a closed-form phase at ``taus`` (s); ``growth``: the phase
    motion's :meth:`~.phases.modal.ModalForm.growth` at ``taus``, if at hand."""
    t = phase.template
    power = phase.form(t.power_shapes, t.power_map, t.power_offset)
    work = np.empty((3, np.size(taus)))
    work[:2] = power.integral(taus, growth)
    c = phase.spec.c
    if t.rate_map is not None:  # (a chain without dampers loses nothing in them)
        rates = phase.form(t.rate_shapes, t.rate_map, np.zeros(phase.spec.n + 1))
        work[2] = square_integral(rates, c, taus)
    else:
        work[2] = 0.0
    return work


def quadrature_work(phase, taus):
    """(3, T) work integrals at ``taus`` (s, increasing) by Gauss-Legendre quadrature."""
    spec = phase.spec
    marks = np.concatenate([[0.0], taus])
    gaps = np.diff(marks)
    piece = PIECE_STEPS * phase.step
    pieces = np.maximum(1, np.ceil(gaps / piece)).astype(int) if np.isfinite(piece) else np.ones(gaps.size, int)
    pieces[gaps <= 0] = 0
    widths = np.repeat(np.where(pieces > 0, gaps / np.maximum(pieces, 1), 0.0), pieces)
    within = np.arange(widths.size) - np.repeat(np.cumsum(pieces) - pieces, pieces)  # piece index inside its gap
    starts = np.repeat(marks[:-1], pieces) + within * widths
    nodes = (starts[:, None] + 0.5 * widths[:, None] * (_GL_X[None, :] + 1)).ravel()
    x, v, a = phase.evaluate(nodes)
    V = phase.belt_velocity(nodes)
    fric = phase.friction_force(x, v, a, nodes)
    dv = np.diff(v, axis=0, prepend=0.0, append=0.0)
    power = np.vstack([V * fric.sum(axis=0), ((V[None, :] - v) * fric).sum(axis=0), spec.c @ dv**2])
    piece_int = (power.reshape(3, -1, _GL_X.size) @ _GL_W) * 0.5 * widths
    cum = np.column_stack([np.zeros(3), np.cumsum(piece_int, axis=1)])
    return cum[:, np.cumsum(pieces)]
