"""The run loop (simulate.Run): forks, piecewise advancing, budgets, settling, divergence at scene scale."""

import math

import numpy as np
import pytest

import asperity2d as a
from asperity2d.run import MAX_STEPS, Run, Stuck, default_dt

SMALL = {"lower_count": 4, "upper_count": 2}


def _arrays(result):
    return np.concatenate([result.t, result.x, result.v, result.drive_force, result.friction_force])


def test_forks_of_one_run_are_bit_identical_and_independent():
    run = Run(a.make_scene(**SMALL))
    run.advance(5e-8)
    one, two = run.fork(), run.fork()
    one.advance(1e-7)
    two.advance(1e-7)
    assert np.array_equal(_arrays(one.result()), _arrays(two.result()))
    assert run.samples and run.time == pytest.approx(5e-8, rel=0.01)  # the original did not move on


def test_advancing_in_pieces_records_what_one_advance_records():
    """The engine steps the same steps either way: samples at the same steps hold the same values."""
    whole = Run(a.make_scene(**SMALL))
    whole.advance(1000 * whole.dt)
    pieces = Run(a.make_scene(**SMALL))
    for _ in range(4):
        pieces.advance(250 * pieces.dt)  # whole multiples of record_every (10 steps)
    w, p = whole.result(), pieces.result()
    common = np.intersect1d(w.t, p.t)
    assert len(common) == len(w.t)
    iw, ip = np.searchsorted(w.t, common), np.searchsorted(p.t, common)
    assert np.array_equal(w.x[iw], p.x[ip]) and np.array_equal(w.drive_force[iw], p.drive_force[ip])


@pytest.mark.parametrize("force, status", [(1e-4, "stuck"), (0.05, "passed")])
def test_an_unrecorded_advance_stops_where_a_recorded_one_does(force, status):
    """record=False keeps no samples, but its stops and guard see the same states at the same steps."""
    from asperity2d.run import default_duration, default_stops

    scene = a.make_scene(drive="force", drive_force=force, **SMALL)
    recorded, bare = Run(scene), Run(scene)
    assert recorded.advance(default_duration(scene), stop=default_stops(scene)) == status
    assert bare.advance(default_duration(scene), stop=default_stops(scene), record=False) == status
    assert bare.time == recorded.time and bare.samples == 0 < recorded.samples
    assert bare.engine.slider_state() == recorded.engine.slider_state()
    assert bare.max_overlap == recorded.max_overlap


def test_an_unrecorded_advance_catches_a_divergence_at_the_step_a_recorded_one_does():
    """The guard of a run that keeps no record (the bisection's) is the recorded run's guard:
    a step too coarse to be stable (T/2, forced) diverges, and both raise at the same time."""
    scene = a.make_scene(**SMALL)
    dt = scene.shortest_period() / 2
    errors = []
    for record in (True, False):
        run = Run(scene, dt=dt, unsafe_dt=True)
        with pytest.raises(a.SimulationError, match="smaller dt") as info:
            run.advance(2e-7, record=record)
        errors.append(info.value)
    assert 0 < errors[0].time == errors[1].time < 2e-7
    assert str(errors[0]) == str(errors[1])


def test_a_stop_condition_instance_can_serve_several_runs():
    scene = a.make_scene(drive="force", drive_force=1e-4, **SMALL)  # stops on the first flank
    stuck = Stuck(speed=0.5, dwell=2e-9)
    first = Run(scene)
    first.advance(4e-7, stop=stuck)
    second = Run(scene)
    assert second.advance(4e-7, stop=stuck) == first.status == "stuck"
    assert second.time == first.time  # the second run did not inherit the first one's clock


def test_a_run_over_the_step_budget_is_refused_naming_what_makes_it_long():
    scene = a.make_scene(**SMALL)
    with pytest.raises(a.SceneError, match="`duration`.*`max_steps`|`max_steps`.*`duration`"):
        a.simulate(scene, duration=1.0)
    heavy = a.make_scene(slider_mass=2.88e-9, track="free", **SMALL)  # settling: 3e5 fast periods a slow one
    with pytest.raises(a.SceneError, match="settl.*`slider_mass`"):
        a.simulate(heavy, duration=1e-9, max_steps=100_000)
    assert MAX_STEPS == 10_000_000


