"""Running a scene script's ``main`` on its ``--quick`` settings, shared by the script tests."""

import json
from pathlib import Path

from asperity2d.cli.args import load_script

SCENES = Path(__file__).resolve().parent.parent / "scenes"


def run_script(name, tmp_path, capsys, *extra):
    """Run ``scenes/<name>.py --quick --json -o tmp_path``; check that the printed summary is the
    one written and that every output it lists exists and is not empty; return the summary."""
    module = load_script(SCENES / f"{name}.py")
    assert module.main(["--quick", "--json", "-o", str(tmp_path), *extra]) == 0
    summary = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert summary == json.loads((tmp_path / "summary.json").read_text())
    for output in summary.get("outputs", []):
        assert (tmp_path / output).stat().st_size > 0
    return summary
