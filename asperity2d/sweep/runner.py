"""Run a study into a results store: skip what is finished, stream the rest.

:func:`run_study` is the one entry point. It expands the study, reads which
runs are already finished (valid run files), sends only the others to the
executor (through the ensemble engine, :mod:`.engine`, and its failure
contract), and writes each run's file as soon as its result arrives. A study
that is interrupted (Ctrl-C, SIGKILL, a lost node) resumes where it stopped
when it is run again; a run that raises, or whose worker dies, is recorded as
failed and the study goes on.
"""

from __future__ import annotations

import contextlib
import os
import time
from dataclasses import dataclass
from typing import Iterator

from .._inputs import check_runs
from ..errors import SceneError
from .engine import is_auto, run_calls
from .executors import DaskExecutor, LocalExecutor, check_executor_args, execute_run, jobs_for, resolve_run
from .progress import Progress
from .record import RunRecord
from .store import ResultStore
from .study import Study, load_study

try:  # advisory lock so two sessions never write one store; POSIX only
    import fcntl
except ImportError:  # pragma: no cover - Windows
    fcntl = None


@dataclass(frozen=True)
class SweepSummary:
    """What a session did: totals after it, and what it ran (``executed`` keys).

    See Also
    --------
    asperity2d.sweep.run_study : returns one.

    Examples
    --------
    >>> from asperity2d import sweep
    >>> study = sweep.Study(name='spacing', run='asperity2d.studies.ooten:critical_force_run',
    ...                     grid={'spacing': ('regular', 'random')}, seeds=(0,),
    ...                     fixed={'lower_count': 4, 'upper_count': 2}, quantities=('critical_force_N',))
    >>> session = sweep.run_study(study, store='spacing', workers=1, progress=False)
    >>> session.total, session.done, session.failed, session.executor
    (2, 2, 0, 'in-process')
    """

    study: str
    store: str
    total: int
    done: int
    failed: int
    pending: int
    skipped: int
    executed: tuple[str, ...]
    wall_time: float
    executor: str

    @property
    def ran(self) -> int:
        """Number of runs executed in this session."""
        return len(self.executed)

    def to_dict(self) -> dict:
        data = {k: v for k, v in self.__dict__.items() if k != "executed"}
        data["ran"] = self.ran
        return data


