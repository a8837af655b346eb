"""Every simulate_chain parameter is checked before any arithmetic (issue 11 for chains).

Bad input: one SceneError naming the parameter the user wrote; runs over a budget:
SceneError up front (when the size is known) or SimulationError naming the budget.
"""

import math
from decimal import Decimal
from fractions import Fraction

import numpy as np
import pytest

from asperity2d.belt import simulate_chain
from asperity2d._inputs import show
from asperity2d.errors import SceneError, SimulationError
from asperity2d.friction import Stribeck

BASE = dict(masses=[1.0, 1.0], springs=[10.0] * 3, dampers=[0.0] * 3, mu_s=0.2, v_belt=0.1,
            x0=[0.0, 0.0], v0=[0.0, 0.0], t_end=1.0)


def _raises(change, name, error=SceneError):
    kwargs = {**BASE, **change}
    with pytest.raises(error, match=f"`{name}`"):
        simulate_chain(**kwargs)


class _Hostile:
    def __repr__(self):
        raise RuntimeError("repr fails")

    def __float__(self):
        raise RuntimeError("float fails")


@pytest.mark.parametrize("change,name", [
    ({"masses": "abc"}, "masses"), ({"masses": [1.0, "2"]}, "masses"), ({"masses": [True, 1.0]}, "masses"),
    ({"masses": [1 + 1j, 1.0]}, "masses"), ({"masses": []}, "masses"), ({"masses": [[1.0, 2.0]]}, "masses"),
    ({"masses": [1.0, 0.0]}, "masses"), ({"masses": [1.0, -1.0]}, "masses"), ({"masses": [1e-300, 1.0]}, "masses"),
    ({"masses": [math.inf, 1.0]}, "masses"), ({"masses": [10**400, 1.0]}, "masses"),
    ({"masses": np.array(["a", "b"])}, "masses"), ({"masses": np.ones((2, 1))}, "masses"),
    ({"masses": [Decimal("NaN"), 1.0]}, "masses"), ({"masses": (m for m in [1.0, 1.0])}, "masses"),
    ({"springs": [10.0, 10.0]}, "springs"), ({"springs": [10.0, -1.0, 10.0]}, "springs"),
    ({"springs": [10.0, math.nan, 10.0]}, "springs"), ({"dampers": [0.0, -1.0, 0.0]}, "dampers"),
    ({"dampers": None}, "dampers"), ({"mu_s": None}, "mu_s"), ({"mu_s": "0.3"}, "mu_s"), ({"mu_s": True}, "mu_s"),
    ({"mu_s": -0.1}, "mu_s"), ({"mu_s": 1e101}, "mu_s"), ({"mu_s": 0.1, "mu_k": 0.2}, "mu_s"),
    ({"mu_k": 0.1j}, "mu_k"), ({"friction": Stribeck(0.4, 0.3, 0.01)}, "mu_s"), ({"friction": "coulomb"}, "friction"),
    ({"v_belt": "fast"}, "v_belt"), ({"v_belt": math.nan}, "v_belt"), ({"v_belt": lambda t: 1 / 0}, "v_belt"),
    ({"v_belt": lambda t: "x"}, "v_belt"), ({"x0": [0.0]}, "x0"), ({"v0": [0.0, math.inf]}, "v0"),
    ({"t_end": 0.0}, "t_end"), ({"t_end": -1.0}, "t_end"), ({"t_end": 1e300}, "t_end"), ({"t_end": "1"}, "t_end"),
    ({"g": -9.81}, "g"), ({"g": "9.81"}, "g"), ({"normal_load": [1.0]}, "normal_load"),
    ({"normal_load": [1.0, -1.0]}, "normal_load"), ({"method": "euler"}, "method"), ({"method": 3}, "method"),
    ({"n_samples": 1}, "n_samples"), ({"n_samples": 2.5}, "n_samples"), ({"n_samples": True}, "n_samples"),
    ({"n_samples": 10**9}, "n_samples"), ({"n_samples": 10**50}, "n_samples"), ({"t_eval": []}, "t_eval"),
    ({"t_eval": [0.0, 0.5, 0.2]}, "t_eval"), ({"t_eval": [0.0, 2.0]}, "t_eval"), ({"t_eval": ["a"]}, "t_eval"),
    ({"include_events": "yes"}, "include_events"), ({"rtol": 0.0}, "rtol"), ({"rtol": 1.0}, "rtol"),
    ({"rtol": 1e-20}, "rtol"), ({"rtol": "1e-8"}, "rtol"), ({"atol": -1.0}, "atol"), ({"atol": "x"}, "atol"),
    ({"integrator": "Euler"}, "integrator"), ({"max_events": 0}, "max_events"), ({"max_events": 1.5}, "max_events"),
    ({"max_events": True}, "max_events"), ({"max_steps": 0}, "max_steps"), ({"max_steps": "many"}, "max_steps"),
    ({"masses": [_Hostile(), 1.0]}, "masses"), ({"t_end": _Hostile()}, "t_end"),
])
def test_bad_parameters_raise_scene_error_naming_them(change, name):
    _raises(change, name)


