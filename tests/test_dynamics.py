"""Time-series tools against closed forms: spectra, Poincaré sections, limit cycles, steady state.

Cost: about 2 s (a few belt runs of a few hundred seconds with the exact solver).
"""

import numpy as np
import pytest

from asperity2d import SceneError
from asperity2d.belt import simulate_chain
from asperity2d.dynamics import (chain_cycle, chain_section, crossings, detect_period, limit_cycle,
                                 poincare_section, resample, signal, spectrum, steady_state)

M, K, G, V, MU_S, MU_K = 1.0, 10.0, 9.81, 0.1, 0.3, 0.2


def one_dof_period():
    """Closed-form stick-slip period of a mass on a belt (spring k to a wall, Fs > Fk, no damping).

    Stick from x_s = 2 x_k - x_b to x_b = Fs/k at the belt speed: 2 (Fs - Fk) / (k V).
    Slip: harmonic about x_k = Fk/k from (x_b, V) until v = V again: phase 2π - 2 atan(a ω / V),
    a = (Fs - Fk) / k.
    """
    omega = np.sqrt(K / M)
    a = (MU_S - MU_K) * M * G / K
    return 2 * a / V + (2 * np.pi - 2 * np.arctan(a * omega / V)) / omega


@pytest.fixture(scope="module")
def one_dof():
    return simulate_chain([M], [K, 0.0], [0.0, 0.0], mu_s=MU_S, mu_k=MU_K, v_belt=V, x0=[0.0], v0=[V],
                          t_end=400.0, n_samples=40001)


def test_one_dof_cycle_period_equals_closed_form(one_dof):
    cycle = chain_cycle(one_dof)
    T = one_dof_period()
    assert cycle.periodic and cycle.multiplicity == 1
    assert abs(cycle.period / T - 1) < 1e-6  # the bar; the exact solver gives ~1e-15
    # the slip is an arc of the circle of radius r = sqrt(a^2 + (V/ω)^2) about x_k, a = (Fs - Fk)/k, that
    # passes both its extremes (the arc spans 2π - 2 atan(aω/V) > π): the amplitude is r
    a = (MU_S - MU_K) * M * G / K
    r = np.hypot(a, V / np.sqrt(K / M))
    assert cycle.amplitude == pytest.approx(r, rel=1e-5)  # extreme sampled at dt = 0.01 s: error ~ (ω dt)^2 / 8


@pytest.mark.parametrize("method", ["welch", "periodogram"])
def test_one_dof_dominant_frequency_within_one_bin(one_dof, method):
    sp = spectrum(*signal(one_dof, "x"), method=method)
    assert abs(sp.dominant - 1 / one_dof_period()) <= sp.resolution


def test_one_dof_series_cycle_agrees_with_exact_section(one_dof):
    # the same period from the generic (scalar series) detector on the velocity
    cycle = limit_cycle(*signal(one_dof, "v"))
    assert cycle.periodic and cycle.multiplicity == 1
    assert abs(cycle.period / one_dof_period() - 1) < 1e-6


def test_chain_section_points_are_the_exact_stick_onsets(one_dof):
    sec = chain_section(one_dof)
    onsets = np.array([e.t for e in one_dof.events if e.kind == "stick"])
    assert np.array_equal(sec.t, onsets)
    assert np.all(sec.points[:, 1] == V)  # v = V to the last bit in a stick
    # every stick starts at x_s = 2 Fk/k - Fs/k (after the first, which starts from rest)
    assert np.allclose(sec.points[:, 0], (2 * MU_K - MU_S) * M * G / K, rtol=1e-12)


T_GRID = np.linspace(0.0, 100.0, 20001)  # dt = 5 ms


def test_pure_sine():
    y = 0.7 * np.sin(2 * np.pi * 0.7 * T_GRID + 0.3)
    sp = spectrum(T_GRID, y)
    assert abs(sp.dominant - 0.7) < 0.05 * sp.resolution  # parabolic refinement: a small part of a bin
    assert sp.thd < 1e-3
    assert sp.harmonics[0].power == pytest.approx(0.7**2 / 2, rel=0.02)  # mean square of the line
    cycle = limit_cycle(T_GRID, y)
    assert cycle.periodic and cycle.multiplicity == 1
    assert cycle.period == pytest.approx(1 / 0.7, rel=1e-7)
    assert cycle.amplitude == pytest.approx(0.7, rel=1e-3)


def test_two_incommensurate_sines_show_both_lines_and_no_period():
    y = np.sin(2 * np.pi * 0.7 * T_GRID) + 0.5 * np.sin(2 * np.pi * np.sqrt(2) * T_GRID)
    sp = spectrum(T_GRID, y)
    (f1, p1), (f2, p2) = [(p.frequency, p.power) for p in sp.peaks[:2]]
    assert abs(f1 - 0.7) < sp.resolution and abs(f2 - np.sqrt(2)) < sp.resolution
    assert p2 / p1 == pytest.approx(0.25, rel=0.05)  # amplitudes 1 and 0.5
    cycle = limit_cycle(T_GRID, y)
    assert not cycle.periodic and cycle.message.startswith("not periodic within the run")


