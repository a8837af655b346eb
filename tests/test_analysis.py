"""Stick–slip events, breakaway force and friction traces.

Synthetic series with known events first (exact recovery, noise, bounces, no
false events), then a real short spring-driven run against the flank law.
"""

import dataclasses
import math
import warnings

import numpy as np
import pytest

import asperity2d as a
from asperity2d.analysis import (Event, breakaway_force, event_statistics, friction_traces,
                                 stick_slip_events, synthetic_stick_slip)


def sample_of(result, t):
    return int(np.argmin(np.abs(result.t - t)))


@pytest.mark.parametrize("noise,seed", [(0.0, 0), (0.1, 1), (0.1, 2), (0.2, 3)])
def test_synthetic_events_recovered_within_one_sample(noise, seed):
    result, truth = synthetic_stick_slip(n_events=10, noise=noise, seed=seed)
    events = stick_slip_events(result)
    assert len(events) == len(truth["slip_index"])  # none missed, none false
    found = np.array([sample_of(result, e.t_slip) for e in events])
    ends = np.array([sample_of(result, e.t_end) for e in events])
    assert np.abs(found - truth["slip_index"]).max() <= 1
    assert np.abs(ends - truth["end_index"]).max() <= 1
    assert all(e.complete for e in events)


def test_synthetic_event_fields_match_the_series_exactly():
    result, truth = synthetic_stick_slip(n_events=5, seed=4)
    events = stick_slip_events(result)
    f, x, t = result.drive_force, result.x, result.t
    for e, i0, i1 in zip(events, truth["slip_index"], truth["end_index"]):
        assert e.t_slip == t[i0] and e.t_end == t[i1]
        assert e.force_peak == pytest.approx(f[i0], rel=1e-12)
        assert e.force_drop == pytest.approx(f[i0] - f[i0:i1 + 1].min(), rel=1e-12)
        assert e.force_drop > 0
        assert e.slip_distance == pytest.approx(x[i1] - x[i0], rel=1e-12)
        assert e.stick_duration == pytest.approx(e.t_slip - e.t_stick)
    for prev, nxt in zip(events, events[1:]):
        assert nxt.t_stick == prev.t_end  # a slip ends where the next stick starts
    assert events[0].t_stick == t[0]


def test_bounces_inside_a_slip_are_not_events():
    result, truth = synthetic_stick_slip(n_events=6, seed=5, samples_per_slip=40)
    v = result.v.copy()
    for i0 in truth["slip_index"]:
        v[i0 + 15:i0 + 18] = 0.0  # the slider stops for 3 samples mid-slip (asperity impact)
    events = stick_slip_events(dataclasses.replace(result, v=v))
    assert [sample_of(result, e.t_slip) for e in events] == list(truth["slip_index"])


def test_no_false_events_without_stick_slip():
    result, _ = synthetic_stick_slip(n_events=3, seed=6)
    V = result.scene.drive.velocity
    omega = 2 * math.pi / (result.t[-1] / 3)
    rng = np.random.default_rng(7)
    # free oscillation on the drive spring from rest peaks at 2 V: not a slip
    v = V * (1 - np.cos(omega * result.t)) + rng.normal(0, 0.1 * V, len(result.t))
    assert stick_slip_events(dataclasses.replace(result, v=v)) == []
    creep = np.full_like(result.t, 0.03 * V)
    assert stick_slip_events(dataclasses.replace(result, v=creep)) == []


def test_short_noise_spike_is_ignored_with_min_slip():
    result, truth = synthetic_stick_slip(n_events=3, seed=8)
    v = result.v.copy()
    spike = truth["slip_index"][1] - 40  # mid-stick
    v[spike] = 10 * result.scene.drive.velocity
    spiky = dataclasses.replace(result, v=v)
    assert len(stick_slip_events(spiky)) == 3
    assert len(stick_slip_events(spiky, min_slip=0.0, min_stick=0.0)) == 3  # it moves 0.01 base
    assert len(stick_slip_events(spiky, min_slip=0.0, min_stick=0.0, min_slip_distance=0.0)) == 4


def test_unfinished_last_slip_is_marked_incomplete():
    result, truth = synthetic_stick_slip(n_events=3, seed=9)
    cut = truth["slip_index"][-1] + 15  # slip lasts 14 samples > default min_slip (11)
    short = dataclasses.replace(result, **{n: getattr(result, n)[:cut] for n in (
        "t", "x", "v", "drive_x", "drive_force")})
    events = stick_slip_events(short)
    assert [e.complete for e in events] == [True, True, False]
    assert events[-1].t_end == short.t[-1]
    stats = event_statistics(events)
    assert stats["count"] == 3
    assert stats["force_drop_mean"] == pytest.approx(np.mean([e.force_drop for e in events[:2]]))


def test_thresholds_are_validated():
    result, _ = synthetic_stick_slip(n_events=2)
    with pytest.raises(a.SceneError, match="`slip_speed`"):
        stick_slip_events(result, stick_speed=5.0, slip_speed=4.0)
    with pytest.raises(a.SceneError, match="`min_stick`"):
        stick_slip_events(result, min_stick=-1.0)
    forced = dataclasses.replace(result, scene=a.make_scene(drive="force", lower_count=2,
                                                            upper_count=1))
    with pytest.raises(a.SceneError, match="`stick_speed`"):
        stick_slip_events(forced)
    with pytest.raises(a.SceneError, match="`result`"):
        breakaway_force(forced)


def test_event_statistics_hand_computed():
    def ev(t_slip, drop, stick):
        return Event(t_stick=t_slip - stick, t_slip=t_slip, t_end=t_slip + 0.1, force_peak=1.0,
                     force_drop=drop, slip_distance=2.0, stick_duration=stick)

    events = [ev(1.0, 0.2, 1.0), ev(2.0, 0.4, 0.8), ev(4.0, 0.6, 1.2)]
    s = event_statistics(events)
    assert s["count"] == 3
    assert s["force_drop_mean"] == pytest.approx(0.4)
    assert s["force_drop_std"] == pytest.approx(0.2)
    assert s["stick_duration_mean"] == pytest.approx(1.0)
    assert s["stick_duration_std"] == pytest.approx(0.2)
    assert s["interval_mean"] == pytest.approx(1.5)  # intervals 1, 2
    assert s["regularity"] == pytest.approx(math.sqrt(0.5) / 1.5)
    empty = event_statistics([])
    assert empty["count"] == 0 and math.isnan(empty["force_drop_mean"])


def test_breakaway_on_synthetic_and_never_breaking_away():
    result, truth = synthetic_stick_slip(n_events=4, seed=10)
    assert breakaway_force(result) == result.drive_force[truth["slip_index"][0]]
    creep = dataclasses.replace(result, v=np.full_like(result.t, 0.03 * result.scene.drive.velocity))
    with pytest.raises(a.SceneError, match="`result`"):
        breakaway_force(creep)


@pytest.fixture(scope="module")
def real_run():
    return a.simulate(a.make_scene(lower_count=6, upper_count=2, track="free"))


def test_real_run_events_and_breakaway_match_the_flank_law(real_run):
    events = stick_slip_events(real_run)
    assert len(events) >= 2
    assert all(e.force_drop > 0 and e.slip_distance > 0 for e in events)
    assert all(e.t_stick <= e.t_slip <= e.t_end for e in events)
    scene = real_run.scene
    flank = scene.slider.normal_load * math.tan(math.radians(45.0) + math.atan(scene.contact.mu_static))
    assert flank == pytest.approx(0.01857, abs=1e-5)
    assert breakaway_force(real_run) == pytest.approx(flank, rel=0.02)
    assert breakaway_force(real_run) == events[0].force_peak


