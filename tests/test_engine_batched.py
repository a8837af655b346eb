"""The batched engine (engine="batched") cross-validated against pymunk, the reference.

Skipped without Numba (the ``[batch]`` extra, also in ``test``). The first test to run compiles
the engine's loop once (cached beside the module afterwards).
"""

import math

import numpy as np
import pytest

pytest.importorskip("numba", reason='the batched engine needs Numba: pip install "asperity2d[batch]"')

import asperity2d as a  # noqa: E402
from asperity2d import analysis, closed_forms  # noqa: E402
from asperity2d.engine import batched  # noqa: E402
from asperity2d.errors import SceneError, SimulationError  # noqa: E402
from asperity2d.experiments.measures import stick_forces_of  # noqa: E402
from asperity2d.run import simulate_many  # noqa: E402

SMALL = {"lower_count": 4, "upper_count": 2}


def test_a_non_chaotic_run_follows_pymunk():
    """The regular default scene under a constant force (0.02 N: it passes without sticking, so
    nothing chaotic decides its path) follows the reference sample for sample.

    Tolerance: both engines make the same IEEE operations in the same order (Chipmunk's contact
    solver, sweep order included) except the contact normal, which pymunk's GJK/EPA takes from
    the Minkowski difference's vertices and this engine from the polygon's edge normal: the
    two differ in the last bits (1e-16 relative), and measured, the run ends 1.0e-14 bases and
    2.3e-15 of its top speed apart. The bound, 1e-9 bases of position and 1e-9 of the top
    speed, is 10^5 above that and 10^6 below the smallest length the model resolves (the
    collision slop, 1e-3 bases): a run inside it is the reference's run to every physical
    digit, while a different contact sequence (a sweep in another order: 2.7e-6) fails it.
    """
    scene = a.make_scene(drive="force")
    ref = a.simulate(scene, record_every=1, progress=False)
    assert ref.status == "passed"
    got = simulate_many([scene], ref.t[-1], record_every=1, engine="batched")[0]
    assert got.meta["engine"] == "batched" and len(got.t) == len(ref.t)
    base = scene.base
    np.testing.assert_array_equal(got.t, ref.t)
    assert np.abs(got.x - ref.x).max() < 1e-9 * base
    assert np.abs(got.y - ref.y).max() < 1e-9 * base
    assert np.abs(got.v - ref.v).max() < 1e-9 * np.abs(ref.v).max()
    assert np.abs(got.normal_force - ref.normal_force).max() < 1e-9 * np.abs(ref.normal_force).max()
    np.testing.assert_array_equal(got.contact_count, ref.contact_count)


@pytest.mark.parametrize("kwargs", [{"profile": "half", "half_shape": "apex-cut"},
                                    {"profile": "half", "half_shape": "full-base"},
                                    {"profile": "flat"}])
def test_every_profile_follows_pymunk(kwargs):
    """Half triangles (both cuts: a vertical face) and flat tops (eight-vertex outlines, face on
    face) under the first test's constant
    force: the reference's contacts and trajectory, to the first test's bound and for its
    reason (measured: at most 2.0e-14 bases and 2.0e-15 of the top speed; the flat scene sticks
    on its first tops, which it does in both engines at the same sample)."""
    scene = a.make_scene(drive="force", **kwargs)
    ref = a.simulate(scene, record_every=1, progress=False)
    got = simulate_many([scene], ref.t[-1], record_every=1, engine="batched")[0]
    assert len(got.t) == len(ref.t) > 300
    assert np.abs(got.x - ref.x).max() < 1e-9 * scene.base
    assert np.abs(got.y - ref.y).max() < 1e-9 * scene.base
    assert np.abs(got.v - ref.v).max() < 1e-9 * np.abs(ref.v).max()
    np.testing.assert_array_equal(got.contact_count, ref.contact_count)


def test_a_measured_profile_with_its_valleys_follows_the_reference():
    """A measured profile's asperities (per-asperity runs, heights and base levels) and its rigid
    valleys (``substrate``, static segments as the floor is): a whole spring-driven pass on the
    fixed track, as the reference (measured: 8e-13 of a base apart; the bound leaves 1,000 x)."""
    from pathlib import Path

    path = Path(__file__).resolve().parent.parent / "scenes" / "data" / "measured_style_profile.csv"
    scene = a.make_scene(lower_surface=path)
    assert scene.lower.substrate
    ref = a.simulate(scene, 0.4e-6, progress=False)
    got = simulate_many([scene], 0.4e-6, engine="batched")[0]
    n = len(got.t)  # the reference also keeps the duration's last, partial sample interval
    assert n > 3000 and len(ref.t) in (n, n + 1)
    np.testing.assert_array_equal(got.t, ref.t[:n])
    assert np.abs(got.x - ref.x[:n]).max() < 1e-9 * scene.base
    assert np.abs(got.drive_force - ref.drive_force[:n]).max() < 1e-9 * np.abs(ref.drive_force).max()


