"""The engine registry (asperity2d.engine.registry): names, the default, refusals, and records
that say which engine made them. Needs no optional dependency."""

import importlib.util
import json
from pathlib import Path

import pytest

import asperity2d as a
from asperity2d.engine import ENGINES, check_engine
from asperity2d.engine import batched
from asperity2d.engine.registry import DEFAULT, choose_engine, engine_label, refuse
from asperity2d.errors import SceneError
from asperity2d.experiments.compare import Comparison

#: A measured-style profile shipped with the package: its asperities and its rigid valleys.
MEASURED = Path(__file__).resolve().parent.parent / "scenes" / "data" / "measured_style_profile.csv"


def test_the_reference_is_first_and_the_default():
    assert list(ENGINES) == ["pymunk", "batched"]
    assert DEFAULT == "pymunk"
    assert ENGINES["pymunk"].unavailable() is None
    assert ENGINES["pymunk"].run is None  # its runs are asperity2d.Run


def test_an_unknown_engine_is_one_line_naming_the_parameter():
    with pytest.raises(SceneError, match=r"`engine` must be one of pymunk, batched, got 'gpu'"):
        check_engine("gpu")
    with pytest.raises(SceneError, match="`engine` must be one of"):
        a.simulate(a.make_scene(lower_count=2, upper_count=1), 1e-9, engine=3)


def test_without_numba_the_batched_engine_says_how_to_install_it(monkeypatch):
    real = importlib.util.find_spec
    monkeypatch.setattr(batched.importlib.util, "find_spec", lambda name, *rest: None if name == "numba" else real(name, *rest))
    with pytest.raises(SceneError) as info:
        check_engine("batched")
    message = str(info.value)
    assert 'pip install "asperity2d[batch]"' in message and "\n" not in message
    with pytest.raises(SceneError, match=r"asperity2d\[batch\]"):
        a.simulate(a.make_scene(lower_count=2, upper_count=1), 1e-9, engine="batched")
    # the reference runs regardless
    assert a.simulate(a.make_scene(lower_count=2, upper_count=1), 1e-9).meta["engine"] == "pymunk"


@pytest.mark.parametrize("kwargs, option", [
    ({"contact_law": "viscous"}, "`contact_law`"),
    ({"slider_start": -4e-6}, "`slider_start`"),
])
def test_the_batched_engine_refuses_what_it_does_not_implement_in_one_line(kwargs, option):
    size = {} if "lower_surface" in kwargs else {"lower_count": 4, "upper_count": 2}
    try:
        scene = a.make_scene(**size, **kwargs)
    except SceneError as exc:  # an option this build of make_scene does not take
        pytest.skip(f"make_scene does not take {kwargs}: {exc}")
    assert ENGINES["pymunk"].refusal(scene) is None
    with pytest.raises(SceneError) as info:
        refuse("batched", scene)
    message = str(info.value)
    assert message.startswith(option) and message.endswith('engine="pymunk" runs it') and "\n" not in message


def test_settling_is_not_refused_on_the_batched_engine():
    # it settles as the reference does (tests/test_engine_critical.py compares the two)
    scene = a.make_scene(lower_count=4, upper_count=2, track="free")
    assert batched.refusal(scene) is None
    assert batched.refusal(scene, settle=True) is None


def test_results_and_comparisons_say_which_engine_made_them(tmp_path):
    result = a.simulate(a.make_scene(lower_count=2, upper_count=1), 1e-9)
    assert result.meta["engine"] == "pymunk"
    c = Comparison(values={"regular": (1.0, 2.0)}, seeds=(0, 1), measure="peak-stick", engine="batched")
    path = c.save(tmp_path / "c.json")
    assert json.loads(path.read_text())["engine"] == "batched"
    assert Comparison.load(path) == c
    # a comparison saved before engines were recorded was made by the reference
    data = json.loads(path.read_text())
    del data["engine"]
    (tmp_path / "old.json").write_text(json.dumps(data))
    assert Comparison.load(tmp_path / "old.json").engine == "pymunk"


def test_the_critical_force_on_the_batched_engine_refuses_what_it_does_not_implement():
    # without Numba the install line comes first; with it, the option it does not implement, named
    expected = (r"asperity2d\[batch\]" if batched.unavailable() else
                r'^`contact_law` .* is not implemented on engine="batched" .*; engine="pymunk" runs it$')
    with pytest.raises(SceneError, match=expected):
        a.critical_force(a.make_scene(lower_count=4, upper_count=2, contact_law="viscous"), engine="batched")


