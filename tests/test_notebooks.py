"""The documentation's downloadable notebooks execute in a Jupyter kernel (nbclient + ipykernel).

The notebooks are made as the documentation makes them (sphinx-gallery's converter, with the
gallery's first cell, made the script's own: the scene script's quick options and ``__file__``), then executed in a copy
of ``scenes/`` (the folder the first cell asks a reader to run them from). Marked slow: the
default run leaves them out; CI runs them after installing the docs extra::

    python -m pytest -q -m slow tests/test_notebooks.py

Without nbclient, ipykernel or sphinx-gallery they skip, saying so.
"""

from __future__ import annotations

import importlib.util
import os
import shutil
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
MISSING = [m for m in ("nbclient", "nbformat", "ipykernel", "sphinx_gallery") if importlib.util.find_spec(m) is None]
pytestmark = [pytest.mark.slow,
              pytest.mark.skipif(bool(MISSING), reason=f"needs the docs extra ({', '.join(MISSING)} missing)")]


def _gallery():
    spec = importlib.util.spec_from_file_location("docs_gallery", DOCS / "_ext" / "gallery.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def notebook(script: Path, first_cell: str | None):
    """The notebook sphinx-gallery makes of ``script``."""
    import nbformat
    from sphinx_gallery.gen_gallery import DEFAULT_GALLERY_CONF
    from sphinx_gallery.notebook import jupyter_notebook
    from sphinx_gallery.py_source_parser import split_code_and_text_blocks

    conf = {**DEFAULT_GALLERY_CONF, "first_notebook_cell": first_cell, "last_notebook_cell": None}
    _, blocks = split_code_and_text_blocks(str(script))[:2]
    nb = nbformat.from_dict(jupyter_notebook(blocks, conf, script.parent))
    for cell in nb.cells:  # as a saved .ipynb reads back: each source one string
        if isinstance(cell.source, list):
            cell.source = "".join(cell.source)
    return nb


@pytest.fixture(autouse=True)
def _kernel_environment(monkeypatch):
    monkeypatch.setenv("TQDM_DISABLE", "1")  # the kernel inherits it: no progress bars
    monkeypatch.setenv("MPLBACKEND", "Agg")


def execute(nb, cwd: Path, timeout: int = 900):
    from nbclient import NotebookClient

    NotebookClient(nb, timeout=timeout, kernel_name="python3", resources={"metadata": {"path": str(cwd)}}).execute()
    return "".join(o.get("text", "") for cell in nb.cells if cell.cell_type == "code"
                   for o in cell.get("outputs", []) if o.get("output_type") == "stream")


def test_tutorial_notebook_executes(tmp_path):
    nb = notebook(DOCS / "tutorial_src" / "first_study.py", None)
    printed = execute(nb, tmp_path)
    assert "Random spacing lowers the critical force:" in printed
    assert (tmp_path / "first_study" / "run.mat").stat().st_size > 0


#: CI executes the first lesson of each gallery section (every script also runs as a script in
#: the docs build and in tests/test_scripts.py; what a notebook adds is the kernel's own argv and
#: working folder, the same for every script); ASPERITY2D_NOTEBOOKS=all executes all of them
#: (about 20 minutes on 2 cores).
_ALL = [name for *_, names in _gallery().SECTIONS for name in names]
SCRIPTS = _ALL if os.environ.get("ASPERITY2D_NOTEBOOKS") == "all" else [names[0] for *_, names in _gallery().SECTIONS]


@pytest.mark.parametrize("name", SCRIPTS)
def test_gallery_notebook_executes_in_jupyter(name, tmp_path):
    """The kernel's own ``-f`` argument does not reach the script's parser; the outputs land in
    ./outputs, and the script's summary is printed there."""
    scenes = tmp_path / "scenes"
    shutil.copytree(ROOT / "scenes", scenes, ignore=shutil.ignore_patterns("__pycache__"))
    nb = notebook(scenes / f"{name}.py", _gallery().first_cell(name))
    execute(nb, scenes)
    written = [p for p in (scenes / "outputs").rglob("*") if p.is_file()]
    assert written, f"{name}: the notebook wrote nothing to ./outputs"
