"""analysis.contact_states: the asperity runs' separated / sliding / sticking states, on a hand-made run."""

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
