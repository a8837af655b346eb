"""Kill a running study with SIGKILL part-way, resume it, compare with an uninterrupted run."""

import json
import os
import signal
import subprocess
import sys
import time

import pytest

import sweep_fixtures
from asperity2d.sweep import ResultStore, load_study, run_study

STUDY_TOML = """\
name = "resume"
run = "sweep_fixtures:slow_run"
seeds = 10
quantities = ["mean", "peak"]

[grid]
amplitude = [1.0, 2.0]

[fixed]
delay = 0.1
"""


def _sweep_cmd(*args):
    return [sys.executable, "-m", "asperity2d", "sweep", *args]


@pytest.mark.skipif(not hasattr(os, "killpg"), reason="needs POSIX process groups")
def test_sigkill_then_resume_gives_every_run_once_and_identical(tmp_path):
    study_path = tmp_path / "study.toml"
    study_path.write_text(STUDY_TOML)
    study = load_study(study_path)
    keys = {s.key for s in study.runs()}
    store = ResultStore(tmp_path / "killed")
    env = sweep_fixtures.subprocess_env()

    # own session, so SIGKILL reaches the runner and its pool workers together
    proc = subprocess.Popen(
        _sweep_cmd("run", str(study_path), "--store", str(store.path), "--workers", "2",
                   "--no-progress"),
        env=env, start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
    )
    try:
        deadline = time.monotonic() + 60
        while len(store.stored_keys()) < 4:
            if proc.poll() is not None or time.monotonic() > deadline:
                pytest.fail(f"runner ended or stalled early: {proc.stderr.read().decode()}")
            time.sleep(0.02)
        os.killpg(proc.pid, signal.SIGKILL)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
    assert proc.returncode == -signal.SIGKILL
    before = store.stored_keys()
    assert 4 <= len(before) < len(keys), "the kill must land part-way through the study"
    (store.runs_dir / f".{next(iter(before))}.json.x1y2.tmp").write_text('{"half')  # as if cut

    resumed = subprocess.run(
        _sweep_cmd("run", str(study_path), "--store", str(store.path), "--workers", "2",
                   "--no-progress", "--json"),
        env=env, capture_output=True, text=True, timeout=120,
    )
    assert resumed.returncode == 0, resumed.stderr
    summary = json.loads(resumed.stdout)
    assert summary["ran"] == len(keys) - len(before) and summary["skipped"] == len(before)
    assert (summary["done"], summary["failed"], summary["pending"]) == (len(keys), 0, 0)

    # every run exactly once, no temporary files left behind
    files = sorted(p.name for p in store.runs_dir.iterdir())
    assert files == sorted(f"{k}.json" for k in keys)

    reference = ResultStore(tmp_path / "reference")
    run_study(study, store=reference, workers=2, progress=False)
    got, want = store.records(), reference.records()
    assert set(got) == set(want) == keys
    for key in keys:
        assert got[key].status == "done"
        assert dict(got[key].quantities) == dict(want[key].quantities)  # bit-identical
        assert (got[key].seed, dict(got[key].params)) == (want[key].seed, dict(want[key].params))
    table = store.table()
    assert len(table) == len(set(table["key"])) == len(keys)
