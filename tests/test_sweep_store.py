"""Results store and runner: failures, corruption, resumption, grid changes, tables."""

import csv
import json
import math

import numpy as np
import pytest

import sweep_fixtures
from asperity2d.errors import SceneError
from asperity2d.sweep import CorruptRunWarning, ResultStore, Study, run_study

RUN = "sweep_fixtures:noisy_run"


def small_study(**overrides) -> Study:
    args = {"name": "small", "run": RUN, "grid": {"amplitude": [1.0, 2.0]}, "seeds": range(3)}
    args.update(overrides)
    return Study(**args)


def expected(spec, fn=sweep_fixtures.noisy_run) -> dict:
    return fn(**spec.params, seed=spec.seed)


def test_run_writes_one_file_per_run_with_exact_values(tmp_path):
    study = small_study()
    summary = run_study(study, store=tmp_path / "s", workers=1, progress=False)
    assert (summary.total, summary.done, summary.failed, summary.pending) == (6, 6, 0, 0)
    store = ResultStore(tmp_path / "s")
    assert sorted(p.stem for p in store.runs_dir.iterdir()) == sorted(s.key for s in study.runs())
    records = store.records()
    for spec in study.runs():
        rec = records[spec.key]
        assert rec.status == "done" and rec.seed == spec.seed and dict(rec.params) == spec.params
        assert dict(rec.quantities) == expected(spec)  # exact: JSON round-trips floats
        assert rec.wall_time >= 0
    manifest = json.loads(store.manifest_path.read_text())
    assert manifest["study"] == study.to_dict()
    assert {"asperity2d", "numpy", "pymunk"} <= set(manifest["versions"])
    assert manifest["created"] and len(manifest["sessions"]) == 1


def test_failed_runs_are_recorded_and_others_finish(tmp_path):
    study = small_study(run="sweep_fixtures:flaky_run", grid={"amplitude": [1.0, -1.0]})
    summary = run_study(study, store=tmp_path / "s", workers=2, progress=False)
    assert (summary.done, summary.failed, summary.pending) == (3, 3, 0)
    records = ResultStore(tmp_path / "s").records()
    for spec in study.runs():
        rec = records[spec.key]
        if spec.params["amplitude"] < 0:
            assert rec.status == "failed" and rec.quantities == {}
            assert rec.error == "ValueError: amplitude must be >= 0, got -1.0"
            assert "flaky_run" in rec.traceback and "Traceback" in rec.traceback
        else:
            assert rec.status == "done" and rec.error is None
            assert dict(rec.quantities) == expected(spec)
    # failed runs count as finished: not re-run unless asked
    assert run_study(study, store=tmp_path / "s", workers=1, progress=False).ran == 0
    again = run_study(study, store=tmp_path / "s", workers=1, progress=False, retry_failed=True)
    assert again.ran == 3 and again.failed == 3


@pytest.mark.parametrize(
    "run, quantities, message",
    [
        ("sweep_fixtures:wrong_type_run", None, "TypeError: run function must return a mapping"),
        (RUN, ("mean", "nope"), "did not return quantities ['nope']"),
    ],
)
def test_bad_return_values_fail_the_run(tmp_path, run, quantities, message):
    study = Study(name="bad", run=run, seeds=[0], quantities=quantities,
                  grid={} if "wrong" in run else {"amplitude": [1.0]})
    run_study(study, store=tmp_path, workers=1, progress=False)
    (rec,) = ResultStore(tmp_path).records().values()
    assert rec.status == "failed" and message in rec.error


def test_bad_run_path_fails_fast(tmp_path):
    with pytest.raises(SceneError, match="`run`"):
        run_study(small_study(run="sweep_fixtures:no_such_fn"), store=tmp_path, progress=False)
    with pytest.raises(SceneError, match="`run`"):
        run_study(small_study(run="no_such_module_xyz:fn"), store=tmp_path, progress=False)
    run_study(small_study(), store=tmp_path, workers=1, progress=False)
    with pytest.raises(SceneError, match="`workers`"):  # checked even with nothing left to run
        run_study(small_study(), store=tmp_path, workers=0, progress=False)


