"""The contact read-out (engine.contacts.Arbiters) on a hand-made batch read, worked by hand.

Each contact is three integers (body A id, body B id, point count) and six floats
(impulse jx jy on body A, normal nx ny, distances d1 d2; negative = overlapping).
"""

from types import SimpleNamespace

import pytest

from asperity2d.engine.contacts import Arbiters

SLIDER = 100
LAYOUT = SimpleNamespace(slider_id=SLIDER, lower_index={7: 0, 8: 1, 9: 2})
CONTACTS = (
    [SLIDER, 7, 2,   # the slider is body A: its impulse as read; two points
     8, SLIDER, 1,   # the slider is body B: the impulse on it is minus the one read; one point
     SLIDER, 9, 0],  # cached but not touching: ignored
    [1.0, 2.0, 0.6, 0.8, -0.01, -0.03,
     0.5, -1.0, 0.0, 1.0, -0.02, -0.5,  # d2 of a one-point contact is not a distance
     9.0, 9.0, 1.0, 0.0, -1.0, -1.0],
)


def test_forces_sum_the_touching_contacts_impulses_on_the_slider():
    fx, fy, ft, count, overlap = Arbiters(CONTACTS, LAYOUT).forces(dt=0.5)
    assert (fx, fy, count) == (pytest.approx((1.0 - 0.5) / 0.5), pytest.approx((2.0 + 1.0) / 0.5), 2)
    # tangential parts on the +x tangents: contact 1 (1 - 2.2 * 0.6) * 0.8 + (2 - 2.2 * 0.8) * -0.6
    # = -0.4; contact 2 (impulse (-0.5, 1) on the slider, normal (0, 1)): -0.5; resisting +x is positive
    assert ft == pytest.approx(0.9 / 0.5)
    assert overlap == 0.03


def test_the_deepest_overlap_counts_only_touching_points():
    assert Arbiters(CONTACTS, LAYOUT).max_overlap() == 0.03
    one_point = ([SLIDER, 8, 1], [0.0, 0.0, 0.0, 1.0, -0.02, -0.5])
    assert Arbiters(one_point, LAYOUT).max_overlap() == 0.02
    assert Arbiters(([], []), LAYOUT).max_overlap() == 0.0
    separated = ([SLIDER, 7, 1], [0.0, 0.0, 0.0, 1.0, 0.01, 0.0])  # positive distance: no overlap
    assert Arbiters(separated, LAYOUT).max_overlap() == 0.0


def test_pairs_and_touched_name_the_lower_asperities_in_contact():
    arbiters = Arbiters(CONTACTS, LAYOUT)
    assert arbiters.pairs() == [(0, 0.6, 0.8), (1, 0.0, 1.0)]
    assert arbiters.touched(3).tolist() == [True, True, False]
