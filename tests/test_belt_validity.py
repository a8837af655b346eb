"""Belt chains that cannot be right raise; every run is bounded (issue 27 items 4, 6, 10).

* energy books: every returned run closes its books to a stated tolerance
  (:data:`asperity2d.belt.result.BOOKS_TOLERANCE`), or raises;
* mu_s = 100 under 1e6 N: the switching tolerance no longer exceeds the chain's speeds;
* a belt-speed callable that raises mid-run is named, with the time;
* ``max_wall_time`` bounds a run that neither budget counts well (a chattering sign() solve).
"""

import math

import numpy as np
import pytest

from asperity2d.belt import presets, simulate_chain
from asperity2d.belt.result import BOOKS_TOLERANCE, check_books
from asperity2d.belt.spec import ChainSpec
from asperity2d.errors import SceneError, SimulationError


def test_huge_static_friction_no_longer_snaps_masses_to_the_belt():
    # issue 27 item 4: mu_s = 100 under 1e6 N on Table 2's 10 N/m springs. The velocity scale took
    # the release swing mu_s N / (m omega) = 2.2e7 m/s, so the switching tolerance (1e-9 of it,
    # 0.022 m/s) declared masses 0.01 - 0.02 m/s from the belt at belt speed: books 2.4e-4 off.
    # The springs can build at most 2 x 20 N/m x (0.07 m + 0.15 m/s x 10 s) = 63 N: that bounds
    # the swing; the masses stick one by one, each when it reaches the belt.
    chain = presets.preset("table2-3dof", mu_s=100.0, mu_k=100.0, normal_load=[1e6] * 3)
    spec = ChainSpec(chain["masses"], chain["springs"], chain["dampers"], 100.0, 100.0, chain["v_belt"],
                     chain["x0"], chain["v0"], chain["t_end"], 9.81, tuple(chain["normal_load"]), None)
    assert spec.velocity_scale < 100.0  # m/s: was 2.2e7
    result = simulate_chain(**chain)
    assert result.energy_balance_error() < 1e-9  # measured 6e-11 (forces of 1e8 N over 6e-10 s)
    sticks = sorted(e.t for e in result.events if e.kind == "stick")
    # each mass reaches the belt after its own (V - v0) m / (mu_k N): 6, 7, 5 x 1e-10 s
    assert sticks == pytest.approx([5e-10, 6e-10, 7e-10], rel=1e-6)


def test_ordinary_chains_keep_their_velocity_scale():
    # the swing is bounded only where the springs cannot reach the static limit: Table 2's
    # 1.96 N limit against up to 43 N of spring force keeps mu_s N / (m omega) (bit-identical runs)
    chain = presets.preset("table2-3dof")
    spec = ChainSpec(chain["masses"], chain["springs"], chain["dampers"], 0.2, 0.2, chain["v_belt"],
                     chain["x0"], chain["v0"], chain["t_end"])
    assert spec.velocity_scale == 0.2 * 9.81 / math.sqrt(20.0)


def test_books_that_do_not_close_raise_and_the_check_is_recorded():
    result = simulate_chain(**presets.preset("table2-3dof"))
    assert result.meta["checks"]["energy_books"]["passed"]
    assert result.meta["checks"]["energy_books"]["limit"] == BOOKS_TOLERANCE
    assert result.summary()["checks"] == {"energy_books": "passed"}
    half = len(result.t) // 2
    result.belt_work[half:] += 1e-3 * np.max(np.abs(result.belt_work))  # energy from nowhere
    with pytest.raises(SimulationError, match="do not close: off by 0.000999 .* beyond the tolerance at t = "
                                              f"{result.t[half]:.6g} s"):
        check_books(result)


def test_cancelling_stores_are_not_an_error_of_one():
    # a mass swinging on its spring against a preload holds E = kinetic + spring + load = 0 at all
    # times: the balance error was |1e-16 J| / 1e-16 J = 1. It is taken over each store now.
    from asperity2d.belt.normal import NormalContact

    nc = NormalContact(stiffness=100.0, preload=-5.0)
    r = simulate_chain(masses=[1.0], springs=[10.0, 0.0], dampers=[0.0, 0.0], mu_s=0.3, v_belt=1.0, x0=[0.0],
                       v0=[0.0], t_end=0.5, g=0.0, normal=nc, y0=[0.1], n_samples=11)
    assert abs(np.max(r.stored_energy)) < 1e-15 < np.max(r.kinetic_energy)
    assert r.energy_balance_error() < 1e-14


def test_books_are_checked_against_t0_when_the_samples_start_later():
    full = simulate_chain(**presets.preset("table2-3dof"))
    late = simulate_chain(**presets.preset("table2-3dof", t_eval=[2.0, 3.0], include_events=False))
    assert late.initial_energy == pytest.approx(full.stored_energy[0], rel=1e-15)
    assert late.energy_balance_error() < 1e-12


def test_a_belt_speed_that_raises_mid_run_is_named_with_the_time():
    def v_belt(t):
        return 0.1 if t < 1.0 else 1 / 0

    with pytest.raises(SimulationError, match=r"`v_belt` raised ZeroDivisionError at t = 1\.0"):
        simulate_chain(**presets.preset("table2-3dof", v_belt=v_belt))


def test_the_wall_clock_budget_stops_a_run_and_names_itself():
    # issue 27 item 6: the sign() method on Table 2 chatters for minutes; here it is stopped at
    # 0.5 s of wall-clock time (the default is 30 s), naming the budget
    with pytest.raises(SimulationError, match=r"`max_wall_time` = 0.5 s"):
        simulate_chain(**presets.preset("table2-3dof", method="sign", t_end=1.0), max_wall_time=0.5)
    with pytest.raises(SceneError, match="`max_wall_time` must be"):
        simulate_chain(**presets.preset("table2-3dof"), max_wall_time=-1.0)
    assert simulate_chain(**presets.preset("table2-3dof"), max_wall_time=30.0).success
