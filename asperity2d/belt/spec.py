"""The chain of masses on a moving belt: a frozen, validated specification and its scales.

n masses ``m_i`` (kg) sit in a row on a belt moving at ``v_belt`` (m/s).
Spring ``k_j`` (N/m) and damper ``c_j`` (N·s/m), j = 0..n, join mass j-1 to
mass j, with the walls as "mass -1" and "mass n": ``springs[0]`` ties m1 to
the left wall, ``springs[n]`` ties mn to the right wall; a zero removes the
link. Positions ``x_i`` (m) are measured from the configuration in which
every spring is unstretched. Each mass presses on the belt with the normal
load ``N_i`` (N, default m_i·g) and feels friction from ``friction``.

The scales the solvers need (fastest rate, velocity and length scales, the
scan step) are properties of the spec, computed once.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import Callable

import numpy as np

from ..errors import SceneError, SimulationError
from ..friction.laws import Coulomb, FrictionLaw, StaticKinetic, law_from_dict
from .. import _inputs as check
from .._inputs import check_real, check_vector, show
from . import chainfile, limits
from .limits import SCALE_LIMIT
from .normal import NormalContact


@dataclass(frozen=True)
class ChainSpec:
    """A validated belt chain (all SI). Build it through :func:`simulate_chain` or directly.

    ``v_belt`` is a constant (m/s) or a callable ``v_belt(t)`` (ramps);
    ``mu_k`` defaults to ``mu_s``; ``friction`` (a law from
    :mod:`asperity2d.friction`) replaces (mu_s, mu_k) -- give one or the other.

    Parameters
    ----------
    masses, springs, dampers, mu_s, mu_k, v_belt, x0, v0, t_end, g, normal_load, friction
        As for :func:`simulate_chain` (tuples here).

    Raises
    ------
    SceneError
        A bad parameter, named.

    See Also
    --------
    asperity2d.belt.simulate_chain : builds one and runs it; ``result.chain`` is the spec it ran.

    Examples
    --------
    >>> from asperity2d import belt
    >>> spec = belt.ChainSpec(masses=(1.0,), springs=(100.0, 0.0), dampers=(0.0, 0.0), mu_s=0.4,
    ...                       mu_k=None, v_belt=0.1, x0=(0.0,), v0=(0.1,), t_end=2.0)
    >>> spec.n, spec.mu_k  # mu_k defaults to mu_s
    (1, 0.4)
    >>> belt.ChainSpec(masses=(1.0,), springs=(100.0,), dampers=(0.0, 0.0), mu_s=0.4, mu_k=None,
    ...                v_belt=0.1, x0=(0.0,), v0=(0.1,), t_end=2.0)
    Traceback (most recent call last):
    ...
    asperity2d.errors.SceneError: `springs` must have 2 entries, got 1
    """

    masses: tuple
    springs: tuple
    dampers: tuple
    mu_s: float | None
    mu_k: float | None
    v_belt: float | Callable[[float], float]
    x0: tuple
    v0: tuple
    t_end: float
    g: float = 9.81
    normal_load: tuple | None = None
    friction: FrictionLaw | None = None
    law: FrictionLaw = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        s = object.__setattr__
        s(self, "masses", check_vector("masses", self.masses, positive=True))
        n = len(self.masses)
        s(self, "springs", check_vector("springs", self.springs, n + 1, nonneg=True))
        s(self, "dampers", check_vector("dampers", self.dampers, n + 1, nonneg=True))
        s(self, "x0", check_vector("x0", self.x0, n))
        s(self, "v0", check_vector("v0", self.v0, n))
        s(self, "t_end", check_real("t_end", self.t_end, positive=True))
        s(self, "g", check_real("g", self.g, nonneg=True))
        if self.normal_load is not None:
            s(self, "normal_load", check_vector("normal_load", self.normal_load, n, nonneg=True))
        if callable(self.v_belt):
            try:
                probe = self.v_belt(0.0)
            except Exception as exc:  # noqa: BLE001 -- the user's callable; report, do not crash
                raise SceneError(f"`v_belt` raised {type(exc).__name__} at t = 0: {show(exc, 120)}") from None
            check_real("v_belt", probe)
        else:
            s(self, "v_belt", check_real("v_belt", self.v_belt))
        s(self, "law", self._law())
        limits.scales(self)

    def _law(self) -> FrictionLaw:
        if self.friction is not None:
            if not isinstance(self.friction, FrictionLaw):
                raise SceneError(f"`friction` must be a law from asperity2d.friction, got {show(self.friction)}")
            if self.mu_s is not None or self.mu_k is not None:
                raise SceneError("give either `mu_s` / `mu_k` or `friction`, not both")
            for name, value in zip(self.friction.param_names, self.friction.params):
                check_real(f"friction.{name}", float(value))
            return self.friction
        if self.mu_s is None:
            raise SceneError("`mu_s` is required unless `friction` is given")
        mu_s = check_real("mu_s", self.mu_s, nonneg=True)
        mu_k = mu_s if self.mu_k is None else check_real("mu_k", self.mu_k, nonneg=True)
        if mu_k > mu_s:
            raise SceneError(f"`mu_s` must be >= `mu_k` ({mu_k!r}), got {mu_s!r}")
        object.__setattr__(self, "mu_s", mu_s)
        object.__setattr__(self, "mu_k", mu_k)
        return Coulomb(mu_s) if mu_s == mu_k else StaticKinetic(mu_s, mu_k)

    # -- derived arrays ---------------------------------------------------
    @property
    def n(self) -> int:
        return len(self.masses)

    @cached_property
    def m(self) -> np.ndarray:
        return np.asarray(self.masses)

    @cached_property
    def k(self) -> np.ndarray:
        return np.asarray(self.springs)

    @cached_property
    def c(self) -> np.ndarray:
        return np.asarray(self.dampers)

    @cached_property
    def normal(self) -> np.ndarray:
        """Normal load per mass (N)."""
        if self.normal_load is not None:
            return np.asarray(self.normal_load)
        return self.m * self.g

    @cached_property
    def static_limit(self) -> np.ndarray:
        """Largest static friction force per mass (N), mu_s·N_i."""
        return self.law.static_coefficient * self.normal

    @cached_property
    def kinetic_force(self) -> np.ndarray:
        """Kinetic friction magnitude per mass (N) for piecewise-constant laws, mu_k·N_i."""
        return self.law.kinetic_coefficient * self.normal

    @cached_property
    def frictional(self) -> np.ndarray:
        """True for masses that feel any friction (the others never stick)."""
        return (self.static_limit > 0) | (self.kinetic_force > 0)

    @property
    def constant_belt(self) -> bool:
        return not callable(self.v_belt)

    # -- scales -----------------------------------------------------------
    @cached_property
    def rate_bound(self) -> float:
        """Upper bound (1/s) on abs(lambda) of every mode of every segment of the chain.

        For lambda²·M + lambda·C + K singular, abs(lambda) <= c' + sqrt(k') with c', k' the
        spectral radii of M⁻¹C and M⁻¹K, each bounded by its largest row sum
        2·max((c_i + c_i+1)/m_i) (Gershgorin). Zero for a chain with no links.
        """
        k_row = 2 * float(np.max((self.k[:-1] + self.k[1:]) / self.m))
        c_row = 2 * float(np.max((self.c[:-1] + self.c[1:]) / self.m))
        return c_row + math.sqrt(k_row)

    @cached_property
    def fastest_rate(self) -> float:
        """max abs(lambda) (1/s) of the whole chain slipping (an O(n³) eigenvalue problem; cached)."""
        n = self.n
        A = np.zeros((2 * n, 2 * n))
        A[:n, n:] = np.eye(n)
        A[n:, :n] = -self.stiffness_matrix() / self.m[:, None]
        A[n:, n:] = -self.damping_matrix() / self.m[:, None]
        return float(np.max(np.abs(np.linalg.eigvals(A))))

    @cached_property
    def scan_step(self) -> float:
        """Time step (s) of the budget estimate: 1/16 of the fastest period; t_end for a linkless chain."""
        rate = self.rate_bound
        return 2 * math.pi / (16 * rate) if rate > 0 else self.t_end

    @cached_property
    def omega(self) -> float:
        """Stiffest spring-mass frequency sqrt(max(k_i + k_i+1) / min m) (rad/s); 1 without springs."""
        return math.sqrt(float(np.max(self.k[:-1] + self.k[1:]) / np.min(self.m))) if self.k.any() else 1.0

    @cached_property
    def velocity_scale(self) -> float:
        """A velocity (m/s) that normalises the slip event functions and the switching tolerance.

        The largest of the belt speed, the initial speeds and the speed swing
        F/(m·omega) of a static-friction release of the force F = mu_s·N (at least 1e-12 m/s).
        On a constant belt F is at most the force the links can build up during the run
        (:attr:`release_force`): a static limit beyond it never releases, and a swing taken
        from it would set the switching tolerance (1e-9 of this scale) above the chain's real
        speeds (mu_s = 100 under 1e6 N on Table 2's springs: a 2e7 m/s "swing", a 0.02 m/s
        tolerance, masses snapped to the belt speed 0.02 m/s away, books 2e-4 off).
        """
        force = self.static_limit if callable(self.v_belt) else np.minimum(self.static_limit, self.release_force)
        swing = float(np.max(force / self.m)) / self.omega
        return float(max(abs(self.belt_velocity(0.0)), float(np.max(np.abs(self.v0))), swing, 1e-12))

    @cached_property
    def release_force(self) -> np.ndarray:
        """Per mass, a generous bound (N) on the spring and damper force it can feel on a constant
        belt: its links stretched by twice the reach (the initial offsets plus the distance the belt
        and the initial speeds cover in ``t_end``) and moving at twice the belt's or the initial speed."""
        speed = abs(float(self.belt_velocity(0.0))) + float(np.max(np.abs(self.v0)))
        reach = float(np.max(np.abs(self.x0))) + speed * self.t_end
        k, c = self.k[:-1] + self.k[1:], self.c[:-1] + self.c[1:]
        return 2.0 * (k * reach + c * speed)

    @cached_property
    def length_scale(self) -> float:
        """A length (m): the initial offsets, or the velocity scale over omega."""
        return max(float(np.max(np.abs(self.x0))), self.velocity_scale / self.omega)

    @cached_property
    def force_scale(self) -> float:
        """A force (N) > 0: the largest static limit, spring force at the length scale, or inertial force
        m·v_scale·omega."""
        return max(float(np.max(self.static_limit)), float(np.max(self.k)) * self.length_scale,
                   float(np.max(self.m)) * self.velocity_scale * self.omega, 1e-300)

    @cached_property
    def limit_scale(self) -> np.ndarray:
        """Per mass, the force (N) that normalises its static-limit event functions and tolerances:
        mu_s·N_i, but at least 1e-12 of the force scale (a vanishing limit must not overflow them)."""
        return np.maximum(self.static_limit, 1e-12 * self.force_scale)

    @cached_property
    def energy_scale(self) -> float:
        """An energy (J) > 0: the force scale times the length scale, or the kinetic energy at the velocity scale."""
        return max(self.force_scale * self.length_scale,
                   float(np.max(self.m)) * self.velocity_scale * self.velocity_scale, 1e-300)

    @cached_property
    def limit_band(self) -> tuple:
        """Per mass, the static limit plus and minus the switching tolerance (N): (above, below)."""
        tol = limits.SWITCH_TOL * self.limit_scale
        return self.static_limit + tol, self.static_limit - tol

    @cached_property
    def frictional_masses(self) -> tuple:
        """Indices (plain ints) of the masses that feel friction."""
        return tuple(np.flatnonzero(self.frictional).tolist())

    @cached_property
    def linked(self) -> tuple:
        """Per pair of neighbours (n - 1), True when a spring or damper joins masses i and i + 1."""
        return tuple(k != 0 or c != 0 for k, c in zip(self.springs[1:-1], self.dampers[1:-1]))

    @cached_property
    def damped(self) -> bool:
        """True when any damper acts."""
        return bool(self.c.any())

    @cached_property
    def force_rows(self) -> tuple:
        """Per mass, ``force_row``: the (columns, coefficients) of its spring + damper force."""
        return tuple(_force_row(self, i) for i in range(self.n))

    # -- belt -------------------------------------------------------------
    def belt_velocity(self, t):
        """Belt speed (m/s) at time(s) ``t`` (s)."""
        if not callable(self.v_belt):
            if isinstance(t, (float, int)):  # (a scalar: asked at every switch; np.ndim costs more)
                return float(self.v_belt)
            return np.full(np.shape(t), self.v_belt) if np.ndim(t) else float(self.v_belt)
        if np.ndim(t):
            return np.array([self._call_belt(s) for s in np.ravel(t)]).reshape(np.shape(t))
        return self._call_belt(t)

    def _call_belt(self, t) -> float:
        try:
            value = self.v_belt(float(t))
        except Exception as exc:  # noqa: BLE001 -- the user's callable: report it, with the time
            raise SimulationError(f"`v_belt` raised {type(exc).__name__} at t = {float(t):.6g} s: {show(exc, 120)}",
                                  time=float(t)) from None
        try:
            out = float(value)
        except (TypeError, ValueError, OverflowError):
            out = math.nan
        if not math.isfinite(out):
            raise SimulationError(f"`v_belt`({float(t):.6g}) returned {show(value)}, not a finite number",
                                  time=float(t))
        return out

    def belt_acceleration(self, t) -> float:
        """dv_belt/dt (m/s²); central difference for callables, 0 for a constant belt."""
        if not callable(self.v_belt):
            return 0.0
        h = 1e-6 * max(1.0, abs(t))
        return (self._call_belt(t + h) - self._call_belt(t - h)) / (2 * h)

    # -- matrices ---------------------------------------------------------
    def stiffness_matrix(self) -> np.ndarray:
        """Tridiagonal K (N/m) with M·x'' + C·x' + K·x = friction."""
        return tridiagonal(self.k)

    def damping_matrix(self) -> np.ndarray:
        """Tridiagonal C (N·s/m)."""
        return tridiagonal(self.c)

    def to_dict(self) -> dict:
        return {
            "masses": list(self.masses),
            "springs": list(self.springs),
            "dampers": list(self.dampers),
            "friction": self.law.to_dict(),
            "v_belt": repr(self.v_belt) if callable(self.v_belt) else self.v_belt,
            "x0": list(self.x0),
            "v0": list(self.v0),
            "t_end": self.t_end,
            "g": self.g,
            "normal_load": list(self.normal) if self.normal_load is not None else None,
        }

    #: The fields of ``to_dict()``'s record.
    RECORD = ("masses", "springs", "dampers", "friction", "v_belt", "x0", "v0", "t_end", "g", "normal_load")

    #: What a chain document (``chainfile``) may hold besides ``RECORD``: the coefficients in
    #: place of ``friction``, and a normal contact.
    DOCUMENT = ("mu_s", "mu_k", "normal", "y0", "vy0")

    @classmethod
    def from_dict(cls, record: dict):
        """The chain ``to_dict()`` wrote (a saved result's ``chain`` record), validated again; or the
        spec of a chain document (``chainfile.document``: ``mu_s`` / ``mu_k`` in place of
        ``friction``, a ``normal`` table with ``y0`` / ``vy0`` -- then a :class:`ContactSpec`).

        ``friction`` is the law's own record (``law_from_dict``); a callable ``v_belt`` was saved
        by its name only and cannot be rebuilt. A record that is not a dict, lacks a field, has
        one this class does not know, or holds a bad value raises :class:`~asperity2d.SceneError` naming the
        field."""
        if not isinstance(record, dict):
            raise SceneError(f"`chain` must be a table of ChainSpec fields, got {show(record)}")
        unknown = sorted(set(record) - set(cls.RECORD) - set(cls.DOCUMENT), key=str)
        if unknown:
            raise SceneError(f"`chain.{unknown[0]}` is not a ChainSpec field (known: "
                             f"{', '.join(cls.RECORD + cls.DOCUMENT)})")
        missing = [name for name in cls.RECORD if name not in record and name not in ("g", "normal_load", "friction")]
        if "friction" not in record and "mu_s" not in record:
            missing.append("friction")
        if missing:
            raise SceneError(f"`chain.{missing[0]}` is missing")
        if isinstance(record["v_belt"], str):
            raise SceneError(f"`chain.v_belt` was a function ({record['v_belt']}), saved by its name only: "
                             "it cannot be rebuilt")
        args = {k: v for k, v in record.items() if not (k == "normal_load" and v is None)}
        if "friction" in args:
            args["friction"] = law_from_dict(args["friction"])
        if "normal" in args and not isinstance(args["normal"], NormalContact):
            args["normal"] = NormalContact.from_dict(args["normal"])
        return spec_of(args)

    def arguments(self) -> dict:
        """``simulate_chain`` keyword arguments that rebuild this spec and run it bit for bit the same."""
        return chainfile.arguments(self)

    def to_toml(self, path, **settings):
        """Write this chain as a TOML chain file (``asperity2d belt FILE`` runs it, bit for bit as
        ``simulate_chain(**spec.arguments())`` does); ``settings`` are run settings the file keeps
        (``method``, ``n_samples``, ``rtol``, ``atol``, ``integrator``). Every number is written
        exactly; a callable ``v_belt`` cannot be (``SceneError``). Returns the path.

        Examples
        --------
        >>> from asperity2d import belt
        >>> spec = belt.ChainSpec(masses=(1.0,), springs=(100.0, 0.0), dampers=(0.0, 0.0), mu_s=0.4,
        ...                       mu_k=0.3, v_belt=0.1, x0=(0.0,), v0=(0.1,), t_end=2.0)
        >>> belt.ChainSpec.from_toml(spec.to_toml("chain.toml")) == spec
        True
        """
        return chainfile.write_chain(self, path, settings)

    @classmethod
    def from_toml(cls, path):
        """The spec of a TOML chain file (``asperity2d.belt.chainfile``; its run settings are left out): a
        ChainSpec, or a :class:`ContactSpec` when the file has a ``[normal]`` table (or ``y0`` /
        ``vy0``). A key the file should not hold, a missing one or a bad table raises one
        ``SceneError`` naming the key and the file; a bad value one naming the parameter."""
        return spec_of(chainfile.read_chain(path))


