"""The critical-force search: toy predicates whose answer is known exactly, then the one
physical case where passing is known not to be monotone in the force (the undamped regular
run-up), checked by brute force, and the run budget, dt and iterations on their way to the runs.

The toys call :func:`smallest_passing` with a plain predicate of the force, so the answer (the
smallest passing force, the band of mixed outcomes) is set by the test, not computed by the
code under test.
"""

from __future__ import annotations

import math
import os
import warnings

import numpy as np
import pytest

import asperity2d as a
from asperity2d.critical import (SCAN_STEP, SCAN_WINDOW, NonMonotoneWarning, critical_force,
                                 critical_force_bracket, measure_dt, passes, settled_run, smallest_passing)
from asperity2d.run import default_dt
from asperity2d.studies.ooten import STUDY_SIZE


class Counting:
    """A predicate that records every force it is asked about."""

    def __init__(self, rule):
        self.rule, self.asked = rule, []

    def __call__(self, force):
        self.asked.append(force)
        return self.rule(force)


def test_a_monotone_threshold_is_bracketed_within_the_tolerance():
    threshold, tol = 0.7312, 0.0025
    test = Counting(lambda f: f >= threshold)
    lo, hi, band, tried = smallest_passing(test, 0.1, rel_tol=tol)
    assert lo < threshold <= hi
    # bisection stops at the first bracket within tol: the one before it was wider than tol,
    # and halving it gives more than tol / 2
    assert tol / 2 < (hi - lo) / hi <= tol
    assert band is None
    assert [f for f, _ in tried] == test.asked  # every force asked once, in order
    assert len(set(test.asked)) == len(test.asked)
    # upward: 0.1 stops, so the bracket doubles it until it passes: 0.1, 0.2, 0.4, 0.8
    assert test.asked[:4] == [0.1, 0.2, 0.4, 0.8]
    # the check: 2 %, 4 %, ..., 10 % below and above hi (all below the threshold stop)
    steps = int(round(SCAN_WINDOW / SCAN_STEP))
    assert test.asked[-2 * steps:] == pytest.approx(
        [hi * (1 - j * SCAN_STEP) for j in range(1, steps + 1)]
        + [hi * (1 + j * SCAN_STEP) for j in range(1, steps + 1)], rel=1e-15)


def test_downward_bracketing_halves_a_passing_estimate():
    test = Counting(lambda f: f >= 1.0)
    lo, hi, band, _ = smallest_passing(test, 8.0, rel_tol=0.01)
    assert test.asked[:4] == [8.0, 4.0, 2.0, 1.0] and test.asked[4] == 0.5
    assert lo < 1.0 <= hi and band is None


def test_a_passing_band_below_the_threshold_is_found_and_reported():
    """Passes at >= 1 and in [0.93, 0.95]: bisection from 0.3 lands on the threshold at 1;
    the check finds 0.94 (6 % below), bisects down to the band's lower edge 0.93 and reports
    the band (0.93, the highest force that stopped, just under 1)."""
    rule = lambda f: f >= 1.0 or 0.93 <= f <= 0.95  # noqa: E731
    lo, hi, band, tried = smallest_passing(rule, 0.3, rel_tol=0.0025)
    assert lo < 0.93 <= hi <= 0.93 * 1.0025
    assert band is not None and band[0] == hi
    stops_above = [f for f, ok in tried if f > hi and not ok]
    assert band[1] == max(stops_above) and 0.95 < band[1] < 1.0
    assert not rule(band[1]) and rule(band[0])


def test_two_bands_below_are_followed_down_to_the_lowest():
    rule = lambda f: f >= 1.0 or 0.90 <= f <= 0.93 or 0.83 <= f <= 0.86  # noqa: E731
    lo, hi, band, _ = smallest_passing(rule, 2.0, rel_tol=0.001)
    assert lo < 0.83 <= hi <= 0.83 * 1.001
    assert band is not None and band[1] < 1.0


