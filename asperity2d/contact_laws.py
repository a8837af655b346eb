"""Friction laws of the asperity model, and the one registry of the friction laws of both models.

The asperity model applies friction per contact: each lower asperity touching the slider
carries a coefficient that pymunk's contact solver uses, and a *contact law* decides it after
every step from what that contact did in the step: its signed slip speed, its normal impulse and
its own state (:class:`ContactLaw` states the contract). Every law has a plain-Python reference,
:meth:`ContactLaw.step`; the engine's Python step loop calls exactly that reference, and the C
step loop (``engine/_kernel.c``) implements the laws named by their :attr:`ContactLaw.kernel`,
held to the reference's bits (``tests/test_engine_kernel.py``, ``tests/test_contact_laws.py``).
For any other law the engine steps in Python and says why
(``Engine.loop_reason`` (``asperity2d.engine``)).

The laws here: :class:`StaticKineticSwitch` (the default: static / kinetic with the hold rule),
:class:`VelocityWeakening` (an exponential Stribeck-type fall from ``mu_static`` to
``mu_kinetic``), :class:`ViscousCoulomb` (``mu_kinetic`` plus a viscous term) and
:class:`RateState` (Dieterich-Ruina rate-and-state friction with the ageing law, regularised at
zero slip speed). Each gives its steady-sliding coefficient in closed form (:meth:`ContactLaw.steady`),
which ``asperity2d validate`` checks against the flat block.

:data:`LAWS` lists every friction law of the package with the model it serves: the belt
chains' laws (:mod:`asperity2d.friction.laws`: a slip force of the relative speed; that module
registers them) and the asperity model's contact laws (here). This module sits low in the layers
(the scene names its law) and imports nothing of the models.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

from ._inputs import check_finite, show
from ._registry import Registry
from .errors import SceneError


@dataclass(frozen=True)
class LawParameter:
    """One parameter of a contact law: a field of the scene's contact, in SI.

    ``name`` is how ``make_scene``, a TOML scene and ``Contact(law_params=...)`` spell it (unique
    among the registered laws, so ``make_scene`` can take it as a keyword); ``default`` its value
    when not given (None: derived, as ``meaning`` says); ``unit`` its SI unit (``"1"``: a pure
    number); ``minimum`` ``"positive"`` (> 0) or ``"nonnegative"`` (>= 0).
    """

    name: str
    default: float | None
    unit: str
    meaning: str
    minimum: str = "positive"

    def check(self, value) -> float:
        """``value`` as a float in this parameter's range, or a ``SceneError`` naming it."""
        out = check_finite(self.name, value)
        if self.minimum == "positive" and out <= 0:
            raise SceneError(f"`{self.name}` must be > 0, got {show(value)}")
        if out < 0:
            raise SceneError(f"`{self.name}` must be >= 0, got {show(value)}")
        return out


