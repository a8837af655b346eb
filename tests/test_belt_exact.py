"""Exact event-driven belt solver against closed forms (DESIGN.md section 6)."""

import numpy as np
import pytest

from asperity2d.belt import simulate_chain
from asperity2d.errors import SceneError
from asperity2d.closed_forms import one_dof_cycle

G = 9.81


def test_one_dof_stick_slip_matches_closed_form_over_100_cycles():
    m, k, mu_s, mu_k, V = 1.0, 10.0, 0.3, 0.2, 0.1
    Fs, Fk, t_slip, t_stick = one_dof_cycle(m, k, mu_s, mu_k, V)
    t_first = Fs / (k * V)
    period = t_slip + t_stick
    n_cycles = 100
    r = simulate_chain([m], [k, 0.0], [0.0, 0.0], mu_s=mu_s, mu_k=mu_k, v_belt=V, x0=[0.0], v0=[V],
                       t_end=t_first + n_cycles * period + 0.5 * t_slip, n_samples=200)
    slips = np.array([e.t for e in r.events if e.kind == "slip"])
    sticks = np.array([e.t for e in r.events if e.kind == "stick"])
    assert len(slips) == n_cycles + 1 and len(sticks) == n_cycles
    want_slip = t_first + period * np.arange(n_cycles + 1)
    want_stick = want_slip[:-1] + t_slip
    # event times are located to machine precision; 1e-8 relative is the contract
    np.testing.assert_allclose(slips, want_slip, rtol=1e-8, atol=0)
    np.testing.assert_allclose(sticks, want_stick, rtol=1e-8, atol=0)
    # (breakaway at k x = mu_s N and the drop of exactly 2 (Fs - Fk): asperity2d.closed_forms)
    durations = np.diff(np.array(r.stick_intervals[0][1:]), axis=1).ravel()
    np.testing.assert_allclose(durations, t_stick, rtol=1e-8)


def test_slip_phase_is_harmonic_about_kinetic_equilibrium():
    m, k, mu_s, mu_k, V = 2.0, 50.0, 0.5, 0.3, 0.2
    Fs, Fk, t_slip, _ = one_dof_cycle(m, k, mu_s, mu_k, V)
    t_first = Fs / (k * V)
    t = t_first + np.linspace(0, t_slip, 50)[1:-1]
    r = simulate_chain([m], [k, 0.0], [0.0, 0.0], mu_s=mu_s, mu_k=mu_k, v_belt=V, x0=[0.0], v0=[V],
                       t_end=t_first + t_slip, t_eval=t, include_events=False)
    w = np.sqrt(k / m)
    tau = r.t - t_first
    x_ref = Fk / k + (Fs - Fk) / k * np.cos(w * tau) + V / w * np.sin(w * tau)
    np.testing.assert_allclose(r.x[0], x_ref, rtol=0, atol=1e-12 * Fs / k)
    assert np.all(r.state[0] == -1)


@pytest.mark.parametrize("mu_s,mu_k", [(0.1, 0.1), (0.15, 0.1)])
def test_coulomb_free_decay_on_still_surface(mu_s, mu_k):
    m, k, x0 = 1.0, 10.0, 0.5
    Fs, Fk = mu_s * m * G, mu_k * m * G
    w = np.sqrt(k / m)
    # turning points every half period; amplitude falls by 2 Fk/k per half cycle (4 Fk/k per cycle)
    amps = [x0]
    while abs(amps[-1]) * k > Fs:
        a = abs(amps[-1]) - 2 * Fk / k
        amps.append(-np.sign(amps[-1]) * a)
    r = simulate_chain([m], [k, 0.0], [0.0, 0.0], mu_s=mu_s, mu_k=mu_k, v_belt=0.0, x0=[x0], v0=[0.0],
                       t_end=len(amps) * np.pi / w + 1.0)
    reversals = [e for e in r.events if e.kind == "reverse"]
    np.testing.assert_allclose([e.t for e in reversals], np.pi / w * np.arange(1, len(amps) - 1), rtol=1e-10)
    np.testing.assert_allclose([e.x for e in reversals], amps[1:-1], rtol=1e-10)
    # it stops at the first turning point where k|x| <= Fs and stays there
    (start, end), = r.stick_intervals[0]
    assert start == pytest.approx((len(amps) - 1) * np.pi / w, rel=1e-10)
    assert end == r.t[-1]
    assert r.x[0, -1] == pytest.approx(amps[-1], rel=1e-10)