def test_a_staircase_of_bands_below_is_bracketed_from_below():
    """Passes at >= 1.05, in [0.90, 0.97] and in [0.43, 0.47]. The bracket lands on 1.05; the
    check finds its lowest scan point (0.945) passing with nothing seen to stop below it, so the
    search bisects down to 0.90 and then halves from there: 0.45 passes too, 0.225 stops, and
    bisection ends on the staircase's lowest edge, 0.43. Halving by anything but two, or
    doubling, would miss the 0.43-0.47 band (its width is under a third of 0.9's distance)."""
    rule = lambda f: f >= 1.05 or 0.90 <= f <= 0.97 or 0.43 <= f <= 0.47  # noqa: E731

    def test(force):
        if len(test.asked) >= 200:  # a search that runs away fails here, not by a time-out
            raise AssertionError("more than 200 forces asked")
        test.asked.append(force)
        return rule(force)

    test.asked = []
    lo, hi, band, tried = smallest_passing(test, 1.0, rel_tol=0.0025)
    assert lo < 0.43 <= hi <= 0.43 * 1.0025 and not rule(lo)
    # the halving from the bisected 0.90 (to within 0.25 %) was asked, and passed
    assert any(0.45 <= f <= 0.90 * 1.0025 / 2 and ok for f, ok in tried)
    assert band is not None and band[0] == hi and 1.0 <= band[1] < 1.05


@pytest.mark.parametrize("island", [(0.945, 0.955), (0.80, 0.82)])
def test_what_the_check_cannot_see_is_what_its_window_and_step_say(island):
    """An island narrower than SCAN_STEP between two scan points, or more than SCAN_WINDOW
    below, is missed: the search returns the threshold and says it saw no band."""
    rule = lambda f: f >= 1.0 or island[0] <= f <= island[1]  # noqa: E731
    lo, hi, band, tried = smallest_passing(rule, 0.3, rel_tol=0.0025)
    assert lo < 1.0 <= hi and band is None
    assert not any(island[0] <= f <= island[1] for f, _ in tried)


@pytest.mark.parametrize("first", [-6, -3, -1, 0, 1, 4])
def test_where_the_bracket_starts_changes_the_runs_not_the_answer(first):
    """A monotone threshold: starting the bracket at any power of two of the estimate tries the
    same powers of two on the way, so it ends on the same bracket and bisects to the same bits;
    only the number of forces asked differs, by how far the start is from the threshold."""
    threshold = 0.7312
    reference = smallest_passing(lambda f: f >= threshold, 0.1)
    test = Counting(lambda f: f >= threshold)
    lo, hi, band, tried = smallest_passing(test, 0.1, first=first)
    assert (lo, hi, band) == reference[:3]
    assert test.asked[0] == 0.1 * 2.0 ** first
    # 0.1 x 2**3 = 0.8 is the first power that passes, 0.4 the last that stops: the bracket asks
    # every power from the start up to 0.8, or down to 0.4 (the reference, from 2**0: 4 asks)
    asks = 4 - first if first < 3 else first - 1
    assert len(tried) - len(reference[3]) == asks - 4


def test_the_first_force_is_the_tracks_power_of_two_and_the_answer_the_one_from_the_estimate():
    """The search on a fixed track from rest starts at a quarter of the flank-law estimate
    (FIRST_POWER); it returns the very bits of the same search started at the estimate itself
    (the forces of both are the estimate times powers of two), with fewer runs."""
    from asperity2d.critical import FIRST_POWER, flank_estimate

    scene = a.make_scene(drive="force", track="fixed", **SMALL)
    bracket = critical_force_bracket(scene)
    estimate = flank_estimate(scene)
    assert bracket.tried[0][0] == estimate * 2.0 ** FIRST_POWER["fixed", "rest"] == estimate / 4
    base = settled_run(scene, start="rest", dt=measure_dt(scene, "rest"))
    lo, hi, band, tried = smallest_passing(lambda f: passes(base, f), estimate)  # from the estimate
    assert tried[0][0] == estimate
    assert (bracket.stops, bracket.passes, bracket.band) == (lo, hi, band)
    assert bracket.runs < len(tried)


# -- the physical non-monotone case ----------------------------------------------------------

