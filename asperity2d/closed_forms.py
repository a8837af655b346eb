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

import functools
import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

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
        from ._format import number, si

        if self.unit == "1":
            return number(value, digits) if abs(value) >= 1e-3 or value == 0 else f"{value:.{digits - 1}e}"
        return si(value, self.unit, digits)


#: The registry: check id -> a function of no arguments returning a :class:`Check`.
CHECKS: dict[str, Callable[[], Check]] = {}


def _register(check_id: str, function: Callable[[], Check]) -> None:
    if check_id in CHECKS:
        raise ValueError(f"check {check_id!r} registered twice")
    CHECKS[check_id] = function


def registered(check_id: str):
    """Decorator: add a no-argument check function to :data:`CHECKS` under ``check_id``."""
    def add(function):
        _register(check_id, function)
        return function
    return add


def run_all(ids=None) -> list[Check]:
    """Run the checks named in ``ids`` (default all, in registry order) and return their records."""
    ids = list(CHECKS) if ids is None else list(ids)
    unknown = [i for i in ids if i not in CHECKS]
    if unknown:
        from .errors import SceneError

        raise SceneError(f"`ids` has unknown checks {unknown}; known: {', '.join(CHECKS)}")
    return [CHECKS[i]() for i in ids]


# -- the asperity engine (pymunk) -----------------------------------------------------------------
def single_asperity(theta: float, mu: float):
    """One tip on the front flank of one lower asperity, a free slider under a light load W.

    The drive spring is preloaded to the frictionless balance W tan(θ), so the slider neither
    slides back nor moves until friction is overcome, and the drive (1 m/s = 9e-5 of base x ω)
    is slow enough that the overshoot at breakaway is under a percent.
    """
    from .builders import make_scene

    height = 0.5 * BASE * math.tan(math.radians(theta))
    load = 0.05 * STEEL_STIFFNESS * height  # the lower spring deflects 5 % of the height
    scene = make_scene(lower_count=1, upper_count=1, flank_angle=theta, mu=mu, track="free",
                       normal_load=load, slider_mass=2.88e-16, drive_velocity=1.0,
                       drive_preload=load * math.tan(math.radians(theta)))
    return scene, load


def _wedge(theta: float, mu: float) -> Check:
    from .run import simulate

    scene, load = single_asperity(theta, mu)
    result = simulate(scene, progress=False)
    return Check(
        name=f"wedge law, θ = {theta:g}°, μ = {mu:g}",
        closed_form="F / W = tan(θ + atan μ)",
        expected=math.tan(math.radians(theta) + math.atan(mu)),
        measured=float(result.drive_force.max() / load) if result.status == "passed" else math.nan,
        unit="1", tolerance=0.02,
        why="a quasi-static law met by a moving drive: the dynamic overshoot at breakaway grows "
            "with the drive speed (3.6 % at 5 m/s, under 1 % at 1 m/s)",
        source="statics of a block pushed up a rigid wedge")


for _theta, _mu in ((45.0, 0.3), (30.0, 0.5), (60.0, 0.2), (20.0, 0.1)):
    _register(f"wedge-{_theta:g}-{_mu:g}", functools.partial(_wedge, _theta, _mu))


@functools.lru_cache(maxsize=1)
def _flat_block_run():
    """A flat block (μs 0.4, μk 0.3) under 2 mN on one flat lower block, spring-driven at 5 m/s."""
    from .builders import make_scene
    from .run import simulate

    load = 0.002
    scene = make_scene(profile="flat", height=0.25e-6, lower_count=1, upper_count=1, track="free",
                       mu_static=0.4, mu_kinetic=0.3, normal_load=load, drive_velocity=5.0)
    return simulate(scene, duration=3e-7, record_every=1, progress=False), scene, load


@registered("flat-block-static")
def flat_block_static() -> Check:
    """Up to breakaway friction balances the drive and peaks at the static limit μs N."""
    result, scene, load = _flat_block_run()
    moved = result.x - result.x[0]
    before = moved < 0.01 * BASE  # until the block has slid 1 % of a base
    return Check(
        name="flat block breaks away at the static limit",
        closed_form="F = μs N", expected=scene.contact.mu_static * load,
        measured=float(result.friction_force[before].max()), unit="N", tolerance=0.01,
        why="force balance in a stick phase is exact up to the solver's convergence (0.01 % "
            "measured)", source="Coulomb's law of static friction")


