"""Fuzzed scene and chain files: the command line answers exit 0 or 2, never a traceback.

Two layers, both with Hypothesis:

* **arbitrary bytes** as a scene file and as a chain file, through the whole
  command line (``main(["run", f, "--duration", "1e-9"])`` and
  ``main(["belt", f, "--t-end", "1e-3"])``). Almost every byte string is
  refused while reading (not UTF-8, not TOML, missing keys); the few valid
  ones (empty, comments, ``seed = 3``) run a bounded 1 ns / 1 ms simulation.
* **arbitrary TOML documents** (keys drawn from the real parameter names
  and at random; values any TOML value: huge integers, inf, nan, strings,
  datetimes, arrays, tables) through the command line's file loaders only:
  ``scene_from_toml`` (reading, the ``[scene]``/``[run]`` structure and
  ``make_scene``'s validation) and ``load_chain``. Running what they build
  is left out on purpose: a valid document may ask for 10^6 asperities or a
  10^9-event chain, and bounding those runs is the simulators' job (issue 11,
  items 1-2), fuzzed in their own tests.

Each file either loads or raises ``SceneError``; any other exception fails the
test. Default run: 40 + 40 + 60 + 60 examples, ~6 s; ``-m slow`` runs 1,000 of each.
"""

from __future__ import annotations

import datetime as dt
import inspect
import json
import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from asperity2d import SceneError
from asperity2d.cli.asperity import scene_from_toml
from asperity2d.belt.chainfile import ALLOWED as CHAIN_KEYS
from asperity2d.belt import read_chain as load_chain
from asperity2d.cli import main

FAST = settings(max_examples=40, deadline=None, derandomize=True,
                suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
SLOW = settings(max_examples=1000, deadline=None,
                suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])


def _scene_keys() -> list[str]:
    from asperity2d import builders

    names = set(inspect.signature(builders.make_scene).parameters) | set(getattr(builders, "DEFAULTS", {}))
    return sorted(n for n in names if n != "overrides")


# -- TOML documents -----------------------------------------------------------------
def _toml_string(text: str) -> str:
    # JSON escapes are TOML escapes, except that TOML also wants DEL escaped
    return json.dumps(text, ensure_ascii=False).replace("\x7f", "\\u007f")


