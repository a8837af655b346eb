"""analysis.contact_states: the asperity runs' separated / sliding / sticking states, on a hand-made run."""

import dataclasses
import math

import numpy as np
import pytest

from asperity2d import SceneError, make_scene
from asperity2d.analysis import contact_states
from asperity2d.result import Result


def _run(track="fixed"):
    """Ten samples 1 s apart whose states are known.

    contact:  1 1 0 0 1 1 1 0 1 1   (two airborne intervals, both between contacts: 2 hops)
    |v|:      0 5 5 5 0 0 5 5 5 0   (stick speed 1 m/s)
    touching: 1 2 0 0 1 3 1 0 2 2   (lower asperities in contact)
    Each sample stands for the second after it (the last for none): 9 s in all, of which
    3 s separated (samples 2, 3, 7), 3 s sliding (1, 6, 8), 3 s sticking (0, 4, 5).
    """
    scene = make_scene(lower_count=4, upper_count=1, track=track)
    t = np.arange(10.0)
    contact = np.array([1, 1, 0, 0, 1, 1, 1, 0, 1, 1])
    v = np.array([0, 5, 5, 5, 0, 0, 5, 5, 5, 0], dtype=float)
    touching = np.array([1, 2, 0, 0, 1, 3, 1, 0, 2, 2])
    lower = np.zeros((4, 10), dtype=bool)
    for k, count in enumerate(touching):
        lower[:count, k] = True
    tips = scene.lower.tips()
    span = tips.max() - tips.min()
    x = np.linspace(0.0, 1.5 * span, 10)  # one and a half passes over the lower tips
    zeros = np.zeros(10)
    return Result(t=t, x=x, v=v, y=zeros, vy=zeros, drive_x=zeros, drive_force=zeros, normal_force=zeros,
                  friction_force=zeros, tangential_force=zeros, contact_count=contact.astype(float),
                  lower_dx=np.zeros((4, 10)), lower_dy=np.zeros((4, 10)), lower_contact=lower, scene=scene,
                  meta={"dt": 1.0, "record_every": 1, "status": "hand-made"})


def test_contact_states_of_a_hand_made_run():
    cs = contact_states(_run(), stick_speed=1.0)
    assert cs.fractions == pytest.approx({"separated": 3 / 9, "sliding": 3 / 9, "sticking": 3 / 9}, abs=1e-15)
    assert cs.hops == 2
    assert cs.separated_intervals == [(2.0, 4.0), (7.0, 8.0)]
    assert cs.passes == pytest.approx(1.5, rel=1e-12) and cs.hops_per_pass == pytest.approx(2 / 1.5, rel=1e-12)
    assert cs.touching.tolist() == [1, 2, 0, 0, 1, 3, 1, 0, 2, 2]
    assert cs.touching_mean == pytest.approx(10 / 9, rel=1e-15)
    assert cs.lift_off == []  # the fixed track cannot lift off
    assert cs.to_dict()["touching_max"] == 3


def test_the_free_slider_reports_its_lift_offs_and_a_run_ending_airborne():
    run = _run("free")
    cs = contact_states(run, stick_speed=1.0)
    assert cs.lift_off == [(2.0, 4.0), (7.0, 8.0)]
    run.contact_count[-2:] = 0  # samples 7-9 airborne to the end: no longer a hop (contact not regained)
    cs = contact_states(run, stick_speed=1.0)
    assert cs.hops == 1 and cs.separated_intervals == [(2.0, 4.0), (7.0, 9.0)]
    assert cs.fractions["separated"] == pytest.approx(4 / 9, abs=1e-15)


def test_contact_states_default_stick_speed_is_half_the_drive_velocity():
    run = _run()
    cs = contact_states(run)
    assert cs.stick_speed == 0.5 * run.scene.drive.velocity


@pytest.mark.parametrize("bad", [0.0, -1.0, float("nan"), "fast"])
def test_contact_states_rejects_a_bad_stick_speed(bad):
    with pytest.raises(SceneError, match="`stick_speed` must be > 0"):
        contact_states(_run(), stick_speed=bad)


def test_to_dict_holds_every_field():
    cs = contact_states(_run("free"), stick_speed=1.0)
    assert cs.to_dict() == {"fractions": {"separated": 3 / 9, "sliding": 3 / 9, "sticking": 3 / 9},
                            "hops": 2, "passes": cs.passes, "hops_per_pass": cs.hops_per_pass,
                            "touching_mean": cs.touching_mean, "touching_max": 3,
                            "separated_intervals": [[2.0, 4.0], [7.0, 8.0]], "lift_off_count": 2,
                            "stick_speed": 1.0, "track": "free"}
    assert cs.passes == pytest.approx(1.5, rel=1e-12)
    assert cs.touching.dtype.kind == "i"  # counts of asperities