@registered("flat-block-kinetic")
def flat_block_kinetic() -> Check:
    """Sliding on the lower block (well above the drive speed), friction is μk N."""
    result, scene, load = _flat_block_run()
    moved = result.x - result.x[0]
    sliding = (moved >= 0.01 * BASE) & (moved < 0.5 * BASE) & (result.v > 2 * scene.drive.velocity)
    return Check(
        name="flat block slides at the kinetic limit",
        closed_form="F = μk N", expected=scene.contact.mu_kinetic * load,
        measured=float(np.median(result.friction_force[sliding])) if sliding.any() else math.nan,
        unit="N", tolerance=0.01,
        why="the median over the sliding samples; the contact impulses converge to 0.01 %",
        source="Coulomb's law of kinetic friction")


@registered("incline")
def incline() -> Check:
    """The incline law as a push: a flat block under N moves from rest iff F > μs N."""
    from .builders import make_scene
    from .critical import critical_force

    load, mu_s = 0.002, 0.4
    scene = make_scene(profile="flat", height=0.25e-6, lower_count=1, upper_count=1, track="free",
                       mu_static=mu_s, mu_kinetic=0.3, normal_load=load, drive="force")
    return Check(
        name="a block moves from rest only above μs N (the incline's tan θ > μ)",
        closed_form="F_crit / N = μs (tan θ_crit = μ)", expected=mu_s,
        measured=critical_force(scene, rel_tol=0.0025) / load, unit="1", tolerance=0.005,
        why="bisected to 0.25 %: the value is the bracket's passing end, at most 0.25 % above the "
            "threshold; twice that allows for the contact solver's convergence",
        source="Coulomb friction on an incline: slides if and only if tan θ > μ")


@functools.lru_cache(maxsize=1)
def _stuck_run():
    from .builders import make_scene
    from .run import simulate

    load = 0.01
    scene = make_scene(lower_count=6, upper_count=2, normal_load=load, track="free")
    result = simulate(scene, duration=4e-8, progress=False)
    stuck = np.abs(result.v) < 0.05 * scene.drive.velocity
    return result, stuck, load


@registered("balance-tangential")
def balance_tangential() -> Check:
    """While stuck, the contacts' tangential force on the slider balances the drive."""
    result, stuck, _ = _stuck_run()
    return Check(
        name="stuck slider: friction balances the drive (mean over the stick phase)",
        closed_form="Σ F_t = F_drive", expected=float(np.mean(result.drive_force[stuck])),
        measured=float(np.mean(result.friction_force[stuck])), unit="N", tolerance=0.01,
        why="exact up to the contact solver's convergence (0.01 % measured)",
        source="Newton's second law at rest")


@registered("balance-normal")
def balance_normal() -> Check:
    """While stuck, the contacts' normal force on a free slider balances its load."""
    result, stuck, load = _stuck_run()
    return Check(
        name="stuck free slider: the contacts carry its load (mean over the stick phase)",
        closed_form="Σ F_n = L", expected=load, measured=float(np.mean(result.normal_force[stuck])),
        unit="N", tolerance=0.01,
        why="exact up to the contact solver's convergence (0.01 % measured)",
        source="Newton's second law at rest")


@registered("flank-law-all-tips")
def flank_law_all_tips() -> Check:
    """Ooten's fixed track, regular spacing: every tip pushes its asperity down by the
    interference δ at once, so the largest stick force is n k δ tan(45° + atan μs)."""
    from .analysis import peak_stick_force
    from .builders import make_scene
    from .run import simulate

    scene = make_scene(lower_count=8, upper_count=3)
    result = simulate(scene, progress=False)
    n, k, delta = scene.slider.count, scene.lower.stiffness[0], scene.slider.interference
    return Check(
        name="peak stick force of n tips on Ooten's fixed track (8 lower, 3 upper)",
        closed_form="n k δ tan(45° + atan μs)",
        expected=n * k * delta * math.tan(math.radians(45.0) + math.atan(scene.contact.mu_static)),
        measured=peak_stick_force(result), unit="N", tolerance=0.02,
        why="quasi-static law met by a spring drive at 20 m/s: the dynamic overshoot is under "
            "0.1 % measured; 2 % allows for it",
        source="the wedge law, summed over the tips that engage together")


