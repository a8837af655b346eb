"""The import contract (pyproject.toml, ``[tool.importlinter]``): every import points down the
package's layers, lazy function-level imports included, and no sibling modules form a cycle.

Run here so that the README's test command enforces it (by hand: ``lint-imports``). import-linter
reads the imports from the source (grimp), so it also sees imports inside functions.
"""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


def test_imports_point_down_the_layers_and_form_no_cycle(capsys):
    from importlinter.cli import lint_imports

    status = lint_imports(config_filename=str(ROOT / "pyproject.toml"), no_cache=True)
    report = capsys.readouterr().out
    assert status == 0, report
    assert "3 kept, 0 broken" in report, report


def test_the_contract_catches_an_upward_import(tmp_path, monkeypatch, capsys):
    # the check can fail: a copy of the package with one lazy upward import (the model's
    # scene module importing the command line inside a function) breaks the layers contract
    import shutil

    from importlinter.cli import lint_imports

    shutil.copytree(ROOT / "asperity2d", tmp_path / "asperity2d",
                    ignore=shutil.ignore_patterns("__pycache__"))
    scene = tmp_path / "asperity2d" / "scene.py"
    scene.write_text(scene.read_text() + "\n\ndef _upward():\n    from .cli import main  # noqa\n")
    shutil.copy(ROOT / "pyproject.toml", tmp_path / "pyproject.toml")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.chdir(tmp_path)
    for name in [m for m in list(__import__("sys").modules) if m == "asperity2d" or m.startswith("asperity2d.")]:
        monkeypatch.delitem(__import__("sys").modules, name)
    status = lint_imports(config_filename=str(tmp_path / "pyproject.toml"), no_cache=True)
    report = capsys.readouterr().out
    assert status == 1
    assert "asperity2d.scene -> asperity2d.cli.main" in report


@pytest.mark.parametrize("argv, handler, command", [
    (["belt", "chain.toml"], "asperity2d.cli.belt.run", "run"),
    (["belt", "-o", "x.png", "chain.toml"], "asperity2d.cli.belt.run", "run"),
    (["belt", "--preset", "table2-3dof"], "asperity2d.cli.belt.run", "run"),
    (["belt", "run", "chain.toml"], "asperity2d.cli.belt.run", "run"),
    (["belt", "basins", "--preset", "table2-3dof", "--grid", "3"], "asperity2d.cli.basins.run", "basins"),
])
def test_belt_basins_is_a_subcommand_of_the_parser(argv, handler, command):
    from asperity2d.cli.main import build_parser

    args = build_parser().parse_args(argv)
    assert f"{args.handler.__module__}.{args.handler.__name__}" == handler
    assert args.belt_command == command
    if "chain.toml" in argv:
        assert args.chain == "chain.toml"
    if "-o" in argv:  # an option before the chain file is kept, not reset by the subcommand
        assert args.output == "x.png"
    if command == "basins":
        assert args.grid == "3" and args.preset == "table2-3dof"


def test_matplotlib_is_drawn_only_in_the_renderers_and_never_through_pyplot():
    # one plotting home: every figure is a matplotlib.figure.Figure made by renderers.plots.figure
    # (pyplot's global state -- current figure, interactive back ends -- is never touched)
    import re

    package = ROOT / "asperity2d"
    pyplot, outside = [], []
    for path in sorted(package.rglob("*.py")):
        text = path.read_text(encoding="utf-8")
        code = "\n".join(line for line in text.splitlines() if not line.lstrip().startswith("#"))
        if re.search(r"^\s*(from|import)\s+matplotlib\.pyplot|^\s*from\s+matplotlib\s+import\s.*pyplot",
                     code, re.M):
            pyplot.append(path.relative_to(ROOT))
        if re.search(r"^\s*(from|import)\s+matplotlib", code, re.M) and "renderers" not in path.parts:
            outside.append(path.relative_to(ROOT))
    assert not pyplot, f"pyplot used in {pyplot}"
    assert not outside, f"matplotlib imported outside asperity2d/renderers: {outside}"


def test_the_one_import_by_name_points_down_to_a_module_that_answers():
    """The model's notebook display hands objects to a back end named by a string
    (``asperity2d._display.BACKEND``: the dependency inversion that keeps the model below the
    renderers, as pandas' plotting back ends do). The contract cannot read a string, so this
    holds it: the name is a module of the renderers layer, and it draws a scene."""
    import importlib
    import tomllib

    import asperity2d as a
    from asperity2d import _display

    layers = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["importlinter"]
    order = [layer.strip() for layer in layers["contracts"][0]["layers"]]
    assert _display.BACKEND.split(".")[1] == "renderers" and order.index("renderers") < order.index(
        "_io | _inputs | _version | _lazy | _format | _display")
    assert callable(importlib.import_module(_display.BACKEND).represent)
    assert a.make_scene(lower_count=4, upper_count=2)._repr_svg_().lstrip().startswith("<")
