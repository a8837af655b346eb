"""Chains with a normal degree of freedom: the linearisation about steady sliding.

``simulate_chain(..., normal=NormalContact(...))`` builds a :class:`~.normal.ContactSpec`
(:func:`~.normal.contact_spec`) and runs the back end ``METHODS["exact"]`` lists for it,
:func:`~.contact.loop.run_contact`, into a :class:`~.contact.result.ContactResult`.

:func:`steady_sliding` linearises a chain about steady sliding -- every mass in
contact, slipping against the belt (s_i = -sign V), at rest -- with the *solver's
own* phase matrix for that mode pattern: its equilibrium solves A·z* + b0 = 0 and
its eigenvalues are those of A. With mu·N coupling A is not symmetric: a pair of
eigenvalues can leave the imaginary axis (flutter, the mode-coupling
instability) where the undamped symmetric problem never could. For the one-mass
minimal model the closed forms are in :mod:`.contact.minimal`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...errors import SceneError
from .phase import ContactTemplate
from ..spec import contact_spec

__all__ = ["SteadySliding", "contact_spec", "steady_sliding"]


@dataclass(frozen=True)
class SteadySliding:
    """Steady sliding of a contact chain and its linear stability.

    ``state`` (4n,) the equilibrium [x; y; v; vy] (v = 0); ``normal_force`` (n,) N there (N);
    ``eigenvalues`` of the phase matrix A (1/s; growth rate = max real part); ``matrix`` A
    (rows: the free coordinates then their rates); ``holds`` True when every N > 0 there
    (else the chain cannot slide steadily in contact).
    """

    state: np.ndarray
    normal_force: np.ndarray
    eigenvalues: np.ndarray
    matrix: np.ndarray
    holds: bool

    @property
    def growth_rate(self) -> float:
        """max Re(lambda) (1/s): > 0 unstable (flutter when the root is complex, divergence when real)."""
        return float(np.max(self.eigenvalues.real))


def steady_sliding(**chain) -> SteadySliding:
    """Linearise ``simulate_chain(**chain)`` (with ``normal``) about steady sliding at rest against the belt.

    Only the chain's parameters matter (its ``x0``, ``v0``, ``t_end`` are ignored). The belt
    speed must not be zero (no sliding direction).

    Parameters
    ----------
    **chain
        :func:`simulate_chain`'s keyword arguments, with ``normal``.

    Returns
    -------
    SteadySliding
        The steady state, its normal forces (N), the linearised matrix and its eigenvalues
        (``growth_rate`` > 0: flutter).

    Raises
    ------
    SceneError
        No ``normal``, a zero belt speed, or a bad parameter.

    See Also
    --------
    asperity2d.belt.MinimalModel : Hoffmann's model in closed form.
    asperity2d.belt.NormalContact

    Examples
    --------
    >>> import numpy as np
    >>> from asperity2d import belt
    >>> s = belt.steady_sliding(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4,
    ...                         mu_k=0.3, v_belt=0.1, x0=[0.0], v0=[0.1], t_end=2.0,
    ...                         normal=belt.NormalContact(stiffness=1e4, contact_stiffness=1e5))
    >>> s.holds, np.round(s.normal_force, 3)
    (True, array([8.918]))
    >>> np.round(np.abs(s.eigenvalues.imag), 2)  # sqrt(k/m) = 10 rad/s and the normal mode
    array([ 10.  ,  10.  , 331.66, 331.66])
    """
    keep = {k: v for k, v in chain.items() if k in ("masses", "springs", "dampers", "mu_s", "mu_k", "v_belt", "g",
                                                     "friction", "normal", "normal_load", "x0", "v0")}
    n = len(keep["masses"]) if isinstance(keep.get("masses"), (list, tuple, np.ndarray)) else 1
    keep.setdefault("x0", [0.0] * n)
    keep.setdefault("v0", [0.0] * n)
    spec = contact_spec(keep.pop("masses"), keep.pop("springs"), keep.pop("dampers"), t_end=1.0, **keep)
    V = float(spec.chain.v_belt)
    if V == 0:
        raise SceneError("`v_belt` must not be 0 for steady sliding (the friction has no direction)")
    modes = np.full(spec.n, -1 if V > 0 else 1)
    t = ContactTemplate(spec, modes)
    A = t.affine.A
    d = t.free.size
    b0 = np.zeros(2 * d)
    b0[d:] = t.g_f / t.m_f  # held coordinates (a rigid contact's y) are 0 and still
    z = -np.linalg.solve(A, b0) if d else np.zeros(0)
    Z = t.E @ z
    N = t.N_map @ Z + t.N_offset
    return SteadySliding(Z, N, np.linalg.eigvals(A) if d else np.zeros(0, complex), A, bool(np.all(N > 0)))
