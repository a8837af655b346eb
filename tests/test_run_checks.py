"""Physical validity of asperity runs (issue 27): impossible results raise, legitimate ones pass.

Each check is exercised both ways: the impossible case (issue 27's reproducers, or a state
written into the engine that no physical run can reach) must raise, naming what happened and
the parameter to change; the legitimate near miss next to it must pass and say so in
``result.meta["checks"]``.
"""

import numpy as np
import pytest

import asperity2d as a
from asperity2d.engine.run_checks import STEP_FRACTION, STEP_WARNING, Validity, load_capacity
from asperity2d.run import Run

SMALL = {"lower_count": 4, "upper_count": 2}


# -- prevention: refused before anything is built ------------------------------------------------
@pytest.mark.parametrize("kw, name", [
    # issue 27 item 1: 10 N on 8 lower springs that carry 56 mN at the bottom of their travel
    (dict(track="free", normal_load=10.0, lower_count=8, upper_count=2), "`normal_load`"),
    (dict(track="free", normal_load=1e6, lower_count=8, upper_count=2), "`normal_load`"),
    # item 2: 1.4e9 m/s from a preloaded drive spring; 3.8e7 m/s from a 1 kN force
    (dict(drive_preload=1e6), "`drive_preload`"),
    (dict(drive="force", drive_force=1e3), "`drive_force`"),
    # item 2: tiny masses pushed with 1 N
    (dict(drive="force", drive_force=1.0, mass=2.88e-18, slider_mass=2.88e-17), "`drive_force`"),
])
def test_issue_27_reproducers_are_refused_up_front(kw, name):
    scene = a.make_scene(**kw)
    with pytest.raises(a.SceneError) as info:
        a.simulate(scene)
    assert name in str(info.value)
    assert "pass through" in str(info.value) or "fall through" in str(info.value)


def test_a_coarse_unsafe_step_on_a_free_slider_is_refused():
    # issue 27 item 3: dt = 2.5 T returned "passed" with the slider 1.5 m below the surface
    scene = a.make_scene(track="free")
    with pytest.raises(a.SceneError, match="`normal_load` makes the slider too fast"):
        a.simulate(scene, dt=2.5 * scene.shortest_period(), unsafe_dt=True)


def test_the_load_capacity_is_the_springs_under_the_slider_at_the_bottom_of_their_travel():
    # 2 upper tips on a 1.25 um pitch: the footprint (their span plus a base each side, 3.25 um)
    # holds 3 lower tips; each spring carries k x travel_down = 37200 N/m x 0.5 um = 18.6 mN
    scene = a.make_scene(track="free", lower_count=8, upper_count=2)
    capacity, count = load_capacity(scene)
    assert count == 3 and capacity == pytest.approx(3 * 37_200 * 0.5e-6, rel=1e-12)
    # the near miss carries its load (resting at most a hair above the floor), the next one is refused
    result = a.simulate(a.make_scene(track="free", lower_count=8, upper_count=2, normal_load=0.95 * capacity),
                        duration=2e-8)
    assert result.success and result.checks["floor"]["passed"]
    assert result.checks["floor"]["worst"] < 0.01  # bases below the floor: none beyond the 1e-3 slop
    with pytest.raises(a.SceneError, match="hold at most 0.0558 N"):
        a.simulate(a.make_scene(track="free", lower_count=8, upper_count=2, normal_load=1.05 * capacity))


def test_a_rigid_substrate_carries_any_load():
    # a profile's valleys are rigid: the load capacity of the springs does not bound the load
    x = np.linspace(0, 20e-6, 401)
    z = 0.4e-6 * np.maximum(0, np.cos(2 * np.pi * x / 2.5e-6))
    scene = a.make_scene(track="free", lower_surface=(x, z), normal_load=1.0, upper_count=2)
    assert scene.lower.substrate and load_capacity(scene)[0] < 1.0
    Run(scene)  # builds: not refused


# -- detection: while running ----------------------------------------------------------------------
def test_a_force_too_fast_for_the_step_raises_and_a_slower_one_passes():
    # prevention judges the speed over one pitch; over 4 pitches 0.2 N makes the slider 1.3 windows
    # a step. 0.05 N moves it 0.55 windows at most: a normal pass (its pass time agrees with
    # dt/8 to 0.1 %); 0.1 N (0.8) passes marked degraded
    with pytest.raises(a.SimulationError, match="the step cannot resolve the motion") as info:
        a.simulate(a.make_scene(drive="force", drive_force=0.2, **SMALL))
    assert "`dt`" in str(info.value) and "`drive_force`" in str(info.value)
    ok = a.simulate(a.make_scene(drive="force", drive_force=0.05, **SMALL))
    assert ok.status == "passed" and ok.success
    assert 0.3 < ok.checks["step_resolution"]["worst"] <= STEP_WARNING
    degraded = a.simulate(a.make_scene(drive="force", drive_force=0.1, **SMALL))
    assert degraded.status == "passed" and not degraded.success
    assert STEP_WARNING < degraded.checks["step_resolution"]["worst"] <= STEP_FRACTION
    assert "WARNING" in degraded.message and "smaller `dt`" in degraded.message