class ContactLaw:
    """A per-contact friction law of the asperity model.

    Contract -- a contact law must:

    1. be a frozen dataclass built by the classmethod
       ``from_contact(contact, *, units, stick_speed, slip_distance, dt)``: the scene's
       :class:`~asperity2d.scene.Contact` (its coefficients and :attr:`parameters` in SI), the
       run's ``Units`` (``asperity2d.units``), and the switch's stick speed, slip distance and
       step already in internal units. ``from_contact`` converts every SI parameter to internal
       units once (a speed divides by ``units.velocity``, a length by ``units.length``, a time by
       ``units.time``): ``step`` works in internal units only;
    2. declare its own parameters as :attr:`parameters` (:class:`LawParameter` records, SI):
       they become fields of the contact (``Contact(law_params=...)``), keywords of
       ``make_scene``, TOML keys and rows of the parameter reference, validated there;
    3. give ``step``: ``step(state, slip, impulse, new) -> (mu, state)`` for one touching
       contact after one step -- ``slip`` the signed slip speed of the slider over the lower
       asperity along the contact's +x tangent (internal units; the largest in magnitude where a
       lower asperity touches two tips), ``impulse`` its normal impulse over the step (internal
       units, >= 0, summed over the tips), ``new`` True when the contact has just formed (then
       ``state`` is :attr:`initial`) -- returning the friction coefficient pymunk uses from the
       next step (>= 0) and the contact's new state, a tuple of the names :attr:`state_names`;
       a lost contact goes back to :attr:`initial` and the coefficient :attr:`idle` without a call;
    4. give ``steady``: the coefficient of a contact in steady sliding at ``v`` (m/s), the
       closed form the flat-block validation and ``tests/test_contact_laws.py`` check every
       registered law against;
    5. be pure: the same inputs give the same outputs, bit for bit (the golden runs and the C
       loop's comparison rely on it);
    6. set :attr:`kernel` to the name of its C implementation in ``engine/_kernel.c`` if it
       has one (held to this reference to the bit), or leave it None: the engine then runs the
       Python loop, naming the law as the reason (``Engine.loop_reason`` (``asperity2d.engine``)).

    Register it with :func:`register_law` (``model="asperity"``).
    """

    #: Name of the C step loop's implementation of this law (None: the Python loop runs it).
    kernel: str | None = None
    #: The law's own parameters (SI): fields of the scene's contact.
    parameters: tuple[LawParameter, ...] = ()
    #: Names of the per-contact state, in the order of the state tuple.
    state_names: tuple[str, ...] = ()
    #: The state of a contact that is not touching (and of one just formed, before its first step).
    initial: tuple = ()

    @classmethod
    def from_contact(cls, contact, *, units, stick_speed: float, slip_distance: float,
                     dt: float) -> "ContactLaw":
        raise NotImplementedError

    @classmethod
    def parameter(cls, contact, name: str):
        """The SI value of this law's parameter ``name`` on ``contact``: given, or its default."""
        given = dict(contact.law_params)
        if name in given:
            return given[name]
        return next(p.default for p in cls.parameters if p.name == name)

    @property
    def active(self) -> bool:
        """Whether the law ever changes a coefficient (if not, the engine skips it)."""
        return True

    @property
    def idle(self) -> float:
        """The coefficient of a contact not touching."""
        raise NotImplementedError

    def step(self, state: tuple, slip: float, impulse: float, new: bool) -> tuple[float, tuple]:
        raise NotImplementedError

    def steady(self, v: float) -> float:
        raise NotImplementedError