def test_messages_never_fail_to_format():
    assert show(10**5000) == "an integer of 16610 bits"
    assert show(_Hostile()) == "<_Hostile object>"
    assert show(Fraction(1, 3)) == "Fraction(1, 3)"
    assert len(show("x" * 1000)) == 60
    with pytest.raises(SceneError, match="an integer of 16610 bits"):
        simulate_chain(**{**BASE, "t_end": 10**5000})


def test_exact_real_types_are_accepted():
    # Fraction, Decimal, NumPy and Python ints are real numbers: same chain, same result
    floats = simulate_chain(**{**BASE, "x0": [0.01, 0.0]}, n_samples=11)
    exotic = simulate_chain(**{**BASE, "masses": [Fraction(1), np.int64(1)], "x0": [Decimal("0.01"), 0],
                               "mu_s": Fraction(1, 5), "t_end": np.float32(1.0)}, n_samples=11)
    np.testing.assert_array_equal(floats.x, exotic.x)


@pytest.mark.parametrize("change,words", [
    # far beyond the chain's periods: refused up front, naming t_end and the budget
    ({"t_end": 1e9}, ["`t_end`", "`max_steps`"]),
    ({"masses": [1e-60, 1.0], "t_end": 1.0}, ["`t_end`", "`masses`"]),
    # each value within its window, jointly overflowing
    ({"v_belt": 1e90, "t_end": 1e80}, ["`v_belt` times `t_end`"]),
    ({"mu_s": 1e80, "g": 1e80}, ["`mu_s`", "scale"]),
])
def test_jointly_absurd_chains_are_refused_naming_the_parameters(change, words):
    with pytest.raises(SceneError) as info:
        simulate_chain(**{**BASE, **change})
    for word in words:
        assert word in str(info.value)


def test_budgets_are_overridable():
    # 1.6e6 steps of 1/16 of the fastest period (frictionless: one phase, quick to run)
    long_run = {**BASE, "mu_s": 0.0, "x0": [0.05, -0.02], "t_end": 1e5}
    with pytest.raises(SceneError, match="`max_steps`"):
        simulate_chain(**long_run, n_samples=11)
    r = simulate_chain(**long_run, n_samples=11, max_steps=2_000_000)
    assert np.all(np.isfinite(r.x))


def test_event_and_step_budgets_stop_a_run_with_simulation_error():
    stick_slip = {**BASE, "masses": [1.0], "springs": [10.0, 0.0], "dampers": [0.0, 0.0], "mu_k": 0.1,
                  "x0": [0.0], "v0": [0.1], "t_end": 30.0}
    with pytest.raises(SimulationError, match="`max_events` = 3"):
        simulate_chain(**stick_slip, max_events=3)
    with pytest.raises(SimulationError, match="`max_steps` = 200"):
        simulate_chain(**{**stick_slip, "t_end": 0.5}, method="sign", max_steps=200)


def test_preset_friction_override_replaces_the_coefficients():
    from asperity2d.belt import presets

    kw = presets.preset("table2-3dof", friction=Stribeck(0.3, 0.2, 0.01), t_end=1.0)
    assert "mu_s" not in kw and "mu_k" not in kw
    assert simulate_chain(**kw).meta["backend"] == "integrated phases"
