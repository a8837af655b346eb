"""Hostile command lines: every bad file or value is one line on stderr, exit 2, no traceback.

The table below is issue 11's list of hostile CLI cases (the 17 that printed a
traceback, the wrong exit statuses and the misleading messages) plus the other
file problems of every argument that reads or writes a file. Each case runs
in-process through ``main(argv)`` (fast); a few run as real subprocesses
(``python -m asperity2d``), where a traceback would really reach the terminal.
Cost: ~6 s on this machine (most of it the six subprocesses and the
belt cases, which import SciPy through ``asperity2d.belt``; the simulations
are ~2,000 steps; every other case fails before anything is computed).
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from asperity2d.cli import main

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "scenes"
#: A scene small enough that a save/render round trip costs ~0.1 s.
TINY_SCENE = "lower_count = 4\nupper_count = 2\n"
CHAIN = ('masses = [1.0]\nsprings = [10.0, 0.0]\ndampers = [0.0, 0.0]\nmu_s = 0.3\nv_belt = 0.1\n'
         'x0 = [0.0]\nv0 = [0.0]\nt_end = 2.0\n')
NOT_UTF8 = b"\xff\xfe\x00\x81 lower_count = 4\n"


def make_files(root: Path) -> dict[str, str]:
    """Write every hostile (and a few valid) input under ``root``; return name -> path."""
    import asperity2d as a
    from asperity2d import _io
    from asperity2d.experiments.compare import Comparison
    from asperity2d.sweep import ResultStore, Study

    root.mkdir(parents=True, exist_ok=True)
    f = {}

    def put(name, content):
        path = root / name
        path.write_bytes(content if isinstance(content, bytes) else content.encode())
        f[name] = str(path)

    def directory(name):
        (root / name).mkdir()
        f[name] = str(root / name)

    put("scene.toml", TINY_SCENE)
    result = a.simulate(a.make_scene(lower_count=4, upper_count=2), 2e-8, progress=False)  # ~1800 steps
    result.save(root / "result.npz")
    f["result.npz"] = str(root / "result.npz")
    good = (root / "result.npz").read_bytes()
    put("truncated.npz", good[: len(good) // 2])
    flipped = bytearray(good)
    flipped[len(good) // 2] ^= 0xFF  # inside a member's compressed data: its CRC-32 fails
    put("flipped.npz", bytes(flipped))
    put("empty.npz", b"")
    np.savez(root / "foreign.npz", a=np.arange(3))
    f["foreign.npz"] = str(root / "foreign.npz")
    # the right arrays but metadata without a scene (issue 11's ``KeyError: 'scene'``)
    arrays = {name: getattr(result, name) for name in ("t", "x", "v", "y", "vy", "drive_x",
              "drive_force", "normal_force", "friction_force", "tangential_force",
              "contact_count", "lower_dx", "lower_dy", "lower_contact")}
    _io.save_npz(root / "nometa.npz", arrays, {"dt": 1.0})
    f["nometa.npz"] = str(root / "nometa.npz")
    put("notes.txt", "a text file, not a result\n")
    for name in ("adir", "adir.npz", "adir.py", "adir.toml", "adir.png", "adir.json", "adir.csv"):
        directory(name)
    put("binary.toml", NOT_UTF8)
    put("scene5.toml", "scene = 5\n")
    put("run5.toml", "lower_count = 4\nrun = 5\n")
    put("notoml.toml", "this is = = not toml\n")
    put("duraton.toml", TINY_SCENE + "[run]\nduraton = 1e-6\n")
    put("stray.toml", "[scene]\nlower_count = 4\n[extra]\nx = 1\n")
    put("latin1.py", b"# caf\xe9\ndef main(argv):\n    return 0\n")
    put("nomain.py", "x = 1\n")
    put("scene.txt", TINY_SCENE)
    put("chain.toml", CHAIN)
    put("chain_empty.toml", "")
    put("chain_partial.toml", "masses = [1.0]\n")
    put("chain_binary.toml", NOT_UTF8)
    put("chain_types.toml", CHAIN.replace("masses = [1.0]", 'masses = "heavy"'))
    put("chain_method.toml", CHAIN + 'method = 5\n')
    put("chain_friction.toml", CHAIN + "friction = 3\n")
    Comparison(values={"regular": (1.0, 2.0)}, seeds=(0, 1)).save(root / "comparison.json")
    f["comparison.json"] = str(root / "comparison.json")
    put("comparison_bad.json", '{"format": "asperity2d.comparison/1", "values": 5}')
    put("study.toml", 'name = "hostile"\nrun = "asperity2d.studies.ooten:critical_force_run"\nseeds = 1\n'
                      '[grid]\nspacing = ["regular"]\n')
    put("study.txt", "name = 1\n")
    store = ResultStore(root / "store")
    store.begin_session(Study.from_dict({"name": "hostile", "run": "asperity2d.studies.ooten:critical_force_run",
                                         "seeds": 1, "grid": {"spacing": ["regular"]}}), executor="test")
    f["store"] = str(root / "store")
    f["missing"] = str(root / "missing")
    f["root"] = str(root)
    return f


#: (case id, argv with {file} placeholders, text the one error line must contain).
CASES = [
    # -- the 17 cases that printed a traceback (issue 11) ------------------------------
    ("analyze truncated .npz", ["analyze", "{truncated.npz}"], "`result`"),
    ("analyze byte-flipped .npz", ["analyze", "{flipped.npz}"], "`result`"),
    ("analyze empty .npz", ["analyze", "{empty.npz}"], "is empty"),
    ("analyze foreign .npz", ["analyze", "{foreign.npz}"], "not an asperity2d result"),
    ("analyze .npz without scene", ["analyze", "{nometa.npz}"], "`result`"),
    ("render truncated .npz", ["render", "{truncated.npz}", "-o", "{root}/x.png"], "`result`"),
    ("render byte-flipped .npz", ["render", "{flipped.npz}", "-o", "{root}/x.png"], "`result`"),
    ("render empty .npz", ["render", "{empty.npz}", "-o", "{root}/x.png"], "is empty"),
    ("render foreign .npz", ["render", "{foreign.npz}", "-o", "{root}/x.png"], "not an asperity2d"),
    ("run --save DIR", ["run", "{scene.toml}", "--save", "{adir.npz}"], "`--save` is a directory"),
    ("run -o DIR", ["run", "{scene.toml}", "-o", "{adir.png}"], "`--output` is a directory"),
    ("render -o DIR", ["render", "{result.npz}", "-o", "{adir.png}"], "`--output` is a directory"),
    ("belt -o DIR", ["belt", "--preset", "table2-3dof", "-o", "{adir.npz}"], "`--output` is a directory"),
    ("run DIR.py", ["run", "{adir.py}"], "`scene` is a directory"),
    ("run DIR", ["run", "{adir}"], "`scene` is a directory"),
    ("belt DIR", ["belt", "{adir.toml}"], "`chain` is a directory"),
    ("run binary .toml", ["run", "{binary.toml}"], "not UTF-8"),
    ("critical binary .toml", ["critical", "{binary.toml}"], "not UTF-8"),
    ("belt binary .toml", ["belt", "{chain_binary.toml}"], "not UTF-8"),
    ("run scene = 5", ["run", "{scene5.toml}"], "`scene`"),
    ("critical scene = 5", ["critical", "{scene5.toml}"], "`scene`"),
    ("run --duration 1e300", ["run", "{scene.toml}", "--duration", "1e300"], "`--duration`"),
    # -- wrong exit statuses ---------------------------------------------------------------
    ("sweep run --store unwritable", ["sweep", "run", "{study.toml}", "--store", "/sys/asperity2d-store"],
     "`--store`"),
    ("sweep run --store under a file", ["sweep", "run", "{study.toml}", "--store", "{notes.txt}/s"],
     "`--store`"),
    ("sweep export -o DIR", ["sweep", "export", "{store}", "-o", "{adir.csv}"], "`--output` is a directory"),
    ("script's own bad argument", ["run", str(SCENES / "stick_slip.py"), "--bogus"], "--bogus"),
    ("script's own bad value", ["run", str(SCENES / "quickstart.py"), "--seeds", "1"], "`seeds`"),
    ("script -o a file", ["run", str(SCENES / "stick_slip.py"), "--quick", "-o", "{notes.txt}"],
     "`-o` is not a directory"),
    # -- misleading messages ---------------------------------------------------------------
    ("analyze text file", ["analyze", "{notes.txt}"], "not an .npz"),
    ("sweep run DIR as study", ["sweep", "run", "{adir}", "--store", "{root}/s1"], "`study` is a directory"),
    ("sweep run missing study dir", ["sweep", "run", "{missing}/", "--store", "{root}/s2"],
     "`study` does not exist"),
    ("sweep status missing dir", ["sweep", "status", "{missing}"], "`store` does not exist"),
    ("belt empty chain", ["belt", "{chain_empty.toml}"], "missing"),
    ("belt partial chain", ["belt", "{chain_partial.toml}"], "`springs`"),
    ("TOML [run] misspelt key", ["run", "{duraton.toml}"], "`duraton`"),
    # -- every other file argument: missing, directory, not UTF-8, not TOML, wrong type ----
    ("run missing", ["run", "{missing}.toml"], "`scene` does not exist"),
    ("run not TOML", ["run", "{notoml.toml}"], "not valid TOML"),
    ("run run = 5", ["run", "{run5.toml}"], "`run`"),
    ("run stray table", ["run", "{stray.toml}"], "`extra`"),
    ("run wrong suffix", ["run", "{scene.txt}"], "`scene` must be"),
    ("run script not UTF-8", ["run", "{latin1.py}"], "not UTF-8"),
    ("run script without main", ["run", "{nomain.py}"], "main(argv)"),
    ("run --duration -1", ["run", "{scene.toml}", "--duration", "-1"], "--duration"),
    ("run --duration nan", ["run", "{scene.toml}", "--duration", "nan"], "--duration"),
    ("run --save wrong suffix", ["run", "{scene.toml}", "--save", "{root}/r.txt"], "`--save`"),
    ("run -o wrong suffix", ["run", "{scene.toml}", "-o", "{root}/r.bmp"], "`--output`"),
    ("run --save under a file", ["run", "{scene.toml}", "--save", "{notes.txt}/r.npz"], "`--save`"),
    ("analyze missing", ["analyze", "{missing}.npz"], "`result` does not exist"),
    ("analyze DIR", ["analyze", "{adir.npz}"], "`result` is a directory"),
    ("render missing", ["render", "{missing}.npz", "-o", "{root}/x.png"], "`result` does not exist"),
    ("render wrong suffix", ["render", "{result.npz}", "-o", "{root}/x.bmp"], "`--output`"),
    ("critical missing", ["critical", "{missing}.toml"], "`scene` does not exist"),
    ("critical DIR", ["critical", "{adir.toml}"], "`scene` is a directory"),
    ("critical a script", ["critical", "{latin1.py}"], "`scene` must be a .toml"),
    ("critical --rel-tol 0", ["critical", "{scene.toml}", "--rel-tol", "0"], "--rel-tol"),
    ("belt missing", ["belt", "{missing}.toml"], "`chain` does not exist"),
    ("belt not TOML", ["belt", "{notoml.toml}"], "not valid TOML"),
    ("belt wrong type", ["belt", "{chain_types.toml}"], "`masses`"),
    ("belt method = 5", ["belt", "{chain_method.toml}"], "`method`"),
    ("belt friction = 3", ["belt", "{chain_friction.toml}"], "`friction`"),
    ("belt --t-end inf", ["belt", "{chain.toml}", "--t-end", "inf"], "--t-end"),
    ("belt -o wrong suffix", ["belt", "{chain.toml}", "-o", "{root}/x.gifx"], "`--output`"),
    ("compare --load missing", ["compare", "--load", "{missing}.json"], "`--load` does not exist"),
    ("compare --load DIR", ["compare", "--load", "{adir.json}"], "`--load` is a directory"),
    ("compare --load text", ["compare", "--load", "{notes.txt}"], "`--load`"),
    ("compare --load not UTF-8", ["compare", "--load", "{binary.toml}"], "`--load`"),
    ("compare --load bad values", ["compare", "--load", "{comparison_bad.json}"], "`--load`"),
    ("compare --save DIR", ["compare", "--load", "{comparison.json}", "--save", "{adir.json}"],
     "`--save` is a directory"),
    ("compare -o DIR", ["compare", "--load", "{comparison.json}", "-o", "{adir.png}"],
     "`--output` is a directory"),
    ("compare --seeds 0", ["compare", "--seeds", "0"], "--seeds"),
    ("sweep run missing study", ["sweep", "run", "{missing}.toml", "--store", "{root}/s3"],
     "`study` does not exist"),
    ("sweep run study wrong suffix", ["sweep", "run", "{study.txt}", "--store", "{root}/s4"], "`study`"),
    ("sweep run study not UTF-8", ["sweep", "run", "{binary.toml}", "--store", "{root}/s5"], "`study`"),
    ("sweep run --store is a file", ["sweep", "run", "{study.toml}", "--store", "{notes.txt}"], "`--store`"),
    ("sweep status a file", ["sweep", "status", "{notes.txt}"], "`store`"),
    ("sweep status not a store", ["sweep", "status", "{adir}"], "`store` is not a sweep store"),
    ("sweep report missing", ["sweep", "report", "{missing}"], "`store` does not exist"),
    ("sweep report -o DIR", ["sweep", "report", "{store}", "-o", "{adir.png}"], "`--output` is a directory"),
    ("sweep export missing", ["sweep", "export", "{missing}", "-o", "{root}/x.csv"], "`store` does not exist"),
    ("sweep export -o under a file", ["sweep", "export", "{store}", "-o", "{notes.txt}/x.csv"], "`--output`"),
    ("no command", [], "command"),
    ("run without a scene", ["run", "--json"], "required: scene"),
    ("unknown option", ["analyze", "{result.npz}", "--bogus"], "--bogus"),
]

#: Cases that also run as real subprocesses (a traceback would reach the terminal).
SUBPROCESS_CASES = {"analyze byte-flipped .npz", "run binary .toml", "run --duration 1e300",
                    "sweep export -o DIR", "script's own bad argument", "belt empty chain"}


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    return make_files(tmp_path_factory.mktemp("hostile"))


def _fill(template: list[str], files: dict[str, str]) -> list[str]:
    out = []
    for part in template:
        for name, path in files.items():
            part = part.replace("{" + name + "}", path)
        out.append(part)
    return out


def _check_one_line(code, out, err, needle):
    lines = err.splitlines()
    assert code == 2, (code, err)
    assert "Traceback" not in err and "Traceback" not in out
    assert len(lines) == 1, err
    assert err.startswith("asperity2d: error: "), err
    assert needle in lines[0], (needle, lines[0])


@pytest.mark.parametrize("case, template, needle", CASES, ids=[c[0] for c in CASES])
def test_hostile_case_in_process(case, template, needle, files, capsys):
    code = main(_fill(template, files))
    out, err = capsys.readouterr()
    _check_one_line(code, out, err, needle)


@pytest.mark.parametrize("case, template, needle", [c for c in CASES if c[0] in SUBPROCESS_CASES],
                         ids=[c[0] for c in CASES if c[0] in SUBPROCESS_CASES])
def test_hostile_case_as_subprocess(case, template, needle, files):
    proc = subprocess.run([sys.executable, "-m", "asperity2d", *_fill(template, files)],
                          capture_output=True, text=True, timeout=120)
    _check_one_line(proc.returncode, proc.stdout, proc.stderr, needle)


def test_version_comes_from_the_installed_metadata(capsys):
    from importlib.metadata import version

    import asperity2d

    from asperity2d.engine import kernel

    assert main(["--version"]) == 0
    name, loop = capsys.readouterr().out.strip().splitlines()
    assert name == f"asperity2d {version('asperity2d')}"
    assert asperity2d.__version__ == version("asperity2d")
    # and which step loop runs: C, or Python with the reason
    assert loop == ("engine step loop: C" if kernel.KERNEL else f"engine step loop: Python ({kernel.KERNEL_REASON})")


def test_run_table_works_with_and_without_a_scene_table(tmp_path, capsys):
    for text in (TINY_SCENE + "[run]\nduration = 2e-8\n",
                 "[scene]\n" + TINY_SCENE + "[run]\nduration = 2e-8\n"):
        scene = tmp_path / "scene.toml"
        scene.write_text(text)
        assert main(["run", str(scene), "--json"]) == 0
        summary = json.loads(capsys.readouterr().out)
        assert summary["status"] == "duration" and summary["duration_s"] == pytest.approx(2e-8, rel=0.05)


def test_sweep_export_takes_json(files, tmp_path, capsys):
    out = tmp_path / "runs.csv"
    assert main(["sweep", "export", files["store"], "-o", str(out), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary == {"output": str(out), "runs": 0}
    assert out.read_text().startswith("key,spacing,seed,status")


def test_run_help_is_the_scripts_own_after_a_script(capsys):
    assert main(["run", str(SCENES / "stick_slip.py"), "--help"]) == 0
    assert capsys.readouterr().out.startswith("usage: stick_slip.py")
    assert main(["run", "--help"]) == 0
    assert capsys.readouterr().out.startswith("usage: asperity2d run")


def test_chain_file_runs(files, capsys):
    assert main(["belt", files["chain.toml"], "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["n"] == 1


def test_a_users_script_that_raises_shows_its_own_traceback(tmp_path):
    """The one case where a traceback is the right output: the bug is in the user's code."""
    script = tmp_path / "buggy.py"
    script.write_text("def main(argv):\n    return 1 / 0\n")
    proc = subprocess.run([sys.executable, "-m", "asperity2d", "run", str(script)],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 1
    assert "Traceback" in proc.stderr and "ZeroDivisionError" in proc.stderr
    assert "buggy.py" in proc.stderr


def test_no_partial_output_is_left_by_a_refused_write(files, tmp_path):
    """A refused output is refused before any work, and nothing is written beside it."""
    before = set(Path(files["adir.npz"]).iterdir())
    assert main(["run", files["scene.toml"], "--save", files["adir.npz"]]) == 2
    assert set(Path(files["adir.npz"]).iterdir()) == before
    assert not list(Path(files["root"]).glob(".*.tmp"))


def test_damaged_result_files_are_refused_or_load_intact(files, tmp_path):
    """Byte flips at 150 seeded positions and 40 truncations of a saved result: each load raises
    SceneError or returns the saved arrays bit for bit (a flip in a field zip does not use).

    The zip format's CRC-32 covers every member's data, so no flip can slip a wrong number
    through; this checks that every other kind of damage is caught too. Cost ~0.5 s.
    """
    import asperity2d as a
    from asperity2d.result import SERIES

    good = Path(files["result.npz"]).read_bytes()
    reference = a.load(files["result.npz"])
    rng = np.random.default_rng(11)
    damaged = [good[:n] for n in rng.integers(0, len(good), 40)]
    for pos in rng.integers(0, len(good), 150):
        flipped = bytearray(good)
        flipped[pos] ^= int(rng.integers(1, 256))
        damaged.append(bytes(flipped))
    path = tmp_path / "damaged.npz"
    refused = 0
    for data in damaged:
        path.write_bytes(data)
        try:
            result = a.load(path)
        except a.SceneError:
            refused += 1
            continue
        for name in SERIES:
            assert np.array_equal(getattr(result, name), getattr(reference, name), equal_nan=True)
    assert refused >= 150  # all truncations and nearly every flip
