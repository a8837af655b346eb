"""The layout page (``docs/layout.md``) names every module of the package, in its folder's block,
so the page cannot drift from the tree again: a module added without a line there fails here.

The page's tree is one fenced block; a folder's block is its line (``  name/``) and every line
below it indented deeper. A module ``pkg/mod.py`` must appear as the word ``mod`` (or ``mod.py``)
in the block of ``pkg/``; a top-level module as ``name.py`` anywhere in the tree.
"""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "asperity2d"
PAGE = ROOT / "docs" / "layout.md"


def _tree() -> list[str]:
    text = PAGE.read_text(encoding="utf-8")
    blocks = re.findall(r"^```\n(.*?)^```", text, re.S | re.M)
    assert blocks, "docs/layout.md has no fenced tree"
    return blocks[0].splitlines()


def _block(lines: list[str], parents: tuple[str, ...]) -> str:
    """The text of the nested folder ``parents`` (("belt", "chain")): its line and the lines below
    it indented deeper, narrowed folder by folder."""
    for name in parents:
        start = next((i for i, line in enumerate(lines) if re.match(rf"^\s*{re.escape(name)}/(\s|$)", line)), None)
        assert start is not None, f"docs/layout.md has no line for the folder {'/'.join(parents)}/"
        indent = len(lines[start]) - len(lines[start].lstrip())
        end = start + 1
        while end < len(lines) and (not lines[end].strip() or len(lines[end]) - len(lines[end].lstrip()) > indent):
            end += 1
        lines = lines[start:end]
    return "\n".join(lines)


def _modules():
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE)
        if path.name != "__init__.py" and "assets" not in rel.parts:
            yield rel


def test_every_module_of_the_package_is_on_the_layout_page():
    lines = _tree()
    whole = "\n".join(lines)
    missing = []
    for rel in _modules():
        if len(rel.parts) == 1:
            found = rel.name in whole
        else:
            block = _block(lines, rel.parts[:-1])
            found = re.search(rf"(?<![\w.]){re.escape(rel.stem)}(\.py)?(?![\w])", block) is not None
        if not found:
            missing.append(str(rel))
    assert not missing, f"docs/layout.md does not name {', '.join(missing)} (add each in its folder's block)"


def test_every_folder_of_the_package_is_on_the_layout_page():
    lines = _tree()
    for init in PACKAGE.rglob("__init__.py"):
        rel = init.parent.relative_to(PACKAGE)
        if rel.parts:
            _block(lines, rel.parts)  # asserts the folder has its line


def test_the_check_fails_for_a_module_the_page_does_not_name():
    # the check can fail: a module that does not exist is not found in its folder's block
    block = _block(_tree(), ("belt", "chain"))
    assert re.search(r"(?<![\w.])hybrid(\.py)?(?![\w])", block)
    assert not re.search(r"(?<![\w.])no_such_module(\.py)?(?![\w])", block)
    assert "spec" not in _block(_tree(), ("belt", "phases"))  # spec is belt's, not phases'
