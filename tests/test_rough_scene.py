"""Rough surfaces in the scene spec (issue 14 phase 2): per-asperity shapes, random heights, profiles.

Closed forms and invariants: every-height-equal scenes are bit-identical to the uniform ones;
the heights' mean and spread match what was asked (or the truncated distribution's closed
form); a profile of known triangles becomes a scene whose asperities are those triangles.
Cost: about 4 s (six short runs of 5-asperity scenes; the rest builds scenes only).
"""

import dataclasses
import math

import numpy as np
import pytest

import asperity2d as a
from asperity2d.geometry import ExplicitSpacing
from asperity2d.shapes import Shapes
from asperity2d.surface import SurfaceProfile
from asperity2d.surface.heights import max_std, truncated_moments
from asperity2d.units import MIN_LENGTH_RATIO

SMALL = dict(lower_count=5, upper_count=2)
FIELDS = ("t", "x", "v", "y", "drive_force", "normal_force", "friction_force", "lower_dx",
          "lower_dy", "lower_contact")


def same_run(one, two, duration=1e-7):
    r1, r2 = a.simulate(one, duration), a.simulate(two, duration)
    return all(np.array_equal(getattr(r1, f), getattr(r2, f)) for f in FIELDS)


# -- every height equal: bit-identical to the uniform scene ---------------------------

@pytest.mark.parametrize("kwargs", [
    dict(SMALL),  # Ooten's fixed track
    dict(SMALL, track="free", spacing="random", seed=3),
    dict(SMALL, profile="half", spacing="random", seed=5),
], ids=["fixed-regular", "free-random", "fixed-half-random"])
def test_every_height_equal_is_bit_identical_to_the_uniform_scene(kwargs):
    """height_std = 0 goes through the per-asperity path (Shapes on both surfaces, per-tip
    runs in the random spacing) and must step exactly like today's uniform scene."""
    uniform = a.make_scene(**kwargs)
    equal = a.make_scene(height_std=0.0, **kwargs)
    assert equal.lower.shapes is not None and equal.slider.shapes is not None
    assert set(equal.lower.shapes.heights) == {uniform.lower.profile.height}
    assert same_run(uniform, equal)


def test_explicit_uniform_shapes_are_bit_identical():
    scene = a.make_scene(**SMALL, track="free")
    lower = dataclasses.replace(scene.lower, shapes=Shapes.uniform(scene.lower.profile, 5, upper=False))
    slider = dataclasses.replace(scene.slider, shapes=Shapes.uniform(scene.slider.profile, 2, upper=True))
    assert same_run(scene, scene.replace(lower=lower, slider=slider))


# -- random heights: their statistics through make_scene ------------------------------

BIG = dict(lower_count=4000, upper_count=4000)


@pytest.mark.parametrize("distribution", ["gaussian", "uniform"])
def test_random_heights_have_the_requested_mean_and_std(distribution):
    """N = 4000 per surface, std = 0.1 um about 0.5 um (the floor, 2e-3 base, is 24 std
    below the mean: nothing is redrawn). Sample mean within 4 SE = 4 std / sqrt(N); sample
    std within 4 SE (std / sqrt(2N) Gaussian, std sqrt(0.2 / N) uniform)."""
    std = 0.1e-6
    scene = a.make_scene(height_std=std, height_distribution=distribution, **BIG)
    mean = scene.lower.profile.height
    se_std = std / math.sqrt(2 * 4000) if distribution == "gaussian" else std * math.sqrt(0.2 / 4000)
    for surface in (scene.lower, scene.slider):
        h = surface.heights()
        assert abs(h.mean() - mean) < 4 * std / math.sqrt(4000)
        assert abs(h.std(ddof=1) - std) < 4 * se_std
        left, right = surface.runs()
        assert np.all(left + right == surface.profile.base)  # same base, own flank angles
    assert not np.array_equal(scene.lower.heights(), scene.slider.heights())  # own streams


