"""Stick-slip events as a table (``asperity2d.events_table``): columns of the events' own fields, and CSV."""

import numpy as np
import pytest

import asperity2d as a
from asperity2d.analysis import EVENT_COLUMNS, synthetic_stick_slip


def test_the_table_holds_every_event_field_and_the_csv_reads_back(tmp_path):
    result = synthetic_stick_slip(n_events=5, seed=3)[0]  # a series whose true events are known
    events = a.stick_slip_events(result)
    assert len(events) >= 4
    table = a.events_table(events, tmp_path / "events.csv")
    assert tuple(table) == EVENT_COLUMNS
    for name in EVENT_COLUMNS:
        assert table[name].tolist() == [getattr(e, name) for e in events]
    assert table["complete"].dtype == bool
    back = np.genfromtxt(tmp_path / "events.csv", delimiter=",", names=True)
    assert back.dtype.names == EVENT_COLUMNS
    np.testing.assert_array_equal(back["force_peak"], table["force_peak"])  # 17 digits: to the bit
    np.testing.assert_array_equal(back["complete"].astype(bool), table["complete"])


def test_no_events_is_an_empty_table_and_bad_input_one_line(tmp_path):
    table = a.events_table([], tmp_path / "none.csv")
    assert all(v.size == 0 for v in table.values())
    assert (tmp_path / "none.csv").read_text().strip() == ",".join(EVENT_COLUMNS)
    with pytest.raises(a.SceneError, match="`events`"):
        a.events_table([1.0, 2.0])
    with pytest.raises(a.SceneError, match="`path` must end in .csv"):
        a.events_table([], tmp_path / "x.txt")
