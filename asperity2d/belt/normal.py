"""The normal degree of freedom of a belt chain: a unilateral contact that can open.

With ``simulate_chain(..., normal=NormalContact(...))`` every mass i gets, besides
its tangential coordinate x_i (m, along the belt), a normal coordinate y_i (m): the
gap between its contact point and the belt surface, positive away from the belt.

Forces on mass i (SI, +x along the belt, +y away from it):

* the chain's links in x, as without a normal degree of freedom;
* a normal spring ``stiffness`` k_n (N/m, unstretched at y = 0) and damper
  ``damping`` c_n (N·s/m) to the frame: -k_n·y - c_n·y';
* ``inclined`` springs (k_a in N/m, alpha_a in degrees from +x towards +y) from the
  mass to the frame, unstretched at x = y = 0: -k_a·(e_a·q)·e_a with
  e_a = (cos alpha_a, sin alpha_a) -- they couple x and y (Hoffmann, Fischer,
  Allgaier & Gaul 2002; their "minimal model" is one mass with two of them);
* its weight and the ``preload`` P (N) pressing it on the belt: -W with
  W = m·g + P;
* the contact force N >= 0 (normal) and the friction force F (tangential, the
  chain's law applied to the *actual* N: |F| = mu_k·N sliding, |F| <= mu_s·N stuck).

The structure is linear: with q = [x_1..x_n, y_1..y_n],
M·q'' + C_s·q' + K_s·q = f0 + [F; N], f0 = [0; -W], K_s and C_s symmetric.
Per mass K_s holds [[sum k_a·c², sum k_a·c·s], [sum k_a·c·s, sum k_a·s² + k_n]]
(c, s the cosine and sine of alpha_a) on (x_i, y_i), plus the chain in x.

The contact is either

* **compliant** (``contact_stiffness`` k_c, N/m): in contact N = k_c·(-y) (the
  penetration times k_c); it opens when N reaches zero, which is y = 0, and closes
  when the gap y comes back to 0 -- velocity is continuous, nothing is lost;
* **rigid** (``contact_stiffness=None``): in contact y = y' = 0 and N is the
  constraint force N = W + (K_s·q + C_s·q')_y; it opens when that force reaches
  zero and closes when the gap does, with an impact: Newton's law y'+ = -e·y'-
  (``restitution`` e), the normal impulse P_n = m·(1 + e)·|y'-|, a Coulomb
  friction impulse of at most mu_k·P_n that stops the slip if it can, and the
  kinetic energy lost, ½·m·(1 - e²)·y'-² (plus the friction impulse's share),
  booked.

The energies: stored E = ½·q'ᵀMq' + ½·qᵀK_s·q + ½·k_c·Σδ² (compliant, in contact)
+ Σ W_i·y_i (work against the weight and the preload); E - E(0) = belt work -
friction loss - damper loss - impact loss (:mod:`.contact.loop`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import SceneError
from .. import _inputs as check


@dataclass(frozen=True)
class NormalContact:
    """A normal degree of freedom and a unilateral contact for every mass of a chain (SI).

    Parameters
    ----------
    stiffness : float
        Normal spring to the frame, k_n (N/m, >= 0), unstretched at y = 0.
    damping : float
        Normal damper to the frame, c_n (N·s/m, >= 0).
    preload : float
        Force pressing each mass on the belt besides its weight (N; negative: a force lifting
        it off).
    contact_stiffness : float or None
        k_c (N/m, > 0) of a compliant contact; ``None`` for a rigid contact (impacts).
    restitution : float
        Newton's coefficient e in [0, 1] of a rigid contact's impacts (0: plastic).
    inclined : sequence of (stiffness, angle) pairs
        Springs from each mass to the frame (N/m >= 0; degrees from +x towards +y,
        within [-180, 180]); they couple the normal and tangential motions.

    Raises
    ------
    SceneError
        A value out of range, named.

    See Also
    --------
    asperity2d.belt.simulate_chain : ``normal=`` takes it.
    asperity2d.belt.steady_sliding : the linearisation about steady sliding.

    Examples
    --------
    A compliant contact under a normal spring: the weight is shared between them, so the
    contact carries 9.81 N × 1e5 / (1e5 + 1e4) = 8.918 N:

    >>> from asperity2d import belt
    >>> r = belt.simulate_chain([1.0], [100.0, 0.0], [0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...                         v_belt=0.1, x0=[0.0], v0=[0.1], t_end=2.0,
    ...                         normal=belt.NormalContact(stiffness=1e4, contact_stiffness=1e5))
    >>> r
    ContactResult(n=1, 2006 samples, t_end=2 s, events=5, separations=0)
    >>> round(float(r.normal_force[0, 0]), 3)
    8.918
    """

    stiffness: float = 0.0
    damping: float = 0.0
    preload: float = 0.0
    contact_stiffness: float | None = None
    restitution: float = 0.0
    inclined: tuple = ()

    def __post_init__(self):
        s = object.__setattr__
        s(self, "stiffness", check.check_real("normal.stiffness", self.stiffness, nonneg=True))
        s(self, "damping", check.check_real("normal.damping", self.damping, nonneg=True))
        s(self, "preload", check.check_real("normal.preload", self.preload))
        if self.contact_stiffness is not None:
            s(self, "contact_stiffness", check.check_real("normal.contact_stiffness", self.contact_stiffness, positive=True))
        e = check.check_real("normal.restitution", self.restitution, nonneg=True)
        if e > 1:
            raise SceneError(f"`normal.restitution` must be within [0, 1], got {check.show(self.restitution)}")
        if e > 0 and self.contact_stiffness is not None:
            raise SceneError("`normal.restitution` applies to a rigid contact (`contact_stiffness=None`): a compliant "
                             f"contact has no impacts, got restitution {check.show(self.restitution)}")
        s(self, "restitution", e)
        s(self, "inclined", _inclined(self.inclined))

    @property
    def rigid(self) -> bool:
        return self.contact_stiffness is None

    def coupling(self) -> tuple[float, float, float]:
        """(K_xx, K_xy, K_yy) (N/m) of the inclined springs on one mass (K_yy without k_n)."""
        kxx = kxy = kyy = 0.0
        for k, angle in self.inclined:
            c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
            kxx, kxy, kyy = kxx + k * c * c, kxy + k * c * s, kyy + k * s * s
        return kxx, kxy, kyy

    def to_dict(self) -> dict:
        return {"stiffness": self.stiffness, "damping": self.damping, "preload": self.preload,
                "contact_stiffness": self.contact_stiffness, "restitution": self.restitution,
                "inclined": [list(p) for p in self.inclined]}

    @classmethod
    def from_dict(cls, record: dict) -> "NormalContact":
        if not isinstance(record, dict):
            raise SceneError(f"`normal` must be a table of NormalContact parameters, got {check.show(record)}")
        known = {"stiffness", "damping", "preload", "contact_stiffness", "restitution", "inclined"}
        unknown = set(record) - known
        if unknown:
            raise SceneError(f"`normal.{sorted(unknown)[0]}` is not a NormalContact parameter "
                             f"(known: {', '.join(sorted(known))})")
        return cls(**{k: (tuple(map(tuple, v)) if k == "inclined" else v) for k, v in record.items()})


def _inclined(value) -> tuple:
    if isinstance(value, (str, bytes)) or not isinstance(value, (list, tuple)):
        raise SceneError(f"`normal.inclined` must be a list of (stiffness, angle) pairs, got {check.show(value)}")
    if len(value) > 16:
        raise SceneError(f"`normal.inclined` may hold at most 16 springs, got {len(value)}")
    out = []
    for i, pair in enumerate(value):
        if isinstance(pair, (str, bytes)) or not isinstance(pair, (list, tuple)) or len(pair) != 2:
            raise SceneError(f"`normal.inclined` entry {i} must be a (stiffness, angle) pair, got {check.show(pair)}")
        k = check.check_real(f"normal.inclined[{i}] stiffness", pair[0], nonneg=True)
        angle = check.check_real(f"normal.inclined[{i}] angle", pair[1])
        if not -180.0 <= angle <= 180.0:
            raise SceneError(f"`normal.inclined[{i}] angle` must be within [-180, 180] degrees, got {check.show(pair[1])}")
        out.append((k, angle))
    return tuple(out)


#: per-mass codes of the contact solver's modes: stuck, slipping (±1) and separated
STUCK, SEPARATED = 0, 2

#: (``ContactSpec``, the validated chain with its normal contact, is in :mod:`.spec`.)
