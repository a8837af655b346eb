"""Results save and load losslessly, export cleanly and are never half-written."""

import json
import os

import numpy as np
import pytest

import asperity2d as a
from asperity2d.result import LOWER_SERIES, SERIES


@pytest.fixture(scope="module")
def result():
    return a.simulate(a.make_scene(lower_count=4, upper_count=2, spacing="random", seed=2),
                      duration=2e-8)


def test_save_load_round_trip_is_exact(result, tmp_path):
    path = result.save(tmp_path / "run.npz")
    again = a.load(path)
    for name in SERIES + LOWER_SERIES:
        assert np.array_equal(getattr(result, name), getattr(again, name), equal_nan=True), name
    assert again.scene == result.scene
    assert again.meta["pymunk_version"] and again.meta["asperity2d_version"] == a.__version__
    assert again.meta["status"] == result.status
    assert [p.name for p in tmp_path.iterdir()] == ["run.npz"]  # no temporary file left


def test_a_failed_save_leaves_the_old_file_intact(result, tmp_path, monkeypatch):
    path = result.save(tmp_path / "run.npz")
    before = path.read_bytes()

    def explode(*args, **kwargs):
        raise OSError("disk full")

    monkeypatch.setattr(np, "savez_compressed", explode)
    with pytest.raises(OSError):
        result.save(path)
    assert path.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["run.npz"]


def test_csv_and_mat_export(result, tmp_path):
    csv = result.export(tmp_path / "run.csv")
    table = np.genfromtxt(csv, delimiter=",", names=True)
    assert table.dtype.names == SERIES
    np.testing.assert_array_equal(table["drive_force"], result.drive_force)
    from scipy.io import loadmat

    mat = loadmat(result.export(tmp_path / "run.mat"))
    np.testing.assert_array_equal(mat["x"].ravel(), result.x)
    assert json.loads(str(mat["metadata"][0]))["status"] == result.status


def test_loading_garbage_is_a_scene_error(tmp_path):
    bad = tmp_path / "bad.npz"
    bad.write_bytes(os.urandom(64))
    with pytest.raises(a.SceneError, match="`path`"):
        a.load(bad)
    with pytest.raises(a.SceneError, match="`path`"):
        a.load(tmp_path / "missing.npz")
