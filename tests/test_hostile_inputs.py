"""Inputs that took the process down or passed unnoticed, each now one clear line naming the
parameter or file (a review and a fuzzing round found them; kept here so they stay found).

Files: an archive whose headers promise more than the inflation limit, lower arrays of the wrong
row count, a null scene record, time running backwards, negative contact counts, a 5,000-deep
TOML; writes that fail on a full disk; tolerances below what a float resolves; bytes given as a
path; a profile with subnormal steps; a belt chain given to the asperity analysis; a scheduler
that is not an address.
"""

from __future__ import annotations

import io
import json
import os
import time
import zipfile

import numpy as np
import pytest

import asperity2d as a
from asperity2d import belt
from asperity2d._io import MAX_INFLATED_BYTES, FileError, save_npz
from asperity2d.cli import main


@pytest.fixture(scope="module")
def run():
    scene = a.make_scene(lower_count=3, upper_count=1)
    return a.simulate(scene, duration=scene.shortest_period() * 20, record_every=20)


@pytest.fixture(scope="module")
def chain():
    return belt.simulate_chain(masses=[1.0, 1.0], springs=[10.0] * 3, dampers=[0.0] * 3, mu_s=0.2, v_belt=0.1,
                               x0=[0.0, 0.0], v0=[0.0, 0.0], t_end=3.0, n_samples=60)


def _rewrite(source, target, change):
    with np.load(source) as data:
        arrays = {k: data[k] for k in data.files if k != "metadata"}
        meta = json.loads(str(data["metadata"]))
    change(meta, arrays)
    return save_npz(target, arrays, meta)


