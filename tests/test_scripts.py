"""The core scene scripts run headless on small settings and write what they promise."""

import json
from pathlib import Path

import pytest
from PIL import Image

from asperity2d.cli.args import load_script
from asperity2d.cli.main import main

SCENES = Path(__file__).resolve().parent.parent / "scenes"


@pytest.mark.parametrize("name, extra", [
    ("stick_slip", []),
    ("constant_force", []),
    ("quickstart", ["--seeds", "2"]),  # --workers auto: the idle second core
])
def test_script_writes_gif_with_requested_frames_and_summary(name, extra, tmp_path, capsys):
    module = load_script(SCENES / f"{name}.py")
    assert module.main(["--quick", "--json", "--frames", "7", "-o", str(tmp_path), *extra]) == 0
    summary = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert summary == json.loads((tmp_path / "summary.json").read_text())
    gif = tmp_path / "run.gif"
    assert gif.stat().st_size > 0
    with Image.open(gif) as im:
        assert im.n_frames == 7


def test_stick_slip_script_reports_the_flank_law_peak_stick_force(tmp_path, capsys):
    """Fixed track, regular spacing: every tip pushes its asperity down by the interference at
    once, so the largest stick force is n k delta tan(45 deg + atan mu_s) (measured within 0.1 %;
    2 % allows for the drive's dynamic overshoot)."""
    assert main(["run", str(SCENES / "stick_slip.py"), "--quick", "--no-gif", "-o", str(tmp_path),
                 "--json"]) == 0
    summary = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert summary["events"]["count"] >= 2
    assert summary["peak_stick_force_N"] == pytest.approx(summary["flank_law_all_tips_N"], rel=0.02)
    assert summary["first_breakaway_force_N"] < 0.5 * summary["peak_stick_force_N"]


def test_toml_scene_runs_saves_and_reanalyses(tmp_path, capsys):
    scene = tmp_path / "scene.toml"
    scene.write_text('[scene]\nlower_count = 6\nupper_count = 2\nspacing = "random"\nseed = 4\n')
    saved = tmp_path / "run.npz"
    assert main(["run", str(scene), "--save", str(saved), "-o", str(tmp_path / "run.png"),
                 "--json"]) == 0
    run = json.loads(capsys.readouterr().out)
    assert run["status"] == "passed" and (tmp_path / "run.png").stat().st_size > 0
    assert main(["analyze", str(saved), "--json"]) == 0
    analysis = json.loads(capsys.readouterr().out)
    assert analysis["peak_drive_force_N"] == run["peak_drive_force_N"]
    assert analysis["events"]["count"] >= 1
    assert main(["render", str(saved), "-o", str(tmp_path / "again.gif"), "--json"]) == 0
    assert (tmp_path / "again.gif").stat().st_size > 0


@pytest.mark.slow  # the whole tribometer lesson, calibration included
def test_tribometer_script_hands_the_stick_slip_law_to_a_belt_chain(tmp_path, capsys):
    """scenes/tribometer.py --quick: held-out period within 5 %, and its chain file runs via the CLI."""
    module = load_script(SCENES / "tribometer.py")
    assert module.main(["--quick", "--json", "-o", str(tmp_path)]) == 0
    summary = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    runs = summary["stick_slip"]["runs"]
    assert [r["held_out"] for r in runs] == [False] + [True] * (len(runs) - 1)
    assert all(r["ratio"] == pytest.approx(1.0, abs=0.05) for r in runs)
    assert (tmp_path / "stick_slip_period.png").stat().st_size > 0
    chain = summary["macroscopic_chain"]
    assert main(["belt", chain["chain_file"], "--json"]) == 0
    belt = json.loads(capsys.readouterr().out)
    assert len(belt["stick_intervals"][0]) == chain["stick_intervals_mass1"] >= 4


@pytest.mark.slow
def test_stick_slip_law_script_transfers_the_pooled_law_to_held_out_seeds(tmp_path, capsys):
    """scenes/stick_slip_law.py --quick (4 random seeds): held-out periods within 10 %."""
    module = load_script(SCENES / "stick_slip_law.py")
    assert module.main(["--quick", "--json", "--no-gif", "--workers", "1", "-o", str(tmp_path)]) == 0
    summary = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert summary["held_out_ratio"]["max_abs_error"] < 0.10
    assert summary["gap"]["random"]["mean"] > summary["gap"]["regular"]
    assert (tmp_path / "stick_slip_law.png").stat().st_size > 0


@pytest.mark.parametrize("track", ["fixed", "free"])
def test_constant_force_script_shows_one_run_below_and_one_above_the_threshold_it_prints(track, tmp_path,
                                                                                         capsys):
    """Both runs start from the rest the critical force was bisected from: 0.95 x stops, 1.05 x
    passes. On the free slider the threshold is the kinetic flank law L tan(45 deg + atan mu_k)
    (measured 0.4 % below it; 2 % allows for the 1 % bisection and the contact solver)."""
    module = load_script(SCENES / "constant_force.py")
    assert module.main(["--quick", "--json", "--no-gif", "--track", track, "-o", str(tmp_path)]) == 0
    summary = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert summary["start"] == "rest" and summary["track"] == track
    assert summary["below"]["status"] == "stuck" and summary["above"]["status"] == "passed"
    if track == "free":
        assert summary["critical_force_N"] == pytest.approx(summary["flank_law_N"], rel=0.02)
    else:  # a force applied at once undercuts what a slow push needs
        assert summary["critical_force_N"] < summary["flank_law_N"]