def test_friction_traces(real_run):
    tr = friction_traces(real_run, bins=20)
    n = len(real_run.t)
    for key in ("time", "displacement", "velocity", "friction_force", "drive_force"):
        assert tr[key].shape == (n,)
    assert tr["displacement"][0] == 0.0
    assert 0 < len(tr["velocity_centers"]) <= 20
    assert np.all(np.diff(tr["velocity_centers"]) > 0)
    v = real_run.v
    moving = v > v.max() / 1e4
    assert tr["bin_count"].sum() == moving.sum()
    total = np.sum(tr["friction_mean"] * tr["bin_count"])
    assert total == pytest.approx(real_run.friction_force[moving].sum(), rel=1e-9)


# -- series built sample by sample (what the mutation run found unpinned) -------------------------

def series(v, *, dt_over_base=1e-3, preload=0.0):
    """A spring-driven series with the slider velocity ``v`` (multiples of V) given sample by
    sample: x integrates v, the drive force is k (V t - x) + preload, so the force peaks
    exactly where v crosses V (computed here, independently of the detector)."""
    base, _ = synthetic_stick_slip(n_events=1)
    scene = base.scene
    V, k = scene.drive.velocity, scene.drive.stiffness
    dt = dt_over_base * scene.base / V
    v = np.asarray(v, dtype=float) * V
    t = dt * np.arange(len(v))
    x = np.concatenate(([0.0], np.cumsum(v[1:] * dt)))
    n = len(t)
    zeros, lower = np.zeros(n), np.zeros((scene.lower.count, n))
    return a.Result(t=t, x=x, v=v, y=zeros, vy=zeros, drive_x=V * t, drive_force=k * (V * t - x) + preload,
                    normal_force=zeros, friction_force=zeros, tangential_force=zeros, contact_count=zeros,
                    lower_dx=lower, lower_dy=lower, lower_contact=lower > 0, scene=scene,
                    meta={"dt": dt, "record_every": 1})


def test_the_onset_is_where_the_slider_overtakes_the_drive_not_where_it_turns_fast():
    """The slider leaves the stick gradually: v rises by 0.25 V per sample, so the drive force
    peaks at the sample where v crosses V, eight samples before v exceeds 3 V (the slip
    threshold). The detector must search back to it."""
    stick = [0.0] * 200
    ramp = list(np.arange(0.25, 40.0, 0.25))  # 0.25 V, 0.5 V, ... up to 39.75 V
    v = stick + ramp + [40.0] * 40 + list(np.linspace(40.0, 0.0, 20)) + [0.0] * 300
    result = series(v)
    events = stick_slip_events(result)
    assert len(events) == 1
    crossing = len(stick) + int(np.argmax(np.array(ramp) >= 1.0))  # first sample at >= V
    top = result.drive_force[: len(stick) + len(ramp)].max()  # the force's top, by brute force
    # at v = V exactly the force is flat for one sample: either end of the plateau is the top
    assert sample_of(result, events[0].t_slip) in (crossing - 1, crossing)
    assert events[0].force_peak == pytest.approx(top, rel=1e-12)
    fast = len(stick) + int(np.argmax(np.array(ramp) > 3.0))
    assert fast - crossing >= 7


def test_a_free_swing_on_the_drive_spring_is_not_a_stick():
    """After a slip the slider swings freely on the drive spring, v = V (1 + 2.4 sin wt):
    from -1.4 V to 3.4 V, below 0.5 V for about 15 % of each period, never at rest. The
    hysteresis holds "stick" through the dead band for 70 % of a period (more than
    min_stick, half a period): that is not a stick, and one slip it remains."""
    base, _ = synthetic_stick_slip(n_events=1)
    scene = base.scene
    period = 2 * math.pi * math.sqrt(scene.slider.mass / scene.drive.stiffness)
    V = scene.drive.velocity
    dt_over_base = period / 200 * V / scene.base  # 200 samples per drive period
    swing = 1.0 + 2.4 * np.sin(2 * math.pi * np.arange(1000) / 200)
    v = [0.0] * 400 + list(np.linspace(0.0, 40.0, 10)) + [40.0] * 30 + list(swing) + [0.0] * 400
    events = stick_slip_events(series(v, dt_over_base=dt_over_base))
    assert len(events) == 1 and events[0].complete
    slow = np.abs(swing) < 0.5
    assert 0.1 < slow.mean() < 0.2  # the premise: the swing is rarely slow


def test_a_micro_slip_is_not_a_slip_however_the_run_was_sampled():
    """A contact letting go of one flank: v jumps to 5 V for 4 samples (0.02 base moved) in
    the middle of a stick. Not a slip, at every sampling of the same motion."""
    v = [0.0] * 300 + [5.0] * 4 + [0.0] * 300 + list(np.linspace(0.0, 40.0, 10)) + [40.0] * 40 + [0.0] * 400
    fine = series(v, dt_over_base=1e-3)
    events = stick_slip_events(fine, min_slip=0.0)
    assert len(events) == 1 and sample_of(fine, events[0].t_slip) > 600
    for every in (2, 3, 10):
        coarse = dataclasses.replace(fine, **{n: getattr(fine, n)[::every] for n in
                                              ("t", "x", "v", "drive_x", "drive_force")})
        assert len(stick_slip_events(coarse, min_slip=0.0)) == 1
    # with no distance rule the micro-slip counts (the rule is what removes it)
    assert len(stick_slip_events(fine, min_slip=0.0, min_slip_distance=0.0)) == 2


def test_a_short_stop_at_the_end_of_the_run_leaves_the_slip_unfinished():
    """The run ends 10 samples into a stop (less than min_stick): the last slip is reported
    incomplete, ending on the last sample."""
    v = [0.0] * 300 + list(np.linspace(0.0, 40.0, 10)) + [40.0] * 40 + [0.0] * 10
    result = series(v)
    period = 2 * math.pi * math.sqrt(result.scene.slider.mass / result.scene.drive.stiffness)
    assert 10 * result.meta["dt"] < 0.5 * period  # the premise: shorter than min_stick
    events = stick_slip_events(result)
    assert len(events) == 1 and not events[0].complete
    assert events[0].t_end == result.t[-1]
    assert events[0].slip_distance == pytest.approx(result.x[-1] - np.interp(events[0].t_slip, result.t, result.x))
    longer = series(v[:-10] + [0.0] * 400)  # a stop that lasts: complete
    assert stick_slip_events(longer)[0].complete


