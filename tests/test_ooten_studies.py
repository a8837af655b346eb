"""The Ooten study scripts (scenes/ooten_*.py) and the user's headline claim.

Default run: the headline -- on Ooten's own set-up (the default scene: fixed-height track)
random spacing lowers the critical force from rest and the peak stick force (the mean of the
named measure's passes), on 7 seeds picked by a rule (``numpy.random.SeedSequence`` of a fixed
entropy, none of the README's), with a one-sided Wilcoxon test and a Hodges-Lehmann interval;
every study script runs headless with ``--quick`` and writes a GIF with exactly the requested
frame count and a summary.json whose claims all carry a verdict and numbers; the
critical-force bracket is checked by running either side of it. Slow (``-m slow``): the
README's verdicts re-run through the studies' own verdict rules on 20 other rule-picked seeds.
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
from asperity2d.critical import critical_force_bracket, measure_dt, passes, settled_run
from asperity2d.studies import claims
from asperity2d.studies import ooten as studies

ROOT = Path(__file__).resolve().parent.parent
SCRIPTS = ("profiles", "spacing", "damping", "drive", "stickslip")
FRAMES = {"profiles": 5, "spacing": 6, "damping": 7, "drive": 4, "stickslip": 3}
SEEDS_SLOW = None  # set below, by a rule


def _command(name: str, out: Path) -> list[str]:
    script = str(ROOT / "scenes" / f"ooten_{name}.py")
    args = ["--quick", "--frames", str(FRAMES[name])]
    if name == "drive":  # through the command line: `asperity2d run SCRIPT -o DIR ARGS`
        return [sys.executable, "-m", "asperity2d", "run", script, "-o", str(out), *args]
    return [sys.executable, script, "-o", str(out), "--workers", "1", *args]


@pytest.fixture(scope="module")
def outputs(tmp_path_factory):
    """Run every script with --quick, two at a time; {name: (returncode, stderr, out dir)}."""
    root = tmp_path_factory.mktemp("ooten")

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
        assert claim["verdict"] in claims.OUTCOMES
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


def test_profiles_half_triangles_keep_their_tips_in_place_and_cannot_push(outputs):
    """ooten_profiles: the half-triangle slider's vertical back face has a horizontal normal
    facing back, so no contact of it pushes the slider on (regular, fixed track: the full
    triangles' back flanks return > 0.1 % of the resisting work, the halves' < 1 % of that)."""
    summary = json.loads((outputs["profiles"][2] / "summary.json").read_text())
    books = summary["mechanism"]["fixed"]["mu_s > mu_k"]["contact_work"]
    full, half = (books[p]["regular"]["pushing_share"]["mean"] for p in ("full", "half"))
    assert full > 1e-3 and 0.0 <= half < 0.01 * full
    for claim in summary["claims"]:
        n = claim["numbers"]
        assert claim["friction"] in ("mu_s > mu_k", "mu_s = mu_k") and claim["half"] in ("half", "half (full-base)")
        assert n["n"] + n["missing"] == summary["seeds"]  # every seed used or counted as left out


def test_drive_spring_pass_names_its_stick_forces(outputs):
    summary = json.loads((outputs["drive"][2] / "summary.json").read_text())
    for setup, n in summary["results"].items():
        spring = n["spring"]
        peaks = spring["stick_forces_N"]
        assert spring["first_breakaway_N"] == peaks[0] and spring["peak_stick_force_N"] == max(peaks)
        assert min(peaks) <= spring["mean_stick_force_N"] <= max(peaks), setup
        assert n["below"]["start"] == n["above"]["start"] == "rest"
        assert n["below"]["force_N"] < n["critical_force_from_rest_N"] < n["above"]["force_N"]


@pytest.mark.slow
def test_micro_spacing_reports_both_setups(tmp_path):
    """scenes/micro_spacing.py --quick (2 seeds, ~40 s CPU): both set-ups, fixed first, one claim each."""
    proc = subprocess.run([sys.executable, str(ROOT / "scenes" / "micro_spacing.py"), "--quick", "--json",
                           "--no-gif", "--workers", "1", "-o", str(tmp_path)], capture_output=True, text=True,
                          cwd=ROOT, timeout=900)
    assert proc.returncode == 0, proc.stderr[-2000:]
    summary = json.loads(proc.stdout.strip().splitlines()[-1])
    assert list(summary["results"]) == ["fixed", "free"]
    assert [c["setup"] for c in summary["claims"]] == ["fixed", "free"]
    for setup, results in summary["results"].items():
        drop = results["force_drop_mean_N"]
        assert drop["regular"] > 0 and drop["random"]["n"] >= 1, setup
    assert "static_kinetic_gap_over_load" in summary["results"]["free"]


# -- the headline, in the default run, on seeds the README did not use --------------------------

#: Seeds are picked by a rule, never by hand: numpy.random.SeedSequence(entropy) -- disjoint from
#: the README's seeds (0-23) and from every other test's.
HEADLINE_ENTROPY = 0x25_0EAD_11
HEADLINE_SIZE = {"lower_count": 8, "upper_count": 3}
VARIANTS = {"regular": {"spacing": "regular"}, "random-upper": {"spacing": "random-upper"},
            "random": {"spacing": "random"}}


def rule_seeds(entropy: int, n: int) -> list[int]:
    seeds = [int(s) for s in np.random.SeedSequence(entropy).generate_state(n, dtype=np.uint32)]
    assert not set(seeds) & set(range(24))
    return seeds


HEADLINE_SEEDS = rule_seeds(HEADLINE_ENTROPY, 7)  # 7: the exact one-sided signed-rank p reaches 2**-7 < 0.01


@pytest.fixture(scope="module")
def headline():
    """Critical force from rest and peak stick force (the mean of the named measure's three
    passes), regular against random spacing on both surfaces, Ooten's default set-up."""
    assert a.make_scene().slider.track == "fixed"  # the default scene is the seed's set-up
    both = {k: VARIANTS[k] for k in ("regular", "random")}
    return {name: a.compare(name, both, HEADLINE_SEEDS, progress=False, workers=2,
                            base={**HEADLINE_SIZE, "drive": drive})
            for name, drive in (("critical", "force"), ("peak-stick", "spring"))}