@dataclass(frozen=True)
class StaticKineticSwitch(ContactLaw):
    """Static / kinetic friction per contact with the hold rule (Ooten's Working Model contacts).

    A contact that forms slower than ``stick_speed`` sticks (``mu_static``); a stuck contact
    keeps ``mu_static`` until it has slid ``slip_distance`` at more than ``stick_speed`` (a
    slow creep under the solver's tolerance does not release it; its count resets whenever the
    slip drops back), then slides at ``mu_kinetic`` until its slip falls under ``stick_speed``.
    The default law; its state is ``(stuck, slid)``. C version: ``switch_update`` in
    ``engine/_kernel.c``.

    Parameters
    ----------
    mu_static, mu_kinetic : float
        The coefficients (the contact's ``mu_static`` and ``mu_kinetic``).
    stick_speed, slip_distance, dt : float
        Stick speed, slip distance and step (internal units).
    velocity : float, default 1.0
        The internal speed unit in m/s (for ``steady``, which takes m/s).

    Examples
    --------
    >>> from asperity2d.contact_laws import StaticKineticSwitch
    >>> law = StaticKineticSwitch(0.3, 0.2, stick_speed=1e-4, slip_distance=1e-3, dt=1e-2)
    >>> law.step(law.initial, 0.0, 1.0, True)  # formed at rest: stuck, at mu_static
    (0.3, (True, 0.0))
    >>> law.step((True, 0.0), 0.05, 1.0, False)  # slid 5e-4 < slip_distance: still held
    (0.3, (True, 0.0005))
    >>> law.step((True, 0.0005), -0.1, 1.0, False)  # slid past it: kinetic
    (0.2, (False, 0.0015))
    >>> law.steady(1.0), law.steady(1e-5)  # sliding faster than the stick speed, and held
    (0.2, 0.3)
    """

    mu_static: float
    mu_kinetic: float
    stick_speed: float
    slip_distance: float
    dt: float
    velocity: float = 1.0
    kernel = "static-kinetic"
    state_names = ("stuck", "slid")
    initial = (False, 0.0)

    @classmethod
    def from_contact(cls, contact, *, units, stick_speed: float, slip_distance: float,
                     dt: float) -> "StaticKineticSwitch":
        return cls(contact.mu_static, contact.mu_kinetic, stick_speed, slip_distance, dt, units.velocity)

    @property
    def active(self) -> bool:
        return self.mu_static != self.mu_kinetic

    @property
    def idle(self) -> float:
        return self.mu_kinetic

    def step(self, state: tuple, slip: float, impulse: float, new: bool) -> tuple[float, tuple]:
        """The reference: the C loop's ``stick_slip`` makes these comparisons and this sum."""
        stuck, slid = self.switch(state[0], state[1], abs(slip), new)
        return (self.mu_static if stuck else self.mu_kinetic), (stuck, slid)

    def switch(self, stuck: bool, slid: float, slip: float, new: bool) -> tuple[bool, float]:
        """``(stuck, slid)`` after a step at slip speed ``slip`` (>= 0, internal units)."""
        v_stick = self.stick_speed
        if new:
            return slip < v_stick, 0.0
        if stuck:
            if slip > v_stick:
                slid += slip * self.dt
                return (False, slid) if slid > self.slip_distance else (True, slid)
            return True, 0.0
        if slip < v_stick:
            return True, 0.0
        return False, slid

    def steady(self, v: float) -> float:
        """``mu_kinetic`` sliding faster than the stick speed; ``mu_static`` (held) below it."""
        return self.mu_kinetic if abs(v) / self.velocity > self.stick_speed else self.mu_static


@dataclass(frozen=True)
class VelocityWeakening(ContactLaw):
    """Velocity-weakening friction: mu(v) = mu_k + (mu_s - mu_k) exp(-abs(v) / v_s).

    An exponential Stribeck-type curve per contact, a function of the contact's slip speed alone
    (no state, no hold rule): ``mu_static`` at rest, falling to ``mu_kinetic`` over the speed
    ``v_s`` (the contact's ``v_s`` parameter, m/s). Its slope at v is
    -(mu_s - mu_k) exp(-v / v_s) / v_s: steady sliding of a block of normal force N on a drive
    of damping c is unstable where c + N mu'(v) < 0 (as for the belt's
    :class:`~asperity2d.friction.Stribeck` law with ``delta=1``). C version in ``engine/_kernel.c``.

    Parameters
    ----------
    mu_static, mu_kinetic : float
        The coefficient at rest and at high speed.
    v_s : float
        The weakening speed (internal units).
    velocity : float, default 1.0
        The internal speed unit in m/s.

    Examples
    --------
    >>> import asperity2d as a
    >>> scene = a.make_scene(contact_law="velocity-weakening", v_s=5.0)  # v_s in m/s
    >>> scene.contact.law, scene.contact.law_params
    ('velocity-weakening', (('v_s', 5.0),))
    >>> from asperity2d.contact_laws import VelocityWeakening
    >>> law = VelocityWeakening(mu_static=0.3, mu_kinetic=0.2, v_s=5.0)  # internal unit 1 m/s
    >>> round(law.steady(5.0), 4), law.step((), -5.0, 1.0, False)[0] == law.steady(5.0)
    (0.2368, True)
    """

    mu_static: float
    mu_kinetic: float
    v_s: float
    velocity: float = 1.0
    kernel = "velocity-weakening"
    parameters = (LawParameter("v_s", 5.0, "m/s", "velocity-weakening law: the slip speed over which mu "
                               "falls from `mu_static` towards `mu_kinetic` by 1/e (default 5 m/s, a "
                               "quarter of Ooten's drive speed)"),)

    @classmethod
    def from_contact(cls, contact, *, units, stick_speed: float, slip_distance: float,
                     dt: float) -> "VelocityWeakening":
        return cls(contact.mu_static, contact.mu_kinetic, cls.parameter(contact, "v_s") / units.velocity,
                   units.velocity)

    @property
    def active(self) -> bool:
        return self.mu_static != self.mu_kinetic

    @property
    def idle(self) -> float:
        return self.mu_kinetic

    def step(self, state: tuple, slip: float, impulse: float, new: bool) -> tuple[float, tuple]:
        """The reference of the C loop's ``velocity-weakening`` branch (the same operations)."""
        return self.mu_kinetic + (self.mu_static - self.mu_kinetic) * math.exp(-abs(slip) / self.v_s), ()

    def steady(self, v: float) -> float:
        return self.step((), v / self.velocity, 0.0, False)[0]


