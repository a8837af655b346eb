"""Friction laws of the asperity model, and the one registry of the friction laws of both models.

The asperity model applies friction per contact: each lower asperity touching the slider
carries a coefficient that pymunk's contact solver uses, and a *contact law* decides it every
step from the contact's slip speed. The law is a small state machine per contact (stuck or
sliding, the distance slid since it stuck) with a plain-Python reference implementation,
:meth:`ContactLaw.step`; the engine's Python step loop calls exactly that reference, and the
C step loop (``engine/_kernel.c``) implements the laws named by their :attr:`ContactLaw.kernel`
and is held to the reference's bits (``tests/test_engine_kernel.py``). For any other law the
engine steps in Python and says why (:attr:`asperity2d.engine.Engine.loop_reason`).

:data:`LAWS` lists every friction law of the package with the model it serves: the belt
chains' laws (:mod:`asperity2d.friction.laws`: a slip force of the relative speed; that module
registers them) and the asperity model's contact laws (here). This module sits low in the layers
(the scene names its law) and imports nothing of the models.
"""

from __future__ import annotations

from dataclasses import dataclass

from ._registry import Registry
from .errors import SceneError


class ContactLaw:
    """A per-contact friction law of the asperity model (internal units).

    Contract -- a new contact law must:

    1. be a frozen dataclass built by ``from_contact(contact, stick_speed, slip_distance, dt)``
       (the scene's :class:`~asperity2d.scene.Contact`, and the stick speed, slip distance and
       step already in internal units);
    2. keep its state per contact as ``(stuck, slid)`` (a bool and a float) and give it in
       :meth:`step`: ``step(stuck, slid, slip, new) -> (stuck, slid)`` from the contact's slip
       speed ``slip`` this step (>= 0), ``new`` True when the contact has just formed; a lost
       contact resets to ``(False, 0.0)`` without calling it;
    3. give the coefficient of a state, :meth:`coefficient` ``(stuck) -> mu``, and the
       coefficient of a contact that is not touching (:attr:`idle`);
    4. be pure: the same inputs give the same outputs, bit for bit (the golden runs and the C
       loop's comparison rely on it);
    5. set :attr:`kernel` to the name of its C implementation in ``engine/_kernel.c`` if it
       has one (held to this reference to the bit by ``tests/test_engine_kernel.py``), or
       leave it None: the engine then runs the Python loop, naming the law as the reason.

    Register it with :func:`register_law` (``model="asperity"``).
    """

    #: Name of the C step loop's implementation of this law (None: the Python loop runs it).
    kernel: str | None = None

    @property
    def active(self) -> bool:
        """Whether the law ever changes a coefficient (if not, the engine skips it)."""
        return True

    @property
    def idle(self) -> float:
        """The coefficient of a contact not touching."""
        raise NotImplementedError

    def coefficient(self, stuck: bool) -> float:
        raise NotImplementedError

    def step(self, stuck: bool, slid: float, slip: float, new: bool) -> tuple[bool, float]:
        raise NotImplementedError


@dataclass(frozen=True)
class StaticKineticSwitch(ContactLaw):
    """Static / kinetic friction per contact (Ooten's Working Model contacts).

    A contact that forms slower than ``stick_speed`` sticks (``mu_static``); a stuck contact
    keeps ``mu_static`` until it has slid ``slip_distance`` at more than ``stick_speed`` (a
    slow creep under the solver's tolerance does not release it; its count resets whenever the
    slip drops back), then slides at ``mu_kinetic`` until its slip falls under ``stick_speed``.
    """

    mu_static: float
    mu_kinetic: float
    stick_speed: float
    slip_distance: float
    dt: float
    kernel = "static-kinetic"

    @classmethod
    def from_contact(cls, contact, stick_speed: float, slip_distance: float, dt: float) -> "StaticKineticSwitch":
        return cls(contact.mu_static, contact.mu_kinetic, stick_speed, slip_distance, dt)

    @property
    def active(self) -> bool:
        return self.mu_static != self.mu_kinetic

    @property
    def idle(self) -> float:
        return self.mu_kinetic

    def coefficient(self, stuck: bool) -> float:
        return self.mu_static if stuck else self.mu_kinetic

    def step(self, stuck: bool, slid: float, slip: float, new: bool) -> tuple[bool, float]:
        """The reference: the C loop's ``switch_update`` makes these comparisons and this sum."""
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
REQUIRED_METHODS = ("from_contact", "step", "coefficient", "idle")


def _check_law(entry) -> LawEntry:
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
    return entry


def _adapt_law(obj, name: str) -> LawEntry:
    """What an entry point or ``"module:Class"`` names, made a LawEntry: an entry as it is; a
    :class:`ContactLaw` subclass under that name (its docstring's first line describes it)."""
    if isinstance(obj, type) and issubclass(obj, ContactLaw):
        return LawEntry(name, "asperity", obj, ((obj.__doc__ or "").strip().splitlines() or [""])[0])
    return obj


#: Every friction law: name -> :class:`LawEntry`, for both models (a
#: :class:`~asperity2d._registry.Registry`: an installed package adds its own through the entry-point
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


register_law(LawEntry("static-kinetic", "asperity", StaticKineticSwitch,
                      "per-contact static/kinetic switch with a slip distance"))
