"""Virtual tribometer: energy balance, both driving directions, pre-sliding."""

import numpy as np
import pytest

from asperity2d.experiments import tribometer as tb


@pytest.fixture(scope="module")
def scene():
    return tb.make_tribometer_scene()


def test_energy_balance_of_steady_sliding_within_one_percent(scene):
    report = tb.energy_window(scene, velocity=30.0, pitches=2)
    # exact bookkeeping of the meter (drive work = dissipation + stored change)
    assert report["residual_fraction"] < 1e-3
    # mean friction force x distance = friction + inelastic contact + damper work + stored change
    assert report["balance_error"] < 0.01
    assert report["friction_work_J"] > 0 and report["damper_work_J"] > 0
    assert report["distance_m"] == pytest.approx(2 * scene.lower.spacing.mean_pitch, rel=0.02)


def test_steady_friction_is_odd_in_velocity_and_loops_reach_the_wedge_law(scene):
    curve = tb.steady_curve(scene, tb.Protocol(velocities=(10.0, 100.0), pitches=2))
    assert np.all(np.sign(curve.force) == np.sign(curve.velocity))
    assert np.all(curve.contact >= 0.9)  # sliding on the tips, no lift-off at these speeds
    neg, pos = curve.force[:2][::-1], curve.force[2:]
    s_neg, s_pos = curve.spread[:2][::-1], curve.spread[2:]
    # both directions driven over a regular surface: |F(-v)| = F(v) within the per-pitch scatter
    assert np.all(np.abs(pos + neg) < 3 * np.hypot(s_neg, s_pos) + 0.02 * pos)
    loops = tb.reversal_loops(scene, tb.Protocol(amplitudes=(5e-9, 5e-8)))
    wedge = scene.slider.normal_load * 1.3 / 0.7  # L tan(45 deg + atan 0.3)
    assert np.abs(loops.force).max() == pytest.approx(wedge, rel=0.05)
    assert 0 < loops.breakaway_displacement() < 0.05 * scene.base
    # inside the static cone the contacts hold: the 5 nm strokes load the slider to ~0.93 L
    # (drive 372,000 N/m x 5 nm) against a 1.86 L limit and it must not move (no pre-sliding
    # compliance in the rigid model; 1e-4 base allows the solver's position correction)
    first = slice(0, int(np.argmax(np.abs(loops.drive) > 1.01 * 5e-9)))
    assert np.abs(loops.force[first]).max() > 0.9 * scene.slider.normal_load
    assert np.abs(loops.displacement[first]).max() < 1e-4 * scene.base


def test_protocol_validation_names_the_parameter():
    with pytest.raises(ValueError, match="`velocities`"):
        tb.Protocol(velocities=(1.0, -2.0))
