"""Closed-form checks: each runs the model on a case with a known answer and reports the error.

Every check is a function returning a :class:`Check` record: its name, the
closed form, the expected and measured values, the relative error, the
tolerance (with why it is that size) and the source of the closed form. The
test suite parametrizes over :data:`CHECKS` (``tests/test_closed_forms.py``) and
the documentation's validation page tabulates the same records, so the page
shows the errors the tests accept, measured at build time.

Check an installation from the command line::

    asperity2d validate          # the table; exit status 1 if a check fails

The asperity checks run small pymunk scenes (under a second each); the belt
checks run the exact event-driven solver; the contact-law checks run the flat block
(2 to 6 s each). The whole set takes about 45 s of CPU.

References for the closed forms:

* the wedge (flank) law: pushing a load W up a rigid flank at angle θ with
  friction angle φ = atan μ takes W tan(θ + φ) (statics of a block on a wedge);
* a block on an incline slides if and only if tan θ > μ; pushed horizontally
  under a normal load N, it moves from rest if and only if F > μs N;
* a mass on a belt, spring k to a wall, static / kinetic forces Fs > Fk: it
  sticks until k x = Fs, slips harmonically about Fk / k and the spring force
  drops by exactly 2 (Fs - Fk) from the slip's start to the next stick (J. P.
  Den Hartog, *Forced vibrations with combined Coulomb and viscous friction*,
  Trans. ASME APM 53, 1931);
* the same block driven through a spring whose far end moves at V, on a fixed
  floor (the asperity model's flat block): with the classical instant switch
  to Fk the spring force peaks at Fk + sqrt((Fs - Fk)**2 + k m V**2); with this
  model's hold rule (a stuck contact keeps mu_s until it has slid its
  ``slip_distance`` d) it peaks at Fs + V sqrt(k m) once omega d / V >= pi/2 - 1,
  the block catching up with the drive before the hold releases (every flat
  block here: 0.72 at 5 m/s on 37.2 kN/m); in between, and the drops and peak
  speeds, :func:`asperity2d.analysis.spring_block_slip`;
* Coulomb free decay: the amplitude falls by 4 Fk / k per cycle and the
  period stays 2π / ω;
* the normal modes of a fixed-fixed chain of n equal masses and springs:
  ω_j = 2 sqrt(k / m) sin(jπ / (2(n + 1)));
* Hoffmann's minimal model of mode-coupling flutter (N. Hoffmann, M. Fischer,
  R. Allgaier, L. Gaul, *A minimal model for studying properties of the
  mode-coupling type instability in friction induced oscillations*, Mech.
  Res. Commun. 29, 2002): its flutter onset μ_crit and growth rates from
  the characteristic polynomial (:mod:`asperity2d.belt.contact.minimal`);
* the asperity contact laws (:mod:`asperity2d.contact_laws`) on the flat block: each law's
  steady curve μ_ss(v) in steady sliding; rate-and-state friction's direct effect a ln(v2/v1)
  and steady change (a - b) ln(v2/v1) (J. H. Dieterich, *Modeling of rock friction 1*, J.
  Geophys. Res. 84, 1979; A. Ruina, *Slip instability and state variable friction laws*, J.
  Geophys. Res. 88, 1983), and its spring-block's critical stiffness
  k_c = N (b - a) / D_c (1 + m V² / (N a D_c)) (J. R. Rice & A. Ruina, *Stability of steady
  frictional slipping*, J. Appl. Mech. 50, 1983); velocity weakening's critical damper
  c = -N μ'(V), the belt chains' criterion.
"""

from __future__ import annotations

import contextlib
import contextvars
import math
from dataclasses import dataclass
from typing import Callable


G = 9.81  # m/s^2, the belt chains' default gravity
#: Ooten's Table 1 steel: lower asperity stiffness (N/m) and base (m).
STEEL_STIFFNESS, BASE = 37_200.0, 1e-6


