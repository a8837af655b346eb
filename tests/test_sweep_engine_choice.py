"""A sweep whose run function has a batched form runs on the batched engine where it is installed
and covers the study's scenes, says so, and keeps the store's contract (resumable, failures as
records). The stand-in run function below steps nothing: the choice and the bookkeeping are
tested here; the batched engine's numbers against pymunk's in tests/test_engine_batched.py."""

import importlib.util
import math

import pytest

import asperity2d as a
from asperity2d import sweep
from asperity2d.engine import batched
from asperity2d.errors import SceneError

GIVEN: list = []


def _scene(params, seed):
    params = dict(params)
    if params.pop("reference_only", False):
        return None
    return a.make_scene(lower_count=4, upper_count=2, seed=seed, **params)


def _runs(calls, engine):
    GIVEN.append((engine, len(calls)))
    return [ValueError("seed 13 diverged") if seed == 13 else {"value": float(seed), "engine_is_batched": 1.0}
            for params, seed in calls]


def fake_run(*, seed=0, reference_only=False, **params):
    """The same function, one run at a time (what the executors call): a different value, so a
    test sees which path ran."""
    return {"value": -float(seed), "engine_is_batched": 0.0}


fake_run.batched = sweep.BatchedRun(scene=_scene, runs=_runs)


def _numba(monkeypatch, present: bool):
    real = importlib.util.find_spec
    monkeypatch.setattr(batched.importlib.util, "find_spec",
                        lambda name, *rest: (real("json") if present else None) if name == "numba" else real(name, *rest))


def _study(**grid):
    return sweep.Study(name="fake", run=f"{__name__}:fake_run", grid=grid or {"spacing": ("regular", "random")},
                       seeds=(11, 12, 13), quantities=("value",))


def test_a_study_with_a_batched_form_runs_on_the_batched_engine_and_says_so(monkeypatch, tmp_path):
    _numba(monkeypatch, True)
    GIVEN.clear()
    session = sweep.run_study(_study(), store=tmp_path / "s", progress=False)
    assert GIVEN == [("batched", 6)]
    assert session.executor == "in-process, engine: batched (Numba)"
    assert (session.done, session.failed) == (4, 2)  # seed 13 failed alone, on both variants
    records = sweep.ResultStore(tmp_path / "s").records(_study())
    failed = [r for r in records.values() if r.status == "failed"]
    assert {r.seed for r in failed} == {13} and all("seed 13 diverged" in r.error for r in failed)
    assert sorted(r.quantities["value"] for r in records.values() if r.status == "done") == [11.0, 11.0, 12.0, 12.0]
    # resumed: nothing left to run, nothing handed to the engine
    GIVEN.clear()
    assert sweep.run_study(_study(), store=tmp_path / "s", progress=False).executed == ()
    assert GIVEN == []


def test_the_reference_runs_it_without_numba_or_when_a_run_is_not_covered(monkeypatch, tmp_path):
    GIVEN.clear()
    _numba(monkeypatch, False)
    session = sweep.run_study(_study(), store=tmp_path / "a", workers=1, progress=False)
    assert GIVEN == [] and session.executor == "in-process" and session.done == 6
    _numba(monkeypatch, True)
    for name, grid in (("law", {"contact_law": ("viscous",)}), ("option", {"reference_only": (True,)})):
        session = sweep.run_study(_study(**grid), store=tmp_path / name, workers=1, progress=False)
        assert GIVEN == [] and session.done == 3, name
    # asked by name, a run the batched engine cannot take is one line naming the way out
    with pytest.raises(SceneError, match=r'engine="pymunk" runs it'):
        sweep.run_study(_study(contact_law=("viscous",)), store=tmp_path / "named", progress=False, engine="batched")
    values = [r.quantities["value"] for r in sweep.ResultStore(tmp_path / "a").records(_study()).values()]
    assert sorted(values) == [-13.0, -13.0, -12.0, -12.0, -11.0, -11.0] and not any(math.isnan(v) for v in values)


def test_the_study_run_functions_batched_form_is_the_same_pass():
    """``spring_pass_run``'s batched form: the scene it declares is the one its runs step, and
    ``contact_work`` (the reference's books) keeps a run on pymunk."""
    from asperity2d.studies import ooten

    form = ooten.spring_pass_run.batched
    scene = form.scene({"lower_count": 4, "upper_count": 2, "spacing": "random"}, 5)
    assert scene == a.make_scene(lower_count=4, upper_count=2, spacing="random", seed=5, drive="spring")
    assert form.scene({"lower_count": 4, "upper_count": 2, "contact_work": True}, 5) is None


@pytest.mark.slow  # two full passes (80 s on a loaded 2-core machine)
def test_a_sweep_of_passes_on_the_batched_engine_gives_the_reference_s_quantities(tmp_path):
    """``spring_pass_run`` over a regular 4/2 scene (nothing chaotic in its pass) on both engines:
    its stick forces within 1e-6 (the engines' measured agreement on a pass: 1e-8; the quantities
    are sums over the pass's records, which the two engines write at the same steps)."""
    pytest.importorskip("numba", reason='the batched engine needs Numba: pip install "asperity2d[batch]"')
    study = sweep.Study(name="pass", run="asperity2d.studies.ooten:spring_pass_run", seeds=(0,),
                        fixed={"lower_count": 4, "upper_count": 2},
                        quantities=("peak_stick_force_N", "mean_stick_force_N", "events"))
    got = sweep.run_study(study, store=tmp_path / "b", progress=False)
    ref = sweep.run_study(study, store=tmp_path / "p", progress=False, engine="pymunk", workers=1)
    assert got.executor == "in-process, engine: batched (Numba)" and ref.executor == "in-process"
    g, = sweep.ResultStore(tmp_path / "b").records(study).values()
    r, = sweep.ResultStore(tmp_path / "p").records(study).values()
    assert g.quantities["events"] == r.quantities["events"] > 0
    for name in ("first_breakaway_N", "peak_stick_force_N", "mean_stick_force_N"):
        assert g.quantities[name] == pytest.approx(r.quantities[name], rel=1e-6), name
