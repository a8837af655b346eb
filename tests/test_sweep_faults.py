"""Faults of the process that runs an ensemble: no worker outlives it.

A sweep killed with SIGKILL cannot clean up: its pool workers (and multiprocessing's resource
tracker) used to be re-parented and live on. Each worker now asks the kernel to kill it when
its parent dies and watches its parent besides; the tracker exits when its pipe closes.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import sweep_fixtures

pytestmark = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads /proc")


def group(pgid: int) -> dict[int, str]:
    """Live (not zombie) processes of process group ``pgid``: pid -> command line."""
    out = {}
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
            cmd = (entry / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
        except OSError:  # gone meanwhile
            continue
        fields = stat.rsplit(")", 1)[1].split()  # after the command name, which may hold spaces
        state, pgrp = fields[0], int(fields[2])
        if pgrp == pgid and state != "Z":
            out[int(entry.name)] = cmd.strip()
    return out


STUDY = """
name = "kill"
run = "sweep_fixtures:slow_run"
seeds = 40
[grid]
amplitude = [1.0]
[fixed]
delay = 2.0
"""


@pytest.mark.parametrize("workers", ["2"])
def test_sigkill_of_a_sweep_leaves_no_process_behind(tmp_path, workers):
    study = tmp_path / "study.toml"
    study.write_text(STUDY)
    sweep = subprocess.Popen([sys.executable, "-m", "asperity2d", "sweep", "run", str(study), "--store",
                              str(tmp_path / "store"), "--workers", workers, "--no-progress"],
                             env=sweep_fixtures.subprocess_env(), start_new_session=True,
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    pgid = sweep.pid  # a new session: the sweep leads its own process group
    try:
        deadline = time.monotonic() + 90
        members = {}
        while time.monotonic() < deadline:  # the sweep, its 2 workers and the resource tracker
            members = group(pgid)
            if sum("multiprocessing" in cmd for cmd in members.values()) >= 3:
                break
            assert sweep.poll() is None, sweep.stderr.read().decode()
            time.sleep(0.2)
        else:
            pytest.fail(f"the sweep's workers did not start: {members}")
        assert any("resource_tracker" in cmd for cmd in members.values()), members
        os.kill(sweep.pid, signal.SIGKILL)
        sweep.wait()
        deadline = time.monotonic() + 5  # the workers watch their parent every 0.2 s
        while group(pgid) and time.monotonic() < deadline:
            time.sleep(0.1)
        left = group(pgid)
        assert not left, f"left alive after SIGKILL of the sweep: {left}"
    finally:
        for pid in group(pgid):  # never leave them behind, even when the test fails
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        sweep.kill()
        sweep.wait()
