"""``asperity2d.explore()`` in a real JupyterLab, driven by headless Chromium.

A JupyterLab server starts in an empty temporary folder (its settings, workspaces and runtime
files there too, on loopback with a random token); Chromium opens a notebook whose one cell
calls ``asperity2d.explore(...)``, runs it as a person would (Run All), and the test checks that
the widget renders in the cell's output (anywidget's front end loads the workbench's module),
that its first run streams in and that the player draws it (frames past the first, pixels on
the stage's canvas), with no widget error in the output and no console error. Screenshots go to
``$ASPERITY2D_SHOTS`` when set (``tools/workbench_screenshots.py``).

Needs JupyterLab (the ``lab`` extra), the ``app`` extra and Debian's ``chromium`` and
``chromium-driver``; skipped, saying which is missing, without them. Marked slow (~40 s here:
JupyterLab's start-up and its first page load dominate); ``.ci/run`` runs it on its own.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest

from test_player_browser import INSTALL, _missing, chromium

pytestmark = pytest.mark.slow


def _lab_missing() -> str | None:
    try:
        import jupyterlab  # noqa: F401
    except ImportError:
        return 'JupyterLab is not installed: pip install -e ".[lab,test]"'
    try:
        import anywidget  # noqa: F401
    except ImportError:
        return 'anywidget is not installed: pip install -e ".[app,test]"'
    if _missing() is not None:
        return f"{_missing()}: {INSTALL}"
    return None


if _lab_missing() is not None:
    pytest.skip(_lab_missing(), allow_module_level=True)

SHOTS = os.environ.get("ASPERITY2D_SHOTS")
TOKEN = "asperity2d-lab-" + os.urandom(8).hex()
CELL = "import asperity2d\nasperity2d.explore(lower_count=6, upper_count=2)"


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def lab():
    """``jupyter lab`` in an empty folder: ``(url of the notebook, folder)``."""
    root = Path(tempfile.mkdtemp(prefix="asperity2d-lab-"))
    work = root / "work"
    work.mkdir()
    notebook = {"cells": [{"cell_type": "code", "execution_count": None, "id": "explore", "metadata": {},
                           "outputs": [], "source": CELL}],
                "metadata": {"kernelspec": {"display_name": "Python 3", "language": "python", "name": "python3"}},
                "nbformat": 4, "nbformat_minor": 5}
    (work / "explore.ipynb").write_text(json.dumps(notebook))
    env = {**os.environ, "JUPYTER_CONFIG_DIR": str(root / "config"), "JUPYTER_RUNTIME_DIR": str(root / "runtime"),
           "JUPYTERLAB_SETTINGS_DIR": str(root / "settings"), "JUPYTERLAB_WORKSPACES_DIR": str(root / "workspaces"),
           "IPYTHONDIR": str(root / "ipython")}
    news = root / "settings" / "@jupyterlab" / "apputils-extension"  # no "Jupyter news?" toast over the cell
    news.mkdir(parents=True)
    (news / "notification.jupyterlab-settings").write_text(json.dumps({"fetchNews": "false"}))
    port = _free_port()
    log = open(root / "lab.log", "w")
    proc = subprocess.Popen([sys.executable, "-m", "jupyter", "lab", "--no-browser", "--ip=127.0.0.1",
                             f"--port={port}", "--port-retries=0", f"--ServerApp.root_dir={work}",
                             f"--IdentityProvider.token={TOKEN}", "--LabApp.expose_app_in_browser=True",
                                                          *(["--allow-root"] if hasattr(os, "geteuid") and os.geteuid() == 0 else [])],  # CI runs as root
                            cwd=work, env=env, stdout=log, stderr=subprocess.STDOUT)
    base = f"http://127.0.0.1:{port}"
    try:
        import urllib.request

        end = time.monotonic() + 120
        while True:  # the server answers its API once it is up
            try:
                with urllib.request.urlopen(f"{base}/api/status?token={TOKEN}", timeout=2) as r:
                    if r.status == 200:
                        break
            except OSError:
                pass
            assert proc.poll() is None and time.monotonic() < end, (root / "lab.log").read_text()[-3000:]
            time.sleep(0.25)
        yield f"{base}/lab/tree/explore.ipynb?token={TOKEN}", root
    finally:
        proc.send_signal(signal.SIGINT)
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait(10)
        log.close()
        shutil.rmtree(root, ignore_errors=True)


@pytest.fixture(scope="module")
def browser():
    with chromium(window="1280,900", page_load_timeout=60) as driver:
        yield driver


def wait_for(browser, script, timeout=180.0, what=""):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = browser.execute_script(script)
        if value:
            return value
        time.sleep(0.1)
    raise AssertionError(f"timed out waiting for {what or script}")


def test_the_widget_renders_and_runs_in_jupyterlab(lab, browser):
    url, root = lab
    browser.get(url)
    # JupyterLab has opened the notebook and its kernel is idle
    wait_for(browser, "const a = window.jupyterapp; const w = a && a.shell.currentWidget;"
                      "return !!(w && w.sessionContext && w.sessionContext.session && w.sessionContext.session.kernel"
                      " && w.sessionContext.session.kernel.status === 'idle' && w.content && w.content.widgets.length);",
             timeout=180, what="the notebook and its kernel")
    started = time.monotonic()
    browser.execute_script("window.jupyterapp.commands.execute('notebook:run-all-cells')")
    # the widget renders in the cell's output: the workbench's own element, its controls built
    wait_for(browser, "const e = document.querySelector('.jp-OutputArea .aw'); return !!(e && e.asperityWorkbench"
                      " && e.asperityWorkbench.state().schema);", timeout=180, what="the widget in the output")
    rendered_s = time.monotonic() - started
    # its first run streams in and the player draws it
    wait_for(browser, "const s = document.querySelector('.jp-OutputArea .aw').asperityWorkbench.state();"
                      "return s.run.finished && s.run.samples > 1000;", timeout=240, what="the first run")
    probe = browser.execute_script("""
        const w = document.querySelector('.jp-OutputArea .aw').asperityWorkbench, p = w.player();
        p.api.seek(p.api.t1 * 0.5);
        const c = document.querySelector('.jp-OutputArea .aw .ap-scene'), d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
        const colours = new Set(); for (let i = 0; i < d.length; i += 4 * 97) colours.add(d[i] << 16 | d[i + 1] << 8 | d[i + 2]);
        const s = w.state();
        return {samples: s.run.samples, status: s.run.summary && s.run.summary.status, index: p.api.state().index,
                colours: colours.size, width: c.width, controls: document.querySelectorAll('.jp-OutputArea .aw-control').length,
                errors: [...document.querySelectorAll('.jp-OutputArea [data-mime-type="application/vnd.jupyter.stderr"]')].map((e) => e.textContent)};""")
    import asperity2d as a
    from asperity2d.app.controls import RUN_CONTROLS
    from asperity2d.builders import KEYWORDS, PARAMETERS

    result = a.simulate(a.make_scene(lower_count=6, upper_count=2))
    assert probe["samples"] == len(result.t) and probe["status"] == result.status  # the kernel's run, every sample
    assert probe["index"] > 0 and probe["width"] > 200 and probe["colours"] > 5, probe  # frames past the first, drawn
    assert probe["controls"] == len(KEYWORDS + PARAMETERS) + len(RUN_CONTROLS)
    assert probe["errors"] == [], probe["errors"]
    text = browser.execute_script("return document.querySelector('.jp-OutputArea').textContent")
    assert "Error displaying widget" not in text and "Failed to load model" not in text
    # at the cell's width nothing is cut off: every header button and every meter's menu and
    # buttons inside the widget's box and their meter's
    cut = browser.execute_script("""
        const aw = document.querySelector('.jp-OutputArea .aw'), R = aw.getBoundingClientRect(), out = [];
        for (const b of aw.querySelectorAll('.aw-header > *:not(.aw-status)')) { const r = b.getBoundingClientRect();
          if (r.width && (r.right > R.right + 1 || r.left < R.left - 1)) out.push(b.textContent); }
        for (const m of aw.querySelectorAll('.aw-player .ap-meter')) { const M = m.getBoundingClientRect();
          for (const b of m.querySelectorAll('.ap-meter-head select, .ap-meter-head button')) { const r = b.getBoundingClientRect();
            if (r.right > M.right + 1) out.push(b.textContent.slice(0, 20)); } }
        return [out, R.width];""")
    assert cut[0] == [], cut
    severe = [e for e in browser.get_log("browser") if e["level"] == "SEVERE" and "favicon" not in e["message"]]
    assert severe == [], severe
    print(f"widget rendered {rendered_s:.1f} s after Run All")
    if SHOTS:
        Path(SHOTS).mkdir(parents=True, exist_ok=True)
        browser.execute_script("document.querySelector('.jp-OutputArea .aw').scrollIntoView()")
        time.sleep(0.5)
        browser.save_screenshot(str(Path(SHOTS) / "jupyterlab.png"))