def test_settling_stops_when_the_motion_has_decayed():
    scene = a.make_scene(track="free", **SMALL)
    run = Run(scene)
    spent = run.settle()
    assert 0 < spent < run.settle_cap()  # ended early, not at the 10-period cap
    rows = run.engine.bodies_internal()
    assert np.abs(rows[:, 2:]).max() == 0.0  # left at rest
    _, y, _, _ = run.engine.slider_state()
    assert y < a.make_scene(track="free", **SMALL).lower.profile.height * 2  # came down onto the tips


def test_default_dt_resolves_the_drive_damper():
    scene = a.make_scene(drive_damping=1e-3, **SMALL)
    m_over_c = scene.slider.mass / 1e-3
    assert default_dt(scene) == pytest.approx(0.2 * m_over_c)
    result = a.simulate(scene, duration=1e-8)  # diverged at T/50 before
    assert np.all(np.isfinite(result.v)) and np.abs(result.v).max() < 2 * scene.drive.velocity
    with pytest.raises(a.SceneError, match="`drive_damping`"):
        a.simulate(scene, duration=1e-8, dt=0.6 * m_over_c)


@pytest.mark.parametrize("track", ["fixed", "free"])
def test_a_wrong_run_is_caught_at_the_scene_scale(track):
    """dt = 10 T is far past stable (T/6 blows up): the run must raise, not return km/s. The free
    slider is refused before it starts: its load alone would drop it 20 asperity heights in
    one such step (issue 27's prevention); the fixed track runs and diverges."""
    scene = a.make_scene(track=track, **SMALL)
    error, match = ((a.SimulationError, "kinetic energy") if track == "fixed"
                    else (a.SceneError, "`normal_load` makes the slider too fast for the step"))
    with pytest.raises(error, match=match):
        a.simulate(scene, duration=1e-7, dt=10 * scene.shortest_period(), unsafe_dt=True, settle=False)


def test_gravity_does_not_trip_the_divergence_guard():
    """Found by the fuzzer: a strong gravity pours energy in; the guard counts its work."""
    result = a.simulate(a.make_scene(gravity=4e14, **SMALL), duration=4e-9)
    assert np.all(np.isfinite(result.v))
    assert math.isfinite(result.meta["max_overlap_fraction"])


def test_a_scene_wider_than_a_million_bases_keeps_its_slider_and_floor():
    # fuzz-found: with a 5 m pitch on a 1 µm base the slider started 5.6e6 bases left of the
    # surface, outside the fixed track's old [-1e6, 1e6] groove, which snapped it onto the
    # groove's end at 4e6 bases per time unit (the divergence guard then fired at step 10).
    scene = a.make_scene(spacing="random", drive="force", seed=0, lower_count=3, upper_count=2, pitch=5.0)
    result = a.simulate(scene, 2e-10, settle=False, record_every=1)
    # the constant force alone moves it from rest (the tips are metres from any contact):
    # pymunk moves positions with the velocity before the step's kick, so after n steps
    # x - x0 = F dt^2 n (n - 1) / 2M, i.e. F t (t - dt) / 2M. Tolerance: 1e-14 m absolute is
    # ~10 ulp of a position 5.6 m from the origin; 1e-6 relative covers the rounding of the
    # recorded times (t is summed step by step)
    t = result.t - result.t[0]
    expected = scene.drive.force * t * (t - (t[1] - t[0])) / (2 * scene.slider.mass)
    assert np.allclose(result.x - result.x[0], expected, rtol=1e-6, atol=1e-14)


def test_observers_see_every_sample_in_si_and_do_not_change_the_run():
    # an observer is called at every sample (the settled state included) with the SI view the
    # stop conditions see; the run it watches is bit-identical to one nobody watches
    scene = a.make_scene(lower_count=4, upper_count=2)
    duration = 400 * scene.shortest_period() / 50
    seen = []
    watched = a.simulate(scene, duration, energy=True,
                         observers=[lambda p: seen.append((p.t, p.x, p.v, p.drive_force, p.energy()))])
    plain = a.simulate(scene, duration, energy=True)
    for name in ("t", "x", "v", "drive_force", "friction_force", "lower_dy"):
        assert np.array_equal(getattr(watched, name), getattr(plain, name))
    assert len(seen) == len(plain.t)
    t, x, v, f, books = map(list, zip(*seen))
    assert t == plain.t.tolist() and x == plain.x.tolist() and v == plain.v.tolist()
    assert f == plain.drive_force.tolist()
    assert books[-1] == watched.meta["energy"]  # the books so far: at the last sample, all of them
    assert books[0]["drive_work_J"] == 0.0 < books[-1]["drive_work_J"]
    with pytest.raises(a.SceneError, match="`observers`"):
        a.simulate(scene, duration, observers=[1])
