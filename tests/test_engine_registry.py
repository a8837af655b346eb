"""The engine registry (asperity2d.engine.registry): names, the default, refusals, and records
that say which engine made them. Needs no optional dependency."""

import importlib.util
import json
from pathlib import Path

import pytest

import asperity2d as a
from asperity2d.engine import ENGINES, check_engine
from asperity2d.engine import batched
from asperity2d.engine.registry import DEFAULT, refuse
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
    ({"lateral_stiffness": 1e4}, "`lateral_stiffness`"),
    ({"lower_surface": MEASURED}, "`substrate`"),
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


def test_settling_is_refused_on_the_batched_engine():
    scene = a.make_scene(lower_count=4, upper_count=2, track="free")
    assert batched.refusal(scene) is None
    assert batched.refusal(scene, settle=True).startswith("`settle`")


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


def test_the_measures_that_need_settling_are_refused_on_the_batched_engine():
    # without Numba the install line comes first; with it, the critical force's own refusal
    expected = (r"asperity2d\[batch\]" if batched.unavailable() else
                r'critical_force is not available on engine=\'batched\'.*engine="pymunk" runs it')
    with pytest.raises(SceneError, match=expected):
        a.critical_force(a.make_scene(lower_count=4, upper_count=2), engine="batched")