def test_heights_near_the_floor_follow_the_truncated_closed_form():
    """At the largest std allowed (1 % of draws redrawn), the heights are the Gaussian
    truncated at the floor: their mean and std match scipy's truncnorm within 4 SE
    (N = 4000); every height is above the floor."""
    base, mean = 1e-6, 0.05e-6  # low, steep-free triangles: the floor matters
    floor = MIN_LENGTH_RATIO * base
    std = max_std(mean, floor)
    scene = a.make_scene(height=mean, lower_height_std=std, **BIG)
    h = scene.lower.heights()
    t_mean, t_std = truncated_moments(mean, std, floor)
    assert h.min() > floor
    assert abs(h.mean() - t_mean) < 4 * t_std / math.sqrt(4000)
    assert abs(h.std(ddof=1) - t_std) < 4 * t_std / math.sqrt(2 * 4000) * 1.2  # ~Gaussian 4th moment
    assert t_mean > mean  # the truncation is visible in the closed form, and small:
    assert (t_mean - mean) / std < 0.03
    with pytest.raises(a.SceneError, match="`lower_height_std`.*<= "):
        a.make_scene(height=mean, lower_height_std=1.01 * std, **SMALL)


def test_height_streams_are_seeded_and_leave_the_spacing_streams_alone():
    plain = a.make_scene(spacing="random", seed=9, **SMALL)
    rough = a.make_scene(spacing="random", seed=9, height_std=0.05e-6, **SMALL)
    np.testing.assert_array_equal(plain.lower.tips(), rough.lower.tips())
    np.testing.assert_array_equal(plain.slider.tips(), rough.slider.tips())
    again = a.make_scene(spacing="random", seed=9, height_std=0.05e-6, **SMALL)
    other = a.make_scene(spacing="random", seed=10, height_std=0.05e-6, **SMALL)
    assert rough == again and rough.lower.shapes != other.lower.shapes
    only_upper = a.make_scene(spacing="random", seed=9, upper_height_std=0.05e-6, **SMALL)
    assert only_upper.lower.shapes is None and only_upper.slider.shapes is not None
    # the upper stream does not depend on whether the lower surface is rough
    np.testing.assert_array_equal(only_upper.slider.heights(), rough.slider.heights())


def test_fixed_track_interference_is_measured_from_the_tallest_lower_tip():
    scene = a.make_scene(height_std=0.1e-6, seed=2, **SMALL)
    tallest = float(scene.lower.heights().max())
    assert scene.lower.top == tallest and scene.lower.travel_down == tallest
    with pytest.raises(a.SceneError, match="`interference`.*highest lower asperity"):
        a.make_scene(height_std=0.1e-6, seed=2, interference=tallest, **SMALL)
    a.make_scene(height_std=0.1e-6, seed=2, interference=0.99 * tallest, **SMALL)


# -- profiles of known triangles become the scene's asperities ---------------------------

def triangle_profile(apex, left, right, height, dx=2e-9):
    x = np.arange(0.0, apex[-1] + right[-1] + 0.5e-6, dx)
    z = np.zeros_like(x)
    for p, lr, rr, h in zip(apex, left, right, height):
        z = np.maximum(z, np.minimum(h * (x - (p - lr)) / lr, h * ((p + rr) - x) / rr))
    return x, z


KNOWN = dict(apex=np.array([1.0e-6, 2.3e-6, 3.3e-6, 4.9e-6]),
             left=np.array([0.5e-6, 0.4e-6, 0.3e-6, 0.6e-6]),
             right=np.array([0.5e-6, 0.3e-6, 0.6e-6, 0.4e-6]),
             height=np.array([0.5e-6, 0.3e-6, 0.45e-6, 0.2e-6]))


