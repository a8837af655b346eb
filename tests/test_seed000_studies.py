"""The seed-000 study scripts (scenes/seed000_*.py) and the statistical claims of issue 4.

Default run: every study script runs headless with ``--quick`` (two at a time,
as subprocesses, one module-scoped fixture) and writes a GIF with exactly the
requested frame count and a summary.json whose claims all carry a verdict and
numbers; the critical-force bracket is checked by running either side of it.
Slow (``-m slow``): the 20-seed spacing tests. They assert what is true in this
model, per set-up: on the free slider random spacing does NOT lower the
critical force with p < 0.01 (pinned regression of a negative result).
"""

from __future__ import annotations

import json
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import asperity2d as a
from asperity2d import studies
from asperity2d.critical import critical_force_bracket

ROOT = Path(__file__).resolve().parent.parent
SCRIPTS = ("profiles", "spacing", "damping", "drive", "stickslip")
FRAMES = {"profiles": 5, "spacing": 6, "damping": 7, "drive": 4, "stickslip": 3}
SEEDS_SLOW = range(20)


def _command(name: str, out: Path) -> list[str]:
    script = str(ROOT / "scenes" / f"seed000_{name}.py")
    args = ["--quick", "--frames", str(FRAMES[name])]
    if name == "drive":  # through the command line: `asperity2d run SCRIPT -o DIR ARGS`
        return [sys.executable, "-m", "asperity2d", "run", script, "-o", str(out), *args]
    return [sys.executable, script, "-o", str(out), "--workers", "1", *args]


@pytest.fixture(scope="module")
def outputs(tmp_path_factory):
    """Run every script with --quick, two at a time; {name: (returncode, stderr, out dir)}."""
    root = tmp_path_factory.mktemp("seed000")

    def run(name):
        out = root / name
        proc = subprocess.run(_command(name, out), capture_output=True, text=True, cwd=ROOT,
                              env={**__import__("os").environ, "MPLBACKEND": "Agg"}, timeout=600)
        return name, (proc.returncode, proc.stderr[-2000:], out)

    with ThreadPoolExecutor(max_workers=2) as pool:
        return dict(pool.map(run, SCRIPTS))


@pytest.mark.parametrize("name", SCRIPTS)
def test_script_writes_gif_and_claims(outputs, name):
    code, stderr, out = outputs[name]
    assert code == 0, stderr
    gifs = sorted(out.glob("*.gif"))
    assert gifs, f"no GIF in {out}"
    for gif in gifs:
        assert gif.stat().st_size > 0
        with Image.open(gif) as im:
            assert im.n_frames == FRAMES[name]
    summary = json.loads((out / "summary.json").read_text())
    assert summary["claims"], "every study states at least one claim"
    for claim in summary["claims"]:
        assert claim["verdict"] in ("holds", "does not hold")
        assert claim["claim"] and claim["test"]
        assert isinstance(claim["numbers"], dict) and claim["numbers"]
    assert list(out.glob("*.png")), "plots written"


def test_every_study_reports_both_setups(outputs):
    for name in SCRIPTS:
        summary = json.loads((outputs[name][2] / "summary.json").read_text())
        assert {c["setup"] for c in summary["claims"]} == {"free", "fixed"}, name


def test_damping_numbers_are_consistent(outputs):
    summary = json.loads((outputs["damping"][2] / "summary.json").read_text())
    for setup, n in summary["results"].items():
        for key in ("fraction_undamped_farther", "fraction_equal", "fraction_passed_damped",
                    "fraction_passed_undamped"):
            assert 0.0 <= n[key] <= 1.0, (setup, key)
        assert n["fraction_undamped_farther"] + n["fraction_equal"] <= 1.0
        for row in n["per_seed"]:
            assert row["travel_damped_m"] > 0 and row["travel_undamped_m"] > 0
            assert row["force_N"] == pytest.approx(0.9 * row["critical_force_N"])


@pytest.mark.parametrize("setup", ["free", "fixed"])
def test_critical_force_brackets_correctly(setup):
    scene = a.make_scene(spacing="random", seed=1, drive="force", **studies.QUICK_SIZE,
                         **studies.SETUPS[setup])
    bracket = critical_force_bracket(scene, rel_tol=0.01)
    assert bracket.stops < bracket.passes and bracket.relative_width <= 0.01
    below = a.simulate(scene.replace(drive=a.ConstantForce(force=0.98 * bracket.value)))
    above = a.simulate(scene.replace(drive=a.ConstantForce(force=1.02 * bracket.value)))
    assert below.status != "passed"
    assert above.status == "passed"


# -- issue 4's statistical tests (slow: ~1-3 minutes each on 2 cores) -----------

def _versus_regular(measure, setup: str, drive: str) -> dict:
    base = {**studies.STUDY_SIZE, **studies.SETUPS[setup], "drive": drive}
    comparison = a.compare(measure, {"random-upper": {"spacing": "random-upper"},
                                     "random": {"spacing": "random"}},
                           seeds=SEEDS_SLOW, base=base, progress=False, workers=2)
    regular = measure(a.make_scene(spacing="regular", **base))
    out = {}
    for name in ("random-upper", "random"):
        out[name] = studies.versus_reference(comparison.values[name], regular, alternative="less")
        n = out[name]
        print(f"{setup} {measure.__name__} {name}: mean {n['mean']:.5g} vs regular {regular:.5g} "
              f"({n['relative_difference'] * 100:+.1f} %, d = {n['effect_size_d']:.2f}, "
              f"Wilcoxon one-sided p = {n['p_wilcoxon']:.3g})")
    return out


@pytest.mark.slow
def test_free_slider_random_spacing_does_not_lower_critical_force():
    # pinned regression of a negative result: with a free slider under a normal load the load
    # is shared by whatever flanks touch, so random spacing does not lower the critical force
    # with p < 0.01 (seed 000 figure 11 was a fixed-height track).
    # 20 seeds: random-upper -0.5 % (p = 0.33), random +1.7 % (p = 0.40).
    for name, n in _versus_regular(studies.critical_force_of, "free", "force").items():
        assert n["p_wilcoxon"] > 0.01, name


@pytest.mark.slow
def test_fixed_track_random_spacing_lowers_critical_force():
    # seed 000's set-up; 20 seeds: random-upper -21 % (d = -3.8), random -10 % (d = -1.3)
    for name, n in _versus_regular(studies.critical_force_of, "fixed", "force").items():
        assert n["mean"] < n["reference"] and n["p_wilcoxon"] < 0.01, name


@pytest.mark.slow
def test_free_slider_random_spacing_breakaway_force():
    # pinned regression of a negative result (20 seeds: random-upper p = 0.78, random p = 0.64):
    # most seeds break away at L tan(45 deg + atan mu_s) like regular spacing, when all the
    # load sits on rising flanks; a few break away much lower, so the mean drops 11-14 % but
    # the median does not and the one-sided Wilcoxon test is far from p < 0.01.
    for name, n in _versus_regular(studies.breakaway_force_of, "free", "spring").items():
        assert n["p_wilcoxon"] > 0.01 and np.isfinite(n["mean"]), name


@pytest.mark.slow
def test_fixed_track_random_spacing_lowers_peak_spring_force():
    # 20 seeds: random-upper -50 % (d = -3.3), random -45 % (d = -2.5), both p ~ 1e-6
    for name, n in _versus_regular(studies.peak_spring_force_of, "fixed", "spring").items():
        assert n["mean"] < n["reference"] and n["p_wilcoxon"] < 0.01, name