@dataclass(frozen=True)
class ContactSpec:
    """A validated chain with a normal degree of freedom per mass (built by ``simulate_chain``).

    ``chain`` is the tangential :class:`~.spec.ChainSpec` (its ``normal_load`` holds the
    static load W = m·g + P, used for its scales); ``y0``, ``vy0`` the initial gaps (m)
    and normal velocities (m/s), ``None`` for the default: at rest in the static
    equilibrium of the contact (or on the surface, rigid).

    Examples
    --------
    The spec of a chain document with a ``normal`` table; by default a compliant contact starts
    in its static equilibrium, pressed in by m·g / (k_c + k_n) = 9.81 / 1.1e5 m:

    >>> from asperity2d import belt
    >>> spec = belt.ChainSpec.from_dict(dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0],
    ...     mu_s=0.4, mu_k=0.3, v_belt=0.1, x0=[0.0], v0=[0.1], t_end=2.0,
    ...     normal=dict(stiffness=1e4, contact_stiffness=1e5)))
    >>> type(spec).__name__, spec.y0
    ('ContactSpec', (-8.918181818181818e-05,))
    >>> [b.name for b in belt.METHODS["exact"] if b.accepts(spec)]  # only the contact solver runs it
    ['closed-form contact phases']
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
        """Upper bound (1/s) on ``abs(lambda)`` of every phase: ``c' + sqrt(k')`` with k', c' the
        largest row sums of ``abs(M⁻¹K)`` and ``abs(M⁻¹C)`` with the contact spring and the friction
        terms ``mu_s·abs(N row)`` added (for ``lambda²M + lambda C + K`` singular,
        ``abs(lambda)² <= abs(lambda)·c' + k'`` in the induced inf-norm)."""
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
    def normal_scales(self) -> np.ndarray:
        """Per mass, the force (N) normalising its own normal-force event function and tolerances: the
        larger of its load ``abs(W_i)`` and the inclined springs' force at the chain's length scale (what
        moves its contact force), within [1e-12, 1] of :attr:`normal_scale` -- never looser than the chain's
        one scale, and the same for a single mass or equal masses.

        Each mass on its own scale: with masses 1e6 and 1 kg, the heavy mass's ~1e7 N would make the
        light one's tolerance 0.01 N, half its weight, and a contact force that pulls by that much
        would pass unseen."""
        kxy = self.normal.coupling()[1]
        own = np.maximum(np.abs(self.load), abs(kxy) * self.chain.length_scale)
        return np.clip(own, 1e-12 * self.normal_scale, self.normal_scale)

    @cached_property
    def gap_scales(self) -> np.ndarray:
        """Per mass, the length (m) normalising its gap event function: for a compliant contact the
        penetration that carries its own force scale (:attr:`normal_scales` / k_c, so opening and
        closing share one tolerance, mass by mass); for a rigid one :attr:`gap_scale`."""
        if not self.normal.rigid:
            return self.normal_scales / self.normal.contact_stiffness
        return np.full(self.n, self.gap_scale)

    @cached_property
    def limit_scale(self) -> np.ndarray:
        """Per mass, the force (N) normalising the stick event functions: ``mu_s·abs(W_i)``, floored."""
        return np.maximum(self.chain.law.static_coefficient * np.abs(self.load),
                          1e-12 * max(self.chain.force_scale, self.normal_scale))

    @cached_property
    def energy_scale(self) -> float:
        return max(self.chain.energy_scale, self.normal_scale * self.gap_scale)

    def to_dict(self) -> dict:
        return {**self.normal.to_dict(), "y0": list(self.y0), "vy0": list(self.vy0)}

    def arguments(self) -> dict:
        """``simulate_chain`` keyword arguments that rebuild this spec (``normal``, ``y0``, ``vy0`` included)."""
        return chainfile.arguments(self)

    def to_toml(self, path, **settings):
        """Write the chain and its normal contact as a TOML chain file (a ``[normal]`` table, ``y0``,
        ``vy0``); as :meth:`ChainSpec.to_toml`. Returns the path."""
        return chainfile.write_chain(self, path, settings)

    from_toml = ChainSpec.from_toml


def contact_spec(masses, springs, dampers, *, mu_s=None, mu_k=None, v_belt, x0, v0, t_end, g=9.81, normal_load=None,
                 friction=None, normal=None, y0=None, vy0=None) -> ContactSpec:
    """The validated :class:`ContactSpec` of ``simulate_chain``'s arguments (with ``normal``)."""
    if normal is None:
        raise SceneError("`y0` and `vy0` need `normal` (a NormalContact): without it the chain has no normal "
                         "coordinate")
    if not isinstance(normal, NormalContact):
        raise SceneError(f"`normal` must be a NormalContact, got {check.show(normal)}")
    if normal_load is not None:
        raise SceneError("give the load through `normal` (NormalContact(preload=...)), not `normal_load`: with a "
                         "normal degree of freedom the normal force is computed, not imposed")
    chain = ChainSpec(masses, springs, dampers, mu_s, mu_k, v_belt, x0, v0, t_end, g, None, friction)
    load = np.abs(chain.m * chain.g + normal.preload)  # the chain's scales (velocity, force) see the real load
    chain = ChainSpec(masses, springs, dampers, mu_s, mu_k, v_belt, x0, v0, t_end, g, tuple(load.tolist()), friction)
    return ContactSpec(chain, normal, y0, vy0)