# -- files ------------------------------------------------------------------------------------
def test_an_archive_that_would_inflate_past_the_limit_is_refused_from_its_headers(tmp_path):
    """A 1.5 MB file of zeros inflating to 1.5 GB: refused before any member is inflated. The
    zip headers are read, not the data: the bomb below is written as stored zeros of 1.1 GiB
    claimed in its header, and read in well under a second."""
    path = tmp_path / "bomb.npz"
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as archive:
        with archive.open("x.npy", "w", force_zip64=True) as fh:
            shape = (2, (MAX_INFLATED_BYTES // 16) + 8)
            np.lib.format.write_array_header_1_0(fh, {"descr": "<f8", "fortran_order": False, "shape": shape})
            chunk = bytes(2**24)
            left = 16 * shape[1]
            while left > 0:
                fh.write(chunk[:left])
                left -= len(chunk)
        for name in ("t", "metadata"):
            buf = io.BytesIO()
            np.save(buf, np.zeros(3) if name == "t" else np.array(json.dumps({"chain": {}})))
            archive.writestr(f"{name}.npy", buf.getvalue())
    assert path.stat().st_size < 5e6
    import tracemalloc

    tracemalloc.start()
    start = time.perf_counter()
    try:
        with pytest.raises(FileError, match=r"`path` is too large to load as .* inflate to 10\d\d MiB, more than "
                                            r"the limit of 1024 MiB"):
            a.load(path)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 50e6 and time.perf_counter() - start < 5


def test_lower_arrays_of_the_wrong_row_count_are_refused_when_loaded(tmp_path, run):
    bad = _rewrite(run.save(tmp_path / "r.npz"), tmp_path / "bad.npz",
                   lambda m, arr: [arr.update({k: arr[k][:-1]}) for k in ("lower_dx", "lower_dy", "lower_contact")])
    with pytest.raises(FileError, match=r"its lower arrays have \[2\] rows for the scene's 3 lower asperities"):
        a.load(bad)
    assert main(["render", str(bad), "-o", str(tmp_path / "bad.gif")]) == 2


@pytest.mark.parametrize("record", [None, "x", 3, [], {}, {"type": "Slider"}, {"type": "Scene"}])
def test_a_scene_record_that_is_not_a_scene_is_refused(tmp_path, run, record):
    bad = _rewrite(run.save(tmp_path / "r.npz"), tmp_path / "bad.npz", lambda m, arr: m.update(scene=record))
    # {"type": "Scene"} is the default scene, valid, whose 16 lower asperities do not fit the arrays
    detail = "its lower arrays have" if record == {"type": "Scene"} else "its scene record is invalid: `scene`"
    with pytest.raises(FileError, match=detail):
        a.load(bad)


def test_time_running_backwards_and_negative_counts_are_refused(tmp_path, run, chain):
    for result, change, detail in [
        (chain, lambda m, arr: arr.update(t=arr["t"][::-1].copy()), "its time runs backwards"),
        (run, lambda m, arr: arr.update(t=arr["t"][::-1].copy()), "its time runs backwards"),
        (run, lambda m, arr: arr.update(contact_count=arr["contact_count"] - 5), "negative or fractional counts"),
        (chain, lambda m, arr: arr.update(state=arr["state"] + 7), "array 'state' holds values other than"),
    ]:
        bad = _rewrite(result.save(tmp_path / "r.npz"), tmp_path / "bad.npz", change)
        with pytest.raises(FileError, match=detail):
            a.load(bad)


@pytest.mark.parametrize("deep", ["[" * 5000 + "]" * 5000, "{a = " * 5000 + "1" + "}" * 5000])
def test_a_toml_nested_thousands_deep_is_one_line(tmp_path, capsys, deep):
    path = tmp_path / "deep.toml"
    path.write_text(f"lower_count = {deep}\n")
    assert main(["run", str(path), "--duration", "1e-9"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "is nested too deeply" in err and str(path) in err
    assert main(["belt", str(path)]) == 2
    assert "is nested too deeply" in capsys.readouterr().err


# -- writes -------------------------------------------------------------------------------------
@pytest.mark.parametrize("what", ["save", "render", "export"])
def test_a_full_disk_is_a_file_error_and_nothing_is_left_half_written(tmp_path, monkeypatch, run, what):
    target = tmp_path / {"save": "r.npz", "render": "r.png", "export": "r.csv"}[what]
    target.write_bytes(b"the old file")

    def full(fd):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "fsync", full)
    write = {"save": run.save, "render": lambda p: a.render(run, p), "export": run.export}[what]
    with pytest.raises(FileError, match=r"`path` could not be written: .* \(No space left on device; the file"):
        write(target)
    assert target.read_bytes() == b"the old file"
    assert [p.name for p in tmp_path.iterdir()] == [target.name]  # no temporary file left


# -- parameters -----------------------------------------------------------------------------------
def test_a_tolerance_below_what_a_float_resolves_is_refused_at_once(tmp_path, capsys):
    scene = a.make_scene(lower_count=3, upper_count=1)
    start = time.perf_counter()
    for rel_tol in (1e-300, 1e-17, 0.0, -1.0, 1.0, float("nan")):
        with pytest.raises(a.SceneError, match="`rel_tol` must be"):
            a.critical_force(scene, rel_tol=rel_tol)
    with pytest.raises(a.SceneError, match=r"`rel_tol` = 1e-15 needs at least 50 runs to bisect, more than `max_runs` = 20"):
        a.critical_force(scene, rel_tol=1e-15, max_runs=20)
    assert time.perf_counter() - start < 2  # refused before any run (80 runs took 400 s)
    path = tmp_path / "s.toml"
    path.write_text("lower_count = 3\nupper_count = 1\n")
    assert main(["critical", str(path), "--rel-tol=1e-300"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--rel-tol" in err and "a float resolves relative differences" in err
    from asperity2d.dynamics.cycles import detect_period

    with pytest.raises(a.SceneError, match="`rtol` must be >= 8.9e-16"):
        detect_period(np.zeros((4, 1)), rtol=1e-300)


def test_bytes_given_as_a_profile_path_name_the_parameter():
    from asperity2d.surface.read import read_profile

    with pytest.raises(a.SceneError, match="`path` must be a file name .* got bytes"):
        read_profile(b"0 1\n1 2\n2 3\n")


def test_a_profile_with_subnormal_steps_names_x():
    from asperity2d.surface.profile import SurfaceProfile

    z = np.random.default_rng(0).normal(size=16) * 1e-7
    with pytest.raises(a.SceneError, match="`x` steps must be at least 1e-15 m"):
        SurfaceProfile(np.arange(16) * 5e-324, z)
    SurfaceProfile(np.arange(16) * 1e-9, z).detrended()  # a nanometre step is an instrument's


@pytest.mark.parametrize("analysis", ["stick_slip_events", "breakaway_force", "peak_stick_force", "friction_traces"])
def test_the_asperity_analysis_of_a_belt_chain_names_the_result(chain, analysis):
    with pytest.raises(a.SceneError, match="`result` must"):
        getattr(a, analysis)(chain)


def test_compare_refuses_a_bad_scheduler_before_any_progress_line(capsys):
    code = main(["compare", "--scheduler", "notaurl", "--seeds", "2", "--set", "lower_count=3"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "`scheduler` must be 'local' or a Dask scheduler address" in err
    with pytest.raises(a.SceneError, match="`scheduler`"):
        a.compare("critical", {"regular": {}}, range(2), scheduler="notaurl", progress=True)
    assert "compare:" not in capsys.readouterr().err


def test_dask_exception_logs_are_one_line():
    """A killed Dask worker makes the scheduler and its peers log CommClosedError tracebacks;
    while a Dask executor is open (and in the workers it starts) they are one line each."""
    import logging

    from asperity2d.sweep.executors import quiet_tracebacks

    stream = io.StringIO()
    handler = logging.StreamHandler(stream)
    logger = logging.getLogger("distributed.test_hostile")
    parent = logging.getLogger("distributed")
    parent.addHandler(handler)
    try:
        undo = quiet_tracebacks()
        try:
            raise ConnectionResetError("Stream is closed")
        except OSError:
            logger.exception("Exception while handling op")
        undo()
        try:
            raise ConnectionResetError("again")
        except OSError:
            logger.exception("after")
    finally:
        parent.removeHandler(handler)
    first, rest = stream.getvalue().split("after", 1)
    assert first == "Exception while handling op (ConnectionResetError: Stream is closed)\n"
    assert "Traceback" in rest  # the filter is taken off again
    # a user's own records keep their tracebacks, even while the filter is on
    user = logging.getLogger("my_study")
    mine = io.StringIO()
    root_handler = logging.StreamHandler(mine)
    logging.getLogger().addHandler(root_handler)
    undo = quiet_tracebacks()
    try:
        try:
            raise ValueError("mine")
        except ValueError:
            user.exception("my run failed")
    finally:
        undo()
        logging.getLogger().removeHandler(root_handler)
    assert "Traceback" in mine.getvalue()


def test_compare_reaches_a_cluster_before_any_progress_line(capsys):
    code = main(["compare", "--scheduler", "tcp://127.0.0.1:1", "--seeds", "2", "--set", "lower_count=3"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "could not be reached within" in err and "compare:" not in err