@contextlib.contextmanager
def _locked(store: ResultStore) -> Iterator[None]:
    if store.path.exists() and not store.path.is_dir():
        raise SceneError(f"`store` exists and is not a directory: {str(store.path)!r}")
    store.path.mkdir(parents=True, exist_ok=True)
    with open(store.path / ".lock", "a+b") as fh:
        if fcntl is not None:
            try:
                fcntl.flock(fh.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                raise SceneError(
                    f"`store` {str(store.path)!r} is in use by another running sweep"
                ) from None
        # the kernel drops the lock if this process dies, even by SIGKILL
        for stale in [*store.path.glob(".*.tmp"), *store.runs_dir.glob(".*.tmp")]:
            with contextlib.suppress(OSError):
                stale.unlink()  # half-written temporary files of a killed session
        yield


def study_size(study: Study) -> str:
    """Where a study's run count comes from, in words (for budget messages)."""
    points = " x ".join(f"{len(v):,}" for v in study.grid.values()) or "1"
    return f"study {study.name!r} has {points} grid point(s) x {len(study.seeds):,} seeds"


def run_study(
    study: Study | str | os.PathLike,
    *,
    store: str | os.PathLike | ResultStore,
    workers: int | str | None = None,
    scheduler: str | None = None,
    progress: bool = True,
    retry_failed: bool = False,
    executor: LocalExecutor | DaskExecutor | None = None,
    max_runs: int | None = None,
) -> SweepSummary:
    """Run every unfinished run of ``study`` and record it in ``store``.

    Parameters
    ----------
    study : Study or path
        The study, or a ``.toml`` / ``.py`` file describing it.
    store : path or ResultStore
        The study's results directory (created if missing).
    workers : int or "auto", optional
        Local worker processes (1 = in-process), or the size of the cluster for
        ``scheduler="local"``. Default (None or ``"auto"``): decided by what a run costs
        (``decide_workers``): the median time of the runs this
        store already holds, else the first run's, timed in this process -- serial when
        starting workers would not pay, every core when it would.
    scheduler : str, optional
        Dask scheduler address ``"tcp://host:port"``, or ``"local"`` to start a
        ``LocalCluster``. Default: the local process pool.
    progress : bool
        Show a progress bar on stderr.
    retry_failed : bool
        Also re-run runs recorded as failed (default: keep them).
    executor : LocalExecutor or DaskExecutor, optional
        An executor to use (and leave open) instead of ``workers``/``scheduler``,
        e.g. to run several studies on one Dask client.
    max_runs : int, optional
        Refuse (``SceneError``, before any run starts) a study of more runs (grid points x
        seeds) than this; default ``MAX_RUNS`` (100,000).

    Returns
    -------
    SweepSummary

    See Also
    --------
    asperity2d.sweep.summarize, asperity2d.sweep.ResultStore
    asperity2d.compare : one measure over variants and seeds, without a store.

    Examples
    --------
    >>> from asperity2d import sweep
    >>> study = sweep.Study(name='spacing', run='asperity2d.studies.ooten:critical_force_run',
    ...                     grid={'spacing': ('regular', 'random')}, seeds=(0,),
    ...                     fixed={'lower_count': 4, 'upper_count': 2}, quantities=('critical_force_N',))
    >>> session = sweep.run_study(study, store='spacing', workers=1, progress=False)
    >>> session.done, session.pending
    (2, 0)
    >>> sweep.run_study(study, store='spacing', workers=1, progress=False).executed  # resumed: nothing left
    ()
    """
    if executor is not None and (not is_auto(workers) or scheduler is not None):
        raise SceneError("`executor` excludes `workers` and `scheduler`")
    workers = None if is_auto(workers) else workers
    if not isinstance(study, Study):
        study = load_study(study)
    check_runs(len(study), max_runs, study_size(study))
    store = store if isinstance(store, ResultStore) else ResultStore(store)
    check_executor_args(workers=workers, scheduler=scheduler)
    resolve_run(study.run)  # fail fast on a bad dotted path, before any process starts
    start = time.perf_counter()
    with _locked(store):
        store.check_study(study)
        specs = study.runs()
        finished = store.records(study)
        if retry_failed:
            finished = {k: r for k, r in finished.items() if r.status == "done"}
        todo = [spec for spec in specs if spec.key not in finished]
        done = sum(r.status == "done" for r in finished.values())
        failed = len(finished) - done
        executed: list[str] = []
        # what a run costs, from the runs this store already timed (None: the engine times one)
        walls = sorted(r.wall_time for r in finished.values() if r.status == "done" and r.wall_time >= 0)
        cost = walls[len(walls) // 2] if walls else None
        report = {"executor": executor.description if executor is not None else
                  ("local processes (decided by cost)" if workers is None and scheduler is None else
                   f"dask ({scheduler})" if scheduler is not None else f"local processes ({workers})")}
        bar, cluster = None, None
        try:
            if todo and executor is None and scheduler not in (None, "local"):
                # reach the cluster before the progress bar: one that cannot be reached is one line
                executor = cluster = DaskExecutor(scheduler=scheduler)
                scheduler = None
            store.begin_session(study, executor=report["executor"] if todo else "none")
            bar = Progress(total=len(specs), done=done, failed=failed, label=study.name,
                           enabled=progress)
            if todo:
                jobs = jobs_for(study.run, todo, study.quantities)
                where = {"executor": executor} if executor is not None else \
                    {"workers": workers, "scheduler": scheduler, "cost": cost}
                for outcome in run_calls(execute_run, jobs, report=report, **where):
                    record = RunRecord.from_outcome(todo[outcome.index], study.run, outcome)
                    store.write_run(record)
                    executed.append(record.key)
                    bar.update(record.status)
        finally:
            if bar is not None:
                bar.close()
            if cluster is not None:
                cluster.close()
    return SweepSummary(
        study=study.name,
        store=str(store.path),
        total=len(specs),
        done=bar.done,
        failed=bar.failed,
        pending=len(specs) - bar.done - bar.failed,
        skipped=len(finished),
        executed=tuple(executed),
        wall_time=time.perf_counter() - start,
        executor=report["executor"] if todo else "none",
    )
