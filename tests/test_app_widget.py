"""``asperity2d.explore`` in a real Jupyter kernel (nbclient + ipykernel): a notebook creates the
widget, displays it, drives it through its protocol end as the front end would, and the widget's
synced state (values, status, samples, the scene as TOML) is read back from the kernel and
checked against a run of the same scene here. (Its front end rendered in Chromium: the browser
test.) Cost: ~10 s (the kernel's start-up and one small run).
"""

from __future__ import annotations

import json
import tomllib

import pytest

nbformat = pytest.importorskip("nbformat", reason='needs nbformat, nbclient and ipykernel: pip install -e ".[test]"')
nbclient = pytest.importorskip("nbclient", reason='needs nbclient: pip install -e ".[test]"')
pytest.importorskip("ipykernel", reason='needs ipykernel: pip install -e ".[test]"')
pytest.importorskip("anywidget", reason='needs the app extra: pip install -e ".[test]"')

import asperity2d as a  # noqa: E402

CELLS = [
    "import asperity2d, json, time\nw = asperity2d.explore(lower_count=6, upper_count=2)\nw",
    # what the front end sends on a change (the widget's custom message), handled by the kernel
    "w.session.handle({'type': 'set', 'values': {'lower_count': '6', 'upper_count': '2', 'mu_static': '0.4'}})\n"
    "end = time.monotonic() + 120\n"
    "while not w.status.startswith('done') and time.monotonic() < end:\n"
    "    time.sleep(0.05)\n"
    "print(json.dumps({'status': w.status, 'samples': w.samples, 'values': w.values, 'toml': w.toml,\n"
    "                  'esm': len(w._esm), 'result': len(w.session.result.t)}))",
    "w.session.handle({'type': 'set', 'values': {'mass': '-1'}})\nprint(json.dumps(w.status))",
]


def test_the_widget_in_a_jupyter_kernel():
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(c) for c in CELLS])
    client = nbclient.NotebookClient(nb, timeout=180, kernel_name="python3", allow_errors=False)
    client.execute()
    shown = nb.cells[0].outputs[0]["data"]
    assert "application/vnd.jupyter.widget-view+json" in shown  # displayed as a widget, not text
    state = json.loads(nb.cells[1].outputs[0]["text"])
    assert state["status"] == "done: passed"
    assert state["values"] == {"lower_count": "6", "upper_count": "2", "mu_static": "0.4"}
    result = a.simulate(a.make_scene(lower_count=6, upper_count=2, mu_static=0.4))
    assert state["samples"] == state["result"] == len(result.t)  # every sample streamed to the view
    assert tomllib.loads(state["toml"])["scene"] == {"lower_count": 6, "upper_count": 2, "mu_static": 0.4}
    assert state["esm"] > 10_000
    refused = json.loads(nb.cells[2].outputs[0]["text"])
    assert refused == "refused: `mass` must be > 0, got -1"
