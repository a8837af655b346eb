"""Text output reads as engineering units: no raw Python dicts or lists, no long floats.

Every computing subcommand in text mode (``--json`` keeps full precision, tested elsewhere) and
the helpers it prints with (asperity2d._format).
"""

import json
import re

import pytest

from asperity2d._format import lines, split_unit, value
from asperity2d.cli.main import main

#: A float printed with more than 5 significant digits (e.g. 0.034528298915715) or a raw
#: exponent with a long mantissa; a Python dict or list literal.
LONG_FLOAT = re.compile(r"\d\.\d{6,}|\d{7,}\.\d")
RAW = re.compile(r"\{'|\['|': ")


def readable(text: str) -> None:
    for line in text.splitlines():
        assert not LONG_FLOAT.search(line), line
        assert not RAW.search(line), line


def test_units_come_from_the_keys():
    assert split_unit("critical_force_N") == ("critical force", "N")
    assert split_unit("max_overlap_fraction") == ("max overlap fraction", "%")
    assert split_unit("force_drop_mean") == ("force drop mean", "N")
    assert split_unit("regime") == ("regime", None)
    assert value(0.034528298915715, "N") == "34.53 mN"
    assert value(0.0231, "%") == "2.31 %"
    assert value(float("nan"), "N") == "n/a" and value(None) == "n/a" and value(True) == "yes"
    assert lines({"a_m": 1.25e-6, "events": {"count": 3}}) == ["a: 1.250 µm", "events:", "  count: 3"]


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    """A small asperity run and a belt chain, saved once."""
    root = tmp_path_factory.mktemp("text")
    scene = root / "scene.toml"
    scene.write_text('lower_count = 5\nupper_count = 2\ntrack = "free"\n')
    assert main(["run", str(scene), "--save", str(root / "run.npz")]) == 0
    assert main(["belt", "--preset", "table2-3dof", "-o", str(root / "chain.npz")]) == 0
    return root


def test_run_analyze_critical_and_belt_text(saved, capsys):
    capsys.readouterr()
    for argv in (["run", str(saved / "scene.toml")], ["analyze", str(saved / "run.npz")],
                 ["analyze", str(saved / "chain.npz")], ["critical", str(saved / "scene.toml")],
                 ["belt", "--preset", "table2-3dof"]):
        assert main(argv) == 0
        out = capsys.readouterr().out
        assert out.strip(), argv
        readable(out)
    assert main(["critical", str(saved / "scene.toml")]) == 0
    assert re.match(r"critical force \d+\.\d+ mN: the slider stops at", capsys.readouterr().out)


def test_json_keeps_full_precision(saved, capsys):
    capsys.readouterr()
    assert main(["analyze", str(saved / "run.npz"), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["peak_drive_force_N"] > 0 and len(repr(data["peak_drive_force_N"])) > 8


def test_compare_and_sweep_report_text(tmp_path, capsys):
    assert main(["compare", "--measure", "critical", "--variants", "regular,random", "--seeds", "2",
                 "--set", "lower_count=4", "--set", "upper_count=1", "--workers", "1"]) == 0
    out = capsys.readouterr().out
    readable(out)
    assert "critical force from rest (step load), 2 seeds:" in out and " mN" in out
    study = tmp_path / "study.toml"
    study.write_text('name = "t"\nrun = "asperity2d.studies.mdof_belt:belt_chain_run"\nseeds = 2\n'
                     '[grid]\nv_belt = [0.1, 0.4]\n[fixed]\npreset_name = "table2-3dof"\nic_spread = 0.02\n')
    store = tmp_path / "store"
    assert main(["sweep", "run", str(study), "--store", str(store), "--workers", "1", "--no-progress"]) == 0
    capsys.readouterr()
    assert main(["sweep", "report", str(store), "-o", str(tmp_path / "summary.png")]) == 0
    out = capsys.readouterr().out
    readable(out)
    assert "total stick: mean" in out and " s," in out


def test_a_claims_effect_reads_its_numbers_back_from_json():
    """A claim saved with a NaN interval (strict JSON: null) reads back without one, not a crash
    (the docs' gallery renders claims from the scripts' summary.json)."""
    from asperity2d import _io
    from asperity2d.studies.claims import effect

    numbers = {"relative_difference": -0.2, "ratio_hl": 0.8, "ratio_ci_low": float("nan"),
               "ratio_ci_high": float("nan"), "below": 2, "n": 2, "p_wilcoxon": 0.25}
    back = json.loads(_io.to_json(numbers))
    assert back["ratio_ci_low"] is None
    assert effect(back) == effect(numbers) == "-20 %, x0.8, 2/2 seeds below, Wilcoxon p = 0.25"