def _numba(monkeypatch, present: bool):
    """Make Numba look installed or missing to the batched engine (nothing compiles here)."""
    real = importlib.util.find_spec
    monkeypatch.setattr(batched.importlib.util, "find_spec",
                        lambda name, *rest: (real("json") if present else None) if name == "numba" else real(name, *rest))


def test_auto_takes_the_batched_engine_only_where_it_is_installed_and_runs_every_scene(monkeypatch):
    fixed = a.make_scene(lower_count=4, upper_count=2, spacing="random", seed=3)
    _numba(monkeypatch, True)
    assert choose_engine("auto", [fixed, a.make_scene(lower_count=4, upper_count=2)]) == "batched"
    # one scene it does not implement keeps the whole ensemble on the reference
    assert choose_engine("auto", [fixed, a.make_scene(lower_count=4, upper_count=2, contact_law="viscous")]) == "pymunk"
    # a free slider settles (as simulate decides it), which the batched engine does as well
    free = a.make_scene(lower_count=4, upper_count=2, track="free")
    assert choose_engine("auto", [free]) == "batched"
    assert choose_engine("auto", [free], settle=False) == "batched"
    # a named engine is that engine, checked
    assert choose_engine("pymunk", [fixed]) == "pymunk"
    with pytest.raises(SceneError, match="`engine` must be one of"):
        choose_engine("gpu", [fixed])
    _numba(monkeypatch, False)
    assert choose_engine("auto", [fixed]) == "pymunk"


def test_output_names_the_engine_and_its_package():
    assert engine_label("pymunk") == "pymunk"
    assert engine_label("batched") == "batched (Numba)"


def test_compare_with_seeds_auto_asks_the_registry_and_records_its_answer(monkeypatch):
    """``compare(seeds="auto")`` of a measure with a batched form runs it on the batched engine
    where that is installed (its batched form is replaced here by a stand-in that records the
    engine it was given and returns a clear effect, so nothing compiles or steps)."""
    from asperity2d.experiments import compare as compare_module

    given = []

    def stand_in(scenes, engine):
        given.append(engine)
        return [1.0 if scene.name.startswith("regular") else 0.5 for scene in scenes]

    monkeypatch.setitem(compare_module.BATCHED, "peak-stick", stand_in)
    variants = {"regular": {"spacing": "regular"}, "random": {"spacing": "random"}}
    _numba(monkeypatch, True)
    c = a.compare("peak-stick", variants, "auto", base={"lower_count": 4, "upper_count": 2}, progress=False)
    assert c.engine == "batched" and set(given) == {"batched"}
    assert set(c.values["random"]) == {0.5} and set(c.values["regular"]) == {1.0}
    # named seeds keep the reference unless told; "auto" asks
    given.clear()
    c = a.compare("peak-stick", variants, range(3), base={"lower_count": 4, "upper_count": 2}, progress=False,
                  engine="auto")
    assert c.engine == "batched" and given == ["batched"]


def test_the_command_lines_compare_takes_the_apis_engine_rule():
    """``asperity2d compare`` without ``--engine`` leaves the choice to ``compare()`` (auto with
    ``--seeds auto``, else pymunk): one rule, not a second default in the command line."""
    from asperity2d.cli.main import build_parser

    parser = build_parser()
    assert parser.parse_args(["compare", "--seeds", "auto"]).engine is None
    assert parser.parse_args(["compare", "--engine", "auto"]).engine == "auto"
    assert parser.parse_args(["run", "scene.toml"]).engine == "pymunk"  # one run: the reference


def test_the_engine_flag_takes_what_the_registry_knows_and_names_itself(tmp_path, capsys):
    """``--engine`` is checked by the registry (so an installed package's engine reaches the
    command line), and a misspelt one is one line naming the flag with the nearest name."""
    from asperity2d.cli.main import main

    assert main(["run", "scenes/default.toml", "--engine", "batchd", "-o", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.endswith("`--engine` must be one of pymunk, batched, got 'batchd' (did you mean 'batched'?)")
    assert "\n" not in err
    assert main(["compare", "--engine", "nosuch", "--seeds", "2"]) == 2
    assert "`--engine`" in capsys.readouterr().err
