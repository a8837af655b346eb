"""The batched engine's settling, stops and critical force against the reference (pymunk).

Settling is :meth:`asperity2d.engine.core.Engine.settle` rebuilt in the compiled loop: the same
phases, global damping, hold on the slider's x, windows and calm test. The contacts take their
normals from another algorithm (the separating-axis test where Chipmunk runs GJK/EPA: the same
normal to the last bit or two). On the fixed track, where the slider's height is held, that stays
in the last bits of the settled state (8e-18 bases measured); a free slider's damped settling
carries it to at most ~3e-7 bases (measured: 1e-10 on a regular surface, 3e-7 on a random one).

The critical-force search is one generator on both engines (``asperity2d.critical.searching``):
a scene's bracket can differ from the reference's only where a trial run's outcome does. Each trial
is a fork of the settled scene, made as the reference makes it (its contacts' impulses kept, its
joints' dropped: what pymunk's pickled copy keeps). The issue's criterion is 1 % per seed; on the
scenes here every trial's outcome is the reference's.

The slow test is the issue's cross-check (24 seeds, both tracks, both profiles, from rest and
with a run-up): ``python -m pytest -n 0 -m slow tests/test_engine_critical.py`` (about ten
minutes on 2 cores, nearly all of it the reference's runs).
"""

import numpy as np
import pytest

pytest.importorskip("numba", reason='the batched engine needs Numba: pip install "asperity2d[batch]"')

import asperity2d as a  # noqa: E402
from asperity2d.critical import PUSH_FRACTION, critical_force_brackets, flank_estimate, measure_dt  # noqa: E402
from asperity2d.engine.batched import HOLD_ERROR_BIAS, Batch  # noqa: E402
from asperity2d.run import Run, settle_cap, simulate_many  # noqa: E402
from asperity2d.scene import ConstantForce  # noqa: E402

SMALL = {"lower_count": 4, "upper_count": 2}
#: How far a settled state may lie from the reference's (internal length units, asperity
#: bases), by track. Fixed: 1e-12, far above the last-bit differences measured (8e-18) and far
#: below anything a contact resolves. Free: 30 x the largest difference measured (3e-7), 5 pm on
#: the default base -- a thousandth of the slop (0.5 % of the interference) the contacts allow.
SETTLED_TOL = {"fixed": 1e-12, "free": 1e-5}


def test_the_hold_has_pymunk_s_default_error_bias():
    import pymunk

    hold = pymunk.GrooveJoint(pymunk.Space().static_body, pymunk.Body(1.0, 1.0), (0, 0), (0, 1), (0, 0))
    assert hold.error_bias == HOLD_ERROR_BIAS


@pytest.mark.parametrize("spacing", ["regular", "random"])
@pytest.mark.parametrize("track, start", [("fixed", "rest"), ("fixed", "entry"), ("free", "rest")])
def test_settling_against_the_flanks_is_the_reference_s(track, start, spacing):
    """The critical force's settling (``start="rest"``: a fixed track lowered into place, a free
    slider dropped, then pushed against the flanks): the same time spent, and the same state."""
    scene = a.make_scene(track=track, spacing=spacing, seed=7, drive="force")
    bare = scene.replace(drive=ConstantForce(force=0.0))
    dt, push = measure_dt(scene, "rest"), PUSH_FRACTION * flank_estimate(scene)
    run = Run(bare, dt=dt, engaged=start == "rest")
    spent = run.settle(push=push)
    batch = Batch([bare], [dt], engaged=start == "rest")
    got = batch.settle(np.array([push]), [settle_cap(bare)])
    assert got[0] == spent
    rows, row = run.engine.bodies_internal(), run.engine.layout.slider_row
    ref_slider, ref_lower = rows[row, :2], rows[:row, 1]
    mine_slider, mine_lower = batch.sp[0], batch.lp[0, :, 1]
    assert not batch.sv.any() and not batch.lv.any()  # settled: at rest, as the reference leaves it
    np.testing.assert_allclose(mine_slider, ref_slider, rtol=0, atol=SETTLED_TOL[track])
    np.testing.assert_allclose(mine_lower, ref_lower, rtol=0, atol=SETTLED_TOL[track])


@pytest.mark.parametrize("track", ["fixed", "free"])
@pytest.mark.parametrize("start", ["rest", "entry", "run-up"])
def test_critical_force_brackets_are_the_reference_s(track, start):
    """Three random seeds of the small scene, from every start on both tracks: every value within
    the issue's 1 % of the reference's, on the same step; on the fixed track (settled to the last
    bits) every trial's outcome is the reference's, so the brackets are the same numbers."""
    scenes = [a.make_scene(**SMALL, track=track, spacing="random", seed=s) for s in (1, 2, 3)]
    ref = critical_force_brackets(scenes, start=start, engine="pymunk")
    got = critical_force_brackets(scenes, start=start, engine="batched")
    for r, g in zip(ref, got):
        assert g.value == pytest.approx(r.value, rel=0.01)
        assert g.dt == r.dt and g.start == r.start == start
    if track == "fixed":
        assert [g.tried for g in got] == [r.tried for r in ref]