@dataclass(frozen=True)
class ViscousCoulomb(ContactLaw):
    """Coulomb plus viscous friction: mu(v) = mu_k + c abs(v).

    ``c`` is the contact's ``viscosity`` parameter, in s/m: the coefficient grows by ``c`` per
    m/s of slip speed, so the tangential force is N (mu_k + c abs(v)) -- a viscous force of
    damping N c (N s/m) on top of Coulomb's. No state, no hold rule (at rest the coefficient is
    ``mu_kinetic``). C version in ``engine/_kernel.c``.

    Parameters
    ----------
    mu_kinetic : float
        The Coulomb part.
    viscosity : float
        ``c`` in internal units (c [s/m] times the internal speed unit).
    velocity : float, default 1.0
        The internal speed unit in m/s.

    Examples
    --------
    >>> import asperity2d as a
    >>> a.make_scene(contact_law="viscous", viscosity=0.01).contact.law_params
    (('viscosity', 0.01),)
    >>> from asperity2d.contact_laws import ViscousCoulomb
    >>> law = ViscousCoulomb(mu_kinetic=0.2, viscosity=0.01)  # internal unit 1 m/s
    >>> round(law.steady(20.0), 6)  # 0.2 + 0.01 s/m x 20 m/s
    0.4
    """

    mu_kinetic: float
    viscosity: float
    velocity: float = 1.0
    kernel = "viscous"
    parameters = (LawParameter("viscosity", 0.005, "s/m", "viscous law: mu = `mu_kinetic` + viscosity "
                               "× slip speed (default 0.005 s/m: +0.1 at Ooten's 20 m/s)",
                               minimum="nonnegative"),)

    @classmethod
    def from_contact(cls, contact, *, units, stick_speed: float, slip_distance: float,
                     dt: float) -> "ViscousCoulomb":
        return cls(contact.mu_kinetic, cls.parameter(contact, "viscosity") * units.velocity, units.velocity)

    @property
    def active(self) -> bool:
        return self.viscosity != 0

    @property
    def idle(self) -> float:
        return self.mu_kinetic

    def step(self, state: tuple, slip: float, impulse: float, new: bool) -> tuple[float, tuple]:
        """The reference of the C loop's ``viscous`` branch (the same operations)."""
        return self.mu_kinetic + self.viscosity * abs(slip), ()

    def steady(self, v: float) -> float:
        return self.step((), v / self.velocity, 0.0, False)[0]


#: ln 2 rounded to a double (what math.log(2.0) gives); ``engine/_kernel.c`` uses the same literal
_LN2 = 0.6931471805599453


