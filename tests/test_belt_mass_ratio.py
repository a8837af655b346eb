"""Chains with a normal contact whose masses differ by orders of magnitude.

A compliant contact checks each mass on its own force scale (``ContactSpec.normal_scales``): with
masses of 1e6 and 1 kg a single scale, the heavy mass's ~1e7 N, made the light mass's tolerance
0.01 N and let its contact force pull by half its load unseen. A rigid contact is solved for mass
ratios up to ``limits.MAX_MASS_RATIO_RIGID`` and refuses larger ones up front, naming `masses`.
"""

import math

import numpy as np
import pytest

from asperity2d import SceneError
from asperity2d.belt import NormalContact, simulate_chain
from asperity2d.belt.limits import MAX_MASS_RATIO_RIGID
from asperity2d.belt.phases.finder import SWITCH_TOL

G = 9.81


def _light_and_heavy(heavy):
    # the light mass's load is 9.81 - 9.792 = 0.018 N: the preload lifts it almost off; an inclined
    # spring couples its contact force to the chain's motion, which lifts it off and presses it back
    return dict(masses=[heavy, 1.0], springs=[1e8, 10.0, 0.0], dampers=[0.0, 0.0, 0.0], mu_s=0.4, mu_k=0.3,
                v_belt=0.1, x0=[0.0, 0.01], v0=[0.0, 0.0], t_end=2.0, y0=[0.0, 0.0],
                normal=NormalContact(contact_stiffness=1e4, inclined=((10.0, 30.0),), preload=-9.792))


@pytest.mark.parametrize("heavy", [1.0, 1e6])
def test_a_compliant_contact_never_pulls_whatever_the_other_masses_weigh(heavy):
    """A compliant contact force is k_c times the penetration, >= 0; the solver lets a mode run on by at
    most twice its touch band (2·SWITCH_TOL of the mass's force scale) before it must switch. The light
    mass's scale is its own load (0.018 N) or the inclined spring's force at the chain's length scale:
    a pull beyond 2·SWITCH_TOL of the larger is a lift-off the solver missed (before the per-mass scales,
    -0.0052 N with a 1e6 kg neighbour, the run returning normally)."""
    r = simulate_chain(**_light_and_heavy(heavy))
    own = max(9.81 - 9.792, 10.0 * math.sqrt(3) / 2 / 2 * np.max(np.abs(r.x[1])))
    assert r.normal_force[1].min() >= -2 * SWITCH_TOL * own
    # and it does lift off: the check is not passed by a contact that never opens
    assert len(r.separation_intervals[1]) >= 3
    assert np.max(r.normal_force[1]) > 1.0  # pressed by the inclined spring far beyond its load


def test_the_light_mass_moves_the_same_next_to_a_heavy_or_an_equal_mass():
    """The 1e8 N/m wall spring holds the heavy mass (and the equal one) still within 1e-7 m, and the
    link to the light mass is 10 N/m: the light mass's motion barely depends on its neighbour's mass,
    so its first five lift-offs happen at the same times (to 1e-3 s) beside 1 kg and beside 1e6 kg (later
    ones drift apart: the chain's stick-slip amplifies the 1e-7 m difference)."""
    a = simulate_chain(**_light_and_heavy(1.0))
    b = simulate_chain(**_light_and_heavy(1e6))
    opens = [[ev.t for ev in r.events if ev.mass == 1 and ev.kind == "open"] for r in (a, b)]
    assert min(len(opens[0]), len(opens[1])) >= 5
    assert np.allclose(opens[0][:5], opens[1][:5], rtol=0, atol=1e-3)


def _drop(heavy):
    return dict(masses=[0.5, heavy], springs=[100.0, 100.0, 0.0], dampers=[0.0, 0.0, 0.0], mu_s=0.4, mu_k=0.3,
                v_belt=0.1, x0=[0.0, 0.01], v0=[0.0, 0.0], t_end=0.2, y0=[0.01, 0.01], normal=NormalContact())


def test_a_rigid_contact_refuses_a_mass_ratio_beyond_its_limit_up_front():
    with pytest.raises(SceneError, match=r"`masses` differ by a factor of 2e\+06 .*up to 100000") as err:
        simulate_chain(**_drop(1e6))
    assert "\n" not in str(err.value)


def test_a_rigid_contact_at_the_limit_lands_both_masses_on_time():
    """Dropped from 1 cm with no normal spring, each mass falls freely until it lands at
    t = sqrt(2·h/g) (their x links do not act on y). The landing is located to the root finder's
    tolerance: 1e-9 relative is far below the 2.7 mm (about 2 ms of fall) once missed."""
    heavy = 0.5 * MAX_MASS_RATIO_RIGID
    r = simulate_chain(**_drop(heavy))
    t_land = math.sqrt(2 * 0.01 / G)
    for mass in (0, 1):
        first = next(ev.t for ev in r.events if ev.mass == mass and ev.kind == "impact")
        assert first == pytest.approx(t_land, rel=1e-9)
    assert np.min(r.y) >= 0.0