def test_keywords_reach_the_detector_in_every_force_measure():
    result, truth = synthetic_stick_slip(n_events=4, seed=11)
    v = result.v.copy()
    v[truth["slip_index"][1] - 40] = 10 * result.scene.drive.velocity  # a one-sample spike mid-stick
    spiky = dataclasses.replace(result, v=v)
    loose = {"min_slip": 0.0, "min_stick": 0.0, "min_slip_distance": 0.0}
    events = stick_slip_events(spiky, **loose)
    assert len(events) == 5 and len(stick_slip_events(spiky)) == 4
    forces = [e.force_peak for e in events]
    assert a.mean_stick_force(spiky, **loose) == pytest.approx(np.mean(forces))
    assert a.mean_stick_force(spiky) == pytest.approx(np.mean([e.force_peak for e in stick_slip_events(spiky)]))
    assert a.mean_stick_force(spiky, **loose) != a.mean_stick_force(spiky)
    assert a.peak_stick_force(spiky, **loose) == max(forces)
    assert breakaway_force(spiky, **loose) == forces[0]
    strict = {"stick_speed": 0.5 * result.scene.drive.velocity, "slip_speed": 100 * result.scene.drive.velocity}
    with pytest.raises(a.SceneError, match="`result` has no stick-to-slip transition"):
        a.mean_stick_force(spiky, **strict)  # 40 V never exceeds 100 V: no slip at all
    with pytest.raises(a.SceneError, match="`result` has no stick-to-slip"):
        a.peak_stick_force(spiky, **strict)


def test_friction_velocity_bins_by_hand():
    """Velocities 1..100 (log-spaced, 5 bins) with friction 2 v: bin edges are the geometric
    sequence from 1 to 100, centres their geometric means, means the bin averages."""
    v = np.geomspace(1.0, 100.0, 51)
    base = series(np.zeros(51))
    result = dataclasses.replace(base, v=v, friction_force=2.0 * v)
    tr = friction_traces(result, bins=5, dynamic_range=1e3)
    edges = np.geomspace(1.0, 100.0 * (1 + 1e-12), 6)
    assert np.allclose(tr["velocity_centers"], np.sqrt(edges[:-1] * edges[1:]), rtol=1e-12)
    which = np.minimum(np.searchsorted(edges, v, side="right") - 1, 4)
    for b in range(5):
        assert tr["bin_count"][b] == np.sum(which == b)
        assert tr["friction_mean"][b] == pytest.approx(np.mean(2.0 * v[which == b]), rel=1e-12)
    # the dynamic range cuts the slow end: with 10x only v > 10 are binned
    cut = friction_traces(result, bins=5, dynamic_range=10.0)
    assert cut["bin_count"].sum() == np.sum(v > 10.0)
    with pytest.raises(a.SceneError, match="`dynamic_range` must be > 1"):
        friction_traces(result, dynamic_range=1.0)
    with pytest.raises(a.SceneError, match="`bins` must be >= 1"):
        friction_traces(result, bins=0)
    still = friction_traces(dataclasses.replace(base, v=np.zeros(51)), bins=5)
    assert len(still["velocity_centers"]) == len(still["friction_mean"]) == len(still["bin_count"]) == 0


# -- the ground-truth generator: its documented properties, from its arguments -------------------

def test_the_synthetic_series_is_the_documented_one():
    """Defaults: 8 events, sticks of 80-160 samples creeping at exactly 3 % of V, slips of 20
    samples that are the half-sine 40 V sin(pi j / 21), a final 80-sample stick; x integrates v
    from 0, the drive moves at V and the force is the spring's k (V t - x), exactly (no noise)."""
    result, truth = synthetic_stick_slip()
    scene = result.scene
    V, k = scene.drive.velocity, scene.drive.stiffness
    slips, ends = truth["slip_index"], truth["end_index"]
    assert len(slips) == len(ends) == 8
    assert np.all(ends - slips == 21)  # last stick sample, 20 slip samples, then the next stick
    sticks = np.diff(np.concatenate(([-1], slips))) - np.concatenate(([0], np.full(7, 20)))
    assert np.all((sticks >= 80) & (sticks <= 160))
    v, t, dt = result.v, result.t, result.meta["dt"]
    assert len(v) == ends[-1] + 80  # the trailing stick has the shortest stick length
    pulse = 40.0 * V * np.sin(np.pi * np.arange(1, 21) / 21)
    stuck = np.ones(len(v), dtype=bool)
    for i0, i1 in zip(slips, ends):
        assert np.array_equal(v[i0 + 1:i1], pulse)
        stuck[i0 + 1:i1] = False
    assert np.all(v[stuck] == 0.03 * V)
    assert dt == t[1] - t[0] and np.allclose(np.diff(t), dt, rtol=1e-9)
    assert result.x[0] == 0.0
    # a difference of the cumulative sum is exact to the rounding of x itself (a few ulp of max x)
    assert np.allclose(np.diff(result.x), v[1:] * dt, rtol=0.0, atol=16 * np.spacing(result.x.max()))
    assert np.array_equal(result.drive_x, V * t)
    assert np.array_equal(result.drive_force, k * (V * t - result.x))
    assert np.array_equal(result.friction_force, result.drive_force)
    # every per-sample series has one value per sample; the slider never leaves y = 0 or touches
    for name in ("y", "vy", "normal_force", "tangential_force", "contact_count"):
        assert np.array_equal(getattr(result, name), np.zeros(len(t))), name
    assert scene.lower.count == 2 and scene.slider.spacing.count == 1
    for name in ("lower_dx", "lower_dy", "lower_contact"):
        assert np.shape(getattr(result, name)) == (2, len(t))
    assert not np.any(result.lower_contact)
    assert result.meta == {"dt": dt, "record_every": 1, "status": "synthetic"} and result.status == "synthetic"


def test_synthetic_stick_lengths_span_both_bounds_and_slips_their_count():
    """Stick lengths are drawn from the closed range [lo, hi]: over 60 draws from {5, 6} both
    appear (each is missing with probability 2^-60) and nothing else does."""
    result, truth = synthetic_stick_slip(n_events=60, samples_per_stick=(5, 6), samples_per_slip=7, seed=2)
    slips, ends = truth["slip_index"], truth["end_index"]
    sticks = np.concatenate(([slips[0] + 1], slips[1:] - ends[:-1] + 1))
    assert set(sticks.tolist()) == {5, 6}
    assert np.all(ends - slips == 8)
    assert len(result.t) == ends[-1] + 5


def test_synthetic_series_is_reproducible_from_its_seed():
    one, truth_one = synthetic_stick_slip(noise=0.2, seed=5)
    two, truth_two = synthetic_stick_slip(noise=0.2, seed=5)
    for name in ("t", "x", "v", "drive_force"):
        assert np.array_equal(getattr(one, name), getattr(two, name)), name
    assert np.array_equal(truth_one["slip_index"], truth_two["slip_index"])
    other, truth_other = synthetic_stick_slip(noise=0.2, seed=6)
    assert not np.array_equal(truth_one["slip_index"], truth_other["slip_index"])
    default, truth_default = synthetic_stick_slip()
    zero, truth_zero = synthetic_stick_slip(seed=0)
    assert np.array_equal(default.v, zero.v) and np.array_equal(truth_default["end_index"], truth_zero["end_index"])


def test_synthetic_noise_has_the_documented_level():
    """noise = 0.5 adds N(0, 0.5 V) to v and N(0, 0.5 k V dt) to the force. The clean v is the
    x increments over dt (x integrates the clean v) and the clean force k (V t - x). Over
    ~9,000 samples the sample std is within 3 % of sigma (its relative error is
    1/sqrt(2 n) = 0.75 %) and the mean within 5 sigma/sqrt(n) of 0."""
    result, _ = synthetic_stick_slip(n_events=60, noise=0.5, seed=12)
    scene = result.scene
    V, k, dt = scene.drive.velocity, scene.drive.stiffness, result.meta["dt"]
    n = len(result.t) - 1
    dv = result.v[1:] - np.diff(result.x) / dt
    df = result.drive_force - k * (V * result.t - result.x)
    assert n > 8000
    for residual, sigma in ((dv, 0.5 * V), (df, 0.5 * k * V * dt)):
        assert np.std(residual) == pytest.approx(sigma, rel=0.03)
        assert abs(np.mean(residual)) < 5 * sigma / math.sqrt(n)


