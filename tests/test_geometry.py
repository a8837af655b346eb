"""Profiles and spacings against closed forms: triangle heights from flank angles, the outlines
vertex by vertex, half triangles cut through the apex, the flat blocks' rounded edges, regular
and seeded random tips (the documented gap law, its mean), and every validation message."""

from __future__ import annotations

import math

import numpy as np
import pytest

import asperity2d as a
from asperity2d.geometry import (FLAT_EDGE, ExplicitSpacing, Profile, RandomSpacing, RegularSpacing,
                                 float_array, half_of, outline)

B = 1e-6


@pytest.mark.parametrize("kind, run", [("full", 0.5), ("half", 1.0), ("flat", 1.0)])
@pytest.mark.parametrize("angle", [20.0, 45.0, 60.0])
def test_height_from_the_flank_angle(kind, run, angle):
    p = Profile.from_angle(kind, base=B, flank_angle=angle)
    assert p.height == pytest.approx(run * B * math.tan(math.radians(angle)), rel=1e-14)
    assert p.kind == kind and p.base == B
    if kind == "flat":
        assert p.flank_angle == 0.0
    else:
        assert p.flank_angle == pytest.approx(angle, rel=1e-12)


def test_runs_of_each_kind_on_each_surface():
    full, half, flat = (Profile(kind=k, base=B, height=0.3e-6) for k in ("full", "half", "flat"))
    assert full.runs(upper=False) == full.runs(upper=True) == (B / 2, B / 2)
    assert half.runs(upper=False) == (B, 0.0)  # lower: sloped flank faces the oncoming slider
    assert half.runs(upper=True) == (0.0, B)  # upper: the mirror image
    assert flat.runs(upper=False) == (B / 2, B / 2)


def test_triangle_outlines_vertex_by_vertex():
    h = 0.3e-6
    assert outline("full", 0.5e-6, 0.5e-6, h, 0.0, upper=False) == [(-0.5e-6, 0.0), (0.5e-6, 0.0), (0.0, h)]
    assert outline("full", 0.5e-6, 0.5e-6, h, 0.0, upper=True) == [(-0.5e-6, 0.0), (0.5e-6, 0.0), (0.0, -h)]
    # a base level lifts a lower asperity and lowers an upper one (levels point along the tips)
    assert outline("full", 0.5e-6, 0.5e-6, h, 0.1e-6, upper=False)[2] == (0.0, 0.1e-6 + h)
    assert outline("full", 0.5e-6, 0.5e-6, h, 0.1e-6, upper=True)[0] == (-0.5e-6, -0.1e-6)
    assert outline("full", 0.5e-6, 0.5e-6, h, 0.1e-6, upper=True)[2] == pytest.approx((0.0, -0.1e-6 - h))
    assert Profile(kind="half", base=B, height=h).vertices(upper=False) == [(-B, 0.0), (0.0, 0.0), (0.0, h)]
    assert Profile(kind="half", base=B, height=h).vertices(upper=True) == [(0.0, 0.0), (B, 0.0), (0.0, -h)]


def test_flat_block_edges_are_a_gentle_slope_then_a_bevel():
    """Width 1 um, height 0.25 um: from each face corner inwards 100 nm at 1:10 (10 nm down)
    then 50 nm at 45 deg (50 nm down); the contact face is the middle 0.7 um."""
    (f1, s1), (f2, s2) = FLAT_EDGE
    assert (f1, s1, f2, s2) == (0.10, 0.1, 0.05, 1.0)
    h = 0.25e-6
    lower = outline("flat", 0.5e-6, 0.5e-6, h, 0.0, upper=False)
    expected = [(-0.5e-6, 0.0), (0.5e-6, 0.0), (0.5e-6, h - 60e-9), (0.45e-6, h - 10e-9), (0.35e-6, h),
                (-0.35e-6, h), (-0.45e-6, h - 10e-9), (-0.5e-6, h - 60e-9)]
    assert np.allclose(lower, expected, rtol=0, atol=1e-18)
    upper = outline("flat", 0.5e-6, 0.5e-6, h, 0.0, upper=True)
    assert np.allclose(upper, [(x, -y) for x, y in expected], rtol=0, atol=1e-18)
    # the outline is convex (pymunk needs it): every turn the same way
    pts = np.array(lower)
    edges = np.roll(pts, -1, axis=0) - pts
    turns = edges[:, 0] * np.roll(edges, -1, axis=0)[:, 1] - edges[:, 1] * np.roll(edges, -1, axis=0)[:, 0]
    assert np.all(turns > 0)
    # a slab thinner than twice the edge depth (60 nm): the edge is scaled to half its height
    thin = np.array(outline("flat", 0.5e-6, 0.5e-6, 40e-9, 0.0, upper=False))
    assert thin[:, 1].max() == pytest.approx(40e-9) and thin[2, 1] == pytest.approx(20e-9)
    assert thin[4, 0] == pytest.approx(0.5e-6 - 150e-9 / 3)  # runs scaled by 20/60