def _validity(scene):
    run = Run(scene)
    check = Validity(run.engine)
    rows = run.engine.bodies_internal().copy()
    return run, check, rows


def test_a_slider_below_the_floor_raises_and_one_resting_on_it_passes():
    run, check, rows = _validity(a.make_scene(track="free", **SMALL))
    r = run.engine.layout.slider_row
    floor = check.floor + check.deepest  # slider datum height with its deepest tip on the floor
    rows[r, 1] = floor - 0.4  # sunk 0.4 bases into the floor: a hard landing, within tolerance
    check.check(rows)
    assert check.report()["floor"]["worst"] == pytest.approx(0.4)
    rows[r, 1] = floor - 3.0  # three bases below the floor: it has fallen through
    with pytest.raises(a.SimulationError, match="fell through the lower surface"):
        check.check(rows)


def _over_the_surface(run, check, rows, x):
    r = run.engine.layout.slider_row
    rows[r, 0], rows[r, 2] = x, 0.0
    return rows


def test_a_tip_passing_an_untouched_asperity_raises_and_a_touched_one_passes():
    # a fixed-track slider carried across lower asperity 1 between two samples, slowly (so the
    # step check is content), and the asperity left exactly at rest: it was not touched
    run, check, rows = _validity(a.make_scene(**SMALL))
    apex = run.engine.layout.lower_apex_x
    rows = _over_the_surface(run, check, rows, apex[1] - 0.3)
    run.engine.step_count = 0
    check.check(rows)
    run.engine.step_count = 10
    rows = _over_the_surface(run, check, rows, apex[1] + 0.3)
    touched = rows.copy()
    lower = run.engine.layout.lower_rows
    with pytest.raises(a.SimulationError, match="passed through lower asperity 1 without touching it"):
        check.check(rows)
    # the same crossing with asperities 1 and 2 (under the two tips) pushed down: touched
    run2, check2, _ = _validity(a.make_scene(**SMALL))
    run2.engine.step_count = 0
    check2.check(_over_the_surface(run2, check2, touched.copy(), apex[1] - 0.3))
    run2.engine.step_count = 10
    touched[lower, 1] = np.where(np.isin(np.arange(len(apex)), [1, 2]), -0.1, 0.0)
    check2.check(touched)
    assert check2.crossings == 2


def test_a_body_moving_a_feature_a_step_raises():
    run, check, rows = _validity(a.make_scene(**SMALL))
    r = run.engine.layout.slider_row
    rows[r, 0] = run.engine.layout.lower_apex_x[1]
    rows[r, 2] = 0.9 * check.fx / check.dt  # 0.9 of the window in one step: a pass, degraded
    check.check(rows)
    rows[r, 2] = 1.2 * check.fx / check.dt
    with pytest.raises(a.SimulationError, match="1.2 times the smallest feature"):
        check.check(rows)


# -- the record of what passed ------------------------------------------------------------------
def test_every_result_carries_the_checks_it_passed():
    result = a.simulate(a.make_scene(**SMALL))
    checks = result.checks
    assert set(checks) == {"divergence", "step_resolution", "contacts", "step_size"}
    assert all(c["passed"] for c in checks.values()) and result.success
    assert checks["contacts"]["crossings"] >= 2 * 4 - 1  # both tips passed the lower tips
    assert result.summary()["checks"] == dict.fromkeys(checks, "passed")
    free = a.simulate(a.make_scene(track="free", **SMALL), duration=2e-8)
    assert {"floor", "step_resolution"} <= set(free.checks) and free.success


def test_an_unsafe_coarse_step_is_returned_marked_unsuccessful():
    scene = a.make_scene(**SMALL)
    result = a.simulate(scene, dt=scene.shortest_period() / 15, unsafe_dt=True, duration=3e-9)
    assert not result.success and not result.checks["step_size"]["passed"]
    assert "WARNING: dt is 1.33 times the coarsest step that converges" in result.message
    assert result.summary()["checks"]["step_size"].startswith("failed")