def _gap_profile():
    """Two 45-degree triangles (0.4 um high) 3 um apart, a flat valley 0.2 um below their feet
    between them (tests/test_rough_scene.py's, without its bump)."""
    x = np.arange(0.0, 6e-6, 5e-9)
    z = np.zeros_like(x)
    for apex in (1e-6, 5e-6):
        z = np.maximum(z, 0.4e-6 - np.abs(x - apex))
    z[(x > 1.6e-6) & (x < 4.4e-6)] = -0.2e-6
    return x, z


@pytest.mark.parametrize("valleys", [True, False])
def test_a_tip_over_a_gap_rests_where_the_reference_rests(valleys):
    """A free slider whose one tip starts over a wide gap comes to rest on the valley floor (the
    substrate) or, without it, on the guard floor -- static segments the batched engine collides
    as Chipmunk does (the segment's normal, its support edge, Chipmunk's contact points): at rest
    at the reference's height, within the collision slop (1e-3 base; measured: the same numbers at
    every sample)."""
    import dataclasses

    scene = a.make_scene(lower_surface=_gap_profile(), surface_detrend=False, upper_count=1, track="free",
                         normal_load=1e-3)
    if not valleys:
        scene = scene.replace(lower=dataclasses.replace(scene.lower, substrate=None))
    ref = a.simulate(scene, 2e-8, progress=False)
    got = simulate_many([scene], 2e-8, engine="batched")[0]
    floor = -0.2e-6 if valleys else scene.lower.floor
    assert abs(ref.y[-1] - scene.slider.depth - floor) < 2e-3 * scene.base  # it rests there
    assert abs(got.y[-1] - ref.y[-1]) < 1e-3 * scene.base


def test_a_scene_alone_equals_the_same_scene_in_a_batch():
    scenes = [a.make_scene(**SMALL, spacing="random", seed=s) for s in (1, 2, 3)]
    alone = simulate_many([scenes[1]], 60e-9, engine="batched")[0]
    together = simulate_many(scenes, 60e-9, engine="batched")[1]
    for name in ("t", "x", "v", "y", "vy", "drive_force", "normal_force", "friction_force", "tangential_force",
                 "contact_count"):
        np.testing.assert_array_equal(getattr(alone, name), getattr(together, name), err_msg=name)


def test_same_scene_same_numbers():
    scene = a.make_scene(**SMALL, spacing="random", seed=5)
    one, two = (simulate_many([scene], 40e-9, engine="batched")[0] for _ in range(2))
    np.testing.assert_array_equal(one.x, two.x)
    np.testing.assert_array_equal(one.drive_force, two.drive_force)


def test_simulate_on_the_batched_engine_passes_the_surface_as_the_reference_does():
    scene = a.make_scene(**SMALL)
    ref, got = a.simulate(scene, progress=False), a.simulate(scene, engine="batched")
    assert got.status == ref.status == "passed"
    assert len(got.t) == len(ref.t)
    # the stick forces of the pass (each a quasi-static barrier): within 1e-6 (measured 1.4e-8)
    ref_events = [e.force_peak for e in analysis.stick_slip_events(ref)]
    got_events = [e.force_peak for e in analysis.stick_slip_events(got)]
    assert len(got_events) == len(ref_events) > 0
    np.testing.assert_allclose(got_events, ref_events, rtol=1e-6)


@pytest.mark.parametrize("kwargs", [{"profile": "half"}, {"height_std": 5e-8, "seed": 3}])
def test_stick_forces_of_other_profiles_agree_with_pymunk(kwargs):
    """A spring-driven pass over half triangles and over random heights: the same stick events,
    their forces within 1e-6 (measured 5e-14 and 9e-15), as for full triangles above."""
    scene = a.make_scene(**SMALL, **kwargs)
    ref, got = a.simulate(scene, progress=False), a.simulate(scene, engine="batched")
    ref_events = [e.force_peak for e in analysis.stick_slip_events(ref)]
    got_events = [e.force_peak for e in analysis.stick_slip_events(got)]
    assert len(got_events) == len(ref_events) > 0
    np.testing.assert_allclose(got_events, ref_events, rtol=1e-6)


