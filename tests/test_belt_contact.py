"""Chains with a normal degree of freedom (issue 26): separated, sliding or sticking, against closed forms.

Closed forms used (derivations in asperity2d/belt/contact/minimal.py and normal.py):

* free flight of a rigid contact's mass with no normal spring: y = vy0·t - ½·(W/m)·t², it
  lands at t = 2·vy0·m/W and rebounds at e·(its landing speed);
* free flight with a normal spring k_n and damper c_n: the damped oscillator about y = -W/k_n;
* an undamped oscillator about y_eq = -W/k_n > 0 (a lifting preload) from y0 = 2·y_eq at rest:
  y = y_eq·(1 + cos(omega·t)) touches the surface at omega·t = pi without closing;
* the minimal model's characteristic polynomial, flutter onset mu_crit and growth rates;
* the 1-DOF oscillator on a falling friction curve: damping c + N·mu'(V).
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, linear_sum_assignment

from asperity2d import SceneError
from asperity2d.belt import presets, simulate_chain
from asperity2d.belt.contact.steady import contact_spec, steady_sliding
from asperity2d.belt.contact.result import load_contact
from asperity2d.belt.phases.finder import SWITCH_TOL
from asperity2d.belt.contact.minimal import MinimalModel
from asperity2d.belt.normal import SEPARATED, NormalContact
from asperity2d.friction.laws import Stribeck

G = 9.81


# -- (d) today's chains are a special case ------------------------------------------------------
@pytest.mark.parametrize("name", presets.names())
@pytest.mark.parametrize("contact", ["rigid", "stiff"])
def test_a_normal_contact_without_coupling_reproduces_the_thesis_presets(name, contact):
    """No inclined spring: the normal force stays m·g, so the tangential motion must be today's.

    Rigid: N = W exactly. Stiff compliant (k_c = 1e6 N/m, the default y0 its static
    equilibrium): N = k_c·W/k_c, W to one rounding, the normal mode at rest. The two
    solvers differ only in how they write the same closed form (symmetric modes against a
    general eigendecomposition), so positions, velocities and switch times agree to
    rounding; 1e-10 of the motion's scale leaves room for a ten-second run's switches."""
    kw = presets.preset(name)
    before = simulate_chain(**kw)
    normal = NormalContact() if contact == "rigid" else NormalContact(contact_stiffness=1e6)
    after = simulate_chain(**kw, normal=normal)
    # events of one instant in any order; a graze by its time only: in the symmetric chain from rest
    # masses 1 and 3 touch belt speed at the same instant and rounding picks the touch that ends the
    # phase (in either solver; a graze changes nothing, the motion stays the same)
    key = lambda e: (round(e.t, 9), e.kind, e.mass)  # noqa: E731
    got, want = sorted(after.events, key=key), sorted(before.events, key=key)
    assert [(e.kind, -1 if e.kind == "graze" else e.mass) for e in got] == \
        [(e.kind, -1 if e.kind == "graze" else e.mass) for e in want]
    assert np.allclose([e.t for e in got], [e.t for e in want], rtol=0, atol=1e-10)
    assert after.t.shape == before.t.shape and np.max(np.abs(after.t - before.t)) <= 1e-10
    scale_x = max(np.ptp(before.x), 1e-300)
    scale_v = max(np.ptp(before.v), 1e-300)
    assert np.max(np.abs(after.x - before.x)) <= 1e-10 * scale_x
    assert np.max(np.abs(after.v - before.v)) <= 1e-10 * scale_v
    for a, b in zip(after.stick_intervals, before.stick_intervals):
        assert len(a) == len(b) and np.allclose(a, b, rtol=0, atol=1e-10)
    assert np.allclose(after.normal_force, before.chain.m[:, None] * before.chain.g, rtol=1e-12)
    assert not any(after.separation_intervals)


# -- (c) free flight ------------------------------------------------------------------------------
def _ballistic(e=0.6):
    nc = NormalContact(restitution=e)  # rigid, no normal spring: a parabola
    return dict(masses=[2.0], springs=[10.0, 0.0], dampers=[0.0, 0.0], mu_s=0.3, v_belt=0.5, x0=[0.01],
                v0=[0.2], t_end=1.5, normal=nc, y0=[0.0], vy0=[2.0])


def test_free_flight_without_a_normal_spring_is_a_parabola_and_lands_on_time():
    kw = _ballistic()
    r = simulate_chain(**kw, n_samples=1501)
    m, k, vy0, e = 2.0, 10.0, 2.0, 0.6
    a = G  # W/m
    t_land = 2 * vy0 / a
    impacts = [ev.t for ev in r.events if ev.kind == "impact"]
    # the landing is the zero of the closed-form gap, located to machine precision
    assert impacts[0] == pytest.approx(t_land, rel=1e-13)
    # then the rebound at e·vy0 flies 2·e·vy0/a
    assert impacts[1] == pytest.approx(t_land + 2 * e * vy0 / a, rel=1e-13)
    flight = (r.t > 0) & (r.t < t_land)
    t = r.t[flight]
    # the flight is propagated on a Taylor grid (A is singular): exact to rounding
    assert np.allclose(r.y[0, flight], vy0 * t - 0.5 * a * t * t, rtol=0, atol=1e-13)
    assert np.all(r.state[0, flight] == SEPARATED) and np.all(r.friction_force[0, flight] == 0)
    assert np.all(r.normal_force[0, flight] == 0)
    # no friction in flight: x is the free oscillator x0·cos + v0/omega·sin
    w = math.sqrt(k / m)
    assert np.allclose(r.x[0, flight], 0.01 * np.cos(w * t) + 0.2 / w * np.sin(w * t), rtol=0, atol=1e-13)
    # each impact loses ½·m·(1 - e²)·v² of the normal motion's kinetic energy (the first at v = vy0)
    first = r.t >= impacts[0]
    assert r.impact_dissipation[first][0] == pytest.approx(0.5 * m * (1 - e * e) * vy0 * vy0, rel=1e-12)


def test_free_flight_with_a_normal_spring_and_damper_follows_the_damped_oscillator():
    m, kn, cn, P = 1.5, 400.0, 3.0, 20.0
    W = m * G + P
    nc = NormalContact(stiffness=kn, damping=cn, preload=P)
    kw = dict(masses=[m], springs=[0.0, 0.0], dampers=[0.0, 0.0], mu_s=0.2, v_belt=1.0, x0=[0.0], v0=[0.3],
              t_end=0.5, normal=nc, y0=[0.02], vy0=[0.5])
    r = simulate_chain(**kw, n_samples=501)
    zeta_w = cn / (2 * m)
    wd = math.sqrt(kn / m - zeta_w**2)
    y_eq = -W / kn
    A0, B0 = 0.02 - y_eq, (0.5 + zeta_w * (0.02 - y_eq)) / wd

    def y(t):
        return y_eq + np.exp(-zeta_w * t) * (A0 * np.cos(wd * t) + B0 * np.sin(wd * t))

    t_land = brentq(y, 0.0, math.pi / wd * 1.5, xtol=1e-16, rtol=1e-15)
    landing = next(ev.t for ev in r.events if ev.kind == "impact")
    assert landing == pytest.approx(t_land, rel=1e-12)
    flight = r.t < t_land
    assert np.allclose(r.y[0, flight], y(r.t[flight]), rtol=0, atol=1e-14)
    # separated, frictionless: x moves at its initial speed (no spring)
    assert np.allclose(r.x[0, flight], 0.3 * r.t[flight], rtol=0, atol=1e-14)


@pytest.mark.parametrize("rigid", [True, False])
def test_free_flight_after_separation_of_a_compliant_contact_is_the_free_oscillator(rigid):
    """Lifting preload: the contact opens at once where N = 0, then y = y_eq·(1 - cos(omega·t))."""
    m, kn, P = 1.0, 100.0, -5.0
    y_eq = -P / kn
    w = math.sqrt(kn / m)
    nc = NormalContact(stiffness=kn, preload=P, contact_stiffness=None if rigid else 1e4)
    r = simulate_chain(masses=[m], springs=[10.0, 0.0], dampers=[0.0, 0.0], mu_s=0.3, v_belt=1.0, x0=[0.0],
                       v0=[1.0], t_end=0.3, g=0.0, normal=nc, y0=[0.0], n_samples=301)
    inside = (r.t > 0) & (r.t < 0.3)
    assert np.allclose(r.y[0, inside], y_eq * (1 - np.cos(w * r.t[inside])), rtol=0, atol=1e-15)
    assert np.all(r.state[0, inside] == SEPARATED)


# -- grazes ------------------------------------------------------------------------------------------
@pytest.mark.parametrize("rigid", [True, False])
@pytest.mark.parametrize("depth", [0.0, 0.5, 2.0, -2.0])
def test_a_gap_that_touches_zero_is_a_graze_and_one_deeper_than_the_tolerance_closes(rigid, depth):
    """y = y_eq + A·cos(omega·t) with A = y_eq + depth·SWITCH_TOL·gap_scale: its minimum,
    -depth·SWITCH_TOL·gap_scale at omega·t = pi, is a touch (graze-gap, the mass stays
    separated) for depth within ±1 and a crossing (an impact, or a closing) beyond."""
    m, kn, P = 1.0, 100.0, -5.0
    y_eq, w = -P / kn, math.sqrt(kn / m)
    nc = NormalContact(stiffness=kn, preload=P, contact_stiffness=None if rigid else 1e4)
    base = dict(masses=[m], springs=[10.0, 0.0], dampers=[0.0, 0.0], mu_s=0.3, v_belt=1.0, x0=[0.0], v0=[0.0],
                t_end=0.5, g=0.0, normal=nc)
    gap_scale = contact_spec(**base, y0=[2 * y_eq]).gap_scale
    r = simulate_chain(**base, y0=[2 * y_eq + depth * SWITCH_TOL * gap_scale], n_samples=11)
    first = r.events[0] if r.events else None
    if depth > 1:
        assert first.kind == ("impact" if rigid else "close")
        assert first.t == pytest.approx(math.pi / w, rel=1e-4)
    elif depth >= -1:
        assert first.kind == "graze-gap"
        # the touch is the minimum of the gap, a simple zero of its derivative: to rounding
        assert first.t == pytest.approx(math.pi / w, rel=1e-14)
        assert not r.separation_intervals[0][1:] and r.impact_dissipation[-1] == 0.0
    else:
        assert first is None


@pytest.mark.parametrize("rigid", [True, False])
def test_a_normal_force_that_touches_zero_is_a_graze(rigid):
    """In contact, N oscillates between 2·N* and exactly 0 without opening.

    Rigid (N = W + kappa·x): an inclined spring at 135 deg, the mass sliding against a fast
    belt (friction +mu·N), x = x* + B·cos(Omega·t) with B = N*/|kappa|, Omega² = (K11 - mu·kappa)/m.
    Compliant (N = -k_c·y): y = y*·(1 + cos(omega·t)) with omega² = k_c/m, from y0 = 2·y*."""
    m, mu, V = 1.0, 0.2, 50.0
    if rigid:
        ka = 40.0
        kxx, kxy = ka * 0.5, -ka * 0.5  # 135 deg: cos² = 1/2, cos·sin = -1/2
        K11 = 10.0 + kxx
        nc = NormalContact(inclined=((ka, 135.0),))
        # s = -1: m x'' = -K11 x + mu (W + kxy x)  ->  Omega² = (K11 - mu kxy)/m
        stiff = K11 - mu * kxy
        x_star = mu * m * G / stiff
        N_star = m * G + kxy * x_star
        B = N_star / abs(kxy)
        kw = dict(x0=[x_star - B], y0=[0.0])  # kxy < 0: N largest at the smallest x
        omega = math.sqrt(stiff / m)
    else:
        kc = 1e4
        nc = NormalContact(contact_stiffness=kc)
        y_star = -m * G / kc
        kw = dict(x0=[0.0], y0=[2 * y_star])
        omega = math.sqrt(kc / m)
    r = simulate_chain(masses=[m], springs=[10.0, 0.0], dampers=[0.0, 0.0], mu_s=mu, v_belt=V, v0=[0.0],
                       t_end=1.2 * math.pi / omega, normal=nc, n_samples=101, **kw)
    grazes = [e for e in r.events if e.kind == "graze-normal"]
    assert len(grazes) == 1 and len(r.events) == 1
    assert grazes[0].t == pytest.approx(math.pi / omega, rel=1e-12)
    assert not any(r.separation_intervals) and np.all(r.state != SEPARATED)
    assert r.normal_force.min() >= 0


# -- energy books with separation and impacts ---------------------------------------------------------
@pytest.mark.parametrize("restitution", [0.0, 0.5, 0.9, 1.0])
def test_energy_books_close_through_separations_and_impacts(restitution):
    """A rigid contact lifted off by an inclined spring, flying and bouncing (Newton's e), with
    dampers: stored energy minus its start equals belt work minus the friction, damper and impact
    losses to 1e-9 of the largest flow (each phase is integrated from its closed form, each
    impact booked exactly, so it closes to rounding: ~1e-13 measured)."""
    nc = NormalContact(stiffness=5.0, damping=0.05, restitution=restitution, inclined=((40.0, 135.0),))
    r = simulate_chain(masses=[1.0, 0.5], springs=[10.0, 5.0, 0.0], dampers=[0.05, 0.02, 0.0], mu_s=0.9, mu_k=0.1,
                       v_belt=0.1, x0=[0.0, 0.0], v0=[5.0, 3.0], t_end=10.0, normal=nc, n_samples=4001)
    assert all(r.separation_intervals) and (r.impact_dissipation[-1] > 0) == (restitution < 1)
    assert sum(e.kind == "impact" for e in r.events) >= 1
    assert r.energy_balance_error() <= 1e-9
    assert np.all(np.diff(r.impact_dissipation) >= 0) and np.all(np.diff(r.friction_dissipation) >= -1e-15)
    # a rigid contact never pulls, and never penetrates beyond the rounding of a located landing (the
    # root finder stops on the far side of the zero: -8e-16 m measured), far inside the touch band
    assert r.y.min() >= -SWITCH_TOL * r.contact.gap_scale and r.normal_force.min() >= 0


def test_energy_books_close_for_the_flutter_limit_cycle_with_separation():
    mm = MinimalModel(eta=50.0)
    r = simulate_chain(**mm.chain(mu=0.5, v_belt=5.0, t_end=0.05, kick=1e-3, n_samples=5001))
    assert sum(len(s) for s in r.separation_intervals) >= 10
    assert r.energy_balance_error() <= 1e-9
    # compliant: in contact the gap is a penetration (y <= 0), separated it is open (y >= 0)
    contact = r.state[0] != SEPARATED
    tol = SWITCH_TOL * r.contact.gap_scale
    assert r.y[0, contact].max() <= tol and r.y[0, ~contact].min() >= -tol
    assert np.allclose(r.normal_force[0, contact], np.maximum(-8.0e6 * r.y[0, contact], 0), rtol=1e-12, atol=1e-9)


# -- (a) the minimal model: flutter ---------------------------------------------------------------------
def test_minimal_model_closed_form_eigenvalues_are_the_solvers_phase_matrix():
    """The characteristic polynomial's roots against the eigenvalues of the solver's own sliding-phase
    matrix (steady_sliding), away from coalescence where both are well conditioned (1e-9)."""
    for eta in (0.0, 150.0):
        mm = MinimalModel(eta=eta)
        for mu in (0.1, 0.3, 0.5, 0.8):
            ss = steady_sliding(**mm.chain(mu=mu, v_belt=5.0, t_end=1.0))
            want = mm.eigenvalues(mu)
            got = ss.eigenvalues
            # pair each root with its nearest (a sort would split pairs on real parts of order 1e-13)
            gap = np.abs(got[:, None] - want[None, :])
            rows, cols = linear_sum_assignment(gap)
            assert np.max(gap[rows, cols]) <= 1e-9 * np.max(np.abs(want))
            x, y, N = mm.equilibrium(mu)
            assert ss.state[:2] == pytest.approx([x, y], rel=1e-12) and ss.normal_force[0] == pytest.approx(N, rel=1e-12)


# The flutter onset found on the solver's own sliding phase against the closed-form mu_crit, and the
# simulated growth rate above the damped onset, are checks of asperity2d.closed_forms.


def test_minimal_model_modes_coalesce_at_mu_crit():
    """Below mu_crit the two frequencies differ by ~ sqrt(mu_crit - mu): 100x closer to the onset,
    10x closer frequencies (within 1 %), meeting at omega_c."""
    mm = MinimalModel()
    split = []
    for rel in (1e-4, 1e-6):
        w = np.sort(np.abs(mm.eigenvalues(mm.mu_crit * (1 - rel)).imag))[::2]
        split.append(w[1] - w[0])
        assert np.mean(w) == pytest.approx(mm.coalescence_frequency, rel=1e-3)
    assert split[0] / split[1] == pytest.approx(10.0, rel=0.01)


def _growth_from_simulation(mm, mu, t_end):
    """Growth rate of the flutter pair measured on the simulated steady sliding: the deviation from the
    equilibrium projected on the left eigenvector u of the pair (from the hand-written M, C, K_eff)
    is c·exp(lambda·t) exactly for the linear sliding phase, so |p(t2)/p(t1)| = exp(sigma·(t2 - t1))."""
    kw = mm.chain(mu=mu, v_belt=50.0, t_end=t_end, kick=1e-4, t_eval=[0.0, t_end], include_events=False)
    r = simulate_chain(**kw)
    assert not r.events  # still sliding in contact: the measurement is on the linear phase
    x, y, _ = mm.equilibrium(mu)
    m, c = mm.mass, mm.eta * mm.mass
    K = mm.k_eff(mu)
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-K / m, -c / m * np.eye(2)]])
    lam, U = np.linalg.eig(A.T)  # left eigenvectors of A
    j = int(np.argmax(lam.real))
    d = np.vstack([r.x[0] - x, r.y[0] - y, r.v[0], r.vy[0]])
    p = U[:, j] @ d
    return math.log(abs(p[1]) / abs(p[0])) / t_end, r


@pytest.mark.parametrize("side", [-1])  # +1 (growth above the onset): asperity2d.closed_forms
def test_minimal_model_simulated_sliding_grows_above_and_decays_below_at_the_closed_form_rate(side):
    """With mass-proportional damping (eta = 150 1/s) the onset moves to mu_crit(eta) (closed form);
    2 % above it the simulated steady sliding grows, 2 % below it decays, at Re(lambda) of the
    characteristic polynomial. The projection is exact for the closed-form solution, so the only
    error is rounding of the state (~1e-16 of the equilibrium offsets against a deviation of
    ~1e-4 of them, over sigma·t of order 1): 1e-9 relative."""
    mm = MinimalModel(eta=150.0)
    mu = mm.mu_crit_damped() * (1 + side * 0.02)
    sigma = mm.growth_rate(mu)
    assert np.sign(sigma) == side
    measured, r = _growth_from_simulation(mm, mu, 2.0 / abs(sigma))
    assert measured == pytest.approx(sigma, rel=1e-9)


def test_minimal_model_damped_onset_from_simulations_is_the_closed_form():
    """Bisection on mu of the sign of the simulated growth rate: relative error <= 1e-6 against
    mu_crit(eta) = [(K11 - K22')² + 4 kappa² + 2 m eta² (K11 + K22')]/(4 s kappa k_c)."""
    mm = MinimalModel(eta=150.0)
    lo, hi = mm.mu_crit * 0.95, mm.mu_crit * 1.1
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        grows = _growth_from_simulation(mm, mid, 5e-3)[0] > 0
        lo, hi = (lo, mid) if grows else (mid, hi)
    assert 0.5 * (lo + hi) == pytest.approx(mm.mu_crit_damped(), rel=1e-6)
    assert mm.mu_crit_damped() > mm.mu_crit  # mass-proportional damping stabilises


def test_minimal_model_sliding_phase_agrees_with_an_independent_integration():
    """The hand-written equations of motion (module docstring of belt/contact/minimal.py) through DOP853 at
    rtol 1e-12 against the solver's closed form, before any switch: 1e-8 of the motion."""
    mm = MinimalModel(eta=40.0)
    mu = 0.5
    kw = mm.chain(mu=mu, v_belt=50.0, t_end=4e-3, kick=1e-3, n_samples=201, include_events=False)
    r = simulate_chain(**kw)
    assert not r.events
    K11, kap, K22 = mm.structure
    kc, m, c, F = mm.contact_stiffness, mm.mass, mm.eta * mm.mass, mm.preload

    def rhs(t, z):
        x, y, vx, vy = z
        N = -kc * y
        return [vx, vy, (-c * vx - K11 * x - kap * y + mu * N) / m, (-c * vy - kap * x - (K22 + kc) * y - F) / m]

    z0 = [r.x[0, 0], r.y[0, 0], r.v[0, 0], r.vy[0, 0]]
    sol = solve_ivp(rhs, (0, r.t[-1]), z0, method="DOP853", t_eval=r.t, rtol=1e-12, atol=1e-18)
    for k, got in enumerate((r.x[0], r.y[0], r.v[0], r.vy[0])):
        assert np.max(np.abs(sol.y[k] - got)) <= 1e-8 * np.ptp(got)


# -- (b) negative damping: a falling friction curve --------------------------------------------------------
@pytest.mark.parametrize("side", [-1, 1])
def test_stribeck_slope_destabilises_steady_sliding_when_c_plus_N_slope_is_negative(side):
    """1-DOF oscillator on the belt with Stribeck friction: the linearised sliding has damping
    c + N·mu'(V) (friction -N·curve(v - V), d/dv = -N·curve'(-V) = -N·slope(V)); c = N·|mu'|·(1 + side·0.1)
    ... side = +1 decays, side = -1 grows, at sigma = -(c + N·mu')/(2m). Measured from samples one
    damped period apart (x(t + T_d) - x* = exp(sigma·T_d)·(x(t) - x*) for the linear motion). Error
    budget: the integrator (rtol 1e-10) and the curve's curvature over the velocity swing (~1e-5 of
    v_s): 1e-3 relative."""
    m, k, V = 1.0, 100.0, 0.1
    law = Stribeck(mu_s=0.4, mu_k=0.2, v_s=0.1, delta=2.0)
    N = m * G
    slope = float(law.slope(V))
    assert slope < 0
    c = -N * slope * (1 + side * 0.1)
    damping = c + N * slope
    sigma = -damping / (2 * m)
    x_star = N * float(law.g(V)) / k  # the belt drags the mass forward with N·mu(V)
    wd = math.sqrt(k / m - sigma**2)
    Td = 2 * math.pi / wd
    t1, periods = 1.0, 8
    r = simulate_chain(masses=[m], springs=[k, 0.0], dampers=[c, 0.0], friction=law, v_belt=V, x0=[x_star + 1e-7],
                       v0=[0.0], t_end=t1 + periods * Td, t_eval=[t1, t1 + periods * Td], include_events=False,
                       rtol=1e-10)
    d = r.x[0] - x_star
    measured = math.log(abs(d[1] / d[0])) / (periods * Td)
    assert np.sign(measured) == -side
    assert measured == pytest.approx(sigma, rel=1e-3)


# -- validation, persistence, determinism ----------------------------------------------------------------
BASE = dict(masses=[1.0], springs=[10.0, 0.0], dampers=[0.0, 0.0], mu_s=0.2, v_belt=0.1, x0=[0.0], v0=[0.0],
            t_end=1.0)


@pytest.mark.parametrize("bad, message", [
    (dict(stiffness=-1.0), "`normal.stiffness` must be >= 0"),
    (dict(damping=float("nan")), "`normal.damping` must be a finite number"),
    (dict(contact_stiffness=0.0), "`normal.contact_stiffness` must be > 0"),
    (dict(restitution=1.5), "`normal.restitution` must be within [0, 1]"),
    (dict(restitution=0.5, contact_stiffness=10.0), "`normal.restitution` applies to a rigid contact"),
    (dict(inclined=((10.0,),)), "`normal.inclined` entry 0 must be a (stiffness, angle) pair"),
    (dict(inclined=((10.0, 200.0),)), "`normal.inclined[0] angle` must be within [-180, 180]"),
    (dict(inclined=((-1.0, 20.0),)), "`normal.inclined[0] stiffness` must be >= 0"),
    (dict(inclined="springs"), "`normal.inclined` must be a list"),
    (dict(preload="1"), "`normal.preload` must be a real number"),
])
def test_normal_contact_parameters_are_validated(bad, message):
    with pytest.raises(SceneError) as info:
        NormalContact(**bad)
    assert message in str(info.value)


@pytest.mark.parametrize("extra, message", [
    (dict(normal={"stiffness": 1.0}), "`normal` must be a NormalContact"),
    (dict(y0=[0.0]), "`y0` and `vy0` need `normal`"),
    (dict(normal=NormalContact(), normal_load=[5.0]), "not `normal_load`"),
    (dict(normal=NormalContact(), method="sign"), "`method` 'sign' has no back end that accepts this chain with a "
     "normal contact (its back ends: sign() friction through solve_ivp); methods that do: 'exact'"),
    (dict(normal=NormalContact(), y0=[-0.1]), "`y0` must be >= 0 with a rigid contact"),
    (dict(normal=NormalContact(), y0=[0.0, 1.0]), "`y0` must have 1 entries"),
    (dict(normal=NormalContact(), vy0=["fast"]), "`vy0` must be a real number at index 0"),
    (dict(normal=NormalContact(), v_belt=lambda t: 0.1), "`v_belt` must be a constant with `normal`"),
    (dict(normal=NormalContact(), mu_s=None, friction=Stribeck(0.3, 0.2, 0.1)), "`friction` must be Coulomb or "
                                                                                 "StaticKinetic"),
    (dict(normal=NormalContact(contact_stiffness=1e12), t_end=100.0), "over the budget `max_steps`"),
])
def test_bad_chains_with_a_normal_contact_name_the_parameter(extra, message):
    with pytest.raises(SceneError) as info:
        simulate_chain(**{**BASE, **extra})
    assert message in str(info.value)


def test_contact_results_save_load_and_repeat_bit_identically(tmp_path):
    mm = MinimalModel(eta=20.0)
    kw = mm.chain(mu=0.5, v_belt=5.0, t_end=0.02, kick=1e-3, n_samples=501)
    a, b = simulate_chain(**kw), simulate_chain(**kw)
    for name in ("t", "x", "y", "v", "vy", "normal_force", "friction_force", "belt_work", "impact_dissipation"):
        assert np.array_equal(getattr(a, name), getattr(b, name))
    path = a.save(tmp_path / "run.npz")
    c = load_contact(path)
    for name in ("t", "x", "y", "v", "vy", "state", "normal_force", "stored_energy", "energy_residual"):
        assert np.array_equal(getattr(a, name), getattr(c, name))
    assert c.separation_intervals == a.separation_intervals and c.events == a.events
    assert c.contact.normal == a.contact.normal and c.contact.y0 == a.contact.y0


# -- limit cycles with separation ---------------------------------------------------------------------------
def test_floquet_multipliers_of_the_separation_limit_cycle_obey_liouville():
    """The minimal model above mu_crit (mu = 0.5, eta = 300 1/s) settles on a cycle that opens the contact
    once a period. The compliant contact's vector field is continuous across y = 0 (N = k_c·max(0, -y),
    friction -s·mu·N): no saltation, so det M = exp(∫ div f dt) = exp(-(c_x + c_y)/m·T) = exp(-2·eta·T)
    (Liouville). The multipliers come from central differences of the exact solver (step 1e-6: error
    ~1e-9, the step-to-step/10 convergence ~5e-9 measured): the product within 1e-6."""
    from asperity2d.dynamics import chain_cycle, floquet

    mm = MinimalModel(eta=300.0)
    kw = mm.chain(mu=0.5, v_belt=5.0, t_end=0.12, kick=1e-3, n_samples=1001)
    r = simulate_chain(**kw)
    cycle = chain_cycle(r)
    assert cycle.periodic and cycle.multiplicity == 1 and cycle.section == "contact 1 opens"
    assert len(r.separation_intervals[0]) > 100 and not any(r.stick_intervals)
    f = floquet(kw)
    assert f.matrix.shape == (4, 4) and f.convergence < 1e-6
    assert abs(f.trivial - 1) < 1e-6
    assert np.prod(f.multipliers).real == pytest.approx(math.exp(-2 * mm.eta * f.period), rel=1e-6)
    assert f.stable and max(abs(m) for m in f.multipliers if m != f.trivial) < 1
