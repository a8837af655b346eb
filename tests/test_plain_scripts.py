"""The documented calls run from a plain script, with no ``if __name__ == "__main__":`` guard.

Worker processes are spawned: each starts by running the main script again, so a script that
calls ``compare`` or ``run_study`` at its top level started the ensemble again inside every
worker (one traceback per worker; ``run_study`` recorded every run as failed and exited 0).
Now such a script runs its calls in its own process, with one warning that says how to get the
workers; a guarded script gets them. Each case runs a real script in a real subprocess.
"""

import json
import subprocess
import sys
import textwrap

import pytest

import sweep_fixtures
from asperity2d.sweep.executors import guarded_line

COMPARE = """
import asperity2d as a

c = a.compare("critical", {"regular": {"spacing": "regular"}, "random": {"spacing": "random"}}, range(2),
              base=dict(lower_count=3, upper_count=1, drive="force"), workers=2, progress=False)
print("VALUES", json.dumps(c.values))
"""

STUDY = """
from asperity2d.sweep import Study, run_study

study = Study(name="plain", run="sweep_fixtures:noisy_run", grid={"amplitude": [1.0, 2.0]}, seeds=range(3))
summary = run_study(study, store=STORE, workers=2, progress=False)
print("SUMMARY", json.dumps({"done": summary.done, "failed": summary.failed, "executor": summary.executor}))
"""


def _run(tmp_path, body: str, *, guard: bool):
    code = textwrap.dedent(body)
    if guard:
        code = "if __name__ == '__main__':\n" + textwrap.indent(code, "    ")
    script = tmp_path / "script.py"
    script.write_text(f"import json\nSTORE = {str(tmp_path / 'store')!r}\n" + code)
    return subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=300,
                          cwd=tmp_path, env=sweep_fixtures.subprocess_env())


def _value(out: str, tag: str):
    line = next(line for line in out.splitlines() if line.startswith(tag))
    return json.loads(line[len(tag):])


def test_compare_in_a_plain_script_runs_here_with_one_warning(tmp_path):
    proc = _run(tmp_path, COMPARE, guard=False)
    assert proc.returncode == 0, proc.stderr
    assert "Traceback" not in proc.stderr
    assert proc.stderr.count("RuntimeWarning") == 1
    assert 'if __name__ == "__main__":' in proc.stderr and "to get the workers" in proc.stderr
    values = _value(proc.stdout, "VALUES")
    assert set(values) == {"regular", "random"} and all(len(v) == 2 for v in values.values())
    # the same values as a guarded script on worker processes: the executor never changes them
    guarded = _run(tmp_path, COMPARE, guard=True)
    assert guarded.returncode == 0 and "RuntimeWarning" not in guarded.stderr, guarded.stderr
    assert _value(guarded.stdout, "VALUES") == values


def test_run_study_in_a_plain_script_runs_every_run(tmp_path):
    proc = _run(tmp_path, STUDY, guard=False)
    assert proc.returncode == 0, proc.stderr
    assert "Traceback" not in proc.stderr and proc.stderr.count("RuntimeWarning") == 1
    summary = _value(proc.stdout, "SUMMARY")
    assert (summary["done"], summary["failed"]) == (6, 0)
    assert "in-process" in summary["executor"]


def test_a_guarded_script_gets_its_workers(tmp_path):
    proc = _run(tmp_path, STUDY, guard=True)
    assert proc.returncode == 0, proc.stderr
    assert "RuntimeWarning" not in proc.stderr and "Traceback" not in proc.stderr
    summary = _value(proc.stdout, "SUMMARY")
    assert (summary["done"], summary["failed"]) == (6, 0)
    assert "local processes" in summary["executor"]


@pytest.mark.parametrize("source, line, inside", [
    ("x = 1\nif __name__ == '__main__':\n    run()\n", 3, True),
    ("x = 1\nif __name__ == '__main__':\n    run()\n", 1, False),
    ("if '__main__' == __name__:\n    a()\n    b()\n", 3, True),
    ("if __name__ != '__main__':\n    run()\n", 2, False),
    ("run()\n", 1, False),
    ("def main():\n    run()\n\nif __name__ == \"__main__\":\n    main()\n", 5, True),
    ("this is not python", 1, False),
])
def test_the_guard_is_found_by_the_line_that_starts_the_ensemble(source, line, inside):
    assert guarded_line(source, line) is inside


def test_a_sweep_whose_runs_all_failed_exits_non_zero(tmp_path, capsys):
    from asperity2d.cli import main

    study = tmp_path / "study.toml"
    study.write_text('name = "doomed"\nrun = "sweep_fixtures:flaky_run"\nseeds = [0, 1]\n'
                     '[grid]\namplitude = [-1.0, -2.0]\n')
    code = main(["sweep", "run", str(study), "--store", str(tmp_path / "store"), "--workers", "1",
                 "--no-progress"])
    err = capsys.readouterr().err
    assert code == 1
    assert "every run of 'doomed' failed; the first: ValueError: amplitude must be >= 0" in err
    assert "Traceback" not in err
