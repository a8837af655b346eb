"""Start-up stays light: ``import asperity2d``, ``--help`` and bad-input errors load no heavy library.

Each check runs a fresh interpreter (what a user starts) and lists the heavy
modules it loaded. Timing lives in ``benchmarks/bench_startup.py``; these
tests check the mechanism (what is imported), which does not depend on load.
Cost: ~1.5 s (six interpreters).
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

HEAVY = ("numpy", "scipy", "matplotlib", "dask", "pymunk", "PIL", "tqdm", "asperity2d.belt.solver")

PROBE = """
import json, sys
{code}
print(json.dumps(sorted(m for m in {heavy!r} if m in sys.modules)))
"""


def _loaded(code: str) -> list[str]:
    proc = subprocess.run([sys.executable, "-c", PROBE.format(code=code, heavy=HEAVY)],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize("code", [
    "import asperity2d",
    "import asperity2d; asperity2d.SceneError; dir(asperity2d)",
    "from asperity2d.cli import main; main(['--help'])",
    "from asperity2d.cli import main; main(['belt', '--help'])",
    "from asperity2d.cli import main; main(['sweep', 'run', '--help'])",
    "from asperity2d.cli import main; main(['run', 'missing.toml'])",
    "from asperity2d.cli import main; main(['run', 'scene.toml', '--duration', 'nan'])",
    "from asperity2d.cli import main; main(['belt', 'missing.toml'])",
], ids=["import", "errors and dir", "--help", "belt --help", "sweep run --help", "missing file",
        "bad value", "belt: missing file"])
def test_nothing_heavy_is_loaded_before_first_use(code):
    assert _loaded(code) == []


def test_public_names_resolve_on_first_use_and_are_the_real_objects():
    code = ("import asperity2d as a, asperity2d.run, asperity2d.experiments.compare, asperity2d.renderers.plots\n"
            "from asperity2d.run import simulate\nfrom asperity2d.experiments.compare import compare\n"
            "from asperity2d.renderers import render\n"
            "assert a.simulate is simulate and a.compare is compare and a.render is render\n"
            "assert a.make_scene.__module__ == 'asperity2d.builders'\n"
            "ns = {}\nexec('from asperity2d import *', ns)\n"
            "assert set(a.__all__) <= set(ns) and set(a.__all__) <= set(dir(a))\n"
            "assert {'belt', 'sweep', 'friction'} <= set(dir(a))")
    # no module shares a public function's name, so importing the modules first changes
    # nothing; the asserts run in the child, whose exit status _loaded checks
    assert "pymunk" in _loaded(code)  # and resolving `simulate` did load the engine


def test_unknown_attribute_is_an_attribute_error():
    import asperity2d

    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        asperity2d.nope  # noqa: B018


def test_render_help_names_every_renderer(capsys):
    # the help text is written by hand (importing the renderers would load matplotlib and
    # imageio at parse time), so this keeps it from drifting when a renderer is added
    from asperity2d.cli import main
    from asperity2d.renderers import RENDERERS

    assert main(["render", "--help"]) == 0
    text = capsys.readouterr().out
    missing = [suffix for suffix in RENDERERS if suffix not in text]
    assert not missing, f"`asperity2d render --help` does not name {missing}"
