"""The command line at a real terminal's edges, each in a real subprocess: a reader that closes the
pipe early, Ctrl-C sent to the whole process group while workers start, TOML nested thousands
deep, a plain script, a script read from standard input, mistyped options, repeated or empty
``--set`` keys, an output that needs a missing extra, and text parameters without bound.

Each case is what a user does at a shell; the check is what the user sees: the exit status and
stderr (one line, no traceback). Cost: about 110 s on a loaded two-core machine (19 interpreters;
the Ctrl-C cases start worker processes).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CLI = [sys.executable, "-m", "asperity2d"]
SCENE = ROOT / "scenes" / "default.toml"


def _run(args, *, cwd, timeout=120, **kwargs):
    return subprocess.run([*CLI, *args], capture_output=True, text=True, cwd=cwd, timeout=timeout, **kwargs)


def _one_error_line(proc) -> str:
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode == 2, (proc.returncode, proc.stderr[-2000:])
    assert len(lines) == 1 and lines[0].startswith("asperity2d: error: "), proc.stderr[-2000:]
    return lines[0]


# -- a reader that closes the pipe early ---------------------------------------------------------------
@pytest.mark.parametrize("args", [["validate"], ["measures"], ["belt", "--list-presets"]],
                         ids=["validate", "measures", "belt --list-presets"])
def test_a_reader_that_closed_the_pipe_ends_the_command_quietly(args, tmp_path):
    # the read end is closed before the command writes a byte: its first write meets EPIPE every
    # time (a `| head -1` meets it only when head exits before the output is flushed)
    read, write = os.pipe()
    proc = subprocess.Popen([*CLI, *args], stdout=write, stderr=subprocess.PIPE, cwd=tmp_path)
    os.close(write)
    os.close(read)
    err = proc.communicate(timeout=300)[1].decode()
    assert "Traceback" not in err and "BrokenPipeError" not in err, err[-2000:]
    assert err == "" and proc.returncode == 141  # 128 + SIGPIPE, what a shell reports


@pytest.mark.parametrize("args", [["validate"], ["measures"], ["belt", "--list-presets"]],
                         ids=["validate", "measures", "belt --list-presets"])
def test_head_1_reads_the_first_line_and_nothing_else_is_printed(args, tmp_path):
    command = " ".join([*map(_quote, CLI), *args]) + " | head -1"
    proc = subprocess.run(["bash", "-c", command], capture_output=True, text=True, cwd=tmp_path, timeout=300)
    assert proc.returncode == 0 and len(proc.stdout.splitlines()) == 1
    assert proc.stderr == "", proc.stderr[-2000:]


def _quote(text: str) -> str:
    import shlex

    return shlex.quote(text)


# -- Ctrl-C while the workers start ----------------------------------------------------------------------
def _workers_of(pid: int) -> list[int]:
    """The spawned worker processes of ``pid`` (children running multiprocessing's spawn_main)."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            ppid = int((entry / "stat").read_text().rpartition(")")[2].split()[1])
            command = (entry / "cmdline").read_bytes()
        except (OSError, ValueError, IndexError):
            continue
        if ppid == pid and b"spawn_main" in command:
            found.append(int(entry.name))
    return found


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads the process table from /proc")
@pytest.mark.parametrize("args, after", [
    (["compare", "--seeds", "40", "--workers", "2", "--json"], 0.0),
    (["compare", "--seeds", "40", "--workers", "2", "--json"], 0.4),
    (["belt", "basins", "--preset", "table2-3dof", "--grid", "12", "--workers", "2", "--json", "-o", "b.png"], 0.1),
], ids=["compare, workers starting", "compare, workers importing", "belt basins, workers starting"])
def test_ctrl_c_to_the_process_group_while_workers_start_is_one_line(args, after, tmp_path):
    # A terminal sends SIGINT to every process of the foreground group: the command and the workers
    # it is starting. Sent as soon as the first worker exists (plus `after` s), it reaches workers
    # still starting their interpreters -- what 2.5-3.5 s into the command did on a loaded machine
    # (before: 47-110 lines of stderr, InvalidStateError tracebacks). The installed command, as a
    # user types it (its workers re-run the console script as their main module).
    script = Path(sys.executable).with_name("asperity2d")
    command = [str(script)] if script.exists() else CLI
    proc = subprocess.Popen([*command, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            cwd=tmp_path, start_new_session=True)
    deadline = time.monotonic() + 120
    while not _workers_of(proc.pid):
        assert proc.poll() is None and time.monotonic() < deadline, "no worker was started"
        time.sleep(0.01)
    time.sleep(after)
    os.killpg(proc.pid, signal.SIGINT)
    started = time.monotonic()
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err[-3000:]
    assert err.strip().splitlines() == ["asperity2d: interrupted"], err[-3000:]
    assert time.monotonic() - started < 30  # the workers are ended, not waited for
    for _ in range(50):  # and none is left behind in the group
        try:
            os.killpg(proc.pid, 0)
        except ProcessLookupError:
            break
        time.sleep(0.1)
    else:
        pytest.fail("worker processes outlived the interrupted command")


# -- TOML nested thousands deep --------------------------------------------------------------------------
def test_a_dotted_key_ten_thousand_levels_deep_is_one_line_naming_it(tmp_path):
    # found on the text before parsing (tomllib takes ~20 s over 10,000 parts: quadratic)
    (tmp_path / "deep.toml").write_text("[run]\n" + ".".join(["duration"] * 10_000) + " = 1\n")
    line = _one_error_line(_run(["run", "deep.toml"], cwd=tmp_path))
    assert "`duration.duration.duration.duration...(10000 levels)`" in line and "nested too deeply" in line

    study = (ROOT / "scenes" / "spacing_study.toml").read_text()
    (tmp_path / "study.toml").write_text(study.replace("seeds = 20", ".".join(["seeds"] + ["a"] * 10_000) + " = 1"))
    line = _one_error_line(_run(["sweep", "run", "study.toml", "--store", "store"], cwd=tmp_path))
    assert "`seeds.a.a.a...(10001 levels)`" in line and "nested too deeply" in line


def test_a_run_table_that_is_not_a_number_is_named_in_one_line(tmp_path):
    (tmp_path / "d.toml").write_text("[run]\nduration.x = 1\n")
    assert "`duration` in [run]" in _one_error_line(_run(["run", "d.toml"], cwd=tmp_path))


# -- scripts ----------------------------------------------------------------------------------------------
def test_a_script_without_main_is_refused_before_its_body_runs(tmp_path):
    (tmp_path / "plain.py").write_text("from pathlib import Path\nPath('ran').write_text('the body ran')\n")
    line = _one_error_line(_run(["run", "plain.py"], cwd=tmp_path))
    assert "no main(argv)" in line
    assert not (tmp_path / "ran").exists()
    # a script that has one still runs (its body too: that is where main is defined)
    (tmp_path / "ok.py").write_text("from pathlib import Path\nPath('ran').write_text('yes')\n"
                                    "def main(argv):\n    print('main', argv)\n    return 0\n")
    proc = _run(["run", "ok.py", "x"], cwd=tmp_path)
    assert proc.returncode == 0 and proc.stdout.strip() == "main ['x']" and (tmp_path / "ran").exists()


def test_a_script_read_from_stdin_runs_its_ensemble_in_this_process(tmp_path):
    script = ("import asperity2d as a\n"
              "c = a.compare('critical', {'regular': {'spacing': 'regular'}, 'random': {'spacing': 'random'}},\n"
              "              range(2), base={'lower_count': 4, 'upper_count': 2}, progress=False, workers=2)\n"
              "print(sorted(c.values), len(c.values['random']))\n")
    proc = subprocess.run([sys.executable, "-"], input=script, capture_output=True, text=True, cwd=tmp_path,
                          timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert proc.stdout.strip() == "['random', 'regular'] 2"
    note = proc.stderr.strip().splitlines()
    assert len(note) == 1 and note[0].startswith("<stdin>:2: RuntimeWarning:") and "standard input" in note[0]


# -- options ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("option, said", [
    ("--verison", "unrecognized option '--verison' (did you mean --version?)"),
    ("-V", "unrecognized option '-V' (did you mean --version?)"),
    ("--bogus", "unrecognized option '--bogus'"),
])
def test_a_mistyped_option_before_the_command_is_named(option, said, tmp_path):
    assert said in _one_error_line(_run([option], cwd=tmp_path))


def test_set_refuses_an_empty_key_and_a_key_given_twice(tmp_path):
    line = _one_error_line(_run(["run", str(SCENE), "--set", "=3"], cwd=tmp_path))
    assert "`--set` key is empty" in line
    line = _one_error_line(_run(["run", str(SCENE), "--set", "lower_count=4", "--set", "lower_count=5"],
                                cwd=tmp_path))
    assert "`--set lower_count` is given twice (4 and 5)" in line


def test_an_mp4_without_the_video_extra_names_the_output_option(tmp_path):
    import importlib.util

    if importlib.util.find_spec("imageio_ffmpeg") is not None:
        pytest.skip("the video extra is installed: .mp4 is written")
    for args in (["run", str(SCENE), "-o", "x.mp4"], ["belt", "--preset", "table2-3dof", "-o", "x.mp4"]):
        line = _one_error_line(_run(args, cwd=tmp_path))
        assert line.startswith("asperity2d: error: `--output` 'x.mp4': writing .mp4 needs the optional video extra")


# -- text has bounds like numbers -------------------------------------------------------------------------
def test_a_huge_scene_name_is_refused_at_once(tmp_path):
    (tmp_path / "named.toml").write_text(f'[scene]\nname = "{"x" * 2_000_000}"\n')
    started = time.monotonic()
    line = _one_error_line(_run(["run", "named.toml"], cwd=tmp_path))
    assert "`name` must be at most 1,000 characters, got 2,000,000" in line
    assert time.monotonic() - started < 30  # refused, not run (a 200 MB name took 40 s and 846 MB)