@pytest.fixture(scope="module")
def undamped_run_up():
    """Ooten's regular fixed track (6 lower, 3 upper) without track dampers, from the run-up:
    the slider arrives with momentum and the lower asperities ring, so whether a force passes
    depends on the phase it meets (on the 10/3 scene a 0.1 % grid shows passing and stopping
    alternating from 0.99 to 1.05 x the smallest passing force)."""
    scene = a.make_scene(drive="force", damping_ratio=0.0, lower_count=6, upper_count=3)
    base = settled_run(scene, start="run-up", dt=measure_dt(scene, "run-up"))  # the bracket's own step
    return scene, critical_force_bracket(scene, start="run-up"), base


def test_non_monotone_run_up_finds_a_lower_passing_force_and_reports_the_band(undamped_run_up):
    scene, bracket, base = undamped_run_up
    assert passes(base, bracket.passes) and not passes(base, bracket.stops)
    assert bracket.band is not None and not bracket.monotone
    low, high = bracket.band
    assert low == bracket.passes and high > low and not passes(base, high)
    # plain bisection (what the search did before the check), run here independently from the
    # same bracket start, ends on a larger force: it trusted the one transition it found
    lo, hi = 0.5 * bracket.passes, 2.0 * bracket.passes
    assert not passes(base, lo) and passes(base, hi)
    while (hi - lo) / hi > 0.0025:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if passes(base, mid) else (mid, hi)
    assert hi > bracket.passes
    # brute force on a 1 % grid over the checked window below: nothing passes more than one
    # scan step below the returned force (what the check guarantees at its resolution)
    grid = bracket.value * np.arange(1.0 - SCAN_WINDOW, 1.0 - SCAN_STEP, 0.01)
    assert not any(passes(base, f) for f in grid)


def test_critical_force_warns_with_the_band(monkeypatch):
    from asperity2d import critical

    def fake_bracket(scene, **kw):
        return critical.CriticalForce(stops=0.9, passes=1.0, runs=3, start=kw["start"], band=(1.0, 1.07))

    monkeypatch.setattr(critical, "critical_force_bracket", fake_bracket)
    with pytest.warns(NonMonotoneWarning, match=r"not monotone in the force \(start='run-up'\): 1 N passes, "
                                                r"1.07 N does not") as record:
        assert critical.critical_force(a.make_scene(drive="force"), start="run-up") == 1.0
    # the warning names a caller's line, not critical.py's (the caller is this file; under a
    # mutation tool's trampoline it is the trampoline)
    assert os.path.samefile(record[0].filename, __file__) or "trampoline" in record[0].filename
    assert not os.path.samefile(record[0].filename, critical.__file__)
    monkeypatch.setattr(critical, "critical_force_bracket",
                        lambda scene, **kw: critical.CriticalForce(stops=0.9, passes=1.0, runs=3))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert critical.critical_force(a.make_scene(drive="force")) == 1.0


def test_a_damped_start_from_rest_is_monotone_and_silent():
    scene = a.make_scene(drive="force", lower_count=6, upper_count=3)
    with warnings.catch_warnings():
        warnings.simplefilter("error", NonMonotoneWarning)
        bracket = critical_force_bracket(scene)
    assert bracket.monotone and bracket.checked == SCAN_WINDOW


# -- the run budget, dt and iterations --------------------------------------------------------

SMALL = {"lower_count": 4, "upper_count": 2}


def test_runs_counts_every_simulation_and_max_runs_is_exact():
    scene = a.make_scene(drive="force", **SMALL)
    bracket = critical_force_bracket(scene)
    assert bracket.runs == len(bracket.tried)  # one simulation per distinct force
    assert critical_force_bracket(scene, max_runs=bracket.runs) == bracket
    with pytest.raises(a.SceneError, match="`max_runs`"):
        critical_force_bracket(scene, max_runs=bracket.runs - 1)