def test_synthetic_series_uses_the_scene_it_is_given():
    base, _ = synthetic_stick_slip(n_events=2)
    scene = dataclasses.replace(base.scene, drive=dataclasses.replace(base.scene.drive, stiffness=2.0 * base.scene.drive.stiffness,
                                                                      velocity=0.5 * base.scene.drive.velocity))
    result, _ = synthetic_stick_slip(n_events=2, scene=scene)
    assert result.scene is scene
    V, k = scene.drive.velocity, scene.drive.stiffness
    assert np.allclose(result.drive_force, k * (V * result.t - result.x), rtol=1e-12, atol=0.0)
    assert result.meta["dt"] == pytest.approx(1e-3 * scene.base / V, rel=1e-15)


# -- every force measure passes every keyword to the detector --------------------------------------

@pytest.mark.parametrize("measure", [breakaway_force, a.peak_stick_force, a.mean_stick_force])
@pytest.mark.parametrize("keyword", ["stick_speed", "slip_speed", "min_stick", "min_slip", "min_slip_distance"])
def test_each_keyword_reaches_the_detector(measure, keyword):
    """A value of each keyword under which the synthetic series (creep 0.03 V, slips peaking near
    40 V for 20 samples moving ~13 bases) has no stick-to-slip transition: the measure must
    raise for it, while it returns the default answer without it. For min_stick the series
    starts with a slip, a 50-sample stop (shorter than half a period, 55 samples) and a slip:
    by default the stop is a bounce, with min_stick = 0 a stick whose breakaway comes first."""
    result, truth = synthetic_stick_slip(n_events=3, seed=13)
    V, dt = result.scene.drive.velocity, result.meta["dt"]
    if keyword != "min_stick":
        impossible = {"stick_speed": 0.01 * V,  # below the creep: never stuck
                      "slip_speed": 100.0 * V,  # above the 40 V pulse: never slips
                      "min_slip": 1e3 * dt,  # longer than any slip
                      "min_slip_distance": 1e3 * result.scene.base}[keyword]
        assert np.isfinite(measure(result))
        # a distance threshold above every slip: the slips were seen, and the error counts them
        said = (r"^`result` has 3 stick-to-slip transition\(s\), every one moving the slider less than"
                if keyword == "min_slip_distance" else "^`result` has no stick-to-slip transition")
        with pytest.raises(a.SceneError, match=said):
            measure(result, **{keyword: impossible})
        return
    lead = np.concatenate((np.full(30, 40.0 * V), np.zeros(50), np.full(30, 40.0 * V)))
    v = np.concatenate((lead, result.v))
    dt_x = np.concatenate(([0.0], np.cumsum(v[1:] * dt)))
    t = dt * np.arange(len(v))
    k = result.scene.drive.stiffness
    force = k * (V * t - dt_x)
    force[79] = 2.0 * np.abs(force).max()  # the stop's last sample carries the largest force of the run
    zeros, lower = np.zeros(len(v)), np.zeros((2, len(v)))
    led = a.Result(t=t, x=dt_x, v=v, y=zeros, vy=zeros, drive_x=V * t, drive_force=force, normal_force=zeros,
                   friction_force=force, tangential_force=zeros, contact_count=zeros, lower_dx=lower,
                   lower_dy=lower, lower_contact=lower > 0, scene=result.scene, meta=dict(result.meta))
    default, eager = measure(led), measure(led, min_stick=0.0)
    assert eager != default
    if measure is breakaway_force:  # the stop's breakaway comes first
        assert eager == force[79]
    elif measure is a.peak_stick_force:
        assert eager == force[79] > default
    else:
        assert eager == pytest.approx((force[79] + 3 * default) / 4, rel=1e-12)


# -- the detector's rules at their boundaries, on series with exact (dyadic) numbers --------------

def plain(v, force=None, drive="force"):
    """Samples 1 s apart with slider velocity ``v`` (m/s, dyadic so every sum below is exact),
    x the running sum of v[1:] (x[i] - x[i-1] = v[i]); on a constant-force drive (no drive
    velocity: every threshold is given) unless ``drive="spring"``."""
    v = np.asarray(v, dtype=float)
    n = len(v)
    t = np.arange(n, dtype=float)
    x = np.concatenate(([0.0], np.cumsum(v[1:])))
    force = -x if force is None else np.asarray(force, dtype=float)
    zeros, lower = np.zeros(n), np.zeros((2, n))
    return a.Result(t=t, x=x, v=v, y=zeros, vy=zeros, drive_x=zeros, drive_force=force, normal_force=zeros,
                    friction_force=force, tangential_force=zeros, contact_count=zeros, lower_dx=lower, lower_dy=lower,
                    lower_contact=lower > 0, scene=a.make_scene(drive=drive, lower_count=2, upper_count=1),
                    meta={"dt": 1.0, "record_every": 1})


#: stick below 0.5 m/s, slip above 3 m/s; no duration or distance rule unless a test sets one
LOOSE = {"stick_speed": 0.5, "slip_speed": 3.0, "min_stick": 0.0, "min_slip": 0.0, "min_slip_distance": 0.0}


def test_speed_thresholds_are_strict():
    """|v| below stick_speed is stick, v above slip_speed is slip: a sample at either threshold
    is in the dead band (it keeps the previous state)."""
    assert len(stick_slip_events(plain([0] * 5 + [4] * 4 + [0] * 5), **LOOSE)) == 1
    assert stick_slip_events(plain([0] * 5 + [3] * 4 + [0] * 5), **LOOSE) == []  # v = slip_speed: not a slip
    # a stop at exactly the stick speed never sticks: the slip runs on to the end of the run
    events = stick_slip_events(plain([0] * 5 + [4] * 4 + [0.5] * 5), **LOOSE)
    assert len(events) == 1 and not events[0].complete and events[0].t_end == 13.0
    with pytest.raises(a.SceneError, match="^`slip_speed` .* must be > `stick_speed`"):
        stick_slip_events(plain([0] * 5), **{**LOOSE, "slip_speed": 0.5})


def test_the_dead_band_keeps_the_previous_state():
    """A slip dipping to 2 m/s (between the thresholds) for 3 samples stays one slip; a run
    starting in the dead band is in no state until its first stick sample."""
    events = stick_slip_events(plain([0] * 5 + [4] * 3 + [2] * 3 + [4] * 3 + [0] * 5), **LOOSE)
    assert len(events) == 1 and events[0].t_end == 14.0  # the first stick sample after the slip
    # one dead-band sample, then a 3 s stick: with min_stick = 4 s it is still the first stick
    # (nothing before it was a slip), so the slip after it is an event
    events = stick_slip_events(plain([2] + [0] * 3 + [4] * 3 + [0] * 5), **{**LOOSE, "min_stick": 4.0})
    assert len(events) == 1 and events[0].t_stick == 1.0