def test_two_commensurate_sines_have_the_common_period():
    y = np.sin(2 * np.pi * 0.5 * T_GRID) + 0.8 * np.sin(2 * np.pi * 1.5 * T_GRID + 0.3)
    cycle = limit_cycle(T_GRID, y)
    assert cycle.periodic and cycle.period == pytest.approx(2.0, rel=1e-7)


def logistic(r, count, x=0.3):
    out = []
    for _ in range(count):
        x = r * x * (1 - x)
        out.append(x)
    return np.array(out)


@pytest.mark.parametrize("r, n", [(2.8, 1), (3.2, 2), (3.5, 4), (4.0, 0)])
def test_logistic_map_period_multiplicity(r, n):
    # r = 2.8: fixed point; 3.2: period 2; 3.5: period 4; 4: chaos
    found, period, k0, _ = detect_period(logistic(r, 400), rtol=1e-6)
    assert found == n
    if n:
        assert period == n


def test_white_noise_is_not_periodic():
    y = np.random.default_rng(0).standard_normal(T_GRID.size)
    cycle = limit_cycle(T_GRID, y)
    assert not cycle.periodic and np.isnan(cycle.period) and cycle.multiplicity == 0


def test_sawtooth_harmonics_fall_as_one_over_k_squared():
    y = (0.5 * T_GRID) % 1.0
    sp = spectrum(T_GRID, y, method="periodogram")
    p = np.array([h.power for h in sp.harmonics])
    k = np.arange(1, p.size + 1)
    assert np.allclose(p / p[0], 1 / k**2, rtol=0.05)
    assert sp.thd == pytest.approx(np.sqrt(np.sum(1 / k[1:] ** 2)), rel=0.03)


def test_crossings_of_a_sine_are_exact_to_interpolation_order():
    t = np.linspace(0, 10, 1001)
    up = crossings(t, np.sin(2 * np.pi * 0.45 * t), direction=1)
    assert np.allclose(up, np.arange(1, up.size + 1) / 0.45, atol=1e-9)
    sec = poincare_section(t, np.vstack([np.sin(t), np.cos(t)]), plane=0, direction=1)
    assert np.allclose(sec.points[:, 1], 1.0, atol=1e-4) and np.all(sec.points[:, 0] == 0)


def test_steady_state_finds_the_end_of_a_decay():
    y = 3 * np.exp(-T_GRID / 5) * np.sin(9 * T_GRID) + np.sin(2 * np.pi * T_GRID)
    st = steady_state(T_GRID, y, rtol=0.05)
    # the transient's envelope 3 exp(-t/5) falls below 5 % of the range 2 at t = 5 ln(30) = 17 s
    assert st.settled and 15 <= st.t_start <= 25


def test_decay_to_rest_is_not_a_cycle():
    r = simulate_chain([M], [K, 0.0], [0.5, 0.0], mu_s=0.2, v_belt=V, x0=[0.3], v0=[0.0], t_end=300.0)
    cycle = chain_cycle(r)
    assert not cycle.periodic and "rest" in cycle.message


def test_belt_acceleration_is_the_derivative_of_velocity(one_dof):
    t, a = signal(one_dof, "acceleration")
    _, v = signal(one_dof, "v")
    slip = (one_dof.state[0] != 0)
    fd = np.gradient(v, t)
    inner = slip & np.roll(slip, 1) & np.roll(slip, -1) & (np.diff(t, prepend=-1) > 0)
    # a 3-point derivative errs by dt^2/6 |v'''| ~ 1e-4 * 0.3 ω^3 ... 2e-4 m/s^2 here
    assert np.max(np.abs(fd[inner] - a[inner])) < 1e-3
    assert np.all(a[one_dof.state[0] == 0] == 0)  # stuck on a constant-speed belt


def test_resample_is_uniform_and_exact_on_a_line():
    t = np.array([0.0, 0.1, 0.1, 0.25, 0.3, 1.0])
    tu, yu = resample(t, 2 * t + 1, dt=0.05)
    assert np.allclose(np.diff(tu), 0.05) and tu[-1] == pytest.approx(1.0)
    assert np.allclose(yu, 2 * tu + 1)


def test_bad_input_names_the_parameter(one_dof):
    with pytest.raises(SceneError, match="`signal`"):
        signal(one_dof, "speed")
    with pytest.raises(SceneError, match="`mass`"):
        signal(one_dof, "x", mass=3)
    with pytest.raises(SceneError, match="`method`"):
        spectrum(T_GRID, np.sin(T_GRID), method="fft")
    with pytest.raises(SceneError, match="`y`"):
        spectrum(T_GRID[:4], T_GRID[:4])
    with pytest.raises(SceneError, match="`rtol`"):
        limit_cycle(T_GRID, np.sin(T_GRID), rtol=0)
    with pytest.raises(SceneError, match="finite"):
        limit_cycle(T_GRID, np.full(T_GRID.size, np.nan))