@functools.lru_cache(maxsize=1)
def _asperity_books() -> dict:
    """The energy books of the validation page's asperity run (free slider, 3/1, frictionless,
    undamped, spring drive at 50 m/s, the default step)."""
    from .builders import make_scene
    from .run import simulate

    scene = make_scene(lower_count=3, upper_count=1, mu=0.0, damping_ratio=0.0, track="free",
                       drive_velocity=50.0)
    return dict(simulate(scene, energy=True, progress=False).meta["energy"])


@registered("energy-books-asperity")
def energy_books_asperity() -> Check:
    """Every energy flow of a run is metered: the books close -- by construction, since every
    flow the numerical method makes is one of their channels (the check is the next one)."""
    e = _asperity_books()
    return Check(
        name="energy books of an asperity run close (free slider, spring drive)",
        closed_form="drive work = Δ stored + dissipated + numerical",
        expected=e["drive_work_J"], measured=e["stored_energy_change_J"] + e["dissipated_J"] + e["numerical_J"],
        unit="J", tolerance=1e-6,
        why="closes by construction: position correction, track projection and the integrator's "
            "term are channels of the books, so this shows only that no flow is unmetered; what is "
            "left is the hanging track springs' geometric non-linearity, 1e-14 - 1e-13 measured",
        source="conservation of energy")


@registered("energy-books-numerical")
def energy_books_numerical() -> Check:
    """What the numerical method took, as a share of the drive work: the books' real check."""
    from .run import NUMERICAL_ENERGY_TOLERANCE

    e = _asperity_books()
    return Check(
        name="numerical channels of the same run (position correction, projection, integrator, "
             "track drift) as a share of the drive work",
        closed_form="0 (the exact dynamics make none)",
        expected=0.0, measured=e["numerical_fraction"], unit="1", tolerance=NUMERICAL_ENERGY_TOLERANCE,
        why="it shrinks with dt (1.31 %, 0.81 %, 0.26 % at dt, dt/2, dt/4) and each halving moves "
            "the physical books by 0.40-0.68 of it: above 2.5 % one halving would move them by more "
            "than the 1 % the step policy allows; every metered run is flagged above it",
        source="a dt study of this run (asperity2d.run.NUMERICAL_ENERGY_TOLERANCE)")


# -- belt chains (exact event-driven solver) --------------------------------------------------------
_BELT = dict(m=1.0, k=10.0, mu_s=0.3, mu_k=0.2, V=0.1)  # kg, N/m, 1, 1, m/s


def one_dof_cycle(m, k, mu_s, mu_k, V):
    """Closed-form stick-slip cycle of a mass on a belt tied to a wall by spring k: Fs, Fk and the
    slip and stick durations (s)."""
    Fs, Fk = mu_s * m * G, mu_k * m * G
    w = math.sqrt(k / m)
    d = (Fs - Fk) / k  # slip starts d above the kinetic equilibrium Fk/k
    phi = math.atan2(d * w, V)
    return Fs, Fk, (2 * math.pi - 2 * phi) / w, 2 * d / V


@functools.lru_cache(maxsize=1)
def _belt_run():
    from .belt import simulate_chain

    m, k, mu_s, mu_k, V = (_BELT[n] for n in ("m", "k", "mu_s", "mu_k", "V"))
    Fs, Fk, t_slip, t_stick = one_dof_cycle(m, k, mu_s, mu_k, V)
    t_first, cycles = Fs / (k * V), 100
    r = simulate_chain([m], [k, 0.0], [0.0, 0.0], mu_s=mu_s, mu_k=mu_k, v_belt=V, x0=[0.0], v0=[V],
                       t_end=t_first + cycles * (t_slip + t_stick) + 0.5 * t_slip, n_samples=200)
    slips = [e for e in r.events if e.kind == "slip"]
    sticks = [e for e in r.events if e.kind == "stick"]
    return r, slips, sticks