def test_motion_before_the_first_stick_is_not_an_event():
    """The run starts sliding (dead band, then a slip), stops for 3 samples, slips again: only
    the slip after the stop is an event; with min_stick above the 3 s stop it is a bounce and
    there is none (a later stop must follow)."""
    v = [2, 4, 4, 4, 0, 0, 0, 4, 4, 4, 0, 0, 0, 0, 0]
    events = stick_slip_events(plain(v), **LOOSE)
    assert [(e.t_stick, e.t_slip, e.t_end) for e in events] == [(4.0, 6.0, 10.0)]
    assert stick_slip_events(plain(v), **{**LOOSE, "min_stick": 3.5}) == []
    assert len(stick_slip_events(plain(v), **{**LOOSE, "min_stick": 3.0})) == 1  # not shorter than 3 s


def test_a_short_first_stick_still_counts():
    """The first stick of the run is not inside a slip: however short, the slip after it is an
    event, even when the run ends sliding."""
    events = stick_slip_events(plain([0, 0, 4, 4, 4, 0, 0, 0, 0, 0, 4, 4]), **{**LOOSE, "min_stick": 3.0})
    assert [(e.t_stick, e.t_slip, e.complete) for e in events] == [(0.0, 1.0, True), (5.0, 9.0, False)]


def test_min_stick_counts_only_the_slow_time():
    """A stop after a slip: 2 samples at rest, then 3 at exactly the stick speed (dead band,
    held as stick): 2 s slow, not 5 s. min_stick = 2 s keeps it a stick, 2.5 s makes it a
    bounce, whatever the 5 s the hysteresis holds."""
    v = [0] * 4 + [4] * 3 + [0, 0, 0.5, 0.5, 0.5] + [4] * 3 + [0] * 4
    assert len(stick_slip_events(plain(v), **{**LOOSE, "min_stick": 2.0})) == 2
    assert len(stick_slip_events(plain(v), **{**LOOSE, "min_stick": 2.5})) == 1


def test_the_slip_rules_measure_from_the_sample_before_to_the_sample_after():
    """A slip of 4 samples at 4 m/s between stick samples at 0.25 m/s: it lasts 4 s and moves
    x[b] - x[a-1] = 4 x 4 + 0.25 = 16.25 m (the sample after it included, the one before not).
    It is a slip at min_slip = 4 s and min_slip_distance = 16.25 m, noise above either."""
    v = [0.25] * 6 + [4] * 4 + [0.25] * 6
    result = plain(v)
    assert result.x[10] - result.x[5] == 16.25
    for rule, value in (("min_slip", 4.0), ("min_slip_distance", 16.25)):
        assert len(stick_slip_events(result, **{**LOOSE, rule: value})) == 1, rule
        assert stick_slip_events(result, **{**LOOSE, rule: value + 0.125}) == [], rule
    # a slip from the second sample counts from the first
    early = plain([0, 4, 4, 4, 4, 0.25, 0, 0])
    assert len(stick_slip_events(early, **{**LOOSE, "min_slip_distance": 16.25})) == 1
    assert stick_slip_events(early, **{**LOOSE, "min_slip_distance": 16.375}) == []


def test_the_last_sample_stands_for_one_sample_interval():
    """The end-of-run rule: a run [a, b) lasts t[b] - t[a], the last sample one interval more.
    A slip in the last 4 samples lasts 4 s and moves x[-1] - x[a-1] = 16 m; a stop in the last
    3 samples is 3 s slow."""
    ending_in_slip = plain([0] * 6 + [4] * 4)
    for rule, value in (("min_slip", 4.0), ("min_slip_distance", 16.0)):
        events = stick_slip_events(ending_in_slip, **{**LOOSE, rule: value})
        assert len(events) == 1 and not events[0].complete and events[0].t_end == 9.0, rule
        assert stick_slip_events(ending_in_slip, **{**LOOSE, rule: value + 0.125}) == [], rule
    ending_in_stop = plain([0] * 6 + [4] * 4 + [0] * 3)
    assert stick_slip_events(ending_in_stop, **{**LOOSE, "min_stick": 3.0})[0].complete
    assert not stick_slip_events(ending_in_stop, **{**LOOSE, "min_stick": 3.125})[0].complete


def test_a_two_sample_run_can_hold_a_slip():
    events = stick_slip_events(plain([0, 4]), **LOOSE)
    assert [(e.t_stick, e.t_slip, e.t_end, e.complete) for e in events] == [(0.0, 0.0, 1.0, False)]
    assert stick_slip_events(plain([0]), **LOOSE) == []


def test_a_noise_slip_joins_the_stick_around_it():
    """A 1-sample spike (too short for min_slip = 2 s) in a stick: the stick runs from the
    start of the run to the real slip, one stick."""
    events = stick_slip_events(plain([0] * 4 + [4] + [0] * 4 + [4] * 3 + [0] * 4), **{**LOOSE, "min_slip": 2.0})
    assert [(e.t_stick, e.t_slip, e.stick_duration) for e in events] == [(0.0, 8.0, 8.0)]


def test_the_onset_search_runs_from_the_last_slow_sample_to_the_first_fast_one():
    """Measured force (not a spring's): it keeps rising 2 samples into the slip (a lagging
    sensor). The onset is searched on [last sample not faster than the drive, first slip
    sample]: it is the first slip sample, not later; the drop is the peak minus the lowest
    force up to the re-stick sample, not after it."""
    v = [0] * 5 + [4] * 4 + [0] * 5
    force = [0, 1, 2, 3, 4, 5, 6, 7, 3, -2, -9, -50, -50, -50]
    events = stick_slip_events(plain(v, force), **LOOSE)
    assert [(e.t_slip, e.force_peak, e.force_drop, e.t_end) for e in events] == [(5.0, 5.0, 7.0, 9.0)]


def test_the_onset_is_the_last_rise_of_the_drive_force_before_the_slip():
    """A spring-driven stick interrupted by a surge: the slider creeps at 0.75 V, surges at 2 V
    for 5 samples (below the 3 V slip speed: still stuck), creeps one sample, then slips. The
    force k (V t - x) tops twice, before and after the surge; the slip starts from the second
    top, the lower one (the surge unloaded the spring by 5 k V dt)."""
    result = series([0.0] * 100 + [0.75] * 20 + [2.0] * 5 + [0.75] + [40.0] * 30 + [0.0] * 300)
    events = stick_slip_events(result)
    assert len(events) == 1
    assert sample_of(result, events[0].t_slip) == 125
    assert events[0].force_peak == pytest.approx(result.drive_force[125], rel=1e-12)
    assert result.drive_force[119] > result.drive_force[125]  # the premise: the first top is higher


def test_thresholds_given_make_any_drive_work():
    """A constant-force run has no drive velocity: with every threshold given it segments like
    a spring-driven one, and its onset search starts at the last sample below the stick speed
    (0.5 m/s). Here the slider creeps at 0.75 m/s for one sample before slipping and the force
    tops before that creep: the forced run's onset is the top (sample 4); the spring-driven
    run's drive (20 m/s) is faster than every sample before the slip, so its search starts at
    the creep sample (5)."""
    v = [0] * 5 + [0.75] + [4] * 4 + [0] * 5
    forced, sprung = stick_slip_events(plain(v), **LOOSE), stick_slip_events(plain(v, drive="spring"), **LOOSE)
    assert [(e.t_stick, e.t_end) for e in forced] == [(e.t_stick, e.t_end) for e in sprung] == [(0.0, 10.0)]
    assert plain(v).drive_force[4] > plain(v).drive_force[5]  # the premise: the force tops at 4
    assert forced[0].t_slip == 4.0 and sprung[0].t_slip == 5.0


# -- statistics and traces: remaining fields, by hand ----------------------------------------------