def test_a_given_dt_reaches_the_runs():
    """Checked through the public simulate() path, which starts where the run-up does: at
    dt/2 the bracket's stopping force stops and its passing force passes."""
    scene = a.make_scene(drive="force", **SMALL)
    half = default_dt(scene) / 2
    fine = critical_force_bracket(scene, start="run-up", dt=half)
    coarse = critical_force_bracket(scene, start="run-up", dt=2 * half)
    assert fine.passes != coarse.passes  # this scene's threshold moves with dt ...
    for force, status in ((fine.stops, False), (fine.passes, True)):  # ... and dt/2 was used
        result = a.simulate(scene.replace(drive=a.ConstantForce(force=force)), dt=half)
        assert (result.status == "passed") is status


def test_run_arguments_reach_every_run(monkeypatch):
    """A spy in place of Run records what the search builds its runs with: the defaults are
    Run's own (iterations 20, default dt), and given values arrive unchanged."""
    import inspect

    from asperity2d import critical
    from asperity2d.run import Run

    built = []

    class Built(Exception):
        pass

    def spy(scene, **kw):  # records the run's arguments and stops the search there
        built.append(kw)
        raise Built

    monkeypatch.setattr(critical, "Run", spy)
    scene = a.make_scene(drive="force", **SMALL)

    def args(**kw):
        with pytest.raises(Built):
            critical.critical_force(scene, **kw)
        return built[-1]

    run_defaults = inspect.signature(Run).parameters
    assert args()["iterations"] == run_defaults["iterations"].default == 20
    with pytest.raises(Built):  # the bracket's own default, not only critical_force's
        critical.critical_force_bracket(scene)
    assert built[-1]["iterations"] == run_defaults["iterations"].default
    # the step: half the simulation's default from rest (converged there), a quarter with a run-up
    assert args()["dt"] == 0.5 * default_dt(scene) == critical.measure_dt(scene, "rest")
    assert args()["max_steps"] == critical.MAX_STEPS
    assert args(start="run-up")["dt"] == 0.25 * default_dt(scene)
    assert args(start="entry")["dt"] == 0.5 * default_dt(scene)
    given = args(dt=3e-12, iterations=7, max_steps=123_456)
    assert (given["dt"], given["iterations"], given["max_steps"]) == (3e-12, 7, 123_456)


def test_bad_arguments():
    scene = a.make_scene(drive="force", **SMALL)
    with pytest.raises(a.SceneError, match="`rel_tol`"):
        critical_force_bracket(scene, rel_tol=1.0)
    with pytest.raises(a.SceneError, match="`rel_tol`"):
        critical_force_bracket(scene, rel_tol=-0.1)
    with pytest.raises(a.SceneError, match=r"^`scene` must be a Scene, got str$"):
        critical_force_bracket("scene")
    with pytest.raises(a.SceneError, match="`start`"):
        critical_force_bracket(scene, start="sideways")
    assert math.isfinite(critical_force(scene))


def test_a_slider_nothing_resists_reports_a_zero_lower_bracket():
    """Every force passes (on a rough surface the only asperity tall enough to reach a fixed
    track can be behind the slider): halving stops below FORCE_FLOOR of the estimate."""
    from asperity2d.critical import FORCE_FLOOR

    test = Counting(lambda f: True)
    lo, hi, band, tried = smallest_passing(test, 3.0)
    assert lo == 0.0 and band is None
    assert FORCE_FLOOR * 3.0 / 2 <= hi < FORCE_FLOOR * 3.0
    assert len(test.asked) == 22  # 3, 3/2, ..., 3 / 2**21


def test_a_small_force_is_cut_to_the_step_budget_not_refused():
    """The time limit of a constant-force run grows as 1/sqrt(F); inside the bracket search it is
    cut to what the run's step budget allows (a run that has not passed by then has not)."""
    scene = a.make_scene(drive="force", **SMALL)
    base = settled_run(scene, dt=measure_dt(scene, "rest"), max_steps=20_000)
    assert not passes(base, 1e-9)  # 20 000 steps: far too short to cross under 1 nN
    with pytest.raises(a.SceneError, match="`max_steps`"):  # the public run is still refused
        a.simulate(scene.replace(drive=a.ConstantForce(force=1e-9)), max_steps=20_000)