def test_half_of_cuts_the_full_triangle_through_its_apex():
    full = Profile.from_angle("full", base=B, flank_angle=45.0)
    half = half_of(full)
    assert (half.kind, half.base, half.height) == ("half", B / 2, full.height)
    assert half.flank_angle == pytest.approx(45.0)
    with pytest.raises(a.SceneError, match="`profile` must be a full triangle to be cut in half, got 'flat'"):
        half_of(Profile(kind="flat"))


def test_profile_validation_names_the_field():
    with pytest.raises(a.SceneError, match="`kind` must be one of"):
        Profile(kind="trapezoid")
    with pytest.raises(a.SceneError, match="`base` must be > 0"):
        Profile(base=0.0)
    with pytest.raises(a.SceneError, match="`height` must be > 0"):
        Profile(height=-1.0)
    for angle in (0.0, 90.0, -5.0):
        with pytest.raises(a.SceneError, match=r"`flank_angle` must be in \(0, 90\) degrees"):
            Profile.from_angle("full", flank_angle=angle)
    with pytest.raises(a.SceneError, match="`flank_angle`"):
        Profile.from_angle("full", flank_angle=math.nan)
    with pytest.raises(a.SceneError, match="`kind`"):
        Profile.from_angle("square")
    with pytest.raises(a.SceneError, match="`base`"):
        Profile.from_angle("full", base=-1.0)


def test_regular_tips_and_touching_bases():
    tips = RegularSpacing(count=4, pitch=1.25e-6, offset=2e-6).tips(0.5e-6, 0.5e-6)
    assert list(tips) == [2e-6 + 1.25e-6 * i for i in range(4)]
    assert RegularSpacing(count=3, pitch=1e-6).tips(0.5e-6, 0.5e-6)[-1] == 2e-6  # bases touching: fine
    with pytest.raises(a.SceneError, match=r"`pitch` is too small: asperity bases \(1e-06 m wide\) would overlap "
                                           r"\(closest tips 9e-07 m apart\)"):
        RegularSpacing(count=3, pitch=0.9e-6).tips(0.5e-6, 0.5e-6)
    assert RegularSpacing(count=1, pitch=0.1e-6).tips(0.5e-6, 0.5e-6).tolist() == [0.0]  # nothing to overlap
    for field, value, message in (("count", 0, "`count`"), ("pitch", 0.0, "`pitch` must be > 0"),
                                  ("offset", math.inf, "`offset`")):
        with pytest.raises(a.SceneError, match=message):
            RegularSpacing(**{field: value})
    assert RegularSpacing(pitch=2e-6).mean_pitch == 2e-6


def test_per_asperity_runs_name_the_overlapping_pair():
    tips = np.array([0.0, 1.0e-6, 2.2e-6])
    left, right = np.array([0.4e-6, 0.5e-6, 0.4e-6]), np.array([0.6e-6, 0.6e-6, 0.4e-6])
    with pytest.raises(a.SceneError, match=r"the bases of asperities 0 and 1 would overlap \(tips 1e-06 m apart, "
                                           r"their flanks need 1.1e-06 m\)"):
        ExplicitSpacing(positions=tuple(tips)).tips(left, right)
    ok = ExplicitSpacing(positions=(0.0, 1.1e-6, 2.2e-6)).tips(left, right)  # exactly touching
    assert list(ok) == [0.0, 1.1e-6, 2.2e-6]


