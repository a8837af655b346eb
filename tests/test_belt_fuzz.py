"""Property-based fuzzing of simulate_chain (issue 11): every call returns finite arrays or raises cleanly.

Each parameter is drawn from a mixture of plausible values (so that most
chains actually run: stick-slip, grazes, damping, Stribeck laws, ramped belts,
the sign() method) and hostile ones (NaN, inf, 1e300, 10**400, bools, strings,
complex, Fractions, wrong lengths, None). The property: ``simulate_chain``
returns a BeltResult whose arrays are finite -- and whose energy books close
to 1e-6 for closed-form runs -- or raises SceneError / SimulationError, within
Hypothesis' deadline.

The budget parameters (``max_steps``, ``max_events``) are drawn small or hostile:
they are the user's own licence to run long, so the wall-time bound holds for the
values drawn here, not for arbitrary budgets.

Default run: 150 examples (~10-20 s); ``-m slow``: 3,000.
"""

import math
from datetime import timedelta
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from asperity2d.belt import simulate_chain
from asperity2d.errors import SceneError, SimulationError
from asperity2d.friction import CoulombViscous, Stribeck

HOSTILE = st.sampled_from([math.nan, math.inf, -math.inf, 1e300, -1e300, 5e-324, 10**400, -(10**30), True, False,
                           "1.0", "abc", 1 + 2j, None, Fraction(1, 3), [], [1.0], [math.nan, 1.0], object(), -1.0, 0])


def _decades(lo, hi):
    return st.floats(min_value=math.log10(lo), max_value=math.log10(hi)).map(lambda e: 10.0**e)


@st.composite
def chains(draw):
    """simulate_chain keyword arguments: a plausible chain, then 0-3 parameters made hostile."""
    n = draw(st.integers(min_value=1, max_value=5))

    def vec(element, size):
        return draw(st.lists(element, min_size=size, max_size=size))

    kw = {
        "masses": vec(_decades(0.1, 10.0), n),
        "springs": vec(st.one_of(_decades(0.1, 100.0), st.just(0.0)), n + 1),
        "dampers": vec(st.one_of(st.just(0.0), st.just(0.0), _decades(1e-3, 3.0)), n + 1),
        "x0": vec(st.floats(-0.1, 0.1), n),
        "v0": vec(st.floats(-0.2, 0.2), n),
        "t_end": draw(st.floats(0.05, 20.0)),
        "v_belt": draw(st.one_of(st.floats(-0.3, 0.3), st.just(0.0),
                                 st.floats(-0.05, 0.05).map(lambda a: (lambda t, a=a: 0.1 + a * t)))),
    }
    law = draw(st.sampled_from(["coulomb", "coulomb", "static-kinetic", "static-kinetic", "stribeck", "viscous"]))
    mu_s = draw(st.floats(0.0, 0.6))
    if law == "coulomb":
        kw["mu_s"] = mu_s
    elif law == "static-kinetic":
        kw["mu_s"], kw["mu_k"] = mu_s, draw(st.floats(0.0, 1.0)) * mu_s
    elif law == "stribeck":
        kw["friction"] = Stribeck(mu_s + 0.05, mu_s, draw(st.floats(0.005, 0.1)))
    else:
        kw["friction"] = CoulombViscous(mu_s, draw(st.floats(0.0, 1.0)))
    optional = {
        "g": st.floats(0.0, 20.0),
        "normal_load": st.lists(st.floats(0.0, 20.0), min_size=n, max_size=n),
        "method": st.sampled_from(["exact", "exact", "exact", "sign"]),
        "n_samples": st.integers(2, 400),
        "include_events": st.booleans(),
        "rtol": st.sampled_from([1e-4, 1e-6, 1e-8]),
        "atol": st.sampled_from([1e-6, 1e-9]),
        "integrator": st.sampled_from(["LSODA", "RK45", "DOP853", "Radau"]),
        "max_events": st.integers(1, 2000),
        "max_steps": st.one_of(st.integers(1, 20_000), st.integers(2_000, 20_000)),
    }
    for name, strategy in optional.items():
        if draw(st.booleans()) or name == "max_steps":
            kw[name] = draw(strategy)
    names = sorted(set(kw) | {"mu_s", "mu_k", "friction", "t_eval"})
    for name in draw(st.lists(st.sampled_from(names), max_size=3, unique=True).filter(lambda x: len(x) != 2)):
        kw[name] = draw(st.one_of(HOSTILE, st.lists(HOSTILE, min_size=n, max_size=n + 1)))
    return kw


def _check(kw):
    try:
        r = simulate_chain(**kw)
    except (SceneError, SimulationError) as exc:
        assert str(exc)  # a message, and formatting it did not raise
        return
    for name in ("t", "x", "v", "friction_force", "belt_work", "friction_dissipation", "damper_dissipation",
                 "kinetic_energy", "spring_energy"):
        assert np.all(np.isfinite(getattr(r, name))), name
    assert r.x.shape == (r.n, r.t.size) and np.all(np.diff(r.t) >= 0)
    if r.meta["backend"] == "closed-form phases":
        assert r.energy_balance_error() < 1e-6


FUZZ = dict(deadline=timedelta(seconds=20), suppress_health_check=[HealthCheck.too_slow], derandomize=True)


@settings(max_examples=150, **FUZZ)
@given(chains())
def test_simulate_chain_returns_finite_results_or_raises_cleanly(kw):
    _check(kw)


@pytest.mark.slow
@settings(max_examples=3000, **FUZZ)
@given(chains())
def test_simulate_chain_fuzz_thousands(kw):
    _check(kw)
