"""What a recorded sample costs, and runs streamed to disk (simulate(..., record_to=path)).

Memory is measured with tracemalloc (NumPy reports its array buffers to it), as the peak of
traced memory during a run: the record's growth with run length is the slope of that peak
between two run lengths. The streamed record must not grow at all; a record in memory grows by
exactly its bytes per sample (written once, in SI, in blocks: no doubling array, no copy at
the end).
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import asperity2d as a
from asperity2d import streamed
from asperity2d._io import FileError
from asperity2d.engine.recorder import COLUMNS, Recorder
from asperity2d.run import Run

ARRAYS = ("t", "x", "v", "y", "vy", "drive_x", "drive_force", "normal_force", "friction_force",
          "tangential_force", "contact_count", "lower_dx", "lower_dy", "lower_contact")


def small_scene():
    return a.make_scene(lower_count=3, upper_count=1)


def steps(scene, n):
    """A duration (s) of ``n`` default steps."""
    return (n - 0.5) * scene.shortest_period() / 50


RSS_CHILD = """
import sys
import asperity2d as a
scene = a.make_scene(lower_count=30, upper_count=1)
a.simulate(scene, 1.0 * scene.shortest_period() / 50)  # every lazy import and cache: before the baseline
n, lower, to = int(sys.argv[1]), sys.argv[2] == "1", sys.argv[3] or None
a.simulate(scene, (n - 0.5) * scene.shortest_period() / 50, record_every=1, record_lower=lower, record_to=to)
# VmHWM: this process's own peak. ru_maxrss would not do: Linux carries it over execve from the
# process that spawned it (pytest's, larger than this run's in a full suite).
print(next(line.split()[1] for line in open("/proc/self/status") if line.startswith("VmHWM:")))
"""


def peak_rss(n: int, *, lower: bool = True, to=None) -> int:
    """Peak resident memory (bytes) of a fresh process that ran ``n`` steps of a 30-asperity
    scene (598 B a sample), recording every step."""
    out = subprocess.run([sys.executable, "-c", RSS_CHILD, str(n), "1" if lower else "0", str(to or "")],
                         capture_output=True, text=True, check=True)
    return 1024 * int(out.stdout.split()[-1])  # VmHWM is in kB


def assert_same(r1, r2, samples=None):
    for name in ARRAYS:
        x, y = np.asarray(getattr(r1, name)), np.asarray(getattr(r2, name))
        if samples is not None:
            x, y = x[..., :samples], y[..., :samples]
        assert x.dtype == y.dtype and x.shape == y.shape, name
        assert x.tobytes() == y.tobytes(), name  # to the bit


def test_a_sample_costs_88_bytes_for_the_slider_and_17_per_lower_asperity():
    run = Run(small_scene())
    assert len(COLUMNS) == 11
    assert Recorder(run.engine).bytes_per_sample == 88 + 17 * 3
    assert Recorder(run.engine, lower=False).bytes_per_sample == 88  # the "<= 100 B"


@pytest.mark.slow  # long runs on purpose; benchmarks/bench_long_run.py measures the same on a 1e8-step run
@pytest.mark.skipif(sys.platform != "linux", reason="/proc/self/status (VmHWM) and page accounting of Linux")
def test_resident_memory_is_flat_against_run_length_when_streamed(tmp_path):
    # steps, each recorded; the short run already fills the streamed record's one 4 MB block
    # (7,014 samples of 598 B), and its record in memory (9 MB) is above the ~3 MB the
    # process's start-up peak leaves free to reuse
    short, long = 15_000, 45_000
    streamed_growth = peak_rss(long, to=tmp_path / "long") - peak_rss(short, to=tmp_path / "short")
    memory_growth = peak_rss(long) - peak_rss(short)
    # in memory, 30,000 more samples cost 30,000 x 598 B = 17.9 MB: the measurement sees the
    # record (within 15 %: pages, allocator), so it would see one that grows
    assert 0.85 * 17.9e6 <= memory_growth <= 1.15 * 17.9e6, memory_growth
    # streamed, the same block is written out and reused in both runs; 1.5 MB allows for the
    # allocator's noise
    assert abs(streamed_growth) < 1.5e6, streamed_growth
    assert len(a.load(tmp_path / "long")) == long + 1 and len(a.load(tmp_path / "short")) == short + 1


def test_records_in_memory_are_views_of_blocks_written_once(tmp_path):
    scene = small_scene()
    r = a.simulate(scene, steps(scene, 2000), record_every=1)
    assert r.x.base is not None and not r.x.flags.writeable  # a view, read-only: shared with the run
    assert r.x.base is r.t.base  # one block holds every column: nothing was copied at the end
    slim = a.simulate(scene, steps(scene, 2000), record_every=1, record_lower=False)
    assert len(slim.t) == 2001 and not slim.lower_recorded and slim.lower_dy.shape == (3, 0)
    for name in ARRAYS[:11]:
        assert np.asarray(getattr(slim, name)).tobytes() == np.asarray(getattr(r, name)).tobytes()
    with pytest.raises(a.SceneError, match="record_lower=False"):
        a.render(slim, tmp_path / "slim.gif")
    assert not (tmp_path / "slim.gif").exists()
    # a record longer than one block is joined once, block by block, bit for bit
    run = Run(scene, record_every=1)
    for _ in range(3):
        run.advance(steps(scene, 700))
    joined = run.result()
    assert len(joined) == 2101 and joined.x.base is joined.t.base
    assert_same(joined, a.simulate(scene, steps(scene, 2100), record_every=1))


def test_a_streamed_run_keeps_its_metadata_and_its_start(tmp_path):
    scene = a.make_scene(lower_count=4, upper_count=2)
    r = a.simulate(scene, steps(scene, 3000), energy=True, record_to=tmp_path / "rec")
    again = a.load(tmp_path / "rec")
    assert "energy" in again.meta and again.meta["dt"] == r.dt and again.scene == scene
    assert_same(again, a.simulate(scene, steps(scene, 3000)))
    run = Run(scene, record_to=tmp_path / "run")
    run.advance(steps(scene, 500))
    first = run.result()
    run.advance(steps(scene, 500))
    assert len(run.result(start=len(first))) == len(run.result()) - len(first)
    assert_same(run.result(), a.load(tmp_path / "run"))


def test_streamed_records_are_refused_when_they_cannot_be_trusted(tmp_path):
    scene = small_scene()
    foreign = tmp_path / "foreign"
    foreign.mkdir()
    (foreign / "notes.txt").write_text("mine")
    with pytest.raises(a.SceneError, match="`record_to` exists and is not a streamed record"):
        a.simulate(scene, steps(scene, 100), record_to=foreign)
    assert (foreign / "notes.txt").read_text() == "mine"
    with pytest.raises(a.SceneError, match="max_steps"):  # refused before anything is written
        a.simulate(scene, steps(scene, 100), max_steps=10, record_to=tmp_path / "never")
    assert not (tmp_path / "never").exists()
    with pytest.raises(FileError, match="`path` is a directory"):
        a.load(foreign)

    path = tmp_path / "rec"
    a.simulate(scene, steps(scene, 1000), record_to=path)
    a.simulate(scene, steps(scene, 300), record_to=path)  # a record is replaced by a new one
    assert len(a.load(path)) == 31
    with open(path / "x.npy", "r+b") as fh:  # the file lost its last samples
        fh.truncate(streamed.HEADER_BYTES + 8 * 20)
    with pytest.raises(FileError, match="damaged record"):
        a.load(path)
    (path / streamed.MANIFEST).write_text("{not json")
    with pytest.raises(FileError, match="record.json is invalid"):
        a.load(path)


def test_a_run_that_raises_leaves_its_samples_saying_why(tmp_path):
    scene = small_scene()

    def boom(probe):
        if probe.t > steps(scene, 400):
            raise RuntimeError("observer gave up")

    with pytest.raises(RuntimeError, match="observer gave up"):
        a.simulate(scene, steps(scene, 2000), record_to=tmp_path / "rec", observers=[boom])
    r = a.load(tmp_path / "rec")
    assert r.status == "interrupted" and not r.success
    assert "RuntimeError: observer gave up" in r.message and len(r) == 41
    assert_same(r, a.simulate(scene, steps(scene, 2000)), samples=41)


CHILD = """
import sys
import asperity2d as a
scene = a.make_scene(lower_count=3, upper_count=1)
a.simulate(scene, 5e6 * scene.shortest_period() / 50, record_every=1, record_to=sys.argv[1],
           max_steps=10**7)
"""


def test_a_killed_run_leaves_a_readable_prefix(tmp_path):
    path = tmp_path / "rec"
    child = subprocess.Popen([sys.executable, "-c", CHILD, str(path)])
    try:
        deadline = time.monotonic() + 120
        samples = 0
        while samples < 30_000 and time.monotonic() < deadline:  # a 4 MB block committed
            time.sleep(0.2)
            try:
                samples = json.loads((path / streamed.MANIFEST).read_text())["samples"]
            except (OSError, ValueError):
                pass
        assert child.poll() is None, "the run ended before it could be killed"
        child.send_signal(signal.SIGKILL)
    finally:
        child.kill()
        child.wait()
    r = a.load(path)
    n = len(r)
    assert n >= samples and r.status == "interrupted" and not r.success
    assert "before it finished (killed?)" in r.message
    # files may hold a block the manifest had not committed yet: it is not read
    assert os.path.getsize(path / "x.npy") >= streamed.HEADER_BYTES + 8 * n
    scene = small_scene()
    assert_same(r, a.simulate(scene, steps(scene, n - 1), record_every=1))