@pytest.mark.parametrize("seeds", [(0,), pytest.param((0, 1, 2), marks=pytest.mark.slow)])
def test_peak_stick_force_per_seed_agrees_with_pymunk(seeds):
    """Random seeds x 3 passes of a small scene: each seed's peak stick force within 1 %
    (measured: 2e-5 at most; the passes are chaotic, but their sticks are the same barriers).
    One seed in the default run (its pymunk passes are most of the file's time), three slow."""
    scenes = [a.make_scene(**SMALL, spacing="random", seed=s) for s in seeds]
    ref = stick_forces_of(scenes, engine="pymunk")
    got = stick_forces_of(scenes, engine="batched")
    for r, g in zip(ref, got):
        assert g.average("peak") == pytest.approx(r.average("peak"), rel=0.01)
        assert g.dt == r.dt


def test_flank_law_on_the_batched_engine():
    """The closed-form check ``flank-law-all-tips`` of ``asperity2d validate`` on this engine:
    n tips on Ooten's fixed track push their asperities down by δ at once, so the largest stick
    force is n k δ tan(45° + atan μs) (2 %: the drive's dynamic overshoot, as the check says)."""
    scene = a.make_scene(lower_count=8, upper_count=3)
    result = a.simulate(scene, engine="batched")
    n, k, delta = scene.slider.count, scene.lower.stiffness[0], scene.slider.interference
    expected = n * k * delta * math.tan(math.radians(45.0) + math.atan(scene.contact.mu_static))
    assert analysis.peak_stick_force(result) == pytest.approx(expected, rel=0.02)


def test_a_diverging_scene_fails_alone():
    """Every scene the checks let through is stable, so divergence is made by hand: one scene's
    slider velocity set to NaN mid-batch. It stops with its own error; its neighbours finish, as
    they would alone."""
    scene = a.make_scene(**SMALL)
    dt = a.simulate(scene, 1e-9).meta["dt"]
    batch = batched.Batch([scene] * 3, [dt] * 3, samples=300)
    batch.advance([500] * 3)
    batch.sv[1, 0] = math.nan
    batch.advance([2000] * 3)
    assert batch.error(0) is None and batch.error(2) is None
    error = batch.error(1)
    assert isinstance(error, SimulationError) and "scene 1" in str(error) and "non-finite" in str(error)
    assert batch.nstep.tolist() == [2500, 501, 2500]
    np.testing.assert_array_equal(batch.rec[0], batch.rec[2])
    alone = batched.Batch([scene], [dt], samples=300)
    alone.advance([2500])
    np.testing.assert_array_equal(alone.rec[0], batch.rec[0])


def test_a_batch_too_large_is_refused_up_front_naming_its_size(monkeypatch):
    monkeypatch.setattr(batched, "MAX_BATCH_BYTES", 10_000)
    scenes = [a.make_scene(**SMALL)] * 40
    with pytest.raises(SceneError, match="a batch of 40 scenes"):
        simulate_many(scenes, 1e-9, engine="batched")