def test_a_speed_at_the_stick_speed_is_sliding():
    """abs(v) >= stick_speed in contact is sliding: with the stick speed at 5 m/s, samples 1, 6
    and 8 (v = 5) slide; only the resting ones (0, 4, 5) stick: 3 s each of 9."""
    cs = contact_states(_run(), stick_speed=5.0)
    assert cs.fractions == pytest.approx({"separated": 3 / 9, "sliding": 3 / 9, "sticking": 3 / 9}, abs=1e-15)
    cs = contact_states(_run(), stick_speed=5.5)  # now every contact sample is slow
    assert cs.fractions == pytest.approx({"separated": 3 / 9, "sliding": 0.0, "sticking": 6 / 9}, abs=1e-15)


def test_a_run_starting_airborne_has_no_hop_before_its_first_contact():
    run = _run()
    run.contact_count[0:2] = 0  # airborne over samples 0-3: lost before the run began, not a hop
    cs = contact_states(run, stick_speed=1.0)
    assert cs.hops == 1 and cs.separated_intervals == [(0.0, 4.0), (7.0, 8.0)]


def test_passes_count_the_travel_over_the_span_of_the_lower_tips():
    """Passes do not depend on where the run starts (only the travel counts); less than one
    pass still divides the hops; no travel gives no rate; one lower asperity has no span."""
    run = _run()
    tips = run.scene.lower.tips()
    span = tips.max() - tips.min()
    shifted = dataclasses.replace(run, x=run.x + 7.0 * span)
    assert contact_states(shifted, stick_speed=1.0).passes == pytest.approx(1.5, rel=1e-12)
    half = dataclasses.replace(run, x=run.x / 3.0)  # half a pass
    cs = contact_states(half, stick_speed=1.0)
    assert cs.passes == pytest.approx(0.5, rel=1e-12) and cs.hops_per_pass == pytest.approx(4.0, rel=1e-12)
    still = contact_states(dataclasses.replace(run, x=np.zeros(10)), stick_speed=1.0)
    assert still.passes == 0.0 and math.isnan(still.hops_per_pass)
    # the lower surface moved along x: the span, and so the passes, are the same
    scene = run.scene
    moved = dataclasses.replace(scene, lower=dataclasses.replace(
        scene.lower, spacing=dataclasses.replace(scene.lower.spacing, offset=3.0 * span)))
    assert moved.lower.tips().min() > 0  # the premise
    assert contact_states(dataclasses.replace(run, scene=moved), stick_speed=1.0).passes == pytest.approx(1.5, rel=1e-12)
    pair = make_scene(lower_count=2, upper_count=1)  # two lower asperities already have a span
    tips = pair.lower.tips()
    paired = dataclasses.replace(run, scene=pair, x=np.linspace(0.0, 2.0 * (tips.max() - tips.min()), 10),
                                 lower_dx=np.zeros((2, 10)), lower_dy=np.zeros((2, 10)), lower_contact=run.lower_contact[:2])
    assert contact_states(paired, stick_speed=1.0).passes == pytest.approx(2.0, rel=1e-12)
    lone = dataclasses.replace(run, scene=make_scene(lower_count=1, upper_count=1), lower_dx=np.zeros((1, 10)),
                               lower_dy=np.zeros((1, 10)), lower_contact=run.lower_contact[:1])
    cs = contact_states(lone, stick_speed=1.0)
    assert math.isnan(cs.passes) and math.isnan(cs.hops_per_pass)


def test_two_samples_are_enough_and_one_is_not():
    run = _run()
    two = dataclasses.replace(run, **{n: getattr(run, n)[:2] for n in ("t", "x", "v", "y", "vy", "drive_x", "drive_force",
                                                                       "normal_force", "friction_force", "tangential_force",
                                                                       "contact_count")},
                              lower_dx=run.lower_dx[:, :2], lower_dy=run.lower_dy[:, :2], lower_contact=run.lower_contact[:, :2])
    cs = contact_states(two, stick_speed=1.0)  # sample 0 (at rest, in contact) stands for the only second
    assert cs.fractions == {"separated": 0.0, "sliding": 0.0, "sticking": 1.0}
    one = dataclasses.replace(two, **{n: getattr(two, n)[:1] for n in ("t", "x", "v")})
    with pytest.raises(SceneError, match="^`result` must have at least 2 samples, got 1$"):
        contact_states(one, stick_speed=1.0)


def test_contact_states_says_what_it_needs():
    run = _run()
    forced = dataclasses.replace(run, scene=make_scene(drive="force", lower_count=4, upper_count=1))
    with pytest.raises(SceneError, match=r"^`stick_speed` must be given for a constant-force drive \(no drive velocity\)$"):
        contact_states(forced)
    bare = dataclasses.replace(run, lower_dx=np.zeros((4, 0)), lower_dy=np.zeros((4, 0)),
                               lower_contact=np.zeros((4, 0), dtype=bool))
    with pytest.raises(SceneError, match="; counting the touching asperities needs them"):
        contact_states(bare, stick_speed=1.0)
