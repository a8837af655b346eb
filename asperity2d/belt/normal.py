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
friction loss - damper loss - impact loss (:mod:`.contact_loop`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..errors import SceneError
from ..friction.laws import Coulomb, StaticKinetic
from .. import _inputs as check
from .limits import SCALE_LIMIT


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


@dataclass(frozen=True)
class ContactSpec:
    """A validated chain with a normal degree of freedom per mass (built by ``simulate_chain``).

    ``chain`` is the tangential :class:`~.spec.ChainSpec` (its ``normal_load`` holds the
    static load W = m·g + P, used for its scales); ``y0``, ``vy0`` the initial gaps (m)
    and normal velocities (m/s), ``None`` for the default: at rest in the static
    equilibrium of the contact (or on the surface, rigid).
    """

    chain: object
    normal: NormalContact
    y0: tuple | None = None
    vy0: tuple | None = None

    def __post_init__(self):
        chain, n = self.chain, self.chain.n
        if not isinstance(self.normal, NormalContact):
            raise SceneError(f"`normal` must be a NormalContact, got {check.show(self.normal)}")
        if not isinstance(chain.law, (Coulomb, StaticKinetic)):
            raise SceneError("`friction` must be Coulomb or StaticKinetic (or `mu_s` / `mu_k`) with `normal`: the "
                             f"contact solver's phases are closed form, got {type(chain.law).__name__}")
        if not chain.constant_belt:
            raise SceneError("`v_belt` must be a constant with `normal` (the contact solver's phases are closed form)")
        vy0 = (0.0,) * n if self.vy0 is None else check.check_vector("vy0", self.vy0, n)
        y0 = self._rest_gaps() if self.y0 is None else check.check_vector("y0", self.y0, n)
        if self.normal.rigid and min(y0) < 0:
            i = int(np.argmin(y0))
            raise SceneError(f"`y0` must be >= 0 with a rigid contact (the belt surface is y = 0), got "
                             f"{check.show(y0[i])} at index {i}")
        object.__setattr__(self, "y0", tuple(y0))
        object.__setattr__(self, "vy0", tuple(vy0))
        for what, value in (("normal rate bound (1/s)", self.rate_bound), ("gap scale (m)", self.gap_scale),
                            ("normal force scale (N)", self.normal_scale)):
            if not (math.isfinite(value) and value <= SCALE_LIMIT):
                raise SceneError(f"the chain's {what} is {check.show(value)}, beyond {SCALE_LIMIT:g}: rescale "
                                 "`normal` (stiffnesses, preload) or `masses`")

    # -- what the budget check and RunOptions need (duck-typed like ChainSpec) --
    @property
    def n(self) -> int:
        return self.chain.n

    @property
    def t_end(self) -> float:
        return self.chain.t_end

    @cached_property
    def load(self) -> np.ndarray:
        """W_i = m_i·g + P (N): what presses each mass on the belt at y = 0."""
        return self.chain.m * self.chain.g + self.normal.preload

    @cached_property
    def stiffness_matrix(self) -> np.ndarray:
        """K_s (2n, 2n, N/m) on q = [x; y]: the chain, the inclined springs, the normal springs."""
        n = self.n
        kxx, kxy, kyy = self.normal.coupling()
        K = np.zeros((2 * n, 2 * n))
        K[:n, :n] = self.chain.stiffness_matrix()
        i = np.arange(n)
        K[i, i] += kxx
        K[i, n + i] = K[n + i, i] = kxy
        K[n + i, n + i] = kyy + self.normal.stiffness
        return K

    @cached_property
    def damping_matrix(self) -> np.ndarray:
        """C_s (2n, 2n, N·s/m): the chain's dampers in x, the normal dampers in y."""
        n = self.n
        C = np.zeros((2 * n, 2 * n))
        C[:n, :n] = self.chain.damping_matrix()
        C[np.arange(n, 2 * n), np.arange(n, 2 * n)] = self.normal.damping
        return C

    @cached_property
    def mass_vector(self) -> np.ndarray:
        return np.concatenate([self.chain.m, self.chain.m])

    @cached_property
    def constant_force(self) -> np.ndarray:
        """f0 (2n, N): -W on every y."""
        return np.concatenate([np.zeros(self.n), -self.load])

    def _rest_gaps(self) -> tuple:
        """Default y0: rigid, on the surface; compliant, the static equilibrium at x0 (in contact if it presses)."""
        n = self.n
        if self.normal.rigid:
            return (0.0,) * n
        kxx, kxy, kyy = self.normal.coupling()
        kyy += self.normal.stiffness
        push = -(self.load + kxy * np.asarray(self.chain.x0))  # net normal force at y = 0 besides the contact
        in_contact = push / (kyy + self.normal.contact_stiffness)
        free = push / kyy if kyy > 0 else np.zeros(n)  # lifted off: where the springs balance the pull
        return tuple(np.where(push < 0, in_contact, free).tolist())

    # -- scales -------------------------------------------------------------
    @cached_property
    def rate_bound(self) -> float:
        """Upper bound (1/s) on |lambda| of every phase: c' + sqrt(k') with k', c' the largest row sums
        of |M⁻¹K| and |M⁻¹C| with the contact spring and the friction terms mu_s·|N row| added
        (for lambda²M + lambda C + K singular, |lambda|² <= |lambda|·c' + k' in the induced inf-norm)."""
        K = np.abs(self.stiffness_matrix)
        n = self.n
        kc = self.normal.contact_stiffness or 0.0
        K[np.arange(n, 2 * n), np.arange(n, 2 * n)] += kc
        mu = self.chain.law.static_coefficient
        rows_N = np.abs(self.stiffness_matrix[n:]) + (kc * np.eye(n, 2 * n, n) if kc else 0.0)
        K[:n] += mu * rows_N
        C = np.abs(self.damping_matrix)
        C[:n] += mu * np.abs(self.damping_matrix[n:])
        m = self.mass_vector[:, None]
        return float(np.max(np.sum(C / m, axis=1)) + math.sqrt(float(np.max(np.sum(K / m, axis=1)))))

    @cached_property
    def scan_step(self) -> float:
        """1/16 of the fastest period (s) bound by :attr:`rate_bound`; ``t_end`` when nothing oscillates."""
        rate = self.rate_bound
        return 2 * math.pi / (16 * rate) if rate > 0 else self.t_end

    @cached_property
    def velocity_scale(self) -> float:
        """The chain's velocity scale, or the largest initial normal speed (m/s)."""
        return max(self.chain.velocity_scale, float(np.max(np.abs(self.vy0))))

    @cached_property
    def normal_scale(self) -> float:
        """A force (N) > 0 normalising the normal-force event functions: the largest load W, at least
        1e-12 of the chain's force scale."""
        return max(float(np.max(np.abs(self.load))), 1e-12 * self.chain.force_scale)

    @cached_property
    def gap_scale(self) -> float:
        """A length (m) normalising the gap event functions: for a compliant contact the penetration
        that carries the force scale (N_scale / k_c, so opening at N = 0 and closing at y = 0 share one
        tolerance); for a rigid one the chain's length scale or the initial gaps."""
        if not self.normal.rigid:
            return self.normal_scale / self.normal.contact_stiffness
        return max(self.chain.length_scale, float(np.max(np.abs(self.y0))))

    @cached_property
    def limit_scale(self) -> np.ndarray:
        """Per mass, the force (N) normalising the stick event functions: mu_s·|W_i|, floored."""
        return np.maximum(self.chain.law.static_coefficient * np.abs(self.load),
                          1e-12 * max(self.chain.force_scale, self.normal_scale))

    @cached_property
    def energy_scale(self) -> float:
        return max(self.chain.energy_scale, self.normal_scale * self.gap_scale)

    def to_dict(self) -> dict:
        return {**self.normal.to_dict(), "y0": list(self.y0), "vy0": list(self.vy0)}