def test_every_argument_is_checked_under_its_own_name():
    """A bad value is refused by the parameter the user wrote, before any run is made."""
    scene = a.make_scene(drive="force", **SMALL)
    for call in (lambda: critical_force(scene, max_runs=1), lambda: critical_force_bracket(scene, max_runs=1)):
        with pytest.raises(a.SceneError, match=r"^`max_runs` must be >= 2, got 1$"):
            call()
    with pytest.raises(a.SceneError, match=r"^`start` must be one of .*'sideways'$"):
        measure_dt(scene, "sideways")
    never = Counting(lambda f: f >= 1.0)
    for first, rule in ((-61, ">= -60"), (61, "<= 60")):
        with pytest.raises(a.SceneError, match=rf"^`first` must be {rule}, got {first}$"):
            smallest_passing(never, 1.0, first=first)
    assert never.asked == []  # refused before the predicate was asked anything
    # the limits themselves are allowed: 2**-60 and 2**60 times the estimate, then the same bracket
    for first in (-60, 60):
        lo, hi, band, _ = smallest_passing(lambda f: f >= 1.0, 1.0, first=first)
        assert (lo, hi, band) == (1.0 - 2.0 ** -9, 1.0, None)  # 1 / 2**9 = 0.2 %: the first width <= 0.25 %


def test_the_tolerance_reaches_the_bisection(monkeypatch):
    """rel_tol given to critical_force arrives at critical_force_bracket, and from there at the
    search, unchanged (a spy in place of each)."""
    from asperity2d import critical

    scene = a.make_scene(drive="force", **SMALL)
    seen = {}

    def fake_bracket(scene, **kw):
        seen["bracket"] = kw["rel_tol"]
        return critical.CriticalForce(stops=0.9, passes=1.0, runs=3)

    def fake_search(test, estimate, **kw):
        seen["search"] = kw["rel_tol"]
        return 0.9, 1.0, None, [(0.9, False), (1.0, True)]

    monkeypatch.setattr(critical, "critical_force_bracket", fake_bracket)
    critical.critical_force(scene, rel_tol=0.125)
    monkeypatch.undo()
    monkeypatch.setattr(critical, "smallest_passing", fake_search)
    critical.critical_force_bracket(scene, rel_tol=0.0625)
    assert seen == {"bracket": 0.125, "search": 0.0625}


@pytest.mark.parametrize("entry", ["critical_force", "critical_force_bracket"])
def test_the_default_run_budget_is_80_runs(monkeypatch, entry):
    """A slider that never passes (every run reports "stopped"): each entry point runs exactly
    its documented default of 80 simulations, then refuses with the budget in the message."""
    from asperity2d import critical

    calls = []
    monkeypatch.setattr(critical, "passes", lambda base, force: calls.append(force) or False)
    with pytest.raises(a.SceneError, match=r"^`max_runs` = 80 runs did not bracket"):
        getattr(critical, entry)(a.make_scene(drive="force", **SMALL))
    assert len(calls) == 80 and calls[1] == 2 * calls[0]  # doubling, each force run once


# -- the remaining mutation survivors: the estimate, the pass/fail run, the search's edges ------

@pytest.mark.parametrize("kw, angle, mu", [({}, 45.0, 0.3), ({"flank_angle": 1.5}, 1.5, 0.3),
                                           ({"flank_angle": 30.0, "mu_static": 0.5}, 30.0, 0.5)])
def test_the_flank_estimate_is_the_wedge_law_of_each_set_up(kw, angle, mu):
    """Free slider: the load on one flank, L tan(theta + atan mu_s); fixed track: every upper tip
    pushing its spring down by the interference at once, n k delta tan(theta + atan mu_s)."""
    from asperity2d.critical import flank_estimate

    wedge = math.tan(math.radians(angle) + math.atan(mu))
    free = a.make_scene(drive="force", track="free", normal_load=0.01, mu_static=mu,
                        **{k: v for k, v in kw.items() if k != "mu_static"})
    assert flank_estimate(free) == pytest.approx(0.01 * wedge, rel=1e-12)
    fixed = a.make_scene(drive="force", mu_static=mu, **{k: v for k, v in kw.items() if k != "mu_static"})
    n, k, delta = fixed.slider.count, max(fixed.lower.stiffness), fixed.slider.interference
    assert flank_estimate(fixed) == pytest.approx(n * k * delta * wedge, rel=1e-12)