def test_random_gaps_follow_the_documented_law():
    """Gap i = base + min_gap + U_i x 2 (mean_pitch - base - min_gap), U from default_rng(seed)."""
    spacing = RandomSpacing(count=6, mean_pitch=1.25e-6, min_gap=0.05e-6, seed=7, offset=1e-6)
    tips = spacing.tips(0.5e-6, 0.5e-6)
    shortest = 1e-6 + 0.05e-6
    u = np.random.default_rng(7).random(5)
    assert np.allclose(np.diff(tips), shortest + 2 * (1.25e-6 - shortest) * u, rtol=1e-13, atol=0)
    assert tips[0] == 1e-6 and spacing.pitch == 1.25e-6
    # the mean pitch over many gaps: within 4 standard errors of mean_pitch
    many = np.diff(RandomSpacing(count=20_001, mean_pitch=1.25e-6, seed=3).tips(0.5e-6, 0.5e-6))
    assert many.min() >= 1e-6 and many.max() <= 1.5e-6
    sd = 2 * 0.25e-6 / math.sqrt(12)
    assert abs(many.mean() - 1.25e-6) < 4 * sd / math.sqrt(len(many))
    with pytest.raises(a.SceneError, match=r"`mean_pitch` \(9e-07 m\) must be >= base \+ min_gap \(1e-06 m\)"):
        RandomSpacing(count=3, mean_pitch=0.9e-6).tips(0.5e-6, 0.5e-6)
    assert RandomSpacing(count=1, mean_pitch=0.5e-6).tips(0.5e-6, 0.5e-6).tolist() == [0.0]


def test_random_gaps_with_per_asperity_runs():
    left, right = np.array([0.3e-6, 0.5e-6, 0.4e-6]), np.array([0.2e-6, 0.6e-6, 0.5e-6])
    tips = RandomSpacing(count=3, mean_pitch=1.3e-6, seed=2).tips(left, right)
    shortest = right[:-1] + left[1:]
    u = np.random.default_rng(2).random(2)
    assert np.allclose(np.diff(tips), shortest + 2 * (1.3e-6 - shortest) * u, rtol=1e-13, atol=0)
    with pytest.raises(a.SceneError, match=r"must be >= base \+ min_gap \(1e-06 m\)"):
        RandomSpacing(count=3, mean_pitch=0.95e-6).tips(left, right)  # the widest pair needs 1.0 um
    # equal runs given as arrays: the very tips of the scalar case
    scalar = RandomSpacing(count=5, seed=4).tips(0.5e-6, 0.5e-6)
    arrays = RandomSpacing(count=5, seed=4).tips(np.full(5, 0.5e-6), np.full(5, 0.5e-6))
    assert np.array_equal(scalar, arrays)


def test_random_spacing_validation():
    for field, value, message in (("count", 0, "`count`"), ("mean_pitch", -1.0, "`mean_pitch` must be > 0"),
                                  ("min_gap", -1e-9, "`min_gap` must be >= 0"), ("seed", -1, "`seed`"),
                                  ("offset", math.nan, "`offset`")):
        with pytest.raises(a.SceneError, match=message):
            RandomSpacing(**{field: value})


def test_explicit_positions():
    s = ExplicitSpacing(positions=[0.0, 1e-6, 3e-6])
    assert s.positions == (0.0, 1e-6, 3e-6) and s.count == 3
    assert s.mean_pitch == pytest.approx(1.5e-6) and s.pitch == s.mean_pitch
    assert ExplicitSpacing(positions=(2e-6,), mean_pitch=1e-6).mean_pitch == 1e-6
    with pytest.raises(a.SceneError, match="`mean_pitch` is required with a single tip position"):
        ExplicitSpacing(positions=(2e-6,))
    with pytest.raises(a.SceneError, match=r"`positions` must increase: 1e-06 follows 2e-06 at index 2"):
        ExplicitSpacing(positions=(0.0, 2e-6, 1e-6))
    with pytest.raises(a.SceneError, match="`positions` must hold at least one tip"):
        ExplicitSpacing(positions=())
    with pytest.raises(a.SceneError, match="`mean_pitch` must be > 0"):
        ExplicitSpacing(positions=(0.0, 1e-6), mean_pitch=-1.0)


def test_float_array_checks_and_names_entries():
    assert float_array("x", [1, 2, 3], 3).dtype == np.float64
    assert float_array("x", np.array([1.0, 2.0]), None, minimum="positive").tolist() == [1.0, 2.0]
    with pytest.raises(a.SceneError, match="`x` must be a sequence of numbers"):
        float_array("x", "123", None)
    with pytest.raises(a.SceneError, match="`x` must be a sequence of numbers"):
        float_array("x", 5.0, None)
    with pytest.raises(a.SceneError, match=r"`x` must be one-dimensional, got shape \(1, 2\)"):
        float_array("x", [[1.0, 2.0]], None)
    with pytest.raises(a.SceneError, match=r"`x` must have 3 entries \(one per asperity\), got 2"):
        float_array("x", [1.0, 2.0], 3)
    with pytest.raises(a.SceneError, match=r"`x\[1\]` must be finite and > 0, got 0.0"):
        float_array("x", [1.0, 0.0], None, minimum="positive")
    with pytest.raises(a.SceneError, match=r"`x\[0\]` must be finite and >= 0, got -1.0"):
        float_array("x", [-1.0, 0.0], None, minimum="nonnegative")
    with pytest.raises(a.SceneError, match=r"`x\[2\]` must be finite, got nan"):
        float_array("x", [0.0, -1.0, math.nan], None)
    assert float_array("x", [0.0, -1.0], None).tolist() == [0.0, -1.0]  # no minimum
    with pytest.raises(a.SceneError, match=r"`x\[0\]`"):
        float_array("x", ["1.0", "a"], None)  # strings: each entry checked and named
    with pytest.raises(a.SceneError, match=r"`x\[0\]`"):
        float_array("x", [True, False], None)  # booleans are not numbers