_BELT_WHY = "event times and positions are located to machine precision; 1e-8 is the solver's contract"


@registered("belt-breakaway")
def belt_breakaway() -> Check:
    """The mass sticks until the spring force reaches the static limit."""
    r, slips, _ = _belt_run()
    k = _BELT["k"]
    forces = np.array([k * e.x for e in slips])
    Fs = _BELT["mu_s"] * _BELT["m"] * G
    return Check(
        name="mass on a belt: breaks away at the static limit (worst of 101 slips)",
        closed_form="k x = Fs = μs m g", expected=Fs,
        measured=float(forces[np.argmax(np.abs(forces - Fs))]), unit="N", tolerance=1e-8,
        why=_BELT_WHY, source="Den Hartog (1931); DESIGN.md section 6")


@registered("belt-force-drop")
def belt_force_drop() -> Check:
    """Den Hartog: the spring force drops by exactly 2 (Fs - Fk) over a slip."""
    r, slips, sticks = _belt_run()
    k = _BELT["k"]
    drops = np.array([k * (a.x - b.x) for a, b in zip(slips, sticks)])
    want = 2 * (_BELT["mu_s"] - _BELT["mu_k"]) * _BELT["m"] * G
    return Check(
        name="mass on a belt: spring force drop per slip (worst of 100)",
        closed_form="ΔF = 2 (Fs - Fk)", expected=want,
        measured=float(drops[np.argmax(np.abs(drops - want))]), unit="N", tolerance=1e-8,
        why=_BELT_WHY, source="Den Hartog (1931); DESIGN.md section 6")


@registered("belt-period")
def belt_period() -> Check:
    """The stick-slip period: harmonic slip back to belt speed, then a stick at belt speed."""
    r, slips, _ = _belt_run()
    _, _, t_slip, t_stick = one_dof_cycle(*(_BELT[n] for n in ("m", "k", "mu_s", "mu_k", "V")))
    times = np.array([e.t for e in slips])
    return Check(
        name="mass on a belt: stick-slip period (mean of 100 cycles)",
        closed_form="T = (2π - 2 atan(ω d / V)) / ω + 2 d / V, d = (Fs - Fk) / k",
        expected=t_slip + t_stick, measured=float(np.mean(np.diff(times))), unit="s", tolerance=1e-8,
        why=_BELT_WHY, source="Den Hartog (1931)")


@functools.lru_cache(maxsize=1)
def _free_decay():
    from .belt import simulate_chain

    m, k, x0, mu = 1.0, 10.0, 2.0, 0.05  # about 10 cycles before it stops
    Fk = mu * m * G
    w = math.sqrt(k / m)
    r = simulate_chain([m], [k, 0.0], [0.0, 0.0], mu_s=mu, mu_k=mu, v_belt=0.0, x0=[x0], v0=[0.0],
                       t_end=30 * math.pi / w)
    reversals = [e for e in r.events if e.kind == "reverse"]
    return reversals, Fk, k, w


@registered("coulomb-decay-amplitude")
def coulomb_decay_amplitude() -> Check:
    """Coulomb free decay on a still surface: the amplitude falls by 4 Fk / k per cycle."""
    reversals, Fk, k, _ = _free_decay()
    amplitudes = np.abs([e.x for e in reversals])
    per_cycle = amplitudes[:-2] - amplitudes[2:]
    want = 4 * Fk / k
    return Check(
        name="Coulomb free decay: amplitude lost per cycle (worst cycle)",
        closed_form="Δx = 4 Fk / k", expected=want,
        measured=float(per_cycle[np.argmax(np.abs(per_cycle - want))]), unit="m", tolerance=1e-10,
        why="turning points are event-located to machine precision",
        source="Coulomb damping of a free oscillator; DESIGN.md section 6")