@pytest.mark.parametrize("measure", ["critical", "peak-stick"])
def test_random_spacing_lowers_the_breakaway_force_on_the_seed_set_up(headline, measure):
    """README: random spacing lowers both on the fixed track, x0.4-0.6. On new seeds every one is
    below the regular value and the Hodges-Lehmann ratio's 95 % interval lies below 0.8."""
    comparison = headline[measure]
    numbers = comparison.versus("random", "regular", alternative="less")
    assert numbers["n"] == len(HEADLINE_SEEDS) and numbers["missing"] == 0  # every run gave a number
    assert numbers["below"] == len(HEADLINE_SEEDS) and numbers["p_wilcoxon"] < 0.01
    assert claims.judge(numbers, 0.01) == claims.HOLDS
    effect = a.stats.relative_effect(comparison.values["random"], comparison.values["regular"][0])
    assert effect["ci_high"] < -0.2


def test_regular_peak_stick_force_is_the_flank_law_for_all_tips(headline):
    """The mechanism: on a regular surface every tip pushes its asperity down by the
    interference at once, n k delta tan(45 deg + atan mu_s) (quasi-static, within 2 %)."""
    scene = a.make_scene(**HEADLINE_SIZE)
    flank = np.tan(np.radians(45.0) + np.arctan(scene.contact.mu_static))
    expected = scene.slider.count * scene.lower.stiffness[0] * scene.slider.interference * flank
    assert headline["peak-stick"].values["regular"][0] == pytest.approx(expected, rel=0.02)


