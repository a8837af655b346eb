"""Every named measure at the step its policy gives it (measures.measure_step) against half that
step, on random seeds no test or study names: drawn from
``numpy.random.SeedSequence(HIDDEN_ENTROPY)``, disjoint from the README's seeds (0-23) and from
the investigation's (entropy 2025).

Deterministic measures (critical forces, quasi-static breakaway, first breakaway) move by at
most their tolerance (measures.STEP_TOLERANCE, 1 %) when the step is halved; so does the travel
on these seeds (a distribution over seeds, its policy is checked in test_travel_policy.py). The peak and mean stick force over a pass are chaotic
(which positions a pass sticks at changes with a 1e-6 change of the drive speed): they are the
means of an ensemble of passes, and what must not move with the step is their distribution --
pooled over seeds the dt/2 ensemble means differ from the dt ones by less than three standard
errors and less than 15 %. Default run: one seed on a small scene; ``-m slow``: three seeds,
the study size, both set-ups.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import asperity2d as a
from asperity2d.critical import critical_force_bracket, measure_dt
from asperity2d.experiments import measures
from asperity2d.run import default_dt
from asperity2d.studies.ooten import SETUPS, STUDY_SIZE

HIDDEN_ENTROPY = 0x25_2026_11
README_SEEDS = range(24)


def hidden_seeds(n: int) -> list[int]:
    seeds = [int(s) for s in np.random.SeedSequence(HIDDEN_ENTROPY).generate_state(n, dtype=np.uint32)]
    assert not set(seeds) & set(README_SEEDS)
    return seeds


def relative(fine: float, coarse: float) -> float:
    return abs(fine - coarse) / abs(fine)


def deterministic(scene) -> dict:
    """Every deterministic measure of ``scene`` at its default step and at half of it."""
    out = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a non-monotone band is reported in the record
        for start in ("rest", "run-up"):
            out[f"critical-{start}"] = [critical_force_bracket(scene, start=start, dt=f * measure_dt(scene, start)).value
                                        for f in (1.0, 0.5)]
    out["quasi-static"] = [measures.quasi_static_breakaway(scene, dt=f * measure_dt(scene, "rest")).force
                           for f in (1.0, 0.5)]
    step = measures.measure_step("first-breakaway", scene)
    out["first-breakaway"] = [measures.stick_forces(scene, passes=1, dt=f * step).first_breakaway[0]
                              for f in (1.0, 0.5)]
    force = 0.9 * out["critical-run-up"][0]
    step = measures.measure_step("travel", scene)
    out["travel"] = [measures.travel_under_force(scene, force=force, dt=f * step)[0] for f in (1.0, 0.5)]
    return out


def test_every_named_measure_has_a_step_and_a_tolerance():
    scene = a.make_scene(lower_count=4, upper_count=2)
    for name in measures.MEASURES:
        assert 0 < measures.measure_step(name, scene) <= default_dt(scene), name
        assert 0 < measures.STEP_TOLERANCE[name] <= 0.05, name
    # the travel is pushed at the step its force was found at
    for start in ("rest", "run-up"):
        assert measures.measure_step("travel", scene, start=start) == measure_dt(scene, start)


def check_deterministic(scene, values: dict) -> None:
    for name, (coarse, fine) in values.items():
        if name == "travel":
            # The travel is a distribution over seeds (its policy: 5 % of the mean over seeds,
            # test_travel_policy.py); on these seeds, whose sliders pass or creep, it moves under
            # 1 % of itself. A travel that stops within a pitch of the start is a creep, not a
            # distance: 1 % of the pitch there (the free slider under 0.9 x critical creeps 0.1-0.2 um)
            tolerance = 0.01 * max(abs(fine), scene.lower.spacing.mean_pitch)
            assert abs(fine - coarse) <= tolerance, (name, coarse, fine)
        else:
            assert math.isfinite(fine) and relative(fine, coarse) <= 0.01, (name, coarse, fine)


@pytest.mark.slow  # every measure at dt and dt/2 (the -m slow study scenes repeat it per seed)
def test_deterministic_measures_converge_at_their_default_step():
    seed = hidden_seeds(1)[0]
    scene = a.make_scene(spacing="random", seed=seed, drive="force", lower_count=6, upper_count=3)
    check_deterministic(scene, deterministic(scene))


#: The stick/slip switch's known defect (a contact lost for one step is reset to kinetic friction)
#: made the free slider's first breakaway on hidden seed 1014623489 break away 4.2 % early at the
#: default step (17.84 against 18.63 mN). The step policy runs the first breakaway at dt/2, where
#: that contact holds: dt/2 and dt/4 agree to 4e-5 on it (measured), so the case is no longer an
#: expected failure. The switch itself is unchanged: a run at the default step still shows it.


@pytest.mark.slow
@pytest.mark.parametrize("seed, setup", [(seed, setup) for seed in hidden_seeds(3) for setup in ("fixed", "free")])
def test_deterministic_measures_converge_on_the_study_scenes(setup, seed):
    scene = a.make_scene(spacing="random", seed=seed, drive="force", **STUDY_SIZE, **SETUPS[setup])
    check_deterministic(scene, deterministic(scene))


@pytest.mark.slow
@pytest.mark.parametrize("setup", ["fixed", "free"])
def test_stick_force_distributions_do_not_move_with_the_step(setup):
    """Three hidden seeds x 5 passes at dt and dt/2: per seed the relative difference of the
    ensemble means; pooled, |mean| < 3 standard errors and < 15 % (a dt bias as large as the
    spread of one pass, 10-25 %, would fail; the chaos itself does not)."""
    diffs = {"peak": [], "mean": []}
    for seed in hidden_seeds(3):
        scene = a.make_scene(spacing="random", seed=seed, **STUDY_SIZE, **SETUPS[setup])
        step = measures.measure_step("peak-stick", scene)
        coarse, fine = (measures.stick_forces(scene, dt=f * step) for f in (1.0, 0.5))
        for name in diffs:
            diffs[name].append(fine.average(name) / coarse.average(name) - 1.0)
    for name, d in diffs.items():
        d = np.array(d)
        se = d.std(ddof=1) / math.sqrt(len(d))
        assert abs(d.mean()) < max(3 * se, 0.01) and abs(d.mean()) < 0.15, (name, d)
