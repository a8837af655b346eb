"""The gallery's scripts teach the public API: they import nothing a user could not.

A scene script is a lesson (the documentation shows it cell by cell, and offers it as a
notebook), so every ``asperity2d`` name it imports must be one the API reference documents: the
top-level names, the modules of the reference (``docs/_ext/asperity_docs.py``'s ``API``) and
their public names (``__all__``, or else the names the module defines without a leading
underscore), ``asperity2d.renderers`` through ``render`` alone. Never the command line's
modules, a private module, a renderer's own module or an internal module of a package.
"""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SCENES = sorted((ROOT / "scenes").glob("*.py"))


def _api_modules() -> set[str]:
    # read as data: the extension itself imports Sphinx, which the default test run does not have
    tree = ast.parse((ROOT / "docs" / "_ext" / "asperity_docs.py").read_text(encoding="utf-8"))
    api = next(ast.literal_eval(n.value) for n in tree.body
               if isinstance(n, ast.Assign) and any(getattr(t, "id", "") == "API" for t in n.targets))
    names = {name for name, *_ in api}
    import pkgutil

    for package in ("asperity2d.experiments", "asperity2d.studies"):  # listed with their submodules
        if package in names:
            names |= {f"{package}.{m.name}" for m in pkgutil.iter_modules(importlib.import_module(package).__path__)}
    names -= {"asperity2d.studies.claims"}  # hidden from the reference (HIDDEN_MODULES there)
    return names


API = _api_modules()
#: Modules a lesson may import only some names of (the rest of them is implementation).
ONLY = {"asperity2d.renderers": {"render", "FORMATS"}}
#: Study code a lesson does not use: its verdicts are asperity2d.experiments.verdicts'.
NOT_FOR_LESSONS = {"asperity2d.studies.claims"}


def _public(module_name: str, name: str) -> bool:
    if module_name in ONLY:
        return name in ONLY[module_name]
    if name.startswith("_"):
        return False
    module = importlib.import_module(module_name)
    listed = getattr(module, "__all__", None)
    if listed is not None:
        return name in listed or f"{module_name}.{name}" in API
    return hasattr(module, name)


def offences(path: Path) -> list[str]:
    """Every import of ``path`` that is not public API, as ``line: what``."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("asperity2d") and (alias.name not in API or alias.name in NOT_FOR_LESSONS):
                    found.append(f"{node.lineno}: import {alias.name}")
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and (node.module or "").startswith("asperity2d"):
            module = node.module
            if module not in API or module in NOT_FOR_LESSONS:
                found.append(f"{node.lineno}: from {module} import ...")
                continue
            for alias in node.names:
                submodule = f"{module}.{alias.name}"
                if submodule in NOT_FOR_LESSONS:
                    found.append(f"{node.lineno}: from {module} import {alias.name}")
                elif submodule not in API and not _public(module, alias.name):
                    found.append(f"{node.lineno}: from {module} import {alias.name}")
    return found


def test_the_checker_catches_a_private_import(tmp_path):
    script = tmp_path / "s.py"
    script.write_text("import asperity2d as a\nfrom asperity2d import scripting, stats\n"
                      "from asperity2d._format import si\nfrom asperity2d.renderers.plots import figure\n"
                      "from asperity2d.renderers import render\nfrom asperity2d.belt import simulate_chain\n"
                      "from asperity2d.cli import scripting as old\nfrom asperity2d.studies import claims\n",
                      encoding="utf-8")
    assert offences(script) == ["3: from asperity2d._format import ...",
                                "4: from asperity2d.renderers.plots import ...",
                                "7: from asperity2d.cli import ...",
                                "8: from asperity2d.studies import claims"]


@pytest.mark.parametrize("path", SCENES, ids=[p.stem for p in SCENES])
def test_a_scene_script_imports_only_public_names(path):
    assert offences(path) == []