def test_event_statistics_slip_distance_and_time_scale():
    """The mean slip distance is over complete events only; the regularity (a coefficient of
    variation) does not depend on the time unit: events nanoseconds apart give the same number
    as events seconds apart. Zero mean interval has no regularity."""
    def ev(t_slip, distance, complete=True):
        return Event(t_stick=t_slip - 0.5, t_slip=t_slip, t_end=t_slip + 0.1, force_peak=1.0, force_drop=0.5,
                     slip_distance=distance, stick_duration=0.5, complete=complete)

    s = event_statistics([ev(1.0, 2.0), ev(2.0, 4.0), ev(4.0, 9.0, complete=False)])
    assert s["slip_distance_mean"] == pytest.approx(3.0)
    nano = event_statistics([ev(1e-9, 2.0), ev(2e-9, 4.0), ev(4e-9, 9.0)])
    assert nano["interval_mean"] == pytest.approx(1.5e-9)
    assert nano["regularity"] == pytest.approx(math.sqrt(0.5) / 1.5)
    assert math.isnan(event_statistics([ev(1.0, 2.0), ev(1.0, 2.0)])["regularity"])


def test_friction_trace_series_and_defaults():
    """Every series is the run's own, as floats; by default 40 log bins over 4 decades below
    the fastest sample, which itself is binned and the slowest at exactly 1e-4 of it is not."""
    n = 2001
    v = np.geomspace(1e-4, 1.0, n)
    base = series(np.zeros(n))
    result = dataclasses.replace(base, v=v, friction_force=3.0 - v, tangential_force=np.linspace(0.0, 1.0, n))
    tr = friction_traces(result)
    for name, key in (("t", "time"), ("v", "velocity"), ("friction_force", "friction_force"),
                      ("tangential_force", "tangential_force"), ("drive_force", "drive_force")):
        assert np.array_equal(tr[key], getattr(result, name)), key
    assert len(tr["velocity_centers"]) == 40  # 2000 samples over 40 bins: none empty
    assert tr["bin_count"].sum() == n - 1
    edges = np.geomspace(v[1], 1.0 * (1 + 1e-12), 41)
    assert np.allclose(tr["velocity_centers"], np.sqrt(edges[:-1] * edges[1:]), rtol=1e-12)


def test_friction_trace_edge_cases_of_the_binning():
    """One bin holds every moving sample (mean friction of all of them); two moving samples are
    enough for a curve; sliding at one speed has no friction-velocity curve (no range to bin)."""
    base = series(np.zeros(6))
    v = np.array([0.0, 1.0, 2.0, 4.0, 12.0, 16.0])
    one = friction_traces(dataclasses.replace(base, v=v, friction_force=v + 1.0), bins=1, dynamic_range=1.5)
    assert one["bin_count"].tolist() == [2]  # only 12 and 16 are above 16 / 1.5
    assert one["friction_mean"].tolist() == [15.0]
    assert np.allclose(one["velocity_centers"], [math.sqrt(12.0 * 16.0)], rtol=1e-9)
    two = friction_traces(dataclasses.replace(base, v=np.array([0.0, 0, 0, 0, 3.0, 12.0]), friction_force=np.ones(6)),
                          bins=2, dynamic_range=10.0)
    assert two["bin_count"].tolist() == [1, 1]
    assert np.allclose(two["velocity_centers"], [3.0 * math.sqrt(2), 6.0 * math.sqrt(2)], rtol=1e-9)
    flat = friction_traces(dataclasses.replace(base, v=np.array([0.0, 5, 5, 5, 5, 5])), bins=3)
    assert len(flat["velocity_centers"]) == len(flat["friction_mean"]) == len(flat["bin_count"]) == 0
    assert flat["bin_count"].dtype.kind == "i"  # counts, even when there are none