def test_known_triangles_become_the_scenes_asperities(tmp_path):
    """Triangles on z = 0 sampled every 2 nm (0.2-0.3 % of the bases): tips, runs and heights
    come back within 1 % of each base (the sampled apex misses the true one by <= dx / 2);
    from arrays and from a CSV file in micrometres alike; the slider's are the same
    triangles pointing down."""
    k = KNOWN
    x, z = triangle_profile(k["apex"], k["left"], k["right"], k["height"])
    base = k["left"] + k["right"]
    path = tmp_path / "triangles.csv"
    np.savetxt(path, np.column_stack([x * 1e6, z * 1e6]), delimiter=",", fmt="%.7f")
    for source, unit in (((x, z), None), (path, "um"), (str(path), "um")):
        scene = a.make_scene(lower_surface=source, upper_surface=source, surface_unit=unit,
                             surface_detrend=False, track="free")
        for surface, sign in ((scene.lower, 1.0), (scene.slider, -1.0)):
            assert isinstance(surface.spacing, ExplicitSpacing) and surface.count == 4
            left, right = surface.runs()
            tips = surface.tips() - surface.tips()[0]
            assert np.max(np.abs(tips - (k["apex"] - k["apex"][0])) / base) < 0.01
            assert np.max(np.abs(surface.heights() - k["height"]) / base) < 0.01
            assert np.max(np.abs(left - k["left"]) / base) < 0.01
            assert np.max(np.abs(right - k["right"]) / base) < 0.01
            assert np.max(np.abs(surface.summits() - k["height"]) / base) < 0.01  # levels ~ 0
            tip_y = [min(v[1] for v in poly) if sign < 0 else max(v[1] for v in poly)
                     for poly in surface.outlines()]
            np.testing.assert_allclose(np.abs(tip_y), surface.summits(), rtol=1e-12)
            assert all(np.sign(y) == sign for y in tip_y)
    assert scene.base == pytest.approx(np.median(base), rel=0.01)


def test_profile_surface_material_rules_and_defaults():
    x, z = triangle_profile(KNOWN["apex"], KNOWN["left"], KNOWN["right"], KNOWN["height"])
    plain = a.make_scene(lower_surface=(x, z), surface_detrend=False)
    assert plain.lower.stiffness == (a.scene.OOTEN_DEFAULTS["stiffness"],) * 4
    steel = a.make_scene(lower_surface=(x, z), surface_detrend=False, modulus=1.86e10, density=7850.0)
    bases = np.asarray(plain.lower.shapes.bases)
    np.testing.assert_allclose(steel.lower.stiffness, 2 * 1.86e10 * bases, rtol=1e-12)
    np.testing.assert_allclose(steel.lower.mass, 7850.0 * bases**2 * plain.lower.heights() / 3, rtol=1e-12)
    # fixed track: a quarter of the median lower height below the highest tip
    assert plain.slider.interference == pytest.approx(np.median(plain.lower.heights()) / 4)
    assert plain.lower.top == pytest.approx(0.5e-6, rel=0.01)


def test_shipped_measured_style_profile_builds_a_scene():
    """The shipped file states its unit (`# unit: um`), so no surface_unit is needed."""
    from pathlib import Path

    path = Path(__file__).resolve().parent.parent / "scenes" / "data" / "measured_style_profile.csv"
    scene = a.make_scene(lower_surface=path)
    assert scene.lower.count > 10 and np.ptp(scene.lower.shapes.levels) > 0
    assert a.Scene.from_dict(scene.to_dict()) == scene


# -- save / load and validation ------------------------------------------------------------

def test_rough_scenes_round_trip_through_a_plain_dict():
    for scene in (a.make_scene(height_std=0.05e-6, spacing="random", seed=1, **SMALL),
                  a.make_scene(lower_surface=triangle_profile(**{k: KNOWN[k] for k in KNOWN}),
                               surface_detrend=False)):
        assert a.Scene.from_dict(scene.to_dict()) == scene


