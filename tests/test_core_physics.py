"""The asperity simulator against closed forms and invariants (DESIGN.md section 6).

Tolerances: the wedge law is a quasi-static result, and the drive here moves
slowly (9e-5 of base x omega), so the dynamic overshoot at breakaway is under
a percent; 2 % is the issue's bound. Force balance
in a stick phase is exact up to solver convergence (measured 0.01 %): 1 %.
"""

import dataclasses
import math
import subprocess
import sys

import numpy as np
import pytest

import asperity2d as a

K, BASE = 37_200.0, 1e-6  # seed 000 Table 1 stiffness (N/m) and base (m)


def single_asperity(theta, mu, **drive):
    """One tip on one flank under a light load: asperity2d.validation's wedge-law scene."""
    from asperity2d.validation import single_asperity as scene_of

    scene, load = scene_of(theta, mu)
    return scene.replace(drive=dataclasses.replace(scene.drive, **drive)), load


# The wedge law for four (theta, mu) pairs, the force balance while stuck and the flat block's
# static and kinetic limits are closed-form checks in asperity2d.validation (tests/test_validation.py).


def test_wedge_jams_when_flank_plus_friction_angle_reaches_90_degrees():
    theta, mu = 60.0, 0.7  # 60 deg + atan(0.7) = 95 deg
    scene, load = single_asperity(theta, mu, velocity=5.0)
    result = a.simulate(scene, duration=1.2e-6)
    # The drive force climbs far past what any unjammed flank would need ...
    assert result.drive_force[-1] > 3.0 * load * math.tan(math.radians(theta))
    # ... while the slider does not advance along the surface.
    assert abs(result.x[-1] - result.x[0]) < 1e-3 * BASE


@pytest.mark.parametrize("force_ratio, slip_distance, moves", [
    (2.2, None, False),  # between the kinetic (1.857) and static (2.333) flank thresholds
    (2.2, 0.0, True),  # switching on instantaneous slip speed alone: micro-slip -> mu_k
    (2.4, None, True),  # above the static threshold: it must move
])
def test_static_friction_survives_a_suddenly_applied_load(force_ratio, slip_distance, moves):
    load = 0.002  # one tip on the middle of a 45 deg front flank, held there while settling
    scene = a.make_scene(lower_count=1, upper_count=1, mu_static=0.4, mu_kinetic=0.3, track="free",
                         normal_load=load, drive="force", drive_force=force_ratio * load,
                         slip_distance=slip_distance)
    result = a.simulate(scene, duration=2e-8)
    moved = abs(result.x[-1] - result.x[0])
    if moves:
        assert moved > 0.5 * BASE
    else:
        assert moved < 1e-3 * BASE


def steel(length_scale=1.0, mass_scale=1.0):
    """Seed 000 Table 1 steel scene, optionally scaled (time unchanged)."""
    ls, ms = length_scale, mass_scale
    return a.make_scene(lower_count=4, upper_count=2, base=1e-6 * ls, pitch=1.25e-6 * ls, track="free",
                        mass=2.88e-16 * ms, stiffness=K * ms, slider_mass=2.88e-15 * ms,
                        normal_load=0.01 * ms * ls, drive_stiffness=3720 * ms,
                        drive_velocity=20 * ls)


def test_micrometre_scene_matches_the_same_scene_scaled_up():
    omega = math.sqrt(K / 2.88e-16)
    numbers = []
    for ls, ms in ((1.0, 1.0), (1e6, 1e3)):
        result = a.simulate(steel(ls, ms))
        force_unit = K * ms * BASE * ls
        peak = int(np.argmax(result.drive_force))
        first_slip = int(np.argmax(result.v > 20 * ls))
        numbers.append([result.drive_force[peak] / force_unit, result.t[peak] * omega,
                        result.t[first_slip] * omega, result.friction_force.max() / force_unit])
    np.testing.assert_allclose(numbers[0], numbers[1], rtol=1e-6)


DETERMINISM_SCRIPT = """
import sys, asperity2d as a
scene = a.make_scene(spacing="random", seed=3, lower_count=6, upper_count=2)
a.simulate(scene, duration=5e-8).save(sys.argv[1])
"""


def test_two_processes_give_bit_identical_arrays(tmp_path):
    paths = [tmp_path / "one.npz", tmp_path / "two.npz"]
    for path in paths:
        subprocess.run([sys.executable, "-c", DETERMINISM_SCRIPT, str(path)], check=True)
    first, second = a.load(paths[0]), a.load(paths[1])
    for name in ("t", "x", "v", "y", "drive_force", "normal_force", "friction_force", "lower_dy"):
        assert np.array_equal(getattr(first, name), getattr(second, name)), name


def test_a_too_coarse_step_is_refused_and_a_forced_one_diverges_loudly():
    scene = a.make_scene(lower_count=4, upper_count=2)
    period = scene.shortest_period()
    with pytest.raises(a.SceneError, match="`dt`"):
        a.simulate(scene, dt=period / 10)
    with pytest.raises(a.SimulationError, match="smaller dt") as info:
        a.simulate(scene, dt=period / 2, unsafe_dt=True, duration=2e-7)
    assert 0 < info.value.time < 2e-7


def test_tracks_and_overlap_stay_within_bounds_on_the_default_scene():
    result = a.simulate(a.make_scene(lower_count=8, upper_count=3))
    assert result.status == "passed"
    assert result.meta["max_overlap_fraction"] < 0.03
    assert result.meta["max_track_drift_fraction"] < 1e-6
    assert np.all(np.abs(result.lower_dx) < 1e-6 * BASE)