def _toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf") if math.isinf(value) else repr(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, str):
        return _toml_string(value)
    if isinstance(value, dt.datetime):
        return value.isoformat()
    if isinstance(value, list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    return "{" + ", ".join(f"{_toml_string(k)} = {_toml_value(v)}" for k, v in value.items()) + "}"


def to_toml(doc: dict) -> str:
    """A TOML document with ``doc``'s keys at top level (nested tables written inline)."""
    return "".join(f"{_toml_string(k)} = {_toml_value(v)}\n" for k, v in doc.items())


SCALARS = st.one_of(
    st.booleans(),
    st.integers(),
    st.integers(min_value=-(10 ** 400), max_value=10 ** 400),
    st.floats(),
    st.sampled_from([0.0, -0.0, 1e-300, 5e-324, 1e300, -1.0, 1.0, 0.5]),
    st.text(max_size=8),
    st.datetimes(min_value=dt.datetime(1000, 1, 1)),
)
VALUES = st.recursive(SCALARS, lambda inner: st.lists(inner, max_size=4)
                      | st.dictionaries(st.text(min_size=1, max_size=6), inner, max_size=3), max_leaves=8)


def documents(keys: list[str], tables: tuple[str, ...]):
    """TOML documents over ``keys`` (plus random ones), with optional sub-tables ``tables``."""
    key = st.one_of(st.sampled_from(keys), st.text(min_size=1, max_size=8))
    body = st.dictionaries(key, VALUES, max_size=6)
    return st.one_of(body, st.fixed_dictionaries({}, optional={t: st.one_of(body, VALUES) for t in tables})
                     .flatmap(lambda extra: body.map(lambda d: {**d, **extra})))


def _check_loader(load, path, text):
    path.write_text(text, encoding="utf-8")
    try:
        load(path)
    except SceneError:
        pass  # the one acceptable failure; anything else propagates and fails the test


def _scene_doc_case(tmp_path, doc):
    _check_loader(scene_from_toml, tmp_path / "scene.toml", to_toml(doc))


def _chain_doc_case(tmp_path, doc):
    _check_loader(load_chain, tmp_path / "chain.toml", to_toml(doc))


@FAST
@given(doc=documents(_scene_keys(), ("scene", "run")))
def test_any_toml_document_as_a_scene_file_loads_or_is_a_scene_error(tmp_path, doc):
    _scene_doc_case(tmp_path, doc)


@FAST
@given(doc=documents(sorted(CHAIN_KEYS), ("friction",)))
def test_any_toml_document_as_a_chain_file_loads_or_is_a_scene_error(tmp_path, doc):
    _chain_doc_case(tmp_path, doc)


# -- hostile TOML: nesting thousands deep, in every place a value goes ------------------------
def _nested(depth: int, kind: str) -> str:
    if kind == "array":
        return "[" * depth + "1" + "]" * depth
    if kind == "table":
        return "{a = " * depth + "1" + "}" * depth
    return "[{a = " * depth + "1" + "}]" * depth  # arrays of inline tables, alternating


HOSTILE = st.builds(lambda depth, kind, key, where: (depth, kind, key, where),
                    st.one_of(st.integers(1, 50), st.integers(900, 6000)),
                    st.sampled_from(["array", "table", "mixed"]),
                    st.sampled_from(["lower_count", "masses", "x", "friction"]),
                    st.sampled_from(["top", "scene", "run"]))


def _hostile_doc(depth, kind, key, where) -> str:
    value = f"{key} = {_nested(depth, kind)}\n"
    return value if where == "top" else f"[{where}]\n{value}"


@settings(FAST, max_examples=30)
@given(case=HOSTILE)
def test_hostile_toml_loads_or_is_one_scene_error(tmp_path, capsys, case):
    """A TOML nested up to 6,000 deep (a RecursionError traceback from the parser at 5,000) as a
    scene and as a chain file: each loader, and the command line, answers in one line."""
    text = _hostile_doc(*case)
    _check_loader(scene_from_toml, tmp_path / "scene.toml", text)
    _check_loader(load_chain, tmp_path / "chain.toml", text)
    _cli_case(tmp_path, capsys, text.encode(), ["run", "{f}", "--duration", "1e-9", "--json"])


# -- arbitrary bytes, through the whole command line -----------------------------------
BYTES = st.one_of(st.binary(max_size=64), st.text(max_size=64).map(lambda s: s.encode("utf-8")))


def _cli_case(tmp_path, capsys, data: bytes, argv):
    path = tmp_path / "input.toml"
    path.write_bytes(data)
    code = main([a.replace("{f}", str(path)) for a in argv])
    out, err = capsys.readouterr()
    assert code in (0, 2), (code, data, err)
    assert "Traceback" not in err
    if code == 2:
        assert len(err.splitlines()) == 1 and err.startswith("asperity2d: error: "), err


@settings(FAST, max_examples=60)
@given(data=BYTES)
def test_any_bytes_as_a_scene_file_exit_0_or_2(tmp_path, capsys, data):
    _cli_case(tmp_path, capsys, data, ["run", "{f}", "--duration", "1e-9", "--json"])


@settings(FAST, max_examples=60)
@given(data=BYTES)
def test_any_bytes_as_a_chain_file_exit_0_or_2(tmp_path, capsys, data):
    _cli_case(tmp_path, capsys, data, ["belt", "{f}", "--t-end", "1e-3", "--json"])


@pytest.mark.slow
@SLOW
@given(doc=documents(_scene_keys(), ("scene", "run")))
def test_many_toml_documents_as_scene_files(tmp_path, doc):
    _scene_doc_case(tmp_path, doc)


@pytest.mark.slow
@SLOW
@given(doc=documents(sorted(CHAIN_KEYS), ("friction",)))
def test_many_toml_documents_as_chain_files(tmp_path, doc):
    _chain_doc_case(tmp_path, doc)


@pytest.mark.slow
@SLOW
@given(data=BYTES)
def test_many_byte_strings_as_scene_and_chain_files(tmp_path, capsys, data):
    _cli_case(tmp_path, capsys, data, ["run", "{f}", "--duration", "1e-9", "--json"])
    _cli_case(tmp_path, capsys, data, ["belt", "{f}", "--t-end", "1e-3", "--json"])


# -- every subcommand, with fuzzed options, each within a time budget (issue 27 item 6) -------------
import os  # noqa: E402

from wall_clock import within  # noqa: E402

#: a command that computes is given tiny work; any case still running after this fails the test
CASE_SECONDS = 60.0
TINY = ["--set", "lower_count=2", "--set", "upper_count=1"]
NUMBERS = ["0", "-1", "1", "2", "0.5", "1e-9", "1e300", "nan", "inf", "-inf", "x", "", "100000000000000000000",
           "1e-300", "3,4", "--json"]
OUTPUTS = ["{root}/o.png", "{root}/o.svg", "{root}/o.npz", "{root}/o.csv", "{root}/o.json", "{root}/o.wav",
           "{root}/o.gif", "{root}/o.html", "{root}/o.txt", "", "/proc/o.png", "{root}", "{root}/d/e/o.png",
           "{missing}/o.png", "{scene.toml}/o.png"]
INPUTS = ["{scene.toml}", "{result.npz}", "{nan.npz}", "{chain.toml}", "{study.toml}", "{missing}", "{root}",
          "{notes.txt}", "", "/proc/version", "{store}"]
#: subcommand -> (fixed words, {option: value pool}); each case takes the words and a random subset
#: of the options (values from the pools, or from any pool)
COMMANDS = {
    "run": (["run", "{scene.toml}", "--duration", "1e-9"],
            {"-o": OUTPUTS, "--save": OUTPUTS, "--duration": NUMBERS, "--json": [None], "scene": INPUTS}),
    "analyze": (["analyze", "{result.npz}"], {"--json": [None], "result": INPUTS}),
    "render": (["render", "{result.npz}", "-o", "{root}/r.png"], {"-o": OUTPUTS, "result": INPUTS, "--json": [None]}),
    "critical": (["critical", "{tiny.toml}"], {"--rel-tol": ["0.3", "0.5"] + NUMBERS, "scene": INPUTS,
                                               "--json": [None]}),
    "compare": (["compare", "--seeds", "1", "--variants", "regular", "--measure", "first-breakaway", *TINY],
                {"--seeds": ["1", "2"] + NUMBERS, "--variants": ["regular", "regular,random", "", "x", "regular,"],
                 "--measure": ["first-breakaway", "x", ""], "--save": OUTPUTS, "-o": OUTPUTS,
                 "--load": INPUTS, "--max-runs": NUMBERS, "--set": ["spacing=random", "x=1", "seed=3", "=", "a"],
                 "--workers": NUMBERS, "--json": [None]}),
    "belt": (["belt", "--preset", "table2-3dof", "--t-end", "0.5"],
             {"--preset": ["table2-3dof", "table1-2dof", "x", ""], "--t-end": ["0.5"] + NUMBERS,
              "--method": ["exact", "sign", "x"], "-o": OUTPUTS, "--max-wall-time": ["5"] + NUMBERS,
              "--json": [None], "chain": INPUTS}),
    "basins": (["belt", "basins", "--preset", "table2-3dof", "--grid", "2", "--t-end", "0.5", "--workers", "1",
                "-o", "{root}/b.png"],
               {"--grid": ["2", "2,3", "1"] + NUMBERS, "--t-end": ["0.5"] + NUMBERS, "-o": OUTPUTS,
                "--store": OUTPUTS, "--x": ["x1", "v3", "x9", ""], "--x-range": ["-0.1,0.1", "1,0", "x"] + NUMBERS,
                "--max-runs": NUMBERS, "--rtol": NUMBERS, "--json": [None]}),
    "sweep run": (["sweep", "run", "{study.toml}", "--store", "{root}/s", "--workers", "1", "--no-progress"],
                  {"--store": OUTPUTS, "--max-runs": NUMBERS, "--workers": ["1"] + NUMBERS,
                   "study": INPUTS, "--json": [None]}),
    "sweep status": (["sweep", "status", "{store}"], {"store": INPUTS, "--json": [None]}),
    "sweep report": (["sweep", "report", "{store}", "-o", "{root}/rep.png"], {"-o": OUTPUTS, "store": INPUTS}),
    "sweep export": (["sweep", "export", "{store}", "-o", "{root}/e.csv"], {"-o": OUTPUTS, "store": INPUTS}),
    "version": (["--version"], {}),
}


@pytest.fixture(scope="module")
def cli_files(tmp_path_factory):
    import asperity2d as a
    import numpy as np
    from asperity2d.sweep import ResultStore, Study

    root = tmp_path_factory.mktemp("cli_fuzz")
    f = {"root": str(root), "missing": str(root / "missing")}
    (root / "scene.toml").write_text("lower_count = 2\nupper_count = 1\n")
    (root / "tiny.toml").write_text('lower_count = 2\nupper_count = 1\ndrive = "force"\n')
    result = a.simulate(a.make_scene(lower_count=2, upper_count=1), 4e-9, progress=False)
    result.save(root / "result.npz")
    data = dict(np.load(root / "result.npz"))
    data["v"] = np.full_like(data["v"], np.nan)
    np.savez(root / "nan.npz", **data)
    (root / "chain.toml").write_text('masses = [1.0]\nsprings = [10.0, 0.0]\ndampers = [0.0, 0.0]\nmu_s = 0.3\n'
                                     'v_belt = 0.1\nx0 = [0.0]\nv0 = [0.0]\nt_end = 0.5\n')
    study = {"name": "fuzz", "run": "asperity2d.studies.ooten:critical_force_run", "seeds": 1,
             "grid": {"spacing": ["regular"]}, "fixed": {"lower_count": 2, "upper_count": 1}}
    (root / "study.toml").write_text('name = "fuzz"\nrun = "asperity2d.studies.ooten:critical_force_run"\n'
                                     'seeds = 1\n[grid]\nspacing = ["regular"]\n[fixed]\nlower_count = 2\n'
                                     'upper_count = 1\n')
    ResultStore(root / "store").begin_session(Study.from_dict(study), executor="test")
    (root / "notes.txt").write_text("not a result\n")
    for name in ("scene.toml", "tiny.toml", "result.npz", "nan.npz", "chain.toml", "study.toml", "notes.txt"):
        f[name] = str(root / name)
    f["store"] = str(root / "store")
    return f


#: where each subcommand's positional argument sits in its words
POSITION = {"run": 1, "analyze": 1, "render": 1, "critical": 1, "sweep run": 2, "sweep status": 2,
            "sweep report": 2, "sweep export": 2}


@st.composite
def command_lines(draw):
    name = draw(st.sampled_from(sorted(COMMANDS)))
    words, options = COMMANDS[name]
    argv = list(words)
    everything = [v for pool in options.values() for v in pool]
    chosen = draw(st.lists(st.sampled_from(sorted(options)), unique=True, max_size=3)) if options else []
    for option in chosen:
        pool = options[option] if draw(st.integers(0, 3)) or not everything else everything
        value = draw(st.sampled_from(pool))
        if option in ("scene", "result", "study", "store"):  # the positional argument
            argv[POSITION[name]] = "" if value is None else value
        elif option == "chain":  # `belt CHAIN` instead of `belt --preset NAME`
            argv = ["belt", "" if value is None else value] + argv[3:]
        else:
            if option in argv:  # replace the fixed value
                i = argv.index(option)
                del argv[i:i + (1 if options[option] == [None] else 2)]
            argv += [option] if value is None else [option, value]
    return name, argv


def _fill_words(argv, files):
    out = []
    for word in argv:
        for key, path in files.items():
            word = word.replace("{" + key + "}", path)
        out.append(word)
    return out


def _any_command_case(capsys, files, argv):
    argv = _fill_words(argv, files)
    here = os.getcwd()
    os.chdir(files["root"])  # a relative output such as `--store 0` lands in the test's folder
    try:
        with within(CASE_SECONDS):
            code = main(argv)
    finally:
        os.chdir(here)
    out, err = capsys.readouterr()
    assert code in (0, 2), (argv, code, err)
    assert "Traceback" not in err, (argv, err)
    if code == 2:
        assert len(err.splitlines()) == 1 and err.startswith("asperity2d: error: "), (argv, err)


@settings(FAST, max_examples=80)
@given(case=command_lines())
def test_every_subcommand_answers_exit_0_or_2_within_its_budget(cli_files, capsys, case):
    _any_command_case(capsys, cli_files, case[1])


@pytest.mark.slow
@settings(SLOW, max_examples=1000)
@given(case=command_lines())
def test_every_subcommand_many_times(cli_files, capsys, case):
    _any_command_case(capsys, cli_files, case[1])
