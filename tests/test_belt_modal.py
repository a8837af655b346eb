"""The closed-form machinery of the exact belt solver against independent references.

Runtime ~3 s. References: scipy's expm and quad, Taylor series, and the closed-form
motions of a critically damped oscillator and of a free mass dragged by the belt.
"""

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.linalg import expm

import asperity2d.belt.phases.modal as modal
from asperity2d.belt import simulate_chain
from asperity2d.belt.phases.modal import ModalForm, phi, square_integral
from asperity2d.belt.phases.segment import TaylorGrid

G = 9.81


@pytest.mark.parametrize("kind", ["random", "nilpotent", "defective"])
def test_taylor_grid_matches_expm(kind):
    rng = np.random.default_rng(3)
    A = {"random": rng.normal(size=(6, 6)),
         "nilpotent": np.triu(rng.normal(size=(6, 6)), k=1),
         "defective": np.array([[-1.0, 1.0, 0.0], [0.0, -1.0, 1.0], [0.0, 0.0, -1.0]])}[kind]
    z0 = rng.normal(size=A.shape[0])
    taus = np.array([0.0, 1e-9, 0.013, 0.7, 2.9])
    got = TaylorGrid(A, z0).at(taus)
    want = np.stack([expm(A * t) @ z0 for t in taus], axis=1)
    # both are accurate to rounding times the growth of the propagator
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-13 * np.abs(want).max())


def test_phi_is_accurate_near_zero_and_far_from_it():
    z = np.array([0.0, 1e-12, 1e-8j, 0.3 - 0.2j, 0.49j, 0.51, 3 + 4j, -20.0])
    series = 1 + z / 2 + z**2 / 6 + z**3 / 24 + z**4 / 120  # enough terms for the tiny |z|
    direct = np.where(z == 0, 1.0, (np.exp(z) - 1) / np.where(z == 0, 1, z))
    np.testing.assert_allclose(phi(z[:3]), series[:3], rtol=1e-15)
    np.testing.assert_allclose(phi(z[3:]), direct[3:], rtol=1e-14)


def _form(rng, R=3, S=4):
    lam = -rng.uniform(0.0, 0.5, S) + 1j * rng.uniform(0.5, 4.0, S)
    lam[0] = -0.7  # a real (overdamped) mode
    B = rng.normal(size=(R, S)) + 1j * rng.normal(size=(R, S))
    return ModalForm(lam, B, rng.normal(size=R), np.zeros(R))


def test_integrals_in_closed_form_match_quadrature():
    form = _form(np.random.default_rng(5))
    taus = np.array([1e-7, 0.4, 3.0])
    lin = form.integral(taus)
    sq = square_integral(form, np.array([0.5, 2.0, 1.0]), taus)
    for j, t in enumerate(taus):
        for r in range(3):
            want = quad(lambda s: form.at(np.array([s]))[r, 0], 0, t, epsabs=1e-15, epsrel=1e-12, limit=200)[0]
            assert lin[r, j] == pytest.approx(want, rel=1e-10, abs=1e-14)
        want = quad(lambda s: float(np.array([0.5, 2.0, 1.0]) @ form.at(np.array([s]))[:, 0] ** 2), 0, t,
                    epsabs=1e-15, epsrel=1e-12, limit=200)[0]
        assert sq[j] == pytest.approx(want, rel=1e-10, abs=1e-14)


def test_critically_damped_oscillator_takes_the_defective_path_exactly():
    # m = k = 1, c = 2: A has the double eigenvalue -1; x = (1 + t) e^-t from x0 = 1 at rest
    r = simulate_chain([1.0], [1.0, 0.0], [2.0, 0.0], mu_s=0.0, v_belt=0.0, x0=[1.0], v0=[0.0], t_end=6.0,
                       n_samples=61)
    np.testing.assert_allclose(r.x[0], (1 + r.t) * np.exp(-r.t), rtol=0, atol=1e-15)
    assert r.energy_balance_error() < 1e-13


def test_free_mass_is_dragged_to_belt_speed_and_sticks():
    # no links at all (singular K): a = mu g until v = V at t* = V/(mu g), x = V²/(2 mu g); then stuck
    mu, V = 0.25, 0.3
    t_star = V / (mu * G)
    r = simulate_chain([2.0], [0.0, 0.0], [0.0, 0.0], mu_s=mu, v_belt=V, x0=[0.0], v0=[0.0], t_end=1.0)
    (stick,) = [e for e in r.events if e.kind == "stick"]
    assert stick.t == pytest.approx(t_star, rel=1e-14)
    assert stick.x == pytest.approx(V**2 / (2 * mu * G), rel=1e-14)
    assert r.x[0, -1] == pytest.approx(V**2 / (2 * mu * G) + V * (1.0 - t_star), rel=1e-14)
    # the belt's work is split exactly: half stored as kinetic energy, half lost in friction
    assert r.friction_dissipation[-1] == pytest.approx(0.5 * 2.0 * V**2, rel=1e-13)


def test_damped_path_tends_to_the_undamped_one():
    # the undamped segments use the symmetric eigenproblem, the damped ones eig(A): c = 1e-9 N s/m
    # perturbs the motion by O(c t / m) ~ 1e-8 relative over 10 s
    kw = dict(masses=[1.0, 1.5, 0.7], springs=[10.0, 20.0, 5.0, 10.0], mu_s=0.4, mu_k=0.25, v_belt=0.2,
              x0=[0.05, -0.02, 0.07], v0=[0.04, 0.3, -0.1], t_end=10.0, n_samples=101)
    plain = simulate_chain(dampers=[0.0] * 4, **kw)
    damped = simulate_chain(dampers=[1e-9] * 4, **kw)
    assert [(e.mass, e.kind) for e in plain.events] == [(e.mass, e.kind) for e in damped.events]
    np.testing.assert_allclose(damped.x, plain.x, rtol=0, atol=1e-8 * np.abs(plain.x).max())


