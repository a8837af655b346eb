"""The documentation's downloadable notebooks execute in a Jupyter kernel (nbclient + ipykernel).

The notebooks are made as the documentation makes them (sphinx-gallery's converter, with the
gallery's first cell, made the script's own: the scene script's quick options and ``__file__``), then executed in a copy
of ``scenes/`` (the folder the first cell asks a reader to run them from); the quickstart, in an empty
folder, as a reader who downloaded it alone would (its ``__file__`` then names no file). Marked slow: the
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
#: (the quickstart, first of its section, runs in an empty folder instead, below: the harder case)
SCRIPTS = _ALL if os.environ.get("ASPERITY2D_NOTEBOOKS") == "all" else [
    names[0] for *_, names in _gallery().SECTIONS if names[0] != "quickstart"]


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


def test_the_quickstart_notebook_runs_in_an_empty_folder(tmp_path):
    """Downloaded from the gallery into any folder: its first cell sets ``__file__`` beside the
    notebook, where no script is. Spawned workers would try to run that missing file; the package's
    measures need nothing from ``__main__``, so ``compare`` starts them without it (it refused with
    "`workers` > 1 needs a main script that worker processes can import" before). Two workers, so
    the pool is used whatever the machine's core count."""
    nb = notebook(ROOT / "scenes" / "quickstart.py",
                  _gallery().first_cell("quickstart").replace('"outputs"]', '"outputs", "--workers", "2"]'))
    assert '"--workers", "2"' in nb.cells[0].source  # the replacement took: the pool is really used
    printed = execute(nb, tmp_path)
    assert "Does random spacing lower the force that breaks the slider loose?" in printed
    assert sorted(p.name for p in tmp_path.iterdir()) == ["outputs"]  # nothing else written: no script there
    assert (tmp_path / "outputs" / "summary.json").stat().st_size > 0