def test_fields_come_back_as_plain_python_numbers():
    """Every dataclass converts what it is given (NumPy scalars, ints, Fractions) to plain float /
    int: what reaches pymunk and JSON is never a NumPy type."""
    from fractions import Fraction

    p = Profile(kind="full", base=np.float32(1e-6), height=1)
    assert type(p.base) is float and type(p.height) is float and p.height == 1.0
    r = RegularSpacing(count=np.int64(3), pitch=Fraction(5, 4), offset=np.int16(2))
    assert (type(r.count), type(r.pitch), type(r.offset)) == (int, float, float)
    assert (r.count, r.pitch, r.offset) == (3, 1.25, 2.0)
    s = RandomSpacing(count=np.int64(4), mean_pitch=np.float32(1.5), min_gap=0, seed=np.uint8(9), offset=1)
    assert [type(v) for v in (s.count, s.mean_pitch, s.min_gap, s.seed, s.offset)] == [int, float, float, int, float]
    e = ExplicitSpacing(positions=np.array([0, 2, 3]), mean_pitch=np.float32(1.5))
    assert e.positions == (0.0, 2.0, 3.0) and all(type(v) is float for v in e.positions)
    assert type(e.mean_pitch) is float
    assert RandomSpacing(seed=2**63 - 1).seed == 2**63 - 1
    with pytest.raises(a.SceneError, match="`seed`"):
        RandomSpacing(seed=2**63)
    assert Profile.from_angle("full", base=2e-6, flank_angle=45.0).base == 2e-6
    assert Profile.from_angle("full", flank_angle=0.5).flank_angle == pytest.approx(0.5)  # any angle in (0, 90)
    with pytest.raises(a.SceneError, match=r"`flank_angle` must be in \(0, 90\) degrees, got 90.0"):
        Profile.from_angle("full", flank_angle=90.0)
    with pytest.raises(a.SceneError, match=r"`flank_angle` must be in \(0, 90\) degrees, got -3"):
        Profile.from_angle("full", flank_angle=-3)
    assert Profile(kind="half").vertices(upper=True)[2][1] < 0  # the kind reaches the outline
    assert len(Profile(kind="flat").vertices(upper=False)) == 8


def test_two_tips_are_checked_and_the_tolerance_is_relative():
    """Two asperities can overlap (the check starts at two, not three); bases overlapping by
    less than 1e-9 of their width are rounding, by more are an error, with one run per tip too."""
    with pytest.raises(a.SceneError, match="`pitch` is too small"):
        RegularSpacing(count=2, pitch=0.9e-6).tips(0.5e-6, 0.5e-6)
    with pytest.raises(a.SceneError, match="asperities 0 and 1"):
        ExplicitSpacing(positions=(0.0, 0.9e-6)).tips(np.array([0.5e-6, 0.5e-6]), np.array([0.5e-6, 0.5e-6]))
    for left, right in ((0.5e-6, 0.5e-6), (np.array([0.5e-6, 0.5e-6]), np.array([0.5e-6, 0.5e-6]))):
        ok = ExplicitSpacing(positions=(0.0, 1e-6 * (1 - 5e-10))).tips(left, right)  # within rounding
        assert len(ok) == 2
        with pytest.raises(a.SceneError, match="too small"):
            ExplicitSpacing(positions=(0.0, 1e-6 * (1 - 2e-9))).tips(left, right)
    # unequal runs: the right run of one and the left run of the next must fit (0.3 + 0.6 > 0.85)
    with pytest.raises(a.SceneError, match=r"their flanks need 9e-07 m"):
        ExplicitSpacing(positions=(0.0, 0.85e-6)).tips(np.array([0.1e-6, 0.6e-6]), np.array([0.3e-6, 0.1e-6]))
    assert len(ExplicitSpacing(positions=(0.0, 0.85e-6)).tips(np.array([0.6e-6, 0.1e-6]),
                                                               np.array([0.1e-6, 0.3e-6]))) == 2
    # one scalar run and one array: checked per tip, not as scalars
    with pytest.raises(a.SceneError, match="asperities 1 and 2"):
        ExplicitSpacing(positions=(0.0, 1.0e-6, 1.5e-6)).tips(0.2e-6, np.array([0.3e-6, 0.4e-6, 0.1e-6]))
    tips = RandomSpacing(count=3, mean_pitch=1.2e-6, seed=1).tips(0.4e-6, np.array([0.5e-6, 0.6e-6, 0.5e-6]))
    shortest = np.array([0.5e-6, 0.6e-6]) + 0.4e-6
    u = np.random.default_rng(1).random(2)
    assert np.allclose(np.diff(tips), shortest + 2 * (1.2e-6 - shortest) * u, rtol=1e-13, atol=0)