def test_the_flank_estimate_caps_the_wedge_at_89_degrees():
    """An 80-degree flank at mu_s = 0.5 (theta + phi = 106.6 degrees: no finite wedge): the
    estimate is the 89-degree wedge, tan 89 = 57.3 times the load, never tan 90's 1.6e16."""
    from asperity2d.critical import flank_estimate

    scene = a.make_scene(drive="force", track="free", normal_load=0.01, flank_angle=80.0, mu_static=0.5)
    assert flank_estimate(scene) == pytest.approx(0.01 * math.tan(math.radians(89.0)), rel=1e-12)


def test_a_pass_fail_run_records_nothing_and_stays_inside_the_step_budget(monkeypatch):
    """passes() asks its fork for at most the steps left in the budget, without a record (a
    critical force makes ~20 such runs: recording them would cost memory for nothing)."""
    from asperity2d.run import Run

    scene = a.make_scene(drive="force", **SMALL)
    base = settled_run(scene, dt=measure_dt(scene, "rest"), max_steps=20_000)
    asked = []
    advance = Run.advance

    def spy(self, duration, **kw):
        asked.append((duration, (self.max_steps - self.engine.step_count) * self.dt, kw))
        return advance(self, duration, **kw)

    monkeypatch.setattr(Run, "advance", spy)
    assert not passes(base, 1e-9)
    duration, room, kw = asked[0]
    assert duration <= room and duration == pytest.approx(0.999 * room, rel=1e-12)
    assert kw["record"] is False


def test_a_bracket_exactly_rel_tol_wide_is_final():
    """The bisection stops when the bracket is at most rel_tol wide: (0.5, 1.0) at rel_tol 0.5
    is final; a search that bisected it once more would return 0.75 as the stopping force."""
    lo, hi, band, _ = smallest_passing(lambda f: f >= 1.0, 1.0, rel_tol=0.5)
    assert (lo, hi, band) == (0.5, 1.0, None)


def test_the_check_never_asks_a_zero_force():
    """A window of the whole force (scan_step 0.25, window 1.0) reaches 0 below the threshold:
    a zero force is not a run (nothing would move), so it is never asked."""
    test = Counting(lambda f: f >= 1.0)
    lo, hi, band, _ = smallest_passing(test, 1.0, rel_tol=0.01, scan_step=0.25, window=1.0)
    assert 0.0 not in test.asked and lo < 1.0 <= hi and band is None


def test_the_second_bisection_starts_from_the_highest_force_seen_to_stop():
    """Passes at >= 1, in [0.90, 0.93] and in [0.55, 0.60], searched from 0.7 (which stops). The
    check finds 0.90 passing; 0.875 was seen to stop on the way, so the bisection down to the
    band's edge runs between them and asks nothing between the bracket's 0.7 and 0.8 (the band
    at 0.55-0.60 is beyond the window, as documented); restarting from half of 0.90 would."""
    rule = lambda f: f >= 1.0 or 0.90 <= f <= 0.93 or 0.55 <= f <= 0.60  # noqa: E731
    lo, hi, band, tried = smallest_passing(rule, 0.7)
    assert lo < 0.90 <= hi <= 0.90 * 1.0025
    assert any(abs(f - 0.875) < 1e-12 and not ok for f, ok in tried)  # the bracket's bisection: (0.7 + 1.05) / 2
    assert [f for f, _ in tried if 0.45 <= f < 0.80] == [0.7]


# -- settling: the start each search forks from ------------------------------------------------

class FakeRun:
    """Stands in for Run inside settled_run: each settle moves the slider ``step`` pitches, and
    a tip touches a flank from the ``touch``-th settle on (never, if None). Records what it was
    built with and every push. ``pitch`` is a power of two: x - x0 lands exactly on two pitches."""

    built: list = []
    pitch, step, touch = 2.0 ** -20, 0.5, None

    def __init__(self, scene, **kw):
        FakeRun.built.append(kw)
        self.pushes, self.x = [], 10.0 * self.pitch  # x far from 0: a position, not a displacement
        self.engine = self

    def slider_state(self):
        return (self.x, -3.0 * self.pitch, 0.0, 0.0)  # (x, y, vx, vy): y would never pass the reach test

    def arbiters_internal(self):
        return [object()] if self.touch is not None and len(self.pushes) >= self.touch else []

    def settle(self, push=None):
        self.pushes.append(push)
        self.x += self.step * self.pitch


