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

K, BASE = 37_200.0, 1e-6  # Ooten's thesis Table 1 stiffness (N/m) and base (m)


def single_asperity(theta, mu, **drive):
    """One tip on one flank under a light load: asperity2d.closed_forms's wedge-law scene."""
    from asperity2d.closed_forms import single_asperity as scene_of

    scene, load = scene_of(theta, mu)
    return scene.replace(drive=dataclasses.replace(scene.drive, **drive)), load


# The wedge law for four (theta, mu) pairs, the force balance while stuck and the flat block's
# static and kinetic limits are closed-form checks in asperity2d.closed_forms (tests/test_closed_forms.py).


def test_wedge_jams_when_flank_plus_friction_angle_reaches_90_degrees():
    theta, mu = 60.0, 0.7  # 60 deg + atan(0.7) = 95 deg
    scene, load = single_asperity(theta, mu, velocity=5.0)
    result = a.simulate(scene, duration=1.2e-6)
    # The drive force climbs far past what any unjammed flank would need ...
    assert result.drive_force[-1] > 3.0 * load * math.tan(math.radians(theta))
    # ... while the slider does not advance along the surface.
    assert abs(result.x[-1] - result.x[0]) < 1e-3 * BASE


def flat_block(**kw):
    load = 0.002
    return a.make_scene(profile="flat", height=0.25e-6, lower_count=1, upper_count=1, track="free",
                        mu_static=0.4, mu_kinetic=0.3, normal_load=load, **kw), load


def test_contiguous_flat_blocks_let_the_slider_slide_at_mu_kinetic():
    """Eight flat blocks side by side (pitch = width), one flat block sliding on them under
    N = 10 uN: the loaded block sits N / k = 0.27 nm below the next one. With square corners the
    slider met that step face-on and jammed (the drive force climbed to 47 mu_s N); with
    rounded edges it crosses every block: it breaks away at mu_s N and slides at mu_k N (median
    over the sliding samples, within 1 %), the brief impacts at the block edges (above mu_s N
    in under 1 % of them) aside."""
    load = 1e-5
    scene = a.make_scene(profile="flat", height=0.25e-6, lower_count=8, upper_count=1, pitch=1e-6,
                         track="free", mu_static=0.4, mu_kinetic=0.3, normal_load=load, drive_velocity=5.0)
    assert load / scene.lower.stiffness[0] == pytest.approx(0.27e-9, rel=0.01)
    result = a.simulate(scene, record_every=1)
    assert result.status == "passed" and result.x[-1] - result.x[0] > 6 * BASE
    moved = result.x - result.x[0]
    before = moved < 1e-5 * BASE
    assert result.friction_force[before].max() == pytest.approx(0.4 * load, rel=0.01)
    sliding = result.v > 0.5 * scene.drive.velocity
    assert sliding.sum() > 1000
    assert np.median(result.friction_force[sliding]) == pytest.approx(0.3 * load, rel=0.01)
    assert np.mean(result.friction_force[sliding] > 1.02 * 0.4 * load) < 0.01
    assert np.median(result.normal_force) == pytest.approx(load, rel=0.01)


def test_a_free_slider_never_passes_beneath_the_lower_surface():
    """One lower asperity, one tip, a free slider under 10 mN: the tip slides down the front
    flank onto the guard floor. The floor used to lie exactly one tip depth below the asperity's
    base, so the slider slid underneath it at ~2 mN (a fifth of the wedge law). Now it lies a
    tenth of the depth higher: the slider must climb, and the critical force with a run-up is
    the static wedge law L tan(45 deg + atan mu_s) (within 2 %, the quasi-static bound here)."""
    scene = a.make_scene(track="free", lower_count=1, upper_count=1, drive="force")
    load, depth = scene.slider.normal_load, scene.slider.depth
    assert scene.floor == pytest.approx(0.0 - 0.9 * depth, rel=1e-12)
    assert scene.lower.floor == pytest.approx(-depth)  # the tracks' bottom, below the new floor
    wedge = load * math.tan(math.radians(45.0) + math.atan(scene.contact.mu_static))
    assert a.critical_force(scene, start="run-up") == pytest.approx(wedge, rel=0.02)
    rest = a.critical_force(scene)
    assert rest > 0.5 * load * math.tan(math.radians(45.0) + math.atan(scene.contact.mu_kinetic))
    # in a passing run the slider's top (its datum) stays above the asperity's base whenever
    # the two overlap in x
    result = a.simulate(scene.replace(drive=a.ConstantForce(force=1.1 * wedge)))
    assert result.status == "passed"
    tip_x = result.x + scene.slider.tips()[0]  # the slider's x is its rear (only) tip's
    overlap = np.abs(tip_x - scene.lower.tips()[0]) < BASE
    assert overlap.sum() > 10
    assert np.all(result.y[overlap] > result.lower_dy[0, overlap] + 0.05 * depth)


def test_the_guard_floor_stays_where_it_was_when_it_is_deep_enough():
    """Taller upper tips (1 um on 0.5 um asperities) reach the base level from the old floor
    already: nothing to raise. A profile's own valleys keep their floor."""
    scene = a.make_scene(track="free", upper_profile="half", half_shape="full-base")
    assert scene.slider.depth == pytest.approx(2 * scene.lower.profile.height)
    assert scene.floor == scene.lower.floor


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
    """Ooten's thesis Table 1 steel scene, optionally scaled (time unchanged)."""
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