def spec_of(kwargs: dict):
    """The validated spec of ``simulate_chain`` keyword arguments (run settings left out): a
    :class:`ChainSpec`, or a :class:`ContactSpec` when ``normal``, ``y0`` or ``vy0`` is given --
    what ``simulate_chain`` runs. Bad values raise ``SceneError`` naming the parameter."""
    chain = {k: v for k, v in kwargs.items() if k not in chainfile.SETTINGS}
    unknown = sorted(set(chain) - set(chainfile.REQUIRED + chainfile.OPTIONAL))
    if unknown:
        raise SceneError(f"`{unknown[0]}` is not a chain parameter (allowed: {', '.join(sorted(chainfile.ALLOWED))})")
    missing = [key for key in chainfile.REQUIRED if key not in chain]
    if missing:
        raise SceneError(f"`{missing[0]}` is missing (required: {', '.join(chainfile.REQUIRED)})")
    masses, springs, dampers = chain.pop("masses"), chain.pop("springs"), chain.pop("dampers")
    if any(key in chain for key in ("normal", "y0", "vy0")):
        return contact_spec(masses, springs, dampers, **chain)
    return ChainSpec(masses, springs, dampers, chain.get("mu_s"), chain.get("mu_k"), chain["v_belt"], chain["x0"],
                     chain["v0"], chain["t_end"], chain.get("g", 9.81), chain.get("normal_load"),
                     chain.get("friction"))