@dataclass(frozen=True)
class RateState(ContactLaw):
    """Rate-and-state friction (Dieterich-Ruina) with the ageing law, one state per contact.

    The coefficient of a contact slipping at v with state theta (a contact age, s) is
    mu = mu_0 + a ln(v / v_0) + b ln(v_0 theta / D_c), and the state ages as
    d theta / dt = 1 - v theta / D_c (J. H. Dieterich, *Modeling of rock friction 1*, J.
    Geophys. Res. 84, 1979; A. Ruina, *Slip instability and state variable friction laws*,
    J. Geophys. Res. 88, 1983). In steady sliding theta = D_c / v and
    mu_ss = mu_0 + (a - b) ln(v / v_0): velocity weakening when b > a. A step in v from v1 to
    v2 changes mu at once by a ln(v2 / v1) (the direct effect), then over a slip of a few D_c by
    (a - b) ln(v2 / v1) in all. The logarithm is regularised at v = 0 as in Rice & Ben-Zion
    (1996) and Rice, Lapusta & Ranjith (*Rate and state dependent friction and the stability of
    sliding between elastically deformable solids*, J. Mech. Phys. Solids 49, 2001):

        mu = a asinh[ v / (2 v_0) exp((mu_0 + b ln(v_0 theta / D_c)) / a) ],

    the same as the logarithmic form wherever v / v_0 exp(mu / a) >> 1 (all slip speeds the
    engine resolves), and 0 at v = 0 (a contact resists only by slipping). Over a step of
    length dt at the step's slip speed v the ageing law is integrated exactly:
    theta <- D_c / v + (theta - D_c / v) exp(-v dt / D_c), and theta <- theta + dt at v = 0,
    which is stable for any dt. It is evaluated as theta e^(-eps) - (D_c / v) expm1(-eps),
    eps = v dt / D_c: two terms >= 0, so theta stays > 0 and keeps its precision at creep
    speeds (the first form subtracts two numbers near D_c / v, which for eps under ~1e-16 left
    nothing of theta). A contact forms at the reference state theta = D_c / v_0
    (mu = mu_0 at v_0). A spring-block of stiffness k, mass m, normal force N sliding at V is
    unstable below k_c = N (b - a) / D_c (1 + m V^2 / (N a D_c)) (J. R. Rice & A. Ruina,
    *Stability of steady frictional slipping*, J. Appl. Mech. 50, 1983).

    C version: ``asp_rate_state_step`` (the ``law_kind == 3`` branch) in ``engine/_kernel.c``, the
    same operations and the same libm functions (``log``, ``exp``, ``expm1``, ``asinh``) as this
    reference, which Python's :mod:`math` calls: the two loops agree to the bit
    (``tests/test_contact_laws.py``).

    Parameters
    ----------
    a, b : float
        The direct and the evolution effect (the contact's ``rs_a``, ``rs_b``).
    d_c, v_0, dt : float
        The memory slip distance, the reference speed and the step (internal units).
    mu_0 : float
        The steady coefficient at ``v_0``.
    velocity : float, default 1.0
        The internal speed unit in m/s.

    Examples
    --------
    >>> import asperity2d as a
    >>> scene = a.make_scene(contact_law="rate-state", rs_a=0.01, rs_b=0.015, d_c=1e-9)
    >>> scene.contact.law_params
    (('rs_a', 0.01), ('rs_b', 0.015), ('d_c', 1e-09))
    >>> from asperity2d.contact_laws import RateState
    >>> law = RateState(a=0.01, b=0.015, d_c=1e-9, v_0=1.0, mu_0=0.2, dt=1e-12)  # SI as internal
    >>> round(law.steady(10.0) - law.steady(1.0), 6)  # (a - b) ln 10
    -0.011513
    >>> mu, state = law.step((law.d_c / 1.0,), 1.0, 0.0, False)  # in steady state at v_0
    >>> round(mu, 9), round(law.step(state, 10.0, 0.0, False)[0] - mu, 4)  # direct effect ~ a ln 10
    (0.2, 0.0229)
    """

    a: float
    b: float
    d_c: float
    v_0: float
    mu_0: float
    dt: float
    velocity: float = 1.0
    parameters = (
        LawParameter("rs_a", 0.01, "1", "rate-and-state law: the direct effect a"),
        LawParameter("rs_b", 0.015, "1", "rate-and-state law: the evolution (ageing) effect b; b > a "
                     "weakens with speed", minimum="nonnegative"),
        LawParameter("d_c", 1e-9, "m", "rate-and-state law: the memory slip distance D_c (default "
                     "1 nm, 0.1 % of Ooten's base)"),
        LawParameter("v_0", 1.0, "m/s", "rate-and-state law: the reference slip speed"),
        LawParameter("mu_0", None, "1", "rate-and-state law: the steady coefficient at `v_0` "
                     "(default `mu_kinetic`)", minimum="nonnegative"),
    )
    kernel = "rate-state"
    state_names = ("theta",)
    initial = (math.nan,)  # replaced on contact by the reference state D_c / v_0

    @classmethod
    def from_contact(cls, contact, *, units, stick_speed: float, slip_distance: float,
                     dt: float) -> "RateState":
        mu_0 = cls.parameter(contact, "mu_0")
        return cls(cls.parameter(contact, "rs_a"), cls.parameter(contact, "rs_b"),
                   cls.parameter(contact, "d_c") / units.length, cls.parameter(contact, "v_0") / units.velocity,
                   contact.mu_kinetic if mu_0 is None else mu_0, dt, units.velocity)

    @property
    def idle(self) -> float:
        return self.mu_0

    def coefficient(self, v: float, theta: float) -> float:
        """mu at slip speed ``v`` (>= 0) and state ``theta`` (internal units), regularised."""
        if v == 0:
            return 0.0
        x = math.log(v / (2.0 * self.v_0)) + (self.mu_0 + self.b * math.log(self.v_0 * theta / self.d_c)) / self.a
        # asinh(e^x) = x + ln 2 + O(e^(-2x)): past x = 30 the correction is below 1e-26
        return self.a * (x + _LN2 if x > 30.0 else math.asinh(math.exp(x)))

    def step(self, state: tuple, slip: float, impulse: float, new: bool) -> tuple[float, tuple]:
        v = abs(slip)
        if new:
            theta = self.d_c / self.v_0
        elif v > 0:
            # the exact solution of the ageing law at constant v over the step, as two terms >= 0
            # (no cancellation between theta and D_c / v, however slow the creep)
            eps = v * self.dt / self.d_c
            theta = state[0] * math.exp(-eps) - self.d_c / v * math.expm1(-eps)
        else:
            theta = state[0] + self.dt
        return self.coefficient(v, theta), (theta,)

    def steady(self, v: float) -> float:
        """mu_ss(v) = a asinh[v / (2 v_0) exp((mu_0 + b ln(v_0 / v)) / a)] (v in m/s, != 0)."""
        v = abs(v) / self.velocity
        if v == 0:
            raise SceneError("`v` must be != 0: rate-and-state steady sliding needs a slip speed")
        return self.coefficient(v, self.d_c / v)