def test_reruns_are_bit_identical():
    kw = dict(masses=[1.0, 1.5, 0.7], springs=[10.0, 20.0, 5.0, 10.0], dampers=[0.5, 0.0, 1.0, 0.3], mu_s=0.4,
              mu_k=0.25, v_belt=0.2, x0=[0.05, -0.02, 0.07], v0=[0.04, 0.3, -0.1], t_end=15.0)
    a, b = simulate_chain(**kw), simulate_chain(**kw)
    for name in ("t", "x", "v", "friction_force", "belt_work", "damper_dissipation"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert a.events == b.events


@pytest.mark.parametrize("law", [None, "stribeck"])
def test_energy_books_do_not_depend_on_the_sampling(law):
    # regression: the quadrature once put every piece of a long gap at the gap's start
    from asperity2d.friction import Stribeck

    kw = dict(masses=[1.0, 1.0], springs=[10.0] * 3, dampers=[0.3] * 3, v_belt=0.1, x0=[0.05, 0.0],
              v0=[0.0, 0.0], t_end=5.0, rtol=1e-9)
    kw.update(friction=Stribeck(0.3, 0.2, 0.02)) if law else kw.update(mu_s=0.3, mu_k=0.2)
    fine, coarse = simulate_chain(**kw, n_samples=501), simulate_chain(**kw, n_samples=3)
    for name in ("belt_work", "friction_dissipation", "damper_dissipation"):
        assert getattr(coarse, name)[-1] == pytest.approx(getattr(fine, name)[-1], rel=1e-9 if law else 1e-13)
    assert coarse.energy_balance_error() < (1e-7 if law else 1e-13)  # integrated: the work rides with rtol


def test_sparse_forms_of_long_chains_agree_with_dense_ones(monkeypatch):
    rng = np.random.default_rng(1)
    n = 40
    kw = dict(masses=[1.0] * n, springs=[10.0] * (n + 1), dampers=[0.0] * (n + 1), mu_s=0.3, mu_k=0.2,
              v_belt=0.1, x0=rng.uniform(-0.05, 0.05, n).tolist(), v0=rng.uniform(0.0, 0.1, n).tolist(),
              t_end=3.0, n_samples=31)
    dense = simulate_chain(**kw)
    monkeypatch.setattr(modal, "SPARSE_ABOVE", 4)
    monkeypatch.setattr(modal, "DENSE_MAP_WIDTH", 4)
    sparse = simulate_chain(**kw)
    assert len(dense.events) > 20
    assert [(e.mass, e.kind) for e in sparse.events] == [(e.mass, e.kind) for e in dense.events]
    np.testing.assert_allclose([e.t for e in sparse.events], [e.t for e in dense.events], rtol=1e-12)
    np.testing.assert_allclose(sparse.x, dense.x, rtol=0, atol=1e-12)
    assert sparse.energy_balance_error() < 1e-12


def test_nearly_defective_damped_segment_matches_the_matrix_exponential():
    # found by fuzzing: this segment's eigenvalues cluster within 1e-4 around -1 (cond(W) = 8e11,
    # though no two are "close"); modal coefficients would be garbage, the Taylor grid is exact
    springs, dampers = np.array([0.0, 1.0, 1.0, 1.0]), np.array([1.0, 1.0, 1.0, 0.0])
    y0 = np.array([1e-9, 0.083, 0.0, 1e-9, 0.083, 0.0])
    r = simulate_chain([1.0] * 3, springs, dampers, mu_s=0.0, v_belt=0.0, x0=y0[:3], v0=y0[3:], t_end=2.0,
                       n_samples=9)
    K = np.diag(springs[:-1] + springs[1:]) - np.diag(springs[1:-1], 1) - np.diag(springs[1:-1], -1)
    C = np.diag(dampers[:-1] + dampers[1:]) - np.diag(dampers[1:-1], 1) - np.diag(dampers[1:-1], -1)
    A = np.block([[np.zeros((3, 3)), np.eye(3)], [-K, -C]])
    want = np.stack([(expm(A * t) @ y0)[:3] for t in r.t], axis=1)
    np.testing.assert_allclose(r.x, want, rtol=0, atol=1e-15)
    assert r.energy_balance_error() < 1e-12


@pytest.mark.filterwarnings("error::RuntimeWarning")
def test_vanishing_static_limit_neither_overflows_nor_holds_the_mass():
    # found by fuzzing: mu_s N = 1e-310 N (subnormal) normalised the stick event functions of a stuck
    # mass to 1e311 (inf, then NaN: the mass could never break away); the limits are now floored at
    # 1e-12 of the chain's force scale. Mass 1 starts stuck (no force, no force rate) and must break
    # away as soon as mass 3's spring reaches it: then everything moves as if frictionless.
    kw = dict(masses=[1.0] * 3, springs=[10.0] * 4, dampers=[0.0] * 4, v_belt=0.0, x0=[0.0, 0.0, 0.05],
              v0=[0.0, 0.0, 0.0], t_end=5.0, n_samples=51, include_events=False)
    tiny = simulate_chain(**kw, mu_s=1e-200, normal_load=[1e-110, 0.0, 0.0])
    free = simulate_chain(**kw, mu_s=0.0)
    assert tiny.stick_intervals[0][0][1] < 1e-3  # breaks away at once (f_req ~ t^4 reaches 1e-310 N)
    np.testing.assert_allclose(tiny.x, free.x, rtol=0, atol=1e-15)
