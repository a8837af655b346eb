"""The belt solver's event functions and the closed-form integral of squares, checked
independently: the sampled event functions (integrated phases) against finite differences of
their own values and against the closed-form ones (modal phases), with dampers on and a belt
whose speed changes; ``square_integral`` on sparse forms (long chains) against the dense
form and against quadrature."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.sparse
from scipy.integrate import quad

from asperity2d.belt.backend import RunOptions, StepBudget
from asperity2d.belt.phases.events import ModalEvents, SampledEvents, event_rows
from asperity2d.belt.chain.hybrid import OdePhase, _atol, _work_atol
from asperity2d.belt.chain.linear import LinearPhase, Template
from asperity2d.belt.phases.modal import SPARSE_ABOVE, ModalForm, square_integral
from asperity2d.belt.spec import ChainSpec

#: two masses, a spring and a damper everywhere; mass 0 stuck, mass 1 slipping forward
CHAIN = dict(masses=(1.0, 1.5), springs=(10.0, 6.0, 8.0), dampers=(0.4, 0.3, 0.5), mu_s=0.4, mu_k=0.25,
             x0=(0.02, -0.01), v0=(0.1, 0.35), t_end=5.0)
MODES = np.array([0, 1])


def ode_phase(v_belt):
    spec = ChainSpec(v_belt=v_belt, **CHAIN)
    options = RunOptions.build(spec, n_samples=11, t_eval=None, include_events=False, rtol=1e-11, atol=None,
                               integrator="LSODA", max_events=1000, max_steps=10**7)
    atol = np.concatenate([_atol(spec, options.rtol, None), _work_atol(spec, options.rtol)])
    v0 = np.array([spec.belt_velocity(0.0), 0.35])
    return OdePhase(spec, MODES, np.array(spec.x0), v0, 0.0, 0.05, options, atol, StepBudget(options))


def finite_difference(events, tau, h=1e-5):
    g_plus, _ = events.values(tau + h)
    g_minus, _ = events.values(tau - h)
    return (g_plus - g_minus) / (2 * h)


def test_rows_of_a_stuck_and_a_slipping_mass():
    spec = ChainSpec(v_belt=0.1, **CHAIN)
    kind, mass = event_rows(spec, MODES)
    assert kind.tolist() == [1, -1, 0] and mass.tolist() == [0, 0, 1]  # two bounds, one slip row


def test_sampled_derivatives_are_the_derivatives_with_dampers_on():
    """Constant belt: every row's dg is the time derivative of its g (central differences of the
    integrated motion, to the integrator's accuracy) -- including the dampers' share of the
    stuck mass's required force, c (a_i - a_j)."""
    events = SampledEvents(ode_phase(0.1))
    tau = np.linspace(0.05, 0.6, 12)
    _, dg = events.values(tau)
    fd = finite_difference(events, tau)
    scale = np.abs(dg).max(axis=1, keepdims=True)
    assert np.all(scale > 0)
    assert np.abs(dg - fd).max() < 1e-5 * scale.max()
    # the dampers matter here: without their term the stuck rows' derivatives are off by more
    phase = events.phase
    x, v, a = phase.evaluate(tau)
    damper_rate = 0.4 * a[0] - 0.3 * (a[1] - a[0])  # d/dt of the damper force on mass 0
    assert np.abs(damper_rate).max() > 1e-3 * scale.max()


def test_sampled_slip_rows_follow_a_changing_belt():
    """Belt speed 0.1 + 0.05 sin(3t): a slipping mass's g = s (v - V) / v_scale changes with the
    belt's acceleration too; dg must be s (a - a_belt) / v_scale."""
    events = SampledEvents(ode_phase(lambda t: 0.1 + 0.05 * math.sin(3.0 * t)))
    tau = np.linspace(0.05, 0.5, 10)
    g, dg = events.values(tau)
    fd = finite_difference(events, tau)
    slip = events.kind == 0
    assert np.abs(dg[slip] - fd[slip]).max() < 1e-5 * np.abs(dg[slip]).max()
    a_belt = events.phase.belt_acceleration(tau)
    assert np.abs(a_belt).max() > 0.1  # the premise: the belt accelerates


def test_sampled_and_closed_form_event_functions_agree():
    """A constant-belt phase has both implementations: values and derivatives from the phase's
    evaluate() (SampledEvents) equal the closed-form modal rows (ModalEvents)."""
    spec = ChainSpec(v_belt=0.1, **CHAIN)
    phase = LinearPhase(Template(spec, MODES, {}), np.array(spec.x0), np.array([0.1, 0.35]))
    assert phase.motion is not None
    modal, sampled = ModalEvents(phase), SampledEvents(phase)
    assert modal.kind.tolist() == sampled.kind.tolist() and modal.mass.tolist() == sampled.mass.tolist()
    tau = np.linspace(0.0, 0.8, 17)
    (g1, dg1), (g2, dg2) = modal.values(tau), sampled.values(tau)
    assert np.allclose(g1, g2, rtol=1e-10, atol=1e-12) and np.allclose(dg1, dg2, rtol=1e-10, atol=1e-12)
    for r in range(len(modal)):
        g, dg, _ = sampled.point(r)(0.3)
        assert (g, dg) == pytest.approx((g1[r, 6], dg1[r, 6]), rel=1e-10, abs=1e-12)
        gm, dgm, d2gm = modal.point(r)(0.3)
        assert (gm, dgm) == pytest.approx((g1[r, 6], dg1[r, 6]), rel=1e-10, abs=1e-12)
    assert np.all(modal.bound4 >= 0)


def random_form(rows, modes, seed):
    rng = np.random.default_rng(seed)
    lam = -rng.uniform(0.1, 2.0, modes) + 1j * rng.uniform(0.0, 5.0, modes)
    B = np.zeros((rows, modes), dtype=complex)
    for r in range(rows):  # block structure: each row touches a few exponentials
        cols = rng.choice(modes, size=3, replace=False)
        B[r, cols] = rng.normal(size=3) + 1j * rng.normal(size=3)
    c0 = rng.normal(size=rows)
    return lam, B, c0


@pytest.mark.parametrize("modes", [SPARSE_ABOVE + 6, 12])
def test_square_integral_on_sparse_and_dense_forms_against_quadrature(modes):
    rows = 9
    lam, B, c0 = random_form(rows, modes, seed=modes)
    weights = np.linspace(0.5, 2.0, rows)
    dense = ModalForm(lam, B, c0, np.zeros(rows))
    sparse = ModalForm(lam, scipy.sparse.csr_array(B), c0, np.zeros(rows))
    tau = np.array([0.0, 0.3, 1.1, 2.5])
    from_dense, from_sparse = square_integral(dense, weights, tau), square_integral(sparse, weights, tau)
    assert np.allclose(from_sparse, from_dense, rtol=1e-12, atol=1e-14)

    def integrand(s):
        r = dense.at(np.array([s]))[:, 0]
        return float(weights @ r**2)

    for t, value in zip(tau, from_sparse):
        expected = quad(integrand, 0.0, t, limit=200, epsabs=1e-13, epsrel=1e-11)[0] if t else 0.0
        assert value == pytest.approx(expected, rel=1e-9, abs=1e-12)