def test_random_gaps_with_a_minimum_gap_and_per_asperity_runs():
    left, right = np.array([0.3e-6, 0.5e-6, 0.4e-6]), np.array([0.2e-6, 0.6e-6, 0.5e-6])
    tips = RandomSpacing(count=3, mean_pitch=1.4e-6, min_gap=0.1e-6, seed=5).tips(left, right)
    shortest = right[:-1] + left[1:] + 0.1e-6
    u = np.random.default_rng(5).random(2)
    assert np.allclose(np.diff(tips), shortest + 2 * (1.4e-6 - shortest) * u, rtol=1e-13, atol=0)
    # exactly the widest pair's need is allowed; one count is never checked
    assert len(RandomSpacing(count=3, mean_pitch=1.2e-6, min_gap=0.1e-6).tips(left, right)) == 3
    assert RandomSpacing(count=1, mean_pitch=1e-9).tips(left[:1], right[:1]).tolist() == [0.0]


def test_flat_edges_at_the_exact_half_height_limit():
    """The edge (6 % of the width deep) is scaled only when it would pass half the height: at
    exactly twice its depth the block keeps it as it is."""
    full = np.array(outline("flat", 0.5e-6, 0.5e-6, 120e-9, 0.0, upper=False))
    assert full[2, 1] == pytest.approx(60e-9) and full[4, 0] == pytest.approx(0.35e-6)
    assert outline("flat", 0.5e-6, 0.5e-6, 0.2e-6, 0.1e-6, upper=False)[0] == (-0.5e-6, 0.1e-6)  # level kept


def test_explicit_positions_limits_and_names():
    from asperity2d._inputs import MAX_COUNT

    with pytest.raises(a.SceneError, match=f"`positions` must hold <= {MAX_COUNT} tips, got {MAX_COUNT + 1}"):
        ExplicitSpacing(positions=np.arange(MAX_COUNT + 1, dtype=float))
    assert ExplicitSpacing(positions=np.arange(MAX_COUNT, dtype=float)).count == MAX_COUNT
    with pytest.raises(a.SceneError, match=r"`positions` must increase: 1.0 follows 1.0 at index 1"):
        ExplicitSpacing(positions=(1.0, 1.0))  # equal tips are not increasing
    with pytest.raises(a.SceneError, match=r"`positions\[1\]` must be finite"):
        ExplicitSpacing(positions=(0.0, math.inf))
    assert ExplicitSpacing(positions=(2e-6, 5e-6, 6e-6)).mean_pitch == pytest.approx(2e-6)
    with pytest.raises(a.SceneError, match="`positions` is too small"):
        ExplicitSpacing(positions=(0.0, 0.5e-6)).tips(0.5e-6, 0.5e-6)
    assert RegularSpacing(count=3, pitch=1.0, offset=0).tips(0.1, 0.1).dtype == np.float64


def test_tips_are_drawn_once_and_handed_out_as_copies():
    """The parts keep their drawn tips (a critical-force search asks for them thousands of times):
    the same floats every time, and a caller writing into what it got changes nothing."""
    scene = a.make_scene(spacing="random", seed=7)
    lower, upper = scene.lower.tips(), scene.slider.tips()
    assert np.array_equal(lower, scene.lower.spacing.tips(*scene.lower.runs()))
    lower[:] = -1.0
    upper[:] = -1.0
    assert np.array_equal(scene.lower.tips(), scene.lower.spacing.tips(*scene.lower.runs()))
    assert scene.slider.tips()[0] == 0.0 and np.all(np.diff(scene.slider.tips()) > 0)
    assert scene.replace(drive=a.ConstantForce(force=1e-3)).lower.tips()[0] == scene.lower.tips()[0]