def test_two_symmetric_masses_move_as_one_dof():
    m, k, kc, mu_s, mu_k, V = 1.0, 10.0, 7.0, 0.3, 0.2, 0.1
    one = simulate_chain([m], [k, 0.0], [0.0, 0.0], mu_s=mu_s, mu_k=mu_k, v_belt=V, x0=[0.0], v0=[V], t_end=20)
    # wall-k-m-kc-m-k-wall with x1 = x2: the coupling stays unstretched, each mass feels k alone
    mirror = simulate_chain([m, m], [k, kc, k], [0.0] * 3, mu_s=mu_s, mu_k=mu_k, v_belt=V,
                            x0=[0.0, 0.0], v0=[V, V], t_end=20)
    assert mirror.meta["n_events"] > 10  # both masses switch together at every event
    np.testing.assert_allclose(mirror.x[0], mirror.x[1], rtol=0, atol=1e-14)
    for i in range(2):
        np.testing.assert_allclose(mirror.stick_intervals[i], one.stick_intervals[0], rtol=1e-10)
    t1 = np.interp(one.t, mirror.t, mirror.x[0])
    np.testing.assert_allclose(t1, one.x[0], atol=1e-9)


@pytest.mark.parametrize("dampers", [[0.0] * 4, [2.0] * 4, [0.5, 0.0, 1.0, 0.3]])
def test_energy_balance_closes(dampers):
    r = simulate_chain([1.0, 1.5, 0.7], [10.0, 20.0, 5.0, 10.0], dampers, mu_s=0.4, mu_k=0.25, v_belt=0.2,
                       x0=[0.05, -0.02, 0.07], v0=[0.04, 0.3, -0.1], t_end=15)
    assert r.meta["n_events"] >= 3  # the balance is checked across switches
    assert r.energy_balance_error() <= 1e-8
    assert np.all(np.diff(r.friction_dissipation) >= -1e-15)
    if any(dampers):
        assert r.damper_dissipation[-1] > 0


def test_stuck_velocity_is_exactly_belt_speed():
    r = simulate_chain([1.0, 1.0, 1.0], [10.0] * 4, [0.0] * 4, mu_s=0.2, v_belt=0.1,
                       x0=[0.05, 0.06, 0.07], v0=[0.04, 0.03, 0.05], t_end=10)
    stuck = r.state == 0
    assert stuck.sum() > 100
    assert np.all(r.v[stuck] == 0.1)
    # static friction never exceeds its limit
    assert np.all(np.abs(r.friction_force[stuck]) <= 0.2 * G * (1 + 1e-9))


@pytest.mark.parametrize(
    "change,name",
    [
        ({"springs": [10.0, 10.0]}, "springs"),
        ({"dampers": [0.0, -1.0, 0.0]}, "dampers"),
        ({"masses": [1.0, 0.0]}, "masses"),
        ({"x0": [float("nan"), 0.0]}, "x0"),
        ({"mu_s": 0.1, "mu_k": 0.2}, "mu_s"),
        ({"t_end": 0.0}, "t_end"),
        ({"n_samples": 1}, "n_samples"),
        ({"method": "euler"}, "method"),
    ],
)
def test_invalid_parameters_name_the_parameter(change, name):
    kwargs = dict(masses=[1.0, 1.0], springs=[10.0] * 3, dampers=[0.0] * 3, mu_s=0.2, v_belt=0.1,
                  x0=[0.0, 0.0], v0=[0.0, 0.0], t_end=1.0)
    kwargs.update(change)
    with pytest.raises(SceneError, match=f"`{name}`"):
        simulate_chain(**kwargs)