def test_a_thousand_full_passes_run_in_batches_under_a_gigabyte():
    """1,000 default scenes, each a full pass at dt/2 (twice the stick step's record): their records alone
    would be 3.5 GB, so :func:`batched.run` steps them in batches whose arrays -- state,
    geometry and record, as allocated -- stay within CHUNK_BYTES (256 MiB), well under 1 GB."""
    from asperity2d.run import default_dt, default_duration

    scenes = [a.make_scene()] * 1000
    dt = 0.5 * default_dt(scenes[0])
    steps = int(default_duration(scenes[0]) / dt)
    size = batched.batch_size(scenes, steps)
    assert 1 < size < 1000
    nbytes = batched.Batch.nbytes_for(size, 16, 4, steps // 10)
    assert nbytes <= batched.CHUNK_BYTES < 2**30
    # the estimate is what a batch allocates (here for a short record, the same formula)
    batch = batched.Batch(scenes[:size], [dt] * size, samples=100)
    allocated = sum(v.nbytes for v in vars(batch).values() if isinstance(v, np.ndarray))
    assert allocated <= batched.Batch.nbytes_for(size, 16, 4, 100) < 1.1 * allocated


def test_results_do_not_depend_on_how_a_call_is_batched(monkeypatch):
    scenes = [a.make_scene(**SMALL, spacing="random", seed=s) for s in range(5)]
    whole = simulate_many(scenes, 30e-9, engine="batched")
    monkeypatch.setattr(batched, "CHUNK_BYTES", 1)  # one scene per batch
    assert batched.batch_size(scenes, 10_000) == 1
    split = simulate_many(scenes, 30e-9, engine="batched")
    for one, two in zip(whole, split):
        np.testing.assert_array_equal(one.x, two.x)
        np.testing.assert_array_equal(one.friction_force, two.friction_force)


def test_results_do_not_depend_on_the_scenes_interleaved_with_them(monkeypatch):
    """A thread steps up to ``LANES`` scenes together, their sweeps interleaved contact by
    contact; each scene's numbers are those it has stepped alone, down to the last bit -- here
    with lanes that differ in asperities, profile, track and when they stop."""
    import numba

    from asperity2d.engine import batched_kernel

    scenes = ([a.make_scene(**SMALL, spacing="random", seed=s) for s in range(6)]
              + [a.make_scene(lower_count=6, upper_count=3, profile="half", spacing="random", seed=7, track="free"),
                 a.make_scene(lower_count=5, upper_count=2, spacing="random", seed=8)])
    threads = numba.get_num_threads()
    try:
        numba.set_num_threads(1)  # one thread: the 8 scenes in 2 groups of LANES
        assert batched_kernel.groups(len(scenes)) * batched_kernel.LANES == len(scenes) and batched_kernel.LANES > 1
        grouped = simulate_many(scenes, 40e-9, engine="batched")
        monkeypatch.setattr(batched_kernel, "LANES", 1)
        alone = simulate_many(scenes, 40e-9, engine="batched")
    finally:
        numba.set_num_threads(threads)
    for one, two in zip(grouped, alone):
        for name in ("x", "v", "y", "vy", "drive_force", "normal_force", "friction_force", "contact_count"):
            np.testing.assert_array_equal(getattr(one, name), getattr(two, name), err_msg=name)


@pytest.mark.parametrize("option", [{"energy": True}, {"contact_work": True}, {"stop": a.Passed()},
                                    {"observers": [print]}])
def test_what_only_the_reference_runs_is_refused_in_one_line(option):
    name = next(iter(option))
    with pytest.raises(SceneError, match=rf'^`{name}` is not available on engine=\'batched\'; engine="pymunk" runs it$'):
        a.simulate(a.make_scene(**SMALL), 1e-9, engine="batched", **option)


def test_bad_input_gets_the_reference_s_message():
    scene = a.make_scene(**SMALL)
    for kwargs in ({"dt": -1.0}, {"dt": 1.0}, {"record_every": 0}):
        with pytest.raises(SceneError) as ref:
            a.simulate(scene, 1e-9, **kwargs)
        with pytest.raises(SceneError) as got:
            a.simulate(scene, 1e-9, engine="batched", **kwargs)
        assert str(got.value) == str(ref.value)


@pytest.mark.slow
def test_stick_force_distributions_agree_over_24_seeds():
    """24 random seeds x 5 passes of the default scene at the step policy's dt: the per-seed means
    of the two engines agree within their standard error, and a two-sample test of the pass
    values does not tell them apart (Mann-Whitney p > 0.05)."""
    from scipy.stats import mannwhitneyu

    from asperity2d.experiments.measures import pass_speeds  # noqa: F401

    scenes = [a.make_scene(spacing="random", seed=9401 + s) for s in range(24)]
    ref = stick_forces_of(scenes, passes=5, engine="pymunk")
    got = stick_forces_of(scenes, passes=5, engine="batched")
    r = np.array([f.average("peak") for f in ref])
    g = np.array([f.average("peak") for f in got])
    se = math.hypot(r.std(ddof=1), g.std(ddof=1)) / math.sqrt(len(r))
    assert abs(r.mean() - g.mean()) < se
    rp = np.concatenate([f.peak for f in ref])
    gp = np.concatenate([f.peak for f in got])
    assert mannwhitneyu(rp[np.isfinite(rp)], gp[np.isfinite(gp)]).pvalue > 0.05


@pytest.mark.parametrize("check_id", [i for i in closed_forms.CHECKS if "batched" in closed_forms.ENGINES_OF[i]])
def test_every_closed_form_check_of_the_asperity_mechanics_holds_on_it(check_id):
    """``asperity2d validate --engine batched``: the wedge law at four angles, the flat block's
    static and kinetic limits, the incline (a critical force), the force balances at rest and the
    flank law of all tips, each within the tolerance it has on the reference."""
    check = closed_forms.run_all([check_id], engine="batched")[0]
    assert check.passed, check.line()


def test_the_reference_s_own_checks_are_refused_on_it_by_name():
    with pytest.raises(SceneError, match=r"energy-books-asperity.*engine=\"pymunk\" runs them"):
        closed_forms.run_all(["energy-books-asperity"], engine="batched")
    assert len(closed_forms.run_all(["wedge-45-0.3"], engine="batched")) == 1
