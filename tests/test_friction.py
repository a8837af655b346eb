"""Friction laws: curves, continuity, steady states of the state-variable laws, validation."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from asperity2d.errors import SceneError
from asperity2d.friction import Coulomb, CoulombViscous, Dahl, LuGre, StaticKinetic, Stribeck, law_from_dict

LAWS = [Coulomb(0.3), StaticKinetic(0.4, 0.3), CoulombViscous(0.3, 0.5), Stribeck(0.4, 0.3, 0.01, 2, 0.1),
        Dahl(1e4, 0.3), LuGre(1e4, 50.0, 0.1, 0.4, 0.3, 0.01)]


@pytest.mark.parametrize("law", LAWS, ids=lambda l: type(l).__name__)
def test_curve_is_odd_and_force_opposes_motion(law):
    v = np.linspace(1e-4, 1.0, 50)
    np.testing.assert_allclose(law.curve(-v), -law.curve(v))
    assert np.all(law.force(v, 10.0) < 0) and np.all(law.force(-v, 10.0) > 0)


@pytest.mark.parametrize("law", LAWS[:4], ids=lambda l: type(l).__name__)
def test_sliding_laws_jump_at_zero_velocity(law):
    eps = 1e-12
    jump = law.curve(eps) - law.curve(-eps)
    assert jump == pytest.approx(2 * law.curve(1e-300), rel=1e-6) and jump > 0.5


def test_stribeck_falls_from_static_to_kinetic():
    law = Stribeck(0.5, 0.3, 0.02)
    assert law.curve(1e-9) == pytest.approx(0.5, rel=1e-9)
    assert law.curve(1.0) == pytest.approx(0.3, rel=1e-9)
    v = np.array([0.01, 0.02, 0.05])
    h = 1e-7
    np.testing.assert_allclose(law.slope(v), (law.curve(v + h) - law.curve(v - h)) / (2 * h), rtol=1e-6)


@pytest.mark.parametrize("law,ref", [(Dahl(1e3, 0.3), Coulomb(0.3)),
                                     (LuGre(1e3, 10.0, 0.2, 0.4, 0.3, 0.05), Stribeck(0.4, 0.3, 0.05, 2, 0.2))])
@pytest.mark.parametrize("v", [-0.2, 0.03, 0.5])
def test_state_laws_settle_on_their_sliding_curve(law, ref, v):
    # bristle ODE at constant sliding speed from rest: z relaxes within a few 1/(sigma0 |v|)
    sol = solve_ivp(lambda t, z: law.state_derivative(z, v), (0, 20 / (law.sigma0 * abs(v)) * 10), [0.0],
                    method="Radau", rtol=1e-10, atol=1e-14)
    force = law.state_force(sol.y[0, -1], v, 1.0)
    assert force == pytest.approx(-ref.curve(v), rel=1e-6)
    assert law.state_derivative(law.steady_state(v), v) == pytest.approx(0.0, abs=1e-12)


def test_state_laws_are_continuous_through_zero():
    law = LuGre(1e4, 50.0, 0.1, 0.4, 0.3, 0.01)
    z = 1e-5
    assert law.state_force(z, 1e-9, 1.0) == pytest.approx(law.state_force(z, -1e-9, 1.0), abs=1e-6)


@pytest.mark.parametrize("law", LAWS, ids=lambda l: type(l).__name__)
def test_parameter_vector_roundtrip(law):
    again = type(law).from_params(law.params)
    assert again == law
    assert law_from_dict(law.to_dict()) == law
    assert len(law.param_names) == law.params.size


@pytest.mark.parametrize("make,name", [
    (lambda: Coulomb(-0.1), "mu"),
    (lambda: StaticKinetic(0.2, 0.3), "mu_k"),
    (lambda: Stribeck(0.4, 0.3, 0.0), "v_s"),
    (lambda: CoulombViscous(0.3, float("nan")), "sigma2"),
    (lambda: Dahl(0.0, 0.3), "sigma0"),
    (lambda: LuGre(1e4, -1.0, 0.0, 0.4, 0.3, 0.01), "sigma1"),
    (lambda: Coulomb.from_params([0.1, 0.2]), "vector"),
])
def test_validation_names_the_parameter(make, name):
    with pytest.raises(SceneError, match=f"`{name}`"):
        make()


def test_micro_scale_stribeck_chain_matches_the_static_kinetic_limit():
    """A Stribeck law whose slip speeds are 1e6 x v_s is static/kinetic during slip.

    Micro-scale chain (2.88e-15 kg, 1000 N/m, 2 mN load, 10 m/s): positions
    ~1e-6 m and speeds ~100 m/s. The ODE path (Stribeck) must give the exact
    path's (StaticKinetic) period; with one absolute tolerance shared by x
    and v it used to fail in LSODA (regression).
    """
    from asperity2d.belt.period import belt_period

    common = dict(mass=2.88e-15, stiffness=1000.0, velocity=10.0, normal_load=2e-3)
    ode = belt_period(Stribeck(1.9, 0.47, 4e-4, 0.2, 0.0), **common)
    exact = belt_period(StaticKinetic(1.9, 0.47), **common)
    assert exact["cycles"] >= 5
    assert ode["period_s"] == pytest.approx(exact["period_s"], rel=1e-4)
    # stuck, the spring force rises by the full Coulomb drop 2 (F_s - F_k)
    assert exact["force_drop_N"] == pytest.approx(2 * (1.9 - 0.47) * 2e-3, rel=1e-6)