def test_too_few_events_give_nan_quietly():
    """No events, or one: the means and spreads that need more are NaN by design, without
    NumPy's empty-slice or degrees-of-freedom warnings (run with warnings as errors)."""
    one = Event(t_stick=0.0, t_slip=1.0, t_end=2.0, force_peak=1.0, force_drop=0.5, slip_distance=2.0,
                stick_duration=1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        empty, single = event_statistics([]), event_statistics([one])
    assert empty["count"] == 0 and all(math.isnan(empty[k]) for k in empty if k != "count")
    assert single["force_drop_mean"] == 0.5 and single["slip_distance_mean"] == 2.0
    assert all(math.isnan(single[k]) for k in ("force_drop_std", "stick_duration_std", "interval_mean", "regularity"))


def test_force_measures_name_the_result_they_cannot_use():
    forced = dataclasses.replace(synthetic_stick_slip(n_events=1)[0],
                                 scene=a.make_scene(drive="force", lower_count=2, upper_count=1))
    for measure in (breakaway_force, a.peak_stick_force, a.mean_stick_force):
        with pytest.raises(a.SceneError, match=r'^`result` must come from a spring-driven run \(drive="spring"\)$'):
            measure(forced)


# -- a flat block's stick-slip on a spring drive (the hold-rule peak), slips far below a base -------
#: A 3 mN flat block, mu 0.5 / 0.35, on a 37.2 kN/m drive spring at 5 m/s: slips of ~31 nm (0.03 of
#: a base), which a fixed 0.1-base threshold did not see.
DEN_HARTOG = dict(profile="flat", height=0.25e-6, lower_count=1, upper_count=1, track="free",
                  mu_static=0.5, mu_kinetic=0.35, normal_load=3e-3, drive="spring",
                  drive_stiffness=37.2e3, drive_velocity=5.0)


@pytest.fixture(scope="module")
def den_hartog_run():
    return a.simulate(a.make_scene(**DEN_HARTOG), 1e-7, record_every=1, progress=False)


def test_den_hartog_stick_slip_is_found_with_its_closed_form(den_hartog_run):
    """Closed form (the spring-driven block with this model's hold rule, mu_s > mu_k): the stuck
    contact holds mu_s N until it has slid its slip distance (1 nm, 0.001 base); the spring force
    keeps rising until the slider catches up with the drive, which happens 0.57 V / omega = 0.8 nm
    into the slip, so the peak is the hold rule's mu_s N + V sqrt(k m) (not Den Hartog's classical
    mu_k N + sqrt((dmu N)^2 + k m V^2), which switches at once); the slip then swings about the
    kinetic level, a drop of 2 (F_peak - mu_k N) less the hold's last 0.2 nm.
    1e-7 s holds 15 cycles."""
    scene, r = den_hartog_run.scene, den_hartog_run
    N, k, m, V = 3e-3, 37.2e3, scene.slider.mass, 5.0
    peak = 0.5 * N + V * math.sqrt(k * m)
    events = stick_slip_events(r)
    assert len(events) == 15 and all(e.complete for e in events[:-1])
    # The default threshold follows the scene: a tenth of the spring's stretch over a slip
    assert a.analysis.slip_scale(scene) == pytest.approx(2 * (peak - 0.35 * N) / k, rel=1e-12)
    assert all(e.slip_distance > 10 * a.analysis.slip_scale(scene) * 0.1 for e in events)
    peaks = np.array([e.force_peak for e in events]) / peak - 1
    drops = np.array([e.force_drop / (2 * (e.force_peak - 0.35 * N)) for e in events if e.complete]) - 1
    # The first cycles start from the settled block and carry a transient that halves every cycle
    # (measured -0.48 %, +0.24 %, -0.13 %, ...): every peak within 0.6 %, every drop within 1 %.
    assert np.abs(peaks).max() < 6e-3 and np.abs(drops).max() < 1e-2
    # Once it has decayed (the last 8 cycles) the closed form holds to 1e-4 (peak, sampled every
    # step: the sampling error V sqrt(k m) (1 - cos(omega dt / 2)) is 1e-7 of it) and 1e-3 (drop,
    # measured -4.8e-4: the first nanometre of each slip still at mu_s)
    assert np.abs(peaks[-8:]).max() < 1e-4 and np.abs(drops[-8:]).max() < 1e-3
    # The general closed form (spring_block_slip) gives the same peak and the drop less the hold's
    # last 0.2 nm: the measured -4.8e-4 above is that, so against it the drops hold to 5e-4 of it
    cycle = a.analysis.scene_slip(scene)  # the general closed form agrees with both limits here
    assert cycle.release_phase > math.pi / 2 and cycle.peak_force == pytest.approx(peak, rel=1e-12)
    assert np.abs(np.array([e.force_drop for e in events[-8:-1]]) / cycle.force_drop - 1).max() < 5e-4


def test_slips_below_the_threshold_are_counted_in_the_error(den_hartog_run):
    """A run whose slips are all shorter than the threshold says so, with the number seen; it does
    not say the slider never broke away."""
    with pytest.raises(a.SceneError, match=r"has 15 stick-to-slip transition\(s\), every one moving the "
                                           r"slider less than `min_slip_distance` = 1e-07 m"):
        breakaway_force(den_hartog_run, min_slip_distance=1e-7)
    with pytest.raises(a.SceneError, match="has 15 stick-to-slip"):
        a.peak_stick_force(den_hartog_run, min_slip_distance=1e-7)


# -- the closed form itself, against a direct integration of the same block ---------------------
def _integrated_cycle(k, m, V, Fs, Fk, d):
    """One cycle of the spring-driven block integrated numerically (SciPy, rtol 1e-11): from rest
    at the breakaway (spring force Fs), held at Fs until it has slid ``d``, then at Fk until it is
    at rest again. Returns the peak and lowest force, the peak speed and the re-stick force."""
    from scipy.integrate import solve_ivp

    def rhs(friction):
        return lambda t, s: [s[1], (Fs + k * (V * t - s[0]) - friction) / m]  # x, v; spring from Fs

    omega = math.sqrt(k / m)
    dense = dict(rtol=1e-11, atol=1e-22, max_step=0.01 / omega, dense_output=True)
    if d > 0:
        held = lambda t, s: s[0] - d  # noqa: E731
        held.terminal = True
        one = solve_ivp(rhs(Fs), (0, 2 * math.pi / omega), [0.0, 0.0], events=held, **dense)
        t1, (x1, v1) = one.t[-1], one.y[:, -1]
    else:
        one, t1, x1, v1 = None, 0.0, 0.0, 0.0
    rest = lambda t, s: s[1]  # noqa: E731
    rest.terminal, rest.direction = True, -1
    two = solve_ivp(lambda t, s: rhs(Fk)(t + t1, s), (0, 20 / omega), [x1, v1], events=rest, **dense)
    ts = [(one, np.linspace(0, t1, 4001), 0.0)] if one is not None else []
    ts.append((two, np.linspace(0, two.t[-1], 40001), t1))
    force = np.concatenate([Fs + k * (V * (t + t0) - sol.sol(t)[0]) for sol, t, t0 in ts])
    speed = np.concatenate([sol.sol(t)[1] for sol, t, _ in ts])
    return force.max(), force.min(), speed.max(), force[-1]


@pytest.mark.parametrize("hold", [0.0, 0.2e-9, 1e-9, 3e-9, 5e-9])
@pytest.mark.parametrize("gap", [0.01, 0.15])
def test_the_closed_form_cycle_is_the_integrated_one(hold, gap):
    """The closed form (release phase, amplitude, peak, drop, re-stick) against the same block
    integrated numerically, across the classical switch (hold 0), a release before the force's
    peak (0.2 nm: omega d / V = 0.14), after it (1 and 3 nm) and after half a swing (5 nm: omega
    d / V = 3.6, theta = 3.37 > pi, the hold has carried the block at 2 V already): to 1e-6 of
    the force scale (the integration's sampling of the peaks at 1e-4 of a period costs under
    1e-8)."""
    k, m, V, N = 37.2e3, 2.88e-15, 5.0, 3e-3
    Fk, Fs = 0.35 * N, (0.35 + gap) * N
    cycle = a.analysis.spring_block_slip(stiffness=k, mass=m, velocity=V, static_force=Fs, kinetic_force=Fk,
                                         hold_distance=hold)
    top, low, fastest, restick = _integrated_cycle(k, m, V, Fs, Fk, hold)
    scale = Fs - Fk + V * math.sqrt(k * m)
    assert abs(cycle.peak_force - top) < 1e-6 * scale
    assert abs(cycle.force_drop - (top - low)) < 1e-6 * scale
    assert abs(cycle.restick_force - restick) < 1e-6 * scale
    assert cycle.peak_speed == pytest.approx(fastest, rel=1e-6)
    if hold == 0.0:  # the classical limit: Den Hartog's instant switch
        assert cycle.peak_force == pytest.approx(Fk + math.hypot(Fs - Fk, V * math.sqrt(k * m)), rel=1e-12)
        assert cycle.force_drop == pytest.approx(2 * math.hypot(Fs - Fk, V * math.sqrt(k * m)), rel=1e-12)
    if math.sqrt(k / m) * hold / V >= math.pi / 2 - 1:  # the hold rule's limit
        assert cycle.peak_force == pytest.approx(Fs + V * math.sqrt(k * m), rel=1e-12)


def test_a_late_release_with_a_small_gap_never_sticks_again():
    """An 8 nm hold (theta = 4.75: released near the end of a swing, the block almost at rest) with
    a 0.01 gap leaves an amplitude under V sqrt(k m): the block slides on about V and never comes
    back to rest. The closed form says so (no re-stick, an endless slip) and the integration
    agrees (its speed stays above 0.5 V for 20 periods after the release)."""
    k, m, V, N = 37.2e3, 2.88e-15, 5.0, 3e-3
    cycle = a.analysis.spring_block_slip(stiffness=k, mass=m, velocity=V, static_force=0.36 * N,
                                         kinetic_force=0.35 * N, hold_distance=8e-9)
    assert cycle.released and cycle.release_phase > math.pi
    assert math.isnan(cycle.restick_force) and math.isnan(cycle.stick_duration) and cycle.slip_duration == math.inf
    assert cycle.peak_speed == 2 * V  # the hold's own swing
    from scipy.integrate import solve_ivp

    omega, theta = math.sqrt(k / m), cycle.release_phase
    x1, v1 = V * (theta - math.sin(theta)) / omega, V * (1 - math.cos(theta))
    Fs, Fk = 0.36 * N, 0.35 * N
    t1 = theta / omega
    after = solve_ivp(lambda t, s: [s[1], (Fs + k * (V * (t + t1) - s[0]) - Fk) / m], (0, 40 * math.pi / omega),
                      [x1, v1], rtol=1e-10, atol=1e-22, max_step=0.01 / omega)
    assert after.y[1].min() > 0.5 * V


def test_the_closed_form_refuses_bad_values():
    good = dict(stiffness=1.0, mass=1.0, velocity=1.0, static_force=2.0, kinetic_force=1.0)
    for name, bad in (("stiffness", 0.0), ("mass", -1.0), ("velocity", math.nan), ("hold_distance", -1e-9)):
        with pytest.raises(a.SceneError, match=f"^`{name}` must be a finite number"):
            a.analysis.spring_block_slip(**{**good, name: bad})
    with pytest.raises(a.SceneError, match="^`static_force` .* must be >= `kinetic_force`"):
        a.analysis.spring_block_slip(**{**good, "static_force": 0.5})


# -- the slip threshold follows the scene: every slip the closed form makes is found ---------------
#: The flat block above with its static/kinetic gap, drive stiffness and drive speed varied.
BLOCK = dict(profile="flat", height=0.25e-6, lower_count=1, upper_count=1, track="free", mu_kinetic=0.35,
             normal_load=3e-3, drive="spring")
K, V0 = 37.2e3, 5.0


def block_events(mu_static, stiffness_factor, speed_factor, cycles=12):
    """The flat block run for its first breakaway (from F = 0: mu_s N / (k V)) plus ``cycles`` + 1/2
    closed-form periods (fewer where that would carry it past 0.45 um: its face leaves the lower
    block's at 0.7 um):
    the scene, its closed-form cycle, the events and the number of slips the closed form makes."""
    scene = a.make_scene(**BLOCK, mu_static=mu_static, drive_stiffness=K * stiffness_factor,
                         drive_velocity=V0 * speed_factor)
    cycle = a.analysis.scene_slip(scene)
    V, k = scene.drive.velocity, scene.drive.stiffness
    n = max(1, min(cycles, int(0.45e-6 / (V * cycle.period))))
    result = a.simulate(scene, mu_static * 3e-3 / (k * V) + (n + 0.5) * cycle.period, record_every=1,
                        progress=False)
    assert result.drive_force[0] == 0.0  # the premise of the first breakaway's time
    assert result.status == "duration"  # on the lower block all along
    return scene, cycle, stick_slip_events(result), n + 1, result


def test_the_small_gap_of_the_issue_is_seen_whole():
    """mu 0.36 / 0.35 (the test block otherwise): every slip peaks at 2.5-2.7 V (closed form 2.58 V),
    under the old fixed 3 V, so none was found. The threshold from the scene is 2.29 V: all 13
    are found, their peaks within 0.5 % of the closed form (the start's transient: -0.33 % at
    most, measured) and within 0.1 % once it has decayed (last 4), their drops within 8 % (a small
    difference of two forces: 4 %, -2.8 %, ... -6.6 % in the first cycles) and 3 % after."""
    scene, cycle, events, expected, result = block_events(0.36, 1, 1)
    V = scene.drive.velocity
    assert a.analysis.slip_speed_threshold(scene) == pytest.approx(2.288 * V, rel=1e-3)
    assert cycle.peak_speed == pytest.approx(2.576 * V, rel=1e-3)
    assert 2.4 * V < result.v.max() < 3 * V  # the premise: the old 3 V saw none of them
    assert stick_slip_events(result, slip_speed=3 * V) == []
    assert len(events) == expected == 13
    peaks = np.array([e.force_peak for e in events]) / cycle.peak_force - 1
    drops = np.array([e.force_drop for e in events if e.complete]) / cycle.force_drop - 1
    assert np.abs(peaks).max() < 5e-3 and np.abs(peaks[-4:]).max() < 1e-3
    assert np.abs(drops).max() < 0.08 and np.abs(drops[-3:]).max() < 0.03


#: The grid: static/kinetic gaps 0.36 .. 0.5 over 0.35, drive stiffness and speed x0.2 .. x5.
GRID = [(mu, kf, vf) for mu in (0.36, 0.4, 0.5) for kf in (0.2, 1.0, 5.0) for vf in (0.2, 1.0, 5.0)]
#: A corner of each regime that runs in about a second: the release after the force's peak
#: (hold rule), before it (near the classical switch: x0.2 stiffness at x5 speed), both gaps' ends.
QUICK = [(0.5, 5.0, 5.0), (0.4, 0.2, 5.0), (0.5, 1.0, 5.0), (0.4, 5.0, 1.0)]


def _check_block(mu, kf, vf):
    """Count, peaks and drops of one grid point against the closed form.

    Where the closed form's peak speed is at least 0.1 V above the threshold, every slip is found
    (0.1 V: the start's transient lifts the first peaks by up to 0.11 V, measured at 0.36 / 0.35);
    a slip whose peak is under the threshold's floor (2.25 V) cannot be told by speed from the
    no-drop swing's transient and is not counted (the docstring of ``slip_speed_threshold`` says
    so); in between the grid point says nothing. Every peak within 1 %: the start's transient and
    the step, which releases the hold at the first step past its 1 nm (omega dt = 2 pi / 50 of
    release phase, up to 0.7 % of the peak where the release comes before the force's top;
    measured up to 0.87 % over the grid); their mean within 0.3 % (measured up to 0.26 %).
    Drops, a difference of two forces, each within 7 % (measured up to 6.6 %, the first cycles of
    0.36 / 0.35) and on average within 2 % (measured 1.6 %)."""
    scene, cycle, events, expected, _ = block_events(mu, kf, vf)
    V = scene.drive.velocity
    threshold = a.analysis.slip_speed_threshold(scene)
    if cycle.peak_speed < threshold:
        assert len(events) <= 1, (mu, kf, vf)
        return "below"
    if cycle.peak_speed < threshold + 0.1 * V:
        return "edge"
    assert len(events) == expected, (mu, kf, vf, len(events), expected)
    peaks = np.array([e.force_peak for e in events]) / cycle.peak_force - 1
    drops = np.array([e.force_drop for e in events if e.complete]) / cycle.force_drop - 1
    assert np.abs(peaks).max() < 1e-2 and abs(peaks.mean()) < 3e-3, (mu, kf, vf, peaks)
    assert np.abs(drops).max() < 7e-2 and abs(drops.mean()) < 2e-2, (mu, kf, vf, drops)
    return "found"


@pytest.mark.parametrize("mu,kf,vf", QUICK)
def test_every_slip_the_closed_form_makes_is_found(mu, kf, vf):
    assert _check_block(mu, kf, vf) == "found"


@pytest.mark.slow
@pytest.mark.parametrize("mu,kf,vf", [g for g in GRID if g[1:] != (5.0, 0.2)])
def test_every_slip_the_closed_form_makes_is_found_over_the_grid(mu, kf, vf):
    """The whole grid (about 2.5 CPU-minutes), less x5 stiffness at x0.2 speed, where omega d / V =
    8 > 2 pi: the hold outlasts a swing and the model releases it after several (its count of slip
    runs on while the swing stays above the contact's stick speed), which the closed form does
    not describe."""
    assert _check_block(mu, kf, vf) in ("found", "below", "edge")


@pytest.mark.parametrize("kf,vf", [(1.0, 1.0), (0.2, 5.0), (5.0, 5.0)])
def test_steady_sliding_makes_no_slip(kf, vf):
    """mu_s = mu_k: no friction drop, the block swings on the drive spring from rest to 2 V (the
    start's transient: up to 2.18 V, measured): no event, whatever the stiffness and speed."""
    scene, cycle, events, _, result = block_events(0.35, kf, vf, cycles=6)
    assert cycle.peak_speed == pytest.approx(2 * scene.drive.velocity, rel=1e-12)
    assert result.v.max() > 1.9 * scene.drive.velocity  # the premise: it does swing
    assert events == []