@registered("coulomb-decay-period")
def coulomb_decay_period() -> Check:
    """Coulomb friction does not change the period of free vibration."""
    reversals, _, _, w = _free_decay()
    return Check(
        name="Coulomb free decay: the period stays that of the free oscillator",
        closed_form="T = 2π / ω", expected=2 * math.pi / w,
        measured=float(2 * np.mean(np.diff([e.t for e in reversals]))), unit="s", tolerance=1e-10,
        why="turning points are event-located to machine precision",
        source="Coulomb damping of a free oscillator; DESIGN.md section 6")


def _chain_mode(j: int) -> Check:
    """Mode j of the 3-mass chain of the multi-DOF belt thesis' Table 2 (m = 1 kg, k = 10 N/m),
    frictionless, started in the mode's shape: its period from the simulated motion."""
    from .belt import simulate_chain

    n, m, k = 3, 1.0, 10.0
    omega = 2 * math.sqrt(k / m) * math.sin(j * math.pi / (2 * (n + 1)))
    shape = [0.01 * math.sin(i * j * math.pi / (n + 1)) for i in range(1, n + 1)]
    periods = 20
    r = simulate_chain([m] * n, [k] * (n + 1), [0.0] * (n + 1), mu_s=0.0, v_belt=0.0, x0=shape,
                       v0=[0.0] * n, t_end=periods * 2 * math.pi / omega + 1.0, n_samples=40_001)
    x = r.x[0] / shape[0]
    up = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    crossings = r.t[up] - x[up] * (r.t[up + 1] - r.t[up]) / (x[up + 1] - x[up])  # linear interpolation
    f = 1.0 / np.mean(np.diff(crossings))
    return Check(
        name=f"belt chain normal mode {j} of 3 (Table 2 chain, frictionless)",
        closed_form="f_j = sqrt(k (2 - 2 cos(jπ/4)) / m) / 2π", expected=omega / (2 * math.pi),
        measured=float(f), unit="Hz", tolerance=1e-6,
        why="zero crossings interpolated linearly between samples 1/2000 of a period apart "
            "(error ~1e-8 of the period)",
        source="normal modes of a fixed-fixed chain of equal masses and springs")


for _j in (1, 2, 3):
    _register(f"chain-mode-{_j}", functools.partial(_chain_mode, _j))


@registered("energy-books-belt")
def energy_books_belt() -> Check:
    """Belt work = change of kinetic and spring energy + friction and damper dissipation."""
    from .belt import simulate_chain

    r = simulate_chain([1.0, 1.5, 0.7], [10.0, 20.0, 5.0, 10.0], [0.5, 0.0, 1.0, 0.3], mu_s=0.4,
                       mu_k=0.25, v_belt=0.2, x0=[0.05, -0.02, 0.07], v0=[0.04, 0.3, -0.1], t_end=15)
    return Check(
        name="energy books of a 3-mass chain with dampers, across stick-slip switches",
        closed_form="(belt work - Δ energy - dissipation) / belt work = 0", expected=0.0,
        measured=float(r.energy_balance_error()), unit="1", tolerance=1e-8,
        why="closed-form phases and exactly located switches: round-off only",
        source="conservation of energy")


@registered("minimal-mu-crit")
def minimal_mu_crit() -> Check:
    """Bisection on μ of 'the solver's sliding phase has a growing mode' against μ_crit."""
    from .belt import MinimalModel, steady_sliding

    mm = MinimalModel()
    threshold = 1e-6 * mm.coalescence_frequency

    def grows(mu):
        return steady_sliding(**mm.chain(mu=mu, v_belt=5.0, t_end=1.0)).growth_rate > threshold

    lo, hi = 0.3, 0.6
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if grows(mid) else (mid, hi)
    return Check(
        name="Hoffmann's minimal model: flutter onset from the solver's sliding phase",
        closed_form="μ_crit = [(K11 - K22')² + 4κ²] / (4 s κ k_c)", expected=mm.mu_crit,
        measured=0.5 * (lo + hi), unit="1", tolerance=1e-6,
        why="near the onset the growth rate is ~sqrt(μ - μ_crit): the threshold 1e-6 ω_c is met "
            "within ~1e-10 of μ_crit",
        source="Hoffmann, Fischer, Allgaier & Gaul (2002)")