def test_critical_force_on_one_scene_takes_the_engine():
    scene = a.make_scene(**SMALL, drive="force")
    assert a.critical_force(scene, engine="batched") == pytest.approx(a.critical_force(scene), rel=0.01)


def test_simulate_settles_a_free_slider_and_stops_where_the_reference_stops():
    """``simulate`` on the batched engine: a free slider settles first (the same time as the
    reference's), and a constant force with ``duration=None`` stops at the reference's stops: a
    force far under the critical force sticks, one far over it passes, at the same sample."""
    free = a.make_scene(**SMALL, track="free", spacing="random", seed=4)
    ref, got = a.simulate(free, 50e-9), a.simulate(free, 50e-9, engine="batched")
    assert got.meta["settle_time"] == ref.meta["settle_time"] > 0
    assert got.meta["engine"] == "batched"
    for track in ("fixed", "free"):
        scene = a.make_scene(**SMALL, track=track, drive="force")
        critical = a.critical_force(scene, start="run-up")  # simulate starts where the builder puts it
        for factor, status in ((0.5, "stuck"), (3.0, "passed")):
            pushed = scene.replace(drive=ConstantForce(force=factor * critical))
            r = a.simulate(pushed)
            g = simulate_many([pushed], engine="batched")[0]
            assert r.status == g.status == status
            assert len(g.t) == len(r.t) and g.t[-1] == r.t[-1]


def _reference(track: str, profile: str, start: str, seed: int) -> float:
    """One seed's critical force on the reference (module level: worker processes run it)."""
    scene = a.make_scene(track=track, profile=profile, spacing="random", seed=seed)
    return critical_force_brackets([scene], start=start, engine="pymunk")[0].value


@pytest.mark.slow
@pytest.mark.parametrize("start", ["rest", "run-up"])
@pytest.mark.parametrize("profile", ["full", "half"])
@pytest.mark.parametrize("track", ["fixed", "free"])
def test_critical_force_per_seed_within_one_percent_on_24_seeds(track, profile, start):
    """The issue's cross-check: per seed, the critical force of the default scene (16 lower
    asperities, random spacing) on the batched engine within 1 % of the reference's, on 24 seeds
    no other test uses, for both tracks, both profiles, from rest and with a run-up."""
    from asperity2d.sweep import map_calls

    seeds = range(9701, 9725)
    scenes = [a.make_scene(track=track, profile=profile, spacing="random", seed=s) for s in seeds]
    got = [b.value for b in critical_force_brackets(scenes, start=start, engine="batched")]
    ref = map_calls(_reference, [{"track": track, "profile": profile, "start": start, "seed": s} for s in seeds],
                    workers=2)
    rel = np.abs(np.array(got) / np.array(ref) - 1.0)
    print(f"{track}/{profile}/{start}: largest per-seed difference {rel.max():.2e}, "
          f"{int(np.sum(rel == 0))}/{len(rel)} seeds the same number")
    assert rel.max() < 0.01


def test_a_seed_s_bracket_does_not_depend_on_the_others_in_its_batch():
    """The searches run in lockstep, each round's trials in one batch: a seed alone and beside
    others gives the same bracket, bit for bit (every force tried and its outcome)."""
    scenes = [a.make_scene(**SMALL, spacing="random", seed=s) for s in (1, 2, 3)]
    alone = critical_force_brackets([scenes[1]], engine="batched")[0]
    together = critical_force_brackets(scenes, engine="batched")[1]
    assert alone == together


def test_the_command_line_finds_a_critical_force_on_the_batched_engine(tmp_path, capsys):
    import json

    from asperity2d.cli.main import main

    scene = a.make_scene(**SMALL, spacing="random", seed=2)
    path = tmp_path / "scene.toml"
    scene.to_toml(path)
    out = {}
    for engine in ("pymunk", "batched"):
        assert main(["critical", str(path), "--start", "run-up", "--engine", engine, "--json"]) == 0
        out[engine] = json.loads(capsys.readouterr().out)
    assert out["batched"]["engine"] == "batched" and out["batched"]["start"] == "run-up"
    assert out["batched"]["critical_force_N"] == out["pymunk"]["critical_force_N"]  # the fixed track: the same bits
    assert main(["critical", str(path), "--engine", "batchd"]) == 2
    assert "--engine" in capsys.readouterr().err
