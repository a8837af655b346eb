"""The Dask executor gives the same numbers as the local one, on real worker processes."""

import os

import numpy as np
import pytest

import sweep_fixtures
from asperity2d.sweep import ResultStore, Study, run_study

distributed = pytest.importorskip("distributed")


def test_dask_cluster_matches_local_executor(tmp_path, monkeypatch):
    # worker processes must import asperity2d and the fixtures
    monkeypatch.setenv("PYTHONPATH", sweep_fixtures.subprocess_env()["PYTHONPATH"])
    study = Study(name="dask", run="sweep_fixtures:flaky_run",
                  grid={"amplitude": [1.0, 2.5, -1.0]}, seeds=range(4))
    local = run_study(study, store=tmp_path / "local", workers=2, progress=False)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        remote = run_study(study, store=tmp_path / "dask", scheduler=cluster.scheduler_address,
                           progress=False)
        pids = Study(name="pids", run="sweep_fixtures:pid_run", seeds=range(8))
        run_study(pids, store=tmp_path / "pids", scheduler=cluster.scheduler_address,
                  progress=False)
        with distributed.Client(cluster) as client:
            worker_pids = set(client.run(os.getpid).values())

    assert remote.executor.startswith("dask") and remote.ran == len(study)
    assert (remote.done, remote.failed) == (local.done, local.failed) == (8, 4)
    a, b = ResultStore(tmp_path / "local").records(), ResultStore(tmp_path / "dask").records()
    assert set(a) == set(b) == {s.key for s in study.runs()}
    for key in a:
        assert (a[key].status, dict(a[key].quantities), a[key].error) == (
            b[key].status, dict(b[key].quantities), b[key].error)
    ta, tb = ResultStore(tmp_path / "local").table(), ResultStore(tmp_path / "dask").table()
    assert list(ta["key"]) == list(tb["key"])
    for q in ("mean", "peak"):
        np.testing.assert_array_equal(ta[q], tb[q])  # exact; NaN where failed
    used = {int(r.quantities["pid"]) for r in ResultStore(tmp_path / "pids").records().values()}
    assert used <= worker_pids and os.getpid() not in used


def test_dask_bad_scheduler_address_is_a_scene_error(tmp_path):
    import time

    from asperity2d.errors import SceneError

    study = Study(name="x", run="sweep_fixtures:noisy_run", grid={"amplitude": [1.0]}, seeds=[0])
    start = time.monotonic()
    with pytest.raises(SceneError, match="`scheduler` 'tcp://127.0.0.1:1' could not be reached within 5 s"):
        run_study(study, store=tmp_path, scheduler="tcp://127.0.0.1:1", progress=False)
    assert time.monotonic() - start < 30  # the connect timeout, not Dask's 30 s default and a 60 s hang
    with pytest.raises(SceneError, match="`workers`"):
        run_study(study, store=tmp_path, scheduler="tcp://127.0.0.1:1", workers=2, progress=False)


def test_compare_can_use_a_cluster(monkeypatch, capsys):
    """`compare --scheduler ADDRESS` used to be refused: `--workers` defaulted to 1, which a
    cluster does not take. The default is auto now, and the values are the local ones."""
    import json

    from asperity2d.cli import main

    monkeypatch.setenv("PYTHONPATH", sweep_fixtures.subprocess_env()["PYTHONPATH"])
    argv = ["compare", "--measure", "critical", "--seeds", "2", "--set", "lower_count=3", "--set",
            "upper_count=1", "--json"]
    assert main(argv + ["--workers", "1"]) == 0
    local = json.loads(capsys.readouterr().out)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        assert main(argv + ["--scheduler", cluster.scheduler_address]) == 0
    remote = json.loads(capsys.readouterr().out)
    assert remote["variants"] == local["variants"]  # means, CIs... of the very same values