@registered("minimal-growth-rate")
def minimal_growth_rate() -> Check:
    """2 % above the damped onset, simulated steady sliding grows at Re(λ)."""
    from .belt import MinimalModel, simulate_chain

    mm = MinimalModel(eta=150.0)
    mu = 1.02 * mm.mu_crit_damped()
    sigma = mm.growth_rate(mu)
    t_end = 2.0 / abs(sigma)
    r = simulate_chain(**mm.chain(mu=mu, v_belt=50.0, t_end=t_end, kick=1e-4, t_eval=[0.0, t_end],
                                  include_events=False))
    x, y, _ = mm.equilibrium(mu)
    m, c = mm.mass, mm.eta * mm.mass
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-mm.k_eff(mu) / m, -c / m * np.eye(2)]])
    lam, U = np.linalg.eig(A.T)  # left eigenvectors: the projection on the flutter pair is c e^(λt)
    j = int(np.argmax(lam.real))
    p = U[:, j] @ np.vstack([r.x[0] - x, r.y[0] - y, r.v[0], r.vy[0]])
    return Check(
        name="Hoffmann's minimal model: simulated flutter growth rate (2 % above the damped onset)",
        closed_form="σ = Re λ of the characteristic polynomial", expected=sigma,
        measured=math.log(abs(p[1]) / abs(p[0])) / t_end, unit="1/s", tolerance=1e-9,
        why="the projection is exact for the closed-form phase; only the state's round-off remains",
        source="Hoffmann, Fischer, Allgaier & Gaul (2002)")


# -- the asperity model's contact laws (asperity2d.contact_laws) ----------------------------------
#: The flat block of the contact-law checks: one flat block on one flat lower block, free under
#: 2 mN, on a drive whose damper (5e-4 N s/m, eight times critical on the 372 kN/m spring) holds
#: the block's speed at the drive's: steady sliding for every law, whatever the slope of mu(v).
LAW_BLOCK = dict(profile="flat", height=0.25e-6, lower_count=1, upper_count=1, track="free",
                 normal_load=2e-3, mu_static=0.4, mu_kinetic=0.3, drive_stiffness=3.72e5,
                 drive_damping=5e-4)
#: Each built-in contact law's parameters in the checks (SI).
LAW_CASES = {"static-kinetic": {}, "velocity-weakening": {"v_s": 3.0}, "viscous": {"viscosity": 0.01},
             "rate-state": {"rs_a": 0.01, "rs_b": 0.015, "d_c": 1e-9, "v_0": 1.0}}
#: The drive speeds (m/s) of the steady-sliding ladder.
LAW_SPEEDS = (1.0, 3.0, 10.0)


def steady_friction(scene, *, duration: float = 2e-8, window: float = 0.4) -> tuple[float, float]:
    """``(mu, v)``: the mean tangential contact force over the normal load, and the mean speed, of
    ``scene`` (a flat block, free) over the last ``window`` of a run of ``duration`` s."""
    from .run import simulate

    result = simulate(scene, duration, record_every=50, progress=False)
    late = result.t >= result.t[-1] - window * duration
    return (float(np.mean(result.tangential_force[late])) / scene.slider.normal_load,
            float(np.mean(result.v[late])))


def contact_law_of(scene):
    """The contact law as the engine builds it for ``scene`` (internal units; ``steady`` in SI)."""
    from .engine import Engine
    from .run import default_dt

    return Engine(scene, default_dt(scene)).switch.law


def _law_steady(law: str) -> Check:
    from .builders import make_scene

    worst = None
    for v in LAW_SPEEDS:
        scene = make_scene(contact_law=law, drive_velocity=v, **LAW_BLOCK, **LAW_CASES[law])
        expected = contact_law_of(scene).steady(v)
        measured, _ = steady_friction(scene)
        if worst is None or abs(measured / expected - 1) > abs(worst[1] / worst[0] - 1):
            worst = (expected, measured, v)
    expected, measured, v = worst
    return Check(
        name=f"flat block in steady sliding follows the {law} law's μ(v) (1, 3, 10 m/s; worst {v:g} m/s)",
        closed_form="F / N = μ_ss(V), the law's steady curve", expected=expected, measured=measured,
        unit="1", tolerance=1e-4,
        why="in steady sliding the contact impulse is μ times the normal one up to the solver's "
            "convergence (the samples scatter by 5e-5 relative, their mean over the window by "
            "less); the block's speed is the drive's to 1e-5, moving μ(v) by under 1e-6",
        source="the law's closed form (asperity2d.contact_laws)")


