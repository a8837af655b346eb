"""Friction-law fits: recovery of known laws, residuals on tribometer-like data."""

import numpy as np
import pytest

from asperity2d import fitting as ft
from asperity2d.friction import CoulombViscous, Stribeck
from asperity2d.tribometer import ReversalLoops, SteadyCurve

V = np.array([-300, -100, -30, -10, -3, -1, 1, 3, 10, 30, 100, 300.0])


def _curve(law, noise=0.0, seed=0):
    rng = np.random.default_rng(seed)
    f = 2e-3 * (law.curve(V) + noise * rng.standard_normal(V.size))
    return SteadyCurve(V, f, np.full(V.size, 1e-6), 2e-3)


def test_coulomb_viscous_fit_recovers_the_law():
    fit = ft.fit_coulomb_viscous(_curve(CoulombViscous(0.44, 1e-3)))
    assert fit.law.mu == pytest.approx(0.44, rel=1e-6) and fit.law.sigma2 == pytest.approx(1e-3, rel=1e-6)
    assert fit.relative_rms < 1e-8


def test_stribeck_fit_reproduces_the_curve_within_its_residual():
    true = Stribeck(1.9, 0.4, 2.0, 1.5, 1e-3)
    curve = _curve(true, noise=0.005)
    fit = ft.fit_stribeck(curve, mu_s=1.9)
    model = fit.law.curve(V) * curve.normal_load
    rms = np.sqrt(np.mean((model - curve.force) ** 2)) / curve.normal_load
    assert rms == pytest.approx(fit.rms, rel=1e-9)
    assert fit.rms < 0.01  # the noise level is 0.005
    assert fit.law.mu_k == pytest.approx(0.4, abs=0.02)


def test_dahl_fit_recovers_sigma0_and_mu_from_loops():
    x = np.concatenate([np.linspace(0, 5e-8, 200), np.linspace(5e-8, -5e-8, 400), np.linspace(-5e-8, 5e-8, 400)])
    force = 2e-3 * ft.dahl_force(4e7, 1.5, x)
    loops = ReversalLoops(displacement=x, force=force, drive=x, normal_load=2e-3, amplitudes=(5e-8,))
    fit = ft.fit_dahl(loops, reach=1e9)
    assert fit.law.sigma0 == pytest.approx(4e7, rel=1e-4) and fit.law.mu == pytest.approx(1.5, rel=1e-4)


def test_steady_mask_drops_lift_off_points():
    curve = SteadyCurve(np.array([-1.0, 1.0, 1000.0]), np.array([-1e-3, 1e-3, 0.0]),
                        np.array([1e-5, 1e-5, 0.0]), 2e-3)
    assert ft.steady_mask(curve).tolist() == [True, True, False]


def test_belt_period_of_a_static_kinetic_law_matches_the_closed_form():
    from asperity2d.friction import StaticKinetic

    m, k, v, n = 2.88e-15, 3720.0, 10.0, 2e-3
    out = ft.belt_period(StaticKinetic(1.9, 0.4), mass=m, stiffness=k, velocity=v, normal_load=n)
    # stick: the spring force climbs 2 (Fs - Fk) at k V; slip: the harmonic arc back to V
    w = np.sqrt(k / m)
    a = (1.9 - 0.4) * n / k
    stick = 2 * a / v
    arc = np.pi + 2 * np.arctan(v / (w * a))  # slip: harmonic about Fk/k from +a back to -a
    assert out["period_s"] == pytest.approx(stick + arc / w, rel=0.01)


def test_asperity_stick_slip_period_is_locked_to_the_pitch():
    """Why a fitted velocity law cannot give the asperity scene's period (pinned finding).

    On a regular surface each slip ends when the tips drop into a valley, so
    the slip length is a whole number of pitches and the period is
    n * pitch / V: with a 1000 N/m drive at 10 m/s, exactly 2 pitches. A
    steady-state law fitted to the tribometer (kinetic ~0.44 L) predicts a
    Coulomb slip of 2 (F_s - F_k) / k ~ 4.6 pitches instead; the belt solver
    with that law is off by the same factor (see scenes/tribometer.py).
    """
    import asperity2d as a
    from asperity2d import tribometer as tb

    scene = tb.make_tribometer_scene(drive_stiffness=1000.0, drive_velocity=10.0, lower_count=16)
    result = a.simulate(scene)
    t_slip = np.array([e.t_slip for e in a.stick_slip_events(result) if e.complete])
    assert len(t_slip) >= 4
    pitch = scene.lower.spacing.pitch
    np.testing.assert_allclose(np.diff(t_slip[1:]), 2 * pitch / 10.0, rtol=0.005)