@pytest.mark.parametrize("start", ["rest", "entry", "run-up"])
@pytest.mark.parametrize("setup", ["free", "fixed"])
def test_critical_force_brackets_correctly(setup, start):
    scene = a.make_scene(spacing="random", seed=1, drive="force", **studies.QUICK_SIZE,
                         **studies.SETUPS[setup])
    bracket = critical_force_bracket(scene, rel_tol=0.01, start=start)
    assert bracket.stops < bracket.passes and bracket.relative_width <= 0.01 and bracket.start == start
    # 5 % either side: within ~2 % of the boundary inertia can make passing non-monotone in the
    # force (measured at the entry start: 0.98 x passes, 0.99 x does not)
    dt = measure_dt(scene, start)  # the bracket's own step
    base = settled_run(scene, start=start, dt=dt)
    assert not passes(base, 0.95 * bracket.value)
    assert passes(base, 1.05 * bracket.value)
    if start == "run-up":  # the public path: simulate from the builder's start, force at t = 0
        below = a.simulate(scene.replace(drive=a.ConstantForce(force=0.95 * bracket.value)), dt=dt)
        above = a.simulate(scene.replace(drive=a.ConstantForce(force=1.05 * bracket.value)), dt=dt)
        assert below.status != "passed" and above.status == "passed"


def test_entry_start_sees_the_first_asperity_only():
    """At rest against the first flank only the front tip touches: the critical force from
    the entry is the same for every spacing of the upper surface (like the first breakaway)."""
    values = {critical_force_bracket(a.make_scene(drive="force", spacing=spacing, seed=seed, **HEADLINE_SIZE),
                                     start="entry").value
              for spacing, seed in (("regular", 0), ("random-upper", 1), ("random-upper", 2))}
    assert len(values) == 1


# -- the 20-seed studies (slow: ~1-3 minutes each on 2 cores) ---------------------

#: The slow re-checks run on 20 seeds of their own, by the same rule.
SEEDS_SLOW = rule_seeds(0x25_51_0E, 20)

def _script(name: str):
    from asperity2d.cli.args import load_script

    return load_script(ROOT / "scenes" / f"ooten_{name}.py")


def _spacing_verdicts(setup: str) -> dict:
    """The spacing study's claims (scenes/ooten_spacing.py, its own verdict rule) re-run on 20
    seeds the README did not use: {(measure, variant): claim}."""
    spacing = _script("spacing")
    rows = spacing.rows_for(setup, size=studies.STUDY_SIZE, seeds=SEEDS_SLOW, workers=2, passes=3)
    found = spacing.claims_for(setup, spacing.comparisons(rows, SEEDS_SLOW, setup))
    for c in found:
        print(claims.verdict_line(c))
    return {(c["measure"], c["variant"]): c for c in found}


@pytest.mark.slow
def test_fixed_track_spacing_verdicts_hold_on_new_seeds():
    """README, fixed track: random spacing (random-upper and random) lowers every force measure
    but the first breakaway (the same for every spacing by construction); random on both
    surfaces is not the smallest for any measure, and random-upper is below random for the
    run-up threshold. (On the study's 24 seeds random-upper was below random in the peak stick
    force too, ×1.16-1.62; on these 20 it is not, ×1.03 [0.86, 1.20], measured 2026-11-25: that
    difference is seed noise, and the findings page says so.)"""
    found = _spacing_verdicts("fixed")
    for measure in ("critical", "critical-run-up", "quasi-static-breakaway", "peak-stick", "mean-stick"):
        for variant in ("random-upper", "random"):
            c = found[measure, variant]
            assert c["verdict"] == claims.HOLDS and c["numbers"]["missing"] == 0, (measure, variant)
            assert c["numbers"]["ratio_ci_high"] < 0.95, (measure, variant)
        # not shown smaller: shown the other way, or undecided (never "holds")
        assert found[measure, "random vs random-upper"]["verdict"] in (claims.FAILS, claims.UNDECIDED), measure
    assert found["critical-run-up", "random vs random-upper"]["numbers"]["ratio_ci_low"] > 1.0
    for variant in ("random-upper", "random"):
        n = found["first-breakaway", variant]["numbers"]
        assert n["ratio_ci_low"] == n["ratio_ci_high"] == 1.0