for _law in LAW_CASES:
    _register(f"law-steady-{_law}", functools.partial(_law_steady, _law))


@registered("rate-state-velocity-step")
def rate_state_velocity_step() -> Check:
    """The rate-and-state law stepped as the engine steps it through a velocity step 3 -> 9 m/s."""
    from .builders import make_scene

    v1, v2 = 3.0, 9.0
    law = contact_law_of(make_scene(contact_law="rate-state", drive_velocity=v1, **LAW_BLOCK,
                                    **LAW_CASES["rate-state"]))
    s1, s2 = v1 / law.velocity, v2 / law.velocity
    mu, state = law.step(law.initial, s1, 1.0, True)
    for _ in range(int(30 * law.d_c / (s1 * law.dt))):  # 30 D_c of slip: theta at D_c / v1 to e^-30
        mu, state = law.step(state, s1, 1.0, False)
    jump, state = law.step(state, s2, 1.0, False)
    return Check(
        name="rate-and-state law: direct effect of a velocity step 3 -> 9 m/s (the engine's step)",
        closed_form="Δμ = a ln(v2 / v1)", expected=law.a * math.log(v2 / v1), measured=jump - mu, unit="1",
        tolerance=0.015,
        why="over its first step at v2 the state already evolves: θ falls by the factor "
            "1 - (1 - v1 / v2)(1 - e^(-v2 dt / D_c)) (0.69 % at the engine's 1.15 ps), lowering μ by "
            "b times that, 0.95 % of the jump; the regularisation differs from the logarithm by "
            "e^(-2 μ / a), nothing",
        source="Dieterich (1979), Ruina (1983); regularised as Rice, Lapusta & Ranjith (2001)")


@registered("rate-state-steady-change")
def rate_state_steady_change() -> Check:
    """The flat block's steady μ at 9 m/s against that at 3 m/s, both from runs."""
    from .builders import make_scene

    mus = [steady_friction(make_scene(contact_law="rate-state", drive_velocity=v, **LAW_BLOCK,
                                      **LAW_CASES["rate-state"]))[0] for v in (3.0, 9.0)]
    p = LAW_CASES["rate-state"]
    return Check(
        name="rate-and-state law: steady change of the flat block's friction from 3 to 9 m/s",
        closed_form="Δμ_ss = (a - b) ln(v2 / v1)", expected=(p["rs_a"] - p["rs_b"]) * math.log(3.0),
        measured=mus[1] - mus[0], unit="1", tolerance=0.015,
        why="each steady μ is within 1e-4 relative of the law (law-steady checks): 3e-5 each on "
            "μ = 0.3, 1.1 % of the 5.5e-3 change at worst; the regularisation differs from the "
            "logarithm by e^(-2 μ / a), nothing",
        source="Dieterich (1979), Ruina (1983)")


def spring_block_growth(scene, *, dampings, settle: float = 2e-8, duration: float = 4e-8,
                        kick: float = 0.01) -> list[float]:
    """The growth rates (1/s) of small oscillations of a flat block in steady sliding.

    ``scene`` (a flat block, free) slides steadily on its drive's damper for ``settle`` s; then,
    in a fork of that run for each of ``dampings`` (N s/m), the damper takes that value and the
    drive speeds up by ``kick`` (a small velocity step, which starts an oscillation about the new
    steady sliding); each rate is the slope of the log of the peaks of abs(v - V) over the last
    three quarters of ``duration`` s.
    """
    from .run import Run

    run = Run(scene, record_every=4)  # >= 40 samples a period in the checks
    run.settle()
    run.advance(settle)
    v = scene.drive.velocity * (1 + kick)
    rates = []
    for damping in dampings:
        fork = run.fork()
        engine = fork.engine
        engine.drive.c = damping / engine.units.damping
        fork.set_drive_velocity(v)
        fork.advance(duration)
        r = fork.result()
        s = np.abs(r.v - v)
        peaks = np.flatnonzero((s[1:-1] > s[:-2]) & (s[1:-1] >= s[2:])) + 1
        t = r.t[peaks]
        keep = t > t[0] + 0.25 * (t[-1] - t[0])
        rates.append(float(np.polyfit(t[keep], np.log(s[peaks][keep]), 1)[0]))
    return rates


