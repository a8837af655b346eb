"""Stick–slip events, breakaway force and friction traces.

Synthetic series with known events first (exact recovery, noise, bounces, no
false events), then a real short spring-driven run against the flank law.
"""

import dataclasses
import math

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