def tridiagonal(links: np.ndarray) -> np.ndarray:
    """The (n, n) matrix of n+1 links (wall, between masses, wall) acting on n masses."""
    n = len(links) - 1
    out = np.diag(links[:-1] + links[1:])
    idx = np.arange(n - 1)
    out[idx, idx + 1] = -links[1:-1]
    out[idx + 1, idx] = -links[1:-1]
    return out


def force_row(spec, i: int):
    """(columns, coefficients) of the spring + damper force on mass ``i`` (N) over the state [x; v].

    F_i = k_i·x_i-1 - (k_i + k_i+1)·x_i + k_i+1·x_i+1 + (the same with c and v); column j is
    x_j, column n + j is v_j; zero coefficients are left out. Tuples, cached per spec (every new
    mode pattern of a run asks for them again).
    """
    return spec.force_rows[i]


def _force_row(spec, i: int):
    n, cols, coefs = spec.n, [], []
    for base, links in ((0, spec.k), (n, spec.c)):
        for j, coef in ((i - 1, links[i]), (i, -(links[i] + links[i + 1])), (i + 1, links[i + 1])):
            if 0 <= j < n and coef != 0:
                cols.append(base + j)
                coefs.append(float(coef))
    return tuple(cols), tuple(coefs)


def link_force(links: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Force on each mass (N) from links of coefficient ``links`` (n+1,) acting on ``x`` (n, ...).

    With springs and positions it is the spring force; with dampers and
    velocities the damper force. Walls sit at 0 and never move.
    """
    tension = link_extension(x)
    tension *= links if tension.ndim == 1 else (links[:, None] if tension.ndim == 2 else
                                                links.reshape((-1,) + (1,) * (tension.ndim - 1)))
    return tension[1:] - tension[:-1]


def link_extension(x: np.ndarray) -> np.ndarray:
    """Extension (m) or extension rate of each of the n+1 links for positions ``x`` (n, ...).

    The differences of ``x`` padded with the walls' zeros (what ``np.diff`` of the padded array
    gives, bit for bit, in three slice operations: this runs at every switch and sample)."""
    x = np.asarray(x, dtype=float)
    n = x.shape[0]
    out = np.empty((n + 1,) + x.shape[1:])
    out[0] = x[0]
    np.subtract(x[1:], x[:-1], out=out[1:n])
    out[n] = 0.0 - x[n - 1]
    return out
