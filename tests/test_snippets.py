"""Every code snippet of the README and the documentation runs, so none can go stale.

* ```python blocks run in order, one namespace per page (a page reads as one session), in a
  scratch directory where ``scenes/`` is the repository's;
* ```toml blocks are built: a scene (make_scene's keywords) into a Scene, a chain into
  simulate_chain's arguments, a study into a Study;
* ```bash blocks: every ``asperity2d ...`` line must parse with the command line's own parser
  and every ``scenes/...`` file it names must exist (they are not run: some take hours).

The snippets are written to be quick (a few asperities, a few seeds); the whole module takes
about a minute of CPU.
"""

from __future__ import annotations

import importlib.util
import os
import re
import shlex
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SCENES = ROOT / "scenes"
PAGES = [ROOT / "README.md"] + sorted(
    p for p in (ROOT / "docs").rglob("*.md")
    if not {"_build", "api", "auto_scenes"} & set(p.relative_to(ROOT / "docs").parts))
#: Snippets that need an optional extra: (text in the snippet, the module it needs, the extra). Where
#: the module is missing, that snippet is left out and the test says so (.ci/run runs them with it).
EXTRAS = (('engine="batched"', "numba", "batch"),)
FENCE = re.compile(r"^(`{3,})\s*\{?([\w-]*)\}?[^\n]*\n(.*?)^\1\s*$", re.S | re.M)


def blocks(page: Path, language: str) -> list[tuple[int, str]]:
    """``(line, code)`` of every fenced block of ``language`` in ``page``."""
    text = page.read_text(encoding="utf-8")
    return [(text[:m.start()].count("\n") + 1, m.group(3)) for m in FENCE.finditer(text)
            if m.group(2) == language]


def _id(page: Path) -> str:
    return str(page.relative_to(ROOT))


@pytest.fixture
def scratch(tmp_path, monkeypatch):
    """A scratch working directory whose ``scenes`` is the repository's."""
    (tmp_path / "scenes").symlink_to(SCENES, target_is_directory=True)
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    return tmp_path


def test_every_page_with_code_is_found():
    assert (ROOT / "README.md") in PAGES and len(PAGES) >= 15
    assert sum(len(blocks(p, "python")) for p in PAGES) >= 20


@pytest.mark.parametrize("page", [p for p in PAGES if blocks(p, "python")], ids=_id)
def test_python_snippets_run(page, scratch, capsys):
    namespace = {"__name__": "__snippet__"}
    left_out = []
    for line, code in blocks(page, "python"):
        extra = next((extra for text, module, extra in EXTRAS
                      if text in code and importlib.util.find_spec(module) is None), None)
        if extra is not None:
            left_out.append(f'line {line} (needs pip install "asperity2d[{extra}]")')
            continue
        try:
            exec(compile(code, f"{_id(page)}:{line}", "exec"), namespace)
        except Exception as exc:  # noqa: BLE001 - name the snippet that broke
            raise AssertionError(f"the snippet at {_id(page)} line {line} raised "
                                 f"{type(exc).__name__}: {exc}") from exc
    capsys.readouterr()
    if left_out:
        pytest.skip(f"every snippet of {_id(page)} ran but {', '.join(left_out)}")


def _toml_kind(data: dict) -> str:
    if "run" in data and ("grid" in data or "seeds" in data):
        return "study"
    if "masses" in data:
        return "chain"
    return "scene"


@pytest.mark.parametrize("page", [p for p in PAGES if blocks(p, "toml")], ids=_id)
def test_toml_snippets_build(page, scratch):
    from asperity2d.cli.asperity import scene_from_toml
    from asperity2d.belt import read_chain as load_chain
    from asperity2d.scene import Scene
    from asperity2d.sweep import load_study

    (scratch / "data").symlink_to(SCENES / "data", target_is_directory=True)  # profiles named relative
    for line, code in blocks(page, "toml"):
        path = scratch / f"snippet_{line}.toml"
        path.write_text(code, encoding="utf-8")
        kind = _toml_kind(tomllib.loads(code))
        where = f"the TOML at {_id(page)} line {line}"
        if kind == "scene":
            scene, _ = scene_from_toml(path)
            assert isinstance(scene, Scene), where
        elif kind == "chain":
            assert load_chain(path)["masses"], where
        else:
            assert load_study(path).runs(), where


def _commands(page: Path):
    for line, code in blocks(page, "bash"):
        for text in code.replace("\\\n", " ").splitlines():
            text = text.split("  #")[0].strip()
            for command in re.split(r"\s*(?:&&|;)\s*", text):
                yield line, command


@pytest.mark.parametrize("page", [p for p in PAGES if blocks(p, "bash")], ids=_id)
def test_command_lines_parse_and_name_existing_files(page):
    from asperity2d.cli.main import build_parser

    parser = build_parser()
    checked = 0
    for line, command in _commands(page):
        words = shlex.split(command)
        for word in words:  # every shipped file a command names exists
            if word.startswith("scenes/"):
                assert (ROOT / word).exists(), f"{_id(page)} line {line}: {word} does not exist"
        if words[:1] == ["asperity2d"]:
            try:
                parser.parse_args(words[1:])
            except SystemExit as exc:  # argparse's way to refuse (code 2), or to answer --version (0)
                if exc.code != 0:
                    raise AssertionError(f"{_id(page)} line {line}: `{command}` does not parse") from exc
            checked += 1
    assert checked or not any(c.startswith("asperity2d") for _, c in _commands(page))


def test_the_example_toml_scenes_run(scratch, capsys):
    """scenes/*.toml (the README and the docs use them) run from the command line."""
    import json

    from asperity2d.cli.main import main

    for name in ("default", "free_slider", "rough"):
        assert main(["run", str(SCENES / f"{name}.toml"), "--json"]) == 0, name
        summary = json.loads(capsys.readouterr().out)
        assert summary["status"] == "passed", name
    assert main(["belt", str(SCENES / "chain.toml"), "--json"]) == 0
    chain = json.loads(capsys.readouterr().out)
    assert chain["n"] == 3 and chain["regime"] == "stick-slip"
    assert os.listdir(scratch) == ["scenes"]  # nothing written without -o / --save