@pytest.mark.parametrize("kwargs, message", [
    (dict(height_std=-1e-7), "`height_std`"),
    (dict(lower_height_std=math.nan), "`lower_height_std`"),
    (dict(height_std=0.3e-6), "`height_std` = 3e-07 m is too wide"),
    (dict(height_distribution="lognormal"), "`height_distribution`"),
    (dict(lower_surface="no/such/file.csv"), "`lower_surface` is not a file"),
    (dict(lower_surface=42), "`lower_surface` must be"),
    (dict(lower_surface=np.zeros((3, 3))), "`lower_surface` arrays"),
    (dict(lower_surface=(np.array([0.0, 2.0, 1.0]), np.zeros(3))), "`lower_surface`: `x` must"),
    (dict(lower_surface=(np.arange(5.0), np.zeros(5))), "`lower_surface` is flat"),
    (dict(upper_surface=(np.arange(5.0), np.zeros(5)), upper_count=3), "`upper_count` and `upper_surface`"),
    (dict(lower_surface=(np.arange(5.0), np.zeros(5)), lower_height_std=1e-8), "`lower_height_std` and"),
    (dict(lower_surface=(np.arange(5.0), np.zeros(5)), stiffness=[1.0, 2.0]), "`stiffness` must be one"),
    (dict(modulus=1e10), "`modulus` / `density`"),
    (dict(modulus=1e10, stiffness=1.0), "`modulus` and `stiffness`"),
    (dict(surface_unit="inch"), "`surface_unit`"),
    (dict(surface_detrend="yes"), "`surface_detrend`"),
    (dict(min_prominence=0.0), "`min_prominence`"),
])
def test_bad_rough_input_names_the_parameter(kwargs, message):
    with pytest.raises(a.SceneError, match=message):
        a.make_scene(**kwargs)


def test_profile_errors_name_what_the_user_wrote(tmp_path):
    path = tmp_path / "trace.csv"
    x, z = triangle_profile(KNOWN["apex"], KNOWN["left"], KNOWN["right"], KNOWN["height"])
    np.savetxt(path, np.column_stack([x * 1e6, z * 1e6]), delimiter=",")
    with pytest.raises(a.SceneError, match="`surface_unit` is required"):
        a.make_scene(lower_surface=path)
    # a shallow bump next to the triangles, 1e-3 of a base high: too low for the engine
    z2 = z + 1e-9 * np.exp(-((x - 5.6e-6) / 0.05e-6) ** 2)
    with pytest.raises(a.SceneError, match="`lower_surface`: asperity 4 .*raise `min_prominence`"):
        a.make_scene(lower_surface=(x, z2), surface_detrend=False, min_prominence=0.5e-9)
    with pytest.raises(a.SceneError, match="both surfaces are profiles"):
        a.make_scene(lower_surface=(x, z), upper_surface=(x, z), spacing="random")


def test_shapes_and_explicit_spacing_are_validated():
    with pytest.raises(a.SceneError, match=r"`heights\[1\]` must be finite and > 0"):
        Shapes(heights=[1e-7, 0.0], left_runs=[1e-7, 1e-7], right_runs=[1e-7, 1e-7])
    with pytest.raises(a.SceneError, match=r"`left_runs\[0\]` \+ `right_runs\[0\]`"):
        Shapes(heights=[1e-7], left_runs=[0.0], right_runs=[0.0])
    with pytest.raises(a.SceneError, match="`right_runs` must have 2 entries"):
        Shapes(heights=[1e-7, 1e-7], left_runs=[1e-7, 1e-7], right_runs=[1e-7])
    with pytest.raises(a.SceneError, match=r"`levels\[0\]`"):
        Shapes(heights=[1e-7], left_runs=[1e-7], right_runs=[1e-7], levels=["x"])
    with pytest.raises(a.SceneError, match="`positions` must increase"):
        ExplicitSpacing(positions=(0.0, 1e-6, 1e-6))
    with pytest.raises(a.SceneError, match="`mean_pitch` is required"):
        ExplicitSpacing(positions=(0.0,))
    scene = a.make_scene(**SMALL)
    wide = Shapes(heights=[5e-7] * 5, left_runs=[5e-7] * 5, right_runs=[5e-7, 8e-7, 5e-7, 5e-7, 5e-7])
    with pytest.raises(a.SceneError, match="asperities 1 and 2 would overlap"):
        dataclasses.replace(scene.lower, shapes=wide)
    with pytest.raises(a.SceneError, match="`shapes` holds 4 asperities"):
        dataclasses.replace(scene.lower, shapes=Shapes.uniform(scene.lower.profile, 4, upper=False))