@dataclass(frozen=True)
class LawEntry:
    """One friction law of the package: its ``name``, the ``model`` it serves (``"belt"``: a slip
    force of the relative speed, :class:`~.laws.FrictionLaw`; ``"asperity"``: a per-contact law,
    :class:`ContactLaw`), the class and a line saying what it is."""

    name: str
    model: str
    law: type
    description: str = ""


#: The methods an asperity-model law must define itself (a class that inherits one of these from
#: :class:`ContactLaw` unchanged is refused at registration, naming the method).
REQUIRED_METHODS = ("from_contact", "step", "idle", "steady")


def _check_law(entry) -> LawEntry:
    """``entry`` checked: a LawEntry of a known model whose class keeps its model's contract; a
    contact law's parameter names must not be taken by another contact law (``make_scene`` takes
    them as keywords)."""
    if not isinstance(entry, LawEntry):
        raise SceneError(f"`entry` must be a LawEntry, got {type(entry).__name__}")
    if entry.model not in ("belt", "asperity"):
        raise SceneError(f"`model` must be 'belt' or 'asperity', got {entry.model!r}")
    belt = entry.model == "belt"
    if not isinstance(entry.law, type) or (belt and not hasattr(entry.law, "piecewise_constant")) or (
            not belt and not issubclass(entry.law, ContactLaw)):
        raise SceneError(f"`law` of {entry.name!r} must be a {'FrictionLaw' if belt else 'ContactLaw'} "
                         f"subclass, got {entry.law!r}")
    if not belt:
        missing = [m for m in REQUIRED_METHODS
                   if getattr(entry.law, m, None) is getattr(ContactLaw, m, None)]
        if missing:
            raise SceneError(f"`law` {entry.name!r} ({entry.law.__name__}) does not define "
                             f"{', '.join(missing)} (the ContactLaw contract)")
        for p in entry.law.parameters:
            owner = next((k for k, e in LAWS.items() if k != entry.name and e.model == "asperity"
                          and any(q.name == p.name for q in e.law.parameters)), None)
            if owner is not None:
                raise SceneError(f"`parameters` of {entry.name!r}: {p.name!r} is already a parameter of "
                                 f"the contact law {owner!r}")
    return entry