def test_corrupt_and_half_written_files_are_rerun_never_read(tmp_path):
    study = small_study()
    store = ResultStore(tmp_path / "s")
    run_study(study, store=store, workers=1, progress=False)
    specs = study.runs()
    half, tampered, swapped = specs[0].key, specs[1].key, specs[2].key
    text = store.run_path(half).read_text()
    store.run_path(half).write_text(text[: len(text) // 2])  # half-written
    doc = json.loads(store.run_path(tampered).read_text())
    doc["payload"]["quantities"]["mean"] = 123.0  # valid JSON, wrong checksum
    store.run_path(tampered).write_text(json.dumps(doc))
    # a valid, checksummed record under the wrong file name
    store.run_path(swapped).write_text(store.run_path(specs[3].key).read_text())

    with pytest.warns(CorruptRunWarning, match="corrupt or half-written"):
        status = store.status()
    assert (status.done, status.pending, status.corrupt) == (3, 3, 3)
    with pytest.warns(CorruptRunWarning):
        table = store.table()
    assert len(table) == 3 and not {half, tampered, swapped} & set(table["key"])
    assert 123.0 not in table["mean"]

    with pytest.warns(CorruptRunWarning):
        summary = run_study(study, store=store, workers=1, progress=False)
    assert sorted(summary.executed) == sorted([half, tampered, swapped])
    records = store.records()  # no warning now: all files valid again
    assert all(dict(records[s.key].quantities) == expected(s) for s in specs)


def test_changing_one_grid_value_reruns_only_affected_runs(tmp_path):
    store = ResultStore(tmp_path / "s")
    first = small_study(grid={"amplitude": [1.0, 2.0]})
    run_study(first, store=store, workers=1, progress=False)
    kept = [s.key for s in first.runs() if s.params["amplitude"] == 1.0]
    mtimes = {k: store.run_path(k).stat().st_mtime_ns for k in kept}

    second = small_study(grid={"amplitude": [1.0, 3.0]})
    summary = run_study(second, store=store, workers=1, progress=False)
    new = {s.key for s in second.runs() if s.params["amplitude"] == 3.0}
    assert set(summary.executed) == new and summary.skipped == 3
    assert {k: store.run_path(k).stat().st_mtime_ns for k in kept} == mtimes
    status = store.status()
    assert (status.total, status.done, status.orphaned) == (6, 6, 3)  # amplitude 2.0 files remain
    assert sorted(set(store.table()["amplitude"])) == [1.0, 3.0]
    with pytest.raises(SceneError, match="`store`"):
        run_study(small_study(name="other"), store=store, workers=1, progress=False)


def test_table_and_csv(tmp_path):
    study = small_study(run="sweep_fixtures:flaky_run",
                        grid={"amplitude": [1.0, -1.0], "label": ["a", "bb"]}, seeds=[0, 4])
    store = ResultStore(tmp_path / "s")
    run_study(study, store=store, workers=1, progress=False)
    table = store.table()
    assert table.dtype.names == ("key", "amplitude", "label", "seed", "status", "mean", "peak",
                                 "wall_time")
    assert list(table["key"]) == [s.key for s in study.runs()]  # study order
    assert table["label"].dtype.kind == "U" and table["seed"].dtype == np.int64
    failed = table["status"] == "failed"
    assert failed.sum() == 4 and np.isnan(table["mean"][failed]).all()
    ok = table[~failed][0]
    spec = next(s for s in study.runs() if s.key == ok["key"])
    assert ok["mean"] == expected(spec, sweep_fixtures.flaky_run)["mean"]

    path = store.export_csv(tmp_path / "runs.csv")
    rows = list(csv.DictReader(path.open()))
    assert len(rows) == len(table) and list(rows[0]) == list(table.dtype.names)
    for row, rec in zip(rows, table):
        assert row["key"] == rec["key"] and int(row["seed"]) == rec["seed"]
        assert float(row["mean"]) == rec["mean"] or (math.isnan(rec["mean"]) and row["mean"] == "nan")


def test_not_a_store_and_locked_store(tmp_path):
    with pytest.raises(SceneError, match="`store` is not a sweep store"):
        ResultStore(tmp_path).status()
    fcntl = pytest.importorskip("fcntl")
    (tmp_path / "s").mkdir()
    with open(tmp_path / "s" / ".lock", "a+b") as fh:
        fcntl.flock(fh.fileno(), fcntl.LOCK_EX)
        with pytest.raises(SceneError, match="in use by another running sweep"):
            run_study(small_study(), store=tmp_path / "s", workers=1, progress=False)
