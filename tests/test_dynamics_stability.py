"""Floquet multipliers and Lyapunov exponents against closed forms.

Cost: about 5 s in the default run (the Benettin run is 400 short exact-solver runs); the
three-mass Floquet check is marked slow (7 s).
"""

import numpy as np
import pytest
import scipy.linalg

from asperity2d import SceneError
from asperity2d.dynamics import chain_lyapunov, floquet, lyapunov_series, monodromy
from asperity2d.dynamics.lyapunov import have_nolds

# a frictionless, damped, non-symmetric 2-mass chain: its flow is linear, x' = A x
LINEAR = dict(masses=[1.0, 2.0], springs=[10.0, 5.0, 8.0], dampers=[0.3, 0.1, 0.2], mu_s=0.0, v_belt=0.1,
              x0=[0.01, 0.0], v0=[0.0, 0.02], t_end=1.0)


def linear_matrix():
    m = np.array(LINEAR["masses"])
    k, c = np.array(LINEAR["springs"]), np.array(LINEAR["dampers"])
    K = np.diag(k[:-1] + k[1:]) - np.diag(k[1:-1], 1) - np.diag(k[1:-1], -1)
    C = np.diag(c[:-1] + c[1:]) - np.diag(c[1:-1], 1) - np.diag(c[1:-1], -1)
    return np.block([[np.zeros((2, 2)), np.eye(2)], [-K / m[:, None], -C / m[:, None]]])


@pytest.mark.parametrize("period", [0.37, 1.3, 4.0])
def test_linear_chain_multipliers_are_exp_lambda_t(period):
    # any return time T: the time-T map of x' = A x is exp(A T), whose eigenvalues are exp(λ T)
    A = linear_matrix()
    M = monodromy(LINEAR, [0.01, -0.02, 0.03, 0.01], period)
    expected = np.sort_complex(np.exp(np.linalg.eigvals(A) * period))
    assert np.allclose(np.sort_complex(np.linalg.eigvals(M)), expected, rtol=1e-7, atol=1e-9)
    # and the matrix itself: central differences of a linear map are exact up to round-off / step
    assert np.max(np.abs(M - scipy.linalg.expm(A * period))) < 1e-7


ONE_DOF = dict(masses=[1.0], springs=[10.0, 0.0], dampers=[0.0, 0.0], mu_s=0.3, mu_k=0.2, v_belt=0.1,
               x0=[0.0], v0=[0.1], t_end=60.0, n_samples=6001)


def test_one_dof_stick_slip_cycle_is_superstable():
    # after one stick phase the state no longer depends on where the orbit started: multipliers {1, 0}
    f = floquet(ONE_DOF)
    assert f.multiplicity == 1 and f.closure < 1e-12
    assert abs(f.trivial - 1) < 1e-7
    others = [m for m in f.multipliers if abs(m - f.trivial) > 0]
    assert len(others) == 1 and abs(others[0]) < 1e-8
    assert f.zero == 1 and f.stable and f.stuck_masses == (0,)
    assert f.convergence < 1e-7


@pytest.mark.slow  # ~7 s: a 200 s run and 24 exact runs of one 10 s period
def test_floquet_trivial_multiplier_of_a_three_mass_cycle():
    # c = 0.5, mu_s = 0.4: a period-3 stick-slip cycle. Whatever the cycle, a shift along the orbit
    # returns as itself: one multiplier is 1 -- a check of the differences across every switch
    chain = dict(masses=[1.0] * 3, springs=[10.0] * 4, dampers=[0.5] * 4, mu_s=0.4, mu_k=0.2, v_belt=0.1,
                 x0=[0.05, 0.06, 0.07], v0=[0.04, 0.03, 0.05], t_end=200.0, n_samples=20001)
    f = floquet(chain)
    assert f.multiplicity == 3 and f.closure < 1e-8  # 200 s: converged onto the cycle to ~1e-9
    assert abs(f.trivial - 1) < 1e-6 and f.convergence < 1e-5
    assert f.stable and f.zero >= 1  # every mass sticks during the cycle


def test_floquet_refuses_a_run_without_a_cycle():
    with pytest.raises(SceneError, match="no limit cycle"):
        floquet({**LINEAR, "mu_s": 0.2, "t_end": 20.0})


def test_benettin_exponent_of_a_linear_chain_is_the_largest_real_part():
    exact = float(np.max(np.linalg.eigvals(linear_matrix()).real))
    est = chain_lyapunov(LINEAR, steps=200, interval=1.0)
    # the estimate carries the log of the initial direction's projection, spread over 180 s: ~1 %
    assert est.value == pytest.approx(exact, rel=0.02)
    assert est.method == "benettin" and est.settings["collapsed_steps"] == 0


def test_benettin_is_deterministic():
    a = chain_lyapunov(LINEAR, steps=10, interval=0.5, seed=3)
    b = chain_lyapunov(LINEAR, steps=10, interval=0.5, seed=3)
    assert a.value == b.value


def logistic(count, r=4.0, x=0.1):
    out = np.empty(count)
    for i in range(count):
        x = r * x * (1 - x)
        out[i] = x
    return out


@pytest.mark.parametrize("method", ["rosenstein", pytest.param("nolds", marks=pytest.mark.skipif(
    not have_nolds(), reason="nolds is an optional extra"))])
def test_series_exponent_of_the_logistic_map_is_ln2(method):
    y = logistic(3000)
    est = lyapunov_series(np.arange(y.size, dtype=float), y, emb_dim=2, lag=1, min_tsep=10, trajectory_len=5,
                          method=method)
    assert est.value == pytest.approx(np.log(2), rel=0.02)  # per iteration: t is the iteration count


def test_series_exponent_of_a_periodic_signal_is_near_zero():
    t = np.linspace(0, 200, 8001)
    est = lyapunov_series(t, np.sin(t), method="rosenstein")
    # Rosenstein's slope on a limit cycle: no divergence beyond sampling noise (here |λ| << ω = 1/s)
    assert abs(est.value) < 0.02


def test_bad_input_names_the_parameter():
    with pytest.raises(SceneError, match="`period`"):
        monodromy(LINEAR, [0, 0, 0, 0], -1.0)
    with pytest.raises(SceneError, match="`steps`"):
        chain_lyapunov(LINEAR, steps=1)
    with pytest.raises(SceneError, match="`method`"):
        lyapunov_series(np.arange(100.0), np.sin(np.arange(100.0)), method="wolf")


def test_auto_falls_back_to_the_own_estimator_without_nolds(monkeypatch):
    import asperity2d.dynamics.lyapunov as lyap

    monkeypatch.setattr(lyap, "have_nolds", lambda: False)
    y = logistic(1000)
    est = lyap.lyapunov_series(np.arange(y.size, dtype=float), y, emb_dim=2, lag=1, min_tsep=10, trajectory_len=5)
    assert est.method == "rosenstein" and est.value == pytest.approx(np.log(2), rel=0.03)
    with pytest.raises(SceneError, match="nolds"):
        lyap.lyapunov_series(np.arange(y.size, dtype=float), y, method="nolds")