def _adapt_law(obj, name: str) -> LawEntry:
    """What an entry point or ``"module:Class"`` names, made a LawEntry: an entry as it is; a
    :class:`ContactLaw` subclass under that name (its docstring's first line describes it)."""
    if isinstance(obj, type) and issubclass(obj, ContactLaw):
        return LawEntry(name, "asperity", obj, ((obj.__doc__ or "").strip().splitlines() or [""])[0])
    return obj


#: Every friction law: name -> :class:`LawEntry`, for both models (a
#: ``Registry`` (``asperity2d._registry``): an installed package adds its own through the entry-point
#: group ``asperity2d.contact_laws``, and ``"module:Class"`` works wherever a law's name does).
LAWS: Registry = Registry("contact law", "asperity2d.contact_laws", key=lambda e: e.name, check=_check_law,
                          adapt=_adapt_law, param="law")
#: The asperity model's law when the scene names none.
DEFAULT_CONTACT_LAW = "static-kinetic"


def register_law(entry: LawEntry, *, replace: bool = False) -> LawEntry:
    """Add ``entry`` to :data:`LAWS`; a name already taken raises ``SceneError`` unless ``replace``."""
    return LAWS.register(entry, replace=replace)


def unregister_law(name: str) -> LawEntry:
    """Remove the law ``name`` from :data:`LAWS` and return its entry."""
    return LAWS.unregister(name)


def contact_law(name: str) -> type:
    """The asperity model's contact law class registered as ``name`` (or named
    ``"module:Class"``)."""
    entry = LAWS.lookup(name, "law")
    if entry.model != "asperity":
        known = [k for k, e in LAWS.items() if e.model == "asperity"]
        raise SceneError(f"`law` must be one of {', '.join(known)}, got {name!r} (a law of the belt chains)")
    return entry.law


def check_law_params(law: str, params) -> tuple[tuple[str, float], ...]:
    """The contact law ``law``'s parameters ``params`` (a mapping or ``(name, value)`` pairs, SI)
    checked and in the law's order, as the scene's contact holds them; a name the law does not
    declare, or a value out of its range, is a ``SceneError`` naming it."""
    cls = contact_law(law)
    if isinstance(params, Mapping):
        pairs = list(params.items())
    else:
        try:
            pairs = [tuple(p) for p in params]
        except TypeError:
            pairs = [()]
        if any(len(p) != 2 for p in pairs):
            raise SceneError(f"`law_params` must be a mapping of parameter names to values, got {show(params)}")
    declared = {p.name: p for p in cls.parameters}
    given = {}
    for name, value in pairs:
        if name not in declared:
            allowed = ", ".join(declared) or "none"
            raise SceneError(f"`{name}` is not a parameter of the contact law {law!r} (its parameters: {allowed})")
        if name in given:
            raise SceneError(f"`{name}` given twice in `law_params`")
        given[name] = declared[name].check(value)
    return tuple((p.name, given[p.name]) for p in cls.parameters if p.name in given)


for _name, _cls, _line in (
        ("static-kinetic", StaticKineticSwitch, "per-contact static/kinetic switch with a slip distance"),
        ("velocity-weakening", VelocityWeakening, "mu_k + (mu_s - mu_k) exp(-|v| / v_s) per contact"),
        ("viscous", ViscousCoulomb, "Coulomb plus viscous: mu_k + c |v| per contact"),
        ("rate-state", RateState, "Dieterich-Ruina rate-and-state friction, ageing law, per contact")):
    register_law(LawEntry(_name, "asperity", _cls, _line))
del _name, _cls, _line