def test_engine_refuses_a_shape_it_cannot_resolve_naming_the_asperity():
    scene = a.make_scene(**SMALL, track="free")
    h = [5e-7, 5e-7, 1e-10, 5e-7, 5e-7]  # 1e-4 base: under the collision slop
    lower = dataclasses.replace(scene.lower, shapes=Shapes(heights=h, left_runs=[5e-7] * 5,
                                                           right_runs=[5e-7] * 5))
    with pytest.raises(a.SceneError, match=r"`height` \(asperity 2\)"):
        a.simulate(scene.replace(lower=lower), 1e-8)


def test_profile_pickles_for_process_pools():
    import pickle

    profile = SurfaceProfile(np.arange(4.0), np.array([0.0, 1.0, 0.0, 1.0]), metadata={"a": 1})
    back = pickle.loads(pickle.dumps(profile))
    np.testing.assert_array_equal(back.z, profile.z)
    assert dict(back.metadata) == {"a": 1}


# -- the rigid valley floor between a profile's asperities -----------------------------------

def gap_profile():
    """Two 45-degree triangles (0.4 um high) 3 um apart, with a flat valley 0.2 um below their
    feet between them, and a 20 nm bump (below the prominence threshold) on the valley floor."""
    x = np.arange(0.0, 6e-6, 5e-9)
    z = np.zeros_like(x)
    for apex in (1e-6, 5e-6):
        z = np.maximum(z, 0.4e-6 - np.abs(x - apex))
    valley = (x > 1.6e-6) & (x < 4.4e-6)
    z[valley] = -0.2e-6 + 20e-9 * np.exp(-((x[valley] - 3e-6) / 0.1e-6) ** 2)
    return x, z


def test_a_profiles_valleys_are_rigid_floor_the_slider_rests_on():
    """A free slider whose one tip starts over the valley settles onto the valley floor, at the
    profile's depth (-0.2 um; the bump is 20 nm below the 40 nm threshold so it stays rigid),
    not on the guard floor 0.6 um down; within 2e-3 base (the collision slop is 1e-3)."""
    x, z = gap_profile()
    scene = a.make_scene(lower_surface=(x, z), surface_detrend=False, min_prominence=40e-9,
                         upper_count=1, track="free", normal_load=1e-3)
    assert scene.lower.count == 2 and len(scene.lower.substrate) == 1
    valley = np.array(scene.lower.substrate[0])
    assert valley[:, 1].min() == pytest.approx(-0.2e-6, abs=1e-12) and valley[:, 1].max() <= 0.0
    assert len(valley) <= 18  # thinned to 16 points plus the two feet
    assert scene.lower.floor < -0.5e-6
    result = a.simulate(scene, 2e-8)
    tip = result.y[-1] - scene.slider.depth
    assert abs(tip - (-0.2e-6 + 20e-9)) < 2e-3 * scene.base or abs(tip + 0.2e-6) < 2e-3 * scene.base
    assert a.Scene.from_dict(scene.to_dict()) == scene


def test_a_fixed_track_below_the_valley_floor_is_refused():
    """A rigid spike 0.3 um high between two 0.5 um asperities: a fixed track with its tips at
    0.375 um passes over it, one at 0.25 um would jam on it and is refused."""
    scene = a.make_scene(lower_count=2, upper_count=1)
    spike = (((0.5e-6, 0.0), (0.6e-6, 0.3e-6), (0.75e-6, 0.0)),)
    lower = dataclasses.replace(scene.lower, substrate=spike)
    assert scene.replace(lower=lower).lower.substrate == spike
    slider = dataclasses.replace(scene.slider, interference=0.25e-6)
    with pytest.raises(a.SceneError, match="`interference`.*rigid valley floor"):
        scene.replace(lower=lower, slider=slider)
    with pytest.raises(a.SceneError, match=r"`substrate\[0\]` must be finite with x strictly"):
        dataclasses.replace(scene.lower, substrate=(((0.0, 0.0), (0.0, 1e-7)),))
