"""Ensembles with worker processes from a session whose main module has no file on disk.

A notebook downloaded from the gallery sets ``__file__`` beside itself, where no script is; spawned
workers would start by running that missing file and die. The package's measures are imported by
name, so workers need nothing from ``__main__``: the pool starts them without it. A function the
session itself defines cannot reach them: that is one clear error. Each case runs in a fresh
interpreter (``python -c``: no main file, like a kernel) with two workers, so a real pool is used.
"""

import subprocess
import sys
import textwrap

SETUP = textwrap.dedent("""
    import __main__
    import asperity2d as a
    __main__.__file__ = "/nonexistent/folder/quickstart.py"  # what the notebook's first cell sets
    small = {"lower_count": 4, "upper_count": 2, "track": "fixed"}
""")


def _run(code: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", SETUP + textwrap.dedent(code)], capture_output=True, text=True,
                          timeout=300, env={"TQDM_DISABLE": "1", "PATH": "/usr/bin:/bin"})


def test_a_package_measure_runs_in_workers_when_main_has_no_file():
    done = _run("""
        c = a.compare("critical", {"regular": {"spacing": "regular"}, "random": {"spacing": "random"}}, [0, 1],
                      base={**small, "drive": "force"}, workers=2, progress=False)
        one = a.compare("critical", {"regular": {"spacing": "regular"}, "random": {"spacing": "random"}}, [0, 1],
                        base={**small, "drive": "force"}, workers=1, progress=False)
        assert c.values == one.values, (c.values, one.values)  # the pool gives the in-process bits
        assert __main__.__file__ == "/nonexistent/folder/quickstart.py"  # given back after the run
        print("ok", sorted(c.values))
    """)
    assert done.returncode == 0, done.stderr[-3000:]
    assert done.stdout.startswith("ok")


def test_a_measure_defined_in_main_is_one_clear_error():
    done = _run("""
        def my_measure(scene):
            return 1.0
        try:
            a.compare(my_measure, {"random": {"spacing": "random"}}, [0, 1], base=small, workers=2, progress=False)
        except a.SceneError as exc:
            print("refused:", exc)
    """)
    assert done.returncode == 0, done.stderr[-3000:]
    assert "refused: `workers` > 1 needs a main script" in done.stdout
    assert "`my_measure` is defined there" in done.stdout and "\\n" not in done.stdout.strip()