def _crossing(x, rates) -> float:
    """Where the growth rate changes sign between the two points ``x`` (linear), NaN if it does not."""
    (x1, x2), (g1, g2) = x, rates
    return x1 + (x2 - x1) * g1 / (g1 - g2) if g1 * g2 < 0 else math.nan


@registered("rate-state-critical-stiffness")
def rate_state_critical_stiffness() -> Check:
    """A spring-block with the rate-and-state law, at 0.9 and 1.1 times Rice & Ruina's k_c."""
    from .builders import make_scene

    p, N, V = LAW_CASES["rate-state"], LAW_BLOCK["normal_load"], 3.0
    a, b, d_c = p["rs_a"], p["rs_b"], p["d_c"]
    m = make_scene(**LAW_BLOCK).slider.mass
    k_c = N * (b - a) / d_c * (1 + m * V ** 2 / (N * a * d_c))
    ks = (0.9 * k_c, 1.1 * k_c)
    rates = [spring_block_growth(make_scene(contact_law="rate-state", drive_velocity=V,
                                            **{**LAW_BLOCK, "drive_stiffness": k,
                                               "drive_damping": 4 * math.sqrt(k * m),
                                               "drive_preload": 0.3 * N}, **p), dampings=[0.0])[0]
             for k in ks]
    return Check(
        name="rate-and-state spring-block: steady sliding turns unstable at the critical stiffness",
        closed_form="k_c = N (b - a) / D_c · (1 + m V² / (N a D_c))", expected=k_c,
        measured=_crossing(ks, rates), unit="N/m", tolerance=0.02,
        why="the growth rate is measured at 0.9 and 1.1 k_c (it must grow below, decay above) and "
            "its zero found between them linearly: 0.9/1.1 and 0.95/1.05 put it within 0.3 % of "
            "each other; the kick's 1 % step keeps the oscillation near the linear regime",
        source="Rice & Ruina (1983)")


@registered("velocity-weakening-critical-damping")
def velocity_weakening_critical_damping() -> Check:
    """A spring-block with the velocity-weakening law, its damper 0.9 and 1.1 times -N μ'(V)."""
    from .builders import make_scene
    from .friction.laws import Stribeck

    N, V, v_s = LAW_BLOCK["normal_load"], 3.0, LAW_CASES["velocity-weakening"]["v_s"]
    # the belt chains' own criterion: steady sliding is unstable where c + N μ'(V) < 0
    c_crit = -N * float(Stribeck(mu_s=0.4, mu_k=0.3, v_s=v_s, delta=1.0).slope(V))
    scene = make_scene(contact_law="velocity-weakening", drive_velocity=V, v_s=v_s, **LAW_BLOCK)
    cs = (0.9 * c_crit, 1.1 * c_crit)
    rates = spring_block_growth(scene, dampings=cs, duration=6e-9, kick=0.005)
    return Check(
        name="velocity weakening: a spring-block oscillates and grows where N μ'(V) outweighs its damper",
        closed_form="c_crit = -N μ'(V) = N (μs - μk) e^(-V / v_s) / v_s", expected=c_crit,
        measured=_crossing(cs, rates), unit="N s/m", tolerance=0.02,
        why="the growth rate -(c + N μ'(V)) / 2m is linear in c, so its zero between 0.9 and 1.1 "
            "c_crit is exact but for the curvature of μ(v) over the oscillation (a 0.5 % kick, "
            "growing 8-fold) and the decay's approach to the solver's noise floor",
        source="the belt model's criterion (asperity2d.belt.regime); Den Hartog's negative damping")