@dataclass(frozen=True)
class Check:
    """One closed-form check and its outcome.

    Attributes
    ----------
    name : str
        What is checked, in words.
    closed_form : str
        The formula the model is checked against.
    expected : float
        The closed form's value, in ``unit``.
    measured : float
        What the model gave, in ``unit``.
    unit : str
        SI unit of both values (``"1"`` for a pure number).
    tolerance : float
        The largest relative error the check (and the test suite) accepts.
    why : str
        Why the tolerance is that size.
    source : str
        Where the closed form comes from.
    """

    name: str
    closed_form: str
    expected: float
    measured: float
    unit: str
    tolerance: float
    why: str
    source: str

    @property
    def error(self) -> float:
        """Relative error abs(measured - expected) / abs(expected) (absolute when expected is 0)."""
        scale = abs(self.expected) if self.expected != 0 else 1.0
        return abs(self.measured - self.expected) / scale

    @property
    def passed(self) -> bool:
        """True when :attr:`error` is within ``tolerance`` (and both values are finite)."""
        return math.isfinite(self.measured) and self.error <= self.tolerance

    def to_dict(self) -> dict:
        """The record as plain values, with its error and verdict (``asperity2d validate --json``)."""
        return {**self.__dict__, "error": self.error, "passed": self.passed}

    def line(self) -> str:
        """One line for a terminal: verdict, name, expected and measured, error, tolerance."""
        return (f"{'ok  ' if self.passed else 'FAIL'} {self.name}: expected {self.show(self.expected)}, "
                f"measured {self.show(self.measured)}, error {self.error:.2g} (tolerance {self.tolerance:.2g})")

    def show(self, value: float, digits: int = 4) -> str:
        """``value`` in this check's unit with an SI prefix (a plain number for a pure number)."""
        from .._format import number, si

        if self.unit == "1":
            return number(value, digits) if abs(value) >= 1e-3 or value == 0 else f"{value:.{digits - 1}e}"
        return si(value, self.unit, digits)


#: The registry: check id -> a function of no arguments returning a :class:`Check`.
CHECKS: dict[str, Callable[[], Check]] = {}
#: Check id -> the asperity engines it runs on (the reference alone unless registered with more).
ENGINES_OF: dict[str, tuple[str, ...]] = {}
#: The engines a check of the asperity model's mechanics runs on (``asperity2d validate --engine``).
ASPERITY_ENGINES = ("pymunk", "batched")
_ENGINE: contextvars.ContextVar = contextvars.ContextVar("asperity2d_closed_forms_engine", default="pymunk")


def current_engine() -> str:
    """The asperity engine the checks now running use (:func:`run_all`'s ``engine``)."""
    return _ENGINE.get()


def _register(check_id: str, function: Callable[[], Check], engines: tuple[str, ...] = ("pymunk",)) -> None:
    if check_id in CHECKS:
        raise ValueError(f"check {check_id!r} registered twice")
    CHECKS[check_id] = function
    ENGINES_OF[check_id] = tuple(engines)


def registered(check_id: str, *, engines: tuple[str, ...] = ("pymunk",)):
    """Decorator: add a no-argument check function to :data:`CHECKS` under ``check_id``, run on
    ``engines`` (the asperity engines it is a check of; the reference's alone by default)."""
    def add(function):
        _register(check_id, function, engines)
        return function
    return add


def run_all(ids=None, *, engine: str = "pymunk") -> list[Check]:
    """Run the checks named in ``ids`` (default all that run on ``engine``, in registry order) and
    return their records. ``engine``: the asperity engine the asperity checks run on
    (``asperity2d.engine.ENGINES``); naming a check that is not one of ``engine``'s (the belt's, the
    energy books, the other contact laws on ``"batched"``) is refused, naming it."""
    from ..engine.registry import check_engine
    from ..errors import SceneError

    engine = check_engine(engine)
    ids = [i for i in CHECKS if engine in ENGINES_OF[i]] if ids is None else list(ids)
    unknown = [i for i in ids if i not in CHECKS]
    if unknown:
        raise SceneError(f"`ids` has unknown checks {unknown}; known: {', '.join(CHECKS)}")
    other = [i for i in ids if engine not in ENGINES_OF[i]]
    if other:
        raise SceneError(f"`ids` has checks that do not run on engine={engine!r}: {', '.join(other)} "
                         "(engine=\"pymunk\" runs them)")
    with using(engine):
        return [CHECKS[i]() for i in ids]


@contextlib.contextmanager
def using(engine: str):
    """Within the block, the asperity checks run on ``engine`` (a checked name)."""
    token = _ENGINE.set(engine)
    try:
        yield engine
    finally:
        _ENGINE.reset(token)


# the checks register themselves on import
from . import asperity, belt, laws  # noqa: E402,F401
from .asperity import single_asperity  # noqa: E402,F401
from .belt import one_dof_cycle  # noqa: E402,F401
from .laws import LAW_BLOCK, LAW_CASES, LAW_SPEEDS, contact_law_of, steady_friction  # noqa: E402,F401