@pytest.mark.parametrize("step, touch, settles", [
    (0.5, None, 5),   # nothing to touch: at exactly 2.0 pitches it pushes once more (past, not at), stops at 2.5
    (0.3, None, 7),   # 0.3 ... 2.1 pitches: the first push past two mean pitches is the last
    (0.0, None, 21),  # never moves, never touches: the first settle and MAX_PUSHES more, then gives up
    (0.5, 3, 3),      # a tip touches after the third settle: no further push
    (0.5, 1, 1),      # touching after the first settle: that settle is all
])
def test_settling_pushes_until_a_tip_touches_or_two_pitches_are_passed(monkeypatch, step, touch, settles):
    from asperity2d import critical

    monkeypatch.setattr(critical, "Run", FakeRun)
    monkeypatch.setattr(FakeRun, "step", step)
    monkeypatch.setattr(FakeRun, "touch", touch)
    scene = a.make_scene(drive="force", **SMALL)
    monkeypatch.setattr(type(scene.lower.spacing), "mean_pitch", property(lambda self: FakeRun.pitch))
    for start in ("rest", "entry"):
        run = critical.settled_run(scene, start=start)
        assert len(run.pushes) == settles
        push = critical.PUSH_FRACTION * critical.flank_estimate(scene)
        assert run.pushes == [push] * settles  # the gentle push every time, from both starts


def test_settling_builds_an_engaged_run_only_from_rest(monkeypatch):
    """From rest the slider starts over the surface (engaged); from the entry and with a run-up it
    starts where the builder puts it. Iterations default to Run's own, and a bad start is refused
    by its name."""
    import inspect

    from asperity2d import critical
    from asperity2d.run import Run

    FakeRun.built = []
    monkeypatch.setattr(critical, "Run", FakeRun)
    scene = a.make_scene(drive="force", **SMALL)
    for start in ("rest", "entry", "run-up"):
        critical.settled_run(scene, start=start)
    assert [kw["engaged"] for kw in FakeRun.built] == [True, False, False]
    assert FakeRun.built[0]["iterations"] == inspect.signature(Run).parameters["iterations"].default
    with pytest.raises(a.SceneError, match=r"^`start` must be one of"):
        critical.settled_run(scene, start="sideways")


def test_from_the_entry_the_front_tip_rests_against_the_first_flank():
    """The real run: settled for the entry, the fixed-track slider touches the surface (it was
    pushed to the first flank); with a run-up it is left before the surface, touching nothing."""
    scene = a.make_scene(drive="force", **SMALL)
    assert len(settled_run(scene, start="entry").engine.arbiters_internal()) > 0
    assert len(settled_run(scene, start="run-up").engine.arbiters_internal()) == 0


def test_a_slider_still_moving_at_the_time_limit_runs_on_until_it_passes_or_stops(monkeypatch):
    """Under the viscous law friction grows with speed, so a force just above the threshold
    crosses at a crawl: on Ooten's 16/4 track (random, seed 0) with a run-up, 34 mN is still
    moving at the first time limit (ten frictionless crossings) and passes in the second. Counting
    the limit as "did not pass" made the run-up critical force measure the time to cross."""
    from asperity2d.run import Run

    scene = a.make_scene(spacing="random", seed=0, contact_law="viscous", viscosity=0.005, drive="force")
    base = settled_run(scene, start="run-up", dt=measure_dt(scene, "run-up"))
    outcomes = []
    advance = Run.advance

    def spy(self, duration, **kw):
        outcomes.append(advance(self, duration, **kw))
        return outcomes[-1]

    monkeypatch.setattr(Run, "advance", spy)
    assert passes(base, 0.034)
    assert outcomes == ["duration", "passed"]  # the first limit alone would have said "stopped"
