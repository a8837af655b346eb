"""The belt subcommand in-process (through the top-level ``main``), and the study scripts in their quick form."""

import importlib.util
import json
import sys
from pathlib import Path

import pytest

from asperity2d.belt import load
from asperity2d.cli import main
from asperity2d.belt.presets import names, preset

ROOT = Path(__file__).resolve().parents[1]


def test_preset_json_summary(capsys):
    assert main(["belt", "--preset", "table2-3dof", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["n"] == 3 and summary["events"] > 0
    assert summary["energy_balance_error"] < 1e-8
    assert len(summary["stick_intervals"]) == 3


def test_toml_chain_and_outputs(tmp_path, capsys):
    chain = tmp_path / "chain.toml"
    chain.write_text('masses = [1.0]\nsprings = [10.0, 0.0]\ndampers = [0.0, 0.0]\nv_belt = 0.05\n'
                     'x0 = [0.0]\nv0 = [0.05]\nt_end = 12.0\n[friction]\nlaw = "Stribeck"\n'
                     'mu_s = 0.4\nmu_k = 0.25\nv_s = 0.02\n')
    assert main(["belt", str(chain), "-o", str(tmp_path / "r.npz"), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["regime"] in ("stick-slip", "stuck")
    assert load(tmp_path / "r.npz").chain.law.v_s == 0.02
    assert main(["belt", "--preset", "table1-2dof", "-o", str(tmp_path / "r.svg")]) == 0
    assert (tmp_path / "r.svg").read_text().lstrip().startswith("<?xml")


@pytest.mark.parametrize("argv, needle", [
    (["belt", "--preset", "nope"], "`preset`"),
    (["belt"], "`--preset`"),
    (["belt", "missing.toml"], "`chain` does not exist"),
    (["belt", "--preset", "table2-3dof", "-o", "x.xyz"], "`--output` must end in"),
    (["belt", "--preset", "table2-3dof", "--t-end", "-1"], "argument --t-end"),
])
def test_bad_input_exits_2_with_one_line(argv, needle, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err and needle in err


def test_bad_toml_key_is_named(tmp_path, capsys):
    chain = tmp_path / "bad.toml"
    chain.write_text("masses = [1.0]\nsprngs = [1.0, 1.0]\n")
    assert main(["belt", str(chain)]) == 2
    assert "`sprngs`" in capsys.readouterr().err


def test_every_preset_builds():
    for name in names():
        kwargs = preset(name)
        assert len(kwargs["springs"]) == len(kwargs["masses"]) + 1


def _scene(name):
    spec = importlib.util.spec_from_file_location(name, ROOT / "scenes" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.path.insert(0, str(ROOT / "scenes"))
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("name,n_claims", [("belt_2dof", 5), ("belt_3dof", 3), ("belt_speed", 4)])
def test_study_scripts_write_claims(name, n_claims, tmp_path, capsys):
    assert _scene(name).main(["--quick", "-o", str(tmp_path)]) == 0
    (out,) = tmp_path.glob("*.json")  # the summary alone: no plots without --plots
    summary = json.loads(out.read_text())
    assert out.name == "summary.json" and summary["solver"].startswith("asperity2d.belt exact")
    assert len(summary["claims"]) == n_claims
    assert all(c["verdict"] in ("holds", "does not hold") for c in summary["claims"])
