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
    from asperity2d._io import FileError

    with pytest.raises(FileError, match="`path` could not be written: .*run.npz.* \\(disk full; the file was left"):
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


def test_mat_export_keeps_booleans_logical_and_reads_them_back_as_bool(tmp_path):
    """``lower_contact`` is a bool array: in the .mat it must be MATLAB ``logical`` (whosmat reads the
    class from the file's array flags, as MATLAB does) and ``read_mat`` must give back dtype bool with
    the same values, where ``scipy.io.loadmat`` alone gives uint8."""
    from scipy.io import loadmat, whosmat

    from asperity2d._io import FileError
    from asperity2d.result import read_mat

    result = a.simulate(a.make_scene(lower_count=4, upper_count=2))  # to the end: contacts made and broken
    assert result.lower_contact.dtype == bool and result.lower_contact.any() and not result.lower_contact.all()
    path = result.export(tmp_path / "run.mat")
    classes = {name: cls for name, _shape, cls in whosmat(path)}
    assert classes["lower_contact"] == "logical" and classes["x"] == "double"
    assert loadmat(path)["lower_contact"].dtype == np.uint8  # SciPy's reader drops the flag
    back = read_mat(path)
    assert back["lower_contact"].dtype == bool
    np.testing.assert_array_equal(back["lower_contact"], result.lower_contact)
    np.testing.assert_array_equal(back["x"].ravel(), result.x)
    assert not any(name.startswith("__") for name in back)
    (tmp_path / "bad.mat").write_bytes(os.urandom(64))
    with pytest.raises(FileError, match="`path` is not a MATLAB .mat file"):
        read_mat(tmp_path / "bad.mat")


def test_loading_garbage_is_a_scene_error(tmp_path):
    bad = tmp_path / "bad.npz"
    bad.write_bytes(os.urandom(64))
    with pytest.raises(a.SceneError, match="`path`"):
        a.load(bad)
    with pytest.raises(a.SceneError, match="`path`"):
        a.load(tmp_path / "missing.npz")


def test_the_one_json_emitter_is_strict_plain_and_exact(tmp_path):
    # NaN and infinities -> null (strict JSON: json.loads with no NaN extension reads it back),
    # NumPy scalars and arrays -> plain numbers and lists, floats at full precision
    import json
    import math

    import numpy as np

    from asperity2d._io import to_json, write_json

    value = {"nan": math.nan, "inf": np.float64(np.inf), "arr": np.array([[1.0, np.nan], [0.1, 2]]),
             "i": np.int64(3), "b": np.bool_(True), "t": (1, 2), "x": 0.1 + 0.2, "p": tmp_path}
    text = to_json(value)
    assert "NaN" not in text and "Infinity" not in text

    def strict(constant):
        raise AssertionError(f"non-strict constant {constant}")

    back = json.loads(text, parse_constant=strict)
    assert back == {"nan": None, "inf": None, "arr": [[1.0, None], [0.1, 2.0]], "i": 3, "b": True,
                    "t": [1, 2], "x": 0.30000000000000004, "p": str(tmp_path)}
    path = write_json(tmp_path / "s.json", value)
    assert json.loads(path.read_text(), parse_constant=strict) == back