def test_a_fork_checks_its_own_run_with_its_parents_limits():
    """A fork reuses the limits its parent's checks computed from the scene (Validity.fresh,
    paid once rather than by each of a critical force's ~20 forks) but keeps books of its own:
    they read the same as checks built anew for the fork's engine, after the same run."""
    run = Run(a.make_scene(**SMALL))
    run.advance(2e-7)  # over the first apexes (the slider leaves the surface by 0.6 us)
    parent = run._record.validity
    assert parent.crossings > 0 and parent.worst_step > 0  # books the forks must not inherit
    fork, rebuilt = run.fork(), run.fork()
    rebuilt._record.validity = Validity(rebuilt.engine)
    assert fork._record.validity.engine is fork.engine
    assert (fork._record.validity.crossings, fork._record.validity.worst_step) == (0, 0.0)
    for r in (fork, rebuilt):
        r.advance(4e-7)
    assert fork._record.validity.crossings > 0
    assert fork.result().checks == rebuilt.result().checks
    assert (parent.crossings, parent.worst_step) == (run._record.validity.crossings,
                                                     run._record.validity.worst_step)


# -- the end of the surface: a run that leaves it says so -------------------------------------------
#: A 3 mN flat block (mu 0.36 / 0.35) on a 37.2 kN/m drive spring at 5 m/s: one lower flat 1 um
#: wide whose face (between its rounded edges) ends 0.35 um from its centre, as does the block's.
FLAT_BLOCK = dict(profile="flat", height=0.25e-6, lower_count=1, upper_count=1, track="free",
                  mu_static=0.36, mu_kinetic=0.35, normal_load=3e-3, drive="spring",
                  drive_stiffness=37.2e3, drive_velocity=5.0)


def test_a_block_that_runs_off_its_flat_ends_the_run_there():
    """Driven 3e-7 s at 5 m/s the block would travel 1.5 um: once its face has passed the lower
    face's far end (x = 0.7 um) it slid down their rounded edges and fell to the guard floor, a
    normal force of 58 x its load, under status "duration". Now the run ends where the faces part,
    status "off-surface", with a message naming the body, the asperity and the place; the samples
    before it are those of the same run cut there, and its load never spiked."""
    scene = a.make_scene(**FLAT_BLOCK)
    result = a.simulate(scene, 3e-7, record_every=1, progress=False)
    assert result.status == "off-surface" and result.success
    assert result.message.startswith("the slider ran off the far end of the lower surface at t = ")
    assert "lower asperity 0's face (x = 3.5e-07 m)" in result.message and "guard floor" in result.message
    assert 0.7e-6 < result.x[-1] < 0.7e-6 + 2 * result.meta["dt"] * np.abs(result.v).max()
    assert np.all(result.x[:-1] <= 0.7e-6)  # it ended at the first sample past the face
    assert result.normal_force.max() < 1.02 * scene.slider.normal_load
    shorter = a.simulate(scene, 1e-7, record_every=1, progress=False)  # on the flat all along
    assert shorter.status == "duration"
    n = len(shorter.t)
    for name in ("t", "x", "v", "y", "normal_force", "drive_force"):
        assert np.array_equal(getattr(result, name)[:n], getattr(shorter, name)), name


@pytest.mark.parametrize("kw", [dict(drive_stiffness=0.2 * 37.2e3), dict(normal_load=9e-3)])
def test_a_softer_spring_or_a_heavier_load_runs_off_the_same_way(kw):
    """The softer spring (k x0.2) and the heavier load (N x3) of the same block, run long enough to
    reach the end: the same status, no spike."""
    scene = a.make_scene(**{**FLAT_BLOCK, "mu_static": 0.5, **kw})
    result = a.simulate(scene, 3e-7, progress=False)
    assert result.status == "off-surface"
    assert result.normal_force.max() < 1.05 * scene.slider.normal_load


def test_a_fixed_track_slider_past_the_last_asperity_keeps_its_samples_and_says_where_it_left():
    """On the fixed track a slider past the end coasts on its track touching nothing: the run keeps
    every sample (the golden force_random run is this case, bit for bit) but ends "off-surface",
    not "duration", its message saying when it left."""
    scene = a.make_scene(drive="force", drive_force=0.02, spacing="random", seed=3, lower_count=8)
    result = a.simulate(scene, 3000 * scene.shortest_period() / 50)
    assert result.status == "off-surface"
    assert "lower asperity 7's face" in result.message and "touched nothing after that" in result.message
    left = float(result.message.split("at t = ")[1].split(" s")[0])
    assert 0 < left < result.t[-1]
    assert np.all(result.contact_count[result.t > left] == 0)


def test_passing_is_still_passing_and_a_stop_wins_over_leaving():
    """With ``duration=None`` the Passed stop (rear tip half a base past the last apex) comes first;
    a free slider on triangles too. A run that ends before the end keeps "duration"."""
    assert a.simulate(a.make_scene(**SMALL)).status == "passed"
    assert a.simulate(a.make_scene(track="free", **SMALL)).status == "passed"
    assert a.simulate(a.make_scene(**SMALL), 20e-9).status == "duration"
    block = a.make_scene(**FLAT_BLOCK)
    assert a.simulate(block, stop=a.Passed()).status == "passed"  # x 0.5 um, before the face ends
