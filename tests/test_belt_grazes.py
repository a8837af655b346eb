"""Tangential contacts with belt speed are decided by one rule, not by round-off (issue 15 item 5).

Closed form used throughout: with mu_s = mu_k, a mass that breaks away while its
only neighbours are stuck (or walls) moves as v(tau) = v_p + (V - v_p)·cos(omega·tau)
(it leaves the belt speed with zero relative acceleration), so its velocity comes
back to V *tangentially* exactly one period 2·pi/omega later: a touch-and-go.
Here omega = sqrt((k_left + k_right)/m) and both neighbours stay stuck over that
period, so the graze time is t_slip + 2·pi/omega.
"""

import numpy as np
import pytest

from asperity2d.belt import presets, simulate_chain
from asperity2d.belt.phases.finder import SWITCH_TOL

G = 9.81


def _slip_before(result, mass, t):
    return max(e.t for e in result.events if e.kind == "slip" and e.mass == mass and e.t < t)


@pytest.mark.parametrize("name,mass,k", [("table2-3dof", 0, 10.0), ("table2-3dof", 2, 10.0),
                                         ("table3-k20", 2, 20.0)])
def test_structural_graze_is_reported_at_the_closed_form_time(name, mass, k):
    r = simulate_chain(**presets.preset(name))
    grazes = [e for e in r.events if e.kind == "graze" and e.mass == mass]
    assert len(grazes) == 1
    t_graze = grazes[0].t
    want = _slip_before(r, mass, t_graze) + 2 * np.pi / np.sqrt(2 * k)  # one period after breakaway
    # the touch is the minimum of v_i - V, a simple zero of its derivative: located to rounding
    assert t_graze == pytest.approx(want, rel=1e-13)
    # a graze is not a stick: no stick interval starts (or ends) near it
    for a, b in r.stick_intervals[mass]:
        assert abs(a - t_graze) > 1e-3 and abs(b - t_graze) > 1e-3
    # the mass keeps slipping on both sides of the touch, below belt speed
    near = simulate_chain(**presets.preset(name, t_eval=[t_graze - 0.01, t_graze + 0.01], include_events=False))
    assert np.all(near.state[mass] == -1) and np.all(near.v[mass] < 0.1 - 1e-6)


def test_table2_graze_no_longer_leaves_a_nanosecond_stick_interval():
    # before the touch rule: a 5.2e-9 s stick interval at 2.977654 s, decided by round-off
    r = simulate_chain(**presets.preset("table2-3dof"))
    durations = [b - a for per in r.stick_intervals for a, b in per]
    assert min(durations) > 1e-3
    assert [(e.mass, round(e.t, 6)) for e in r.events if e.kind == "graze"] == [(2, 2.576205), (0, 2.977654)]


def _orbit(depth):
    """1-DOF orbit whose velocity overshoots belt speed by a dip of ``depth`` (in SWITCH_TOL units).

    x = mu·N/k + d·cos(omega t) + V/omega·sin(omega t): v = V·cos - d·omega·sin peaks at
    sqrt(V² + d²omega²) ≈ V + d²omega²/(2V), so the slip event function s·(v - V)/v_scale
    dips to -d²omega²/(2·V·v_scale). Returns (result, d, omega, V).
    """
    m, k, mu, V = 1.0, 10.0, 0.2, 0.1
    omega = np.sqrt(k / m)
    v_scale = max(V, mu * G / omega)  # the chain's velocity scale (see ChainSpec.velocity_scale)
    d = np.sqrt(2 * V * v_scale * depth * SWITCH_TOL) / omega
    r = simulate_chain([m], [k, 0.0], [0.0, 0.0], mu_s=mu, v_belt=V, x0=[mu * G / k + d], v0=[V],
                       t_end=20.0, n_samples=201)
    return r, d, omega, V


@pytest.mark.parametrize("depth", [0.0, 0.3, 0.7, 0.99])
def test_dips_shallower_than_the_tolerance_are_grazes(depth):
    r, d, omega, V = _orbit(depth)
    assert r.chain.velocity_scale == pytest.approx(0.2 * G / omega)
    assert r.stick_intervals == [[]]
    assert len([e for e in r.events if e.kind == "graze"]) == 10  # one touch per period 2 pi/omega ~ 1.99 s


@pytest.mark.parametrize("depth", [1.01, 1.5, 4.0])
def test_dips_deeper_than_the_tolerance_stick_for_the_closed_form_time(depth):
    # v crosses V at omega t = 2 pi - 2 phi, tan phi = d omega / V, where x = mu N/k - d: stuck, the
    # mass rides the belt until k x = mu N again, d/V later. After that breakaway the orbit is the
    # tangential one (x = mu N/k + V/omega sin): grazes from then on.
    r, d, omega, V = _orbit(depth)
    (start, end), = r.stick_intervals[0]
    assert start == pytest.approx((2 * np.pi - 2 * np.arctan(d * omega / V)) / omega, rel=1e-12)
    # the start is a near-tangent crossing (slope ~1e-4 of the scale): 1e-12 s in time, 1e-7 of d/V
    assert end - start == pytest.approx(d / V, rel=1e-6)
    assert [e.kind for e in r.events][:3] == ["stick", "slip", "graze"]
