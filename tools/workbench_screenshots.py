"""Screenshots of the workbench for the guide (``docs/guide/workbench.md``), from real runs.

Runs the workbench's browser tests (``tests/test_app_browser.py``: ``asperity2d explore`` in
headless Chromium, driven as a person uses it, at 375, 1000 and 1280 px) and the widget's test in
a headless JupyterLab (``tests/test_app_jupyterlab.py``, the widget in a notebook cell) with
``ASPERITY2D_SHOTS`` pointing at ``docs/_static/workbench/``, where each test saves the page as it
is at that step. Needs the ``app``, ``lab`` and ``test`` extras and Debian's ``chromium`` and
``chromium-driver`` (without JupyterLab its picture is skipped, saying so). About 10 min on a
loaded 2-core machine.

    python tools/workbench_screenshots.py
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SHOTS = ROOT / "docs" / "_static" / "workbench"


def main() -> int:
    SHOTS.mkdir(parents=True, exist_ok=True)
    env = {**os.environ, "ASPERITY2D_SHOTS": str(SHOTS)}
    return subprocess.call([sys.executable, "-m", "pytest", "-n", "0", "-q", "-p", "no:cacheprovider", "-m", "",
                            str(ROOT / "tests" / "test_app_browser.py"), str(ROOT / "tests" / "test_app_jupyterlab.py")],
                           cwd=ROOT, env=env)


if __name__ == "__main__":
    raise SystemExit(main())
