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
from typing import Callable, Iterator

from .._inputs import check_runs
from ..errors import SceneError
from .engine import Outcome, is_auto, run_calls
from .executors import (DaskExecutor, LocalExecutor, check_executor_args, execute_run, jobs_for, resolve_run,
                        run_values)
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


@dataclass(frozen=True)
class BatchedRun:
    """A run function's batched form, set as its attribute ``batched``: what lets a sweep run the
    whole study on the batched engine (:func:`run_study`'s ``engine``).

    ``scene(params, seed)``: the scene the run ``fn(**params, seed=seed)`` steps, or None when
    the run needs the reference for something else than its scene (an option only pymunk has);
    the engine registry decides from these scenes (``asperity2d.engine.registry.choose_engine``).
    ``runs(calls, engine)``: every run of ``calls`` (``(params, seed)`` pairs) at once on
    ``engine``, per call, in order, what ``fn`` returns or the exception that stopped that run
    alone (returned, not raised).

    Examples
    --------
    The study runs' own: a spring-driven pass of Ooten's set-up declares the scene it steps,
    which is what the registry looks at to choose the engine.

    >>> from asperity2d.engine.registry import choose_engine
    >>> from asperity2d.studies.ooten import spring_pass_run
    >>> form = spring_pass_run.batched
    >>> scene = form.scene({"lower_count": 4, "upper_count": 2}, 7)
    >>> scene.lower.count, choose_engine("pymunk", [scene])
    (4, 'pymunk')
    """

    scene: Callable
    runs: Callable


#: Runs handed to a batched form at once: the store gets their records after each such batch, so a
#: stopped sweep loses at most one batch.
BATCH_CALLS = 64


def _study_engine(engine: str, fn, todo: list) -> str:
    """The engine the unfinished runs ``todo`` of run function ``fn`` run on."""
    from ..engine.registry import AUTO, DEFAULT, check_engine, choose_engine, refuse

    form = getattr(fn, "batched", None)
    if engine != AUTO:
        engine = check_engine(engine)
        if engine == DEFAULT or not todo:
            return engine
        if not isinstance(form, BatchedRun):
            raise SceneError(f"`run` {getattr(fn, '__name__', fn)!r} has no batched form (a BatchedRun as its "
                             f"attribute `batched`): engine={engine!r} cannot run it; engine=\"pymunk\" runs it")
    if not isinstance(form, BatchedRun) or not todo:
        return DEFAULT
    scenes = [form.scene(dict(spec.params), spec.seed) for spec in todo]
    if any(scene is None for scene in scenes):
        if engine == AUTO:
            return DEFAULT
        raise SceneError(f"a run of the study needs an option engine={engine!r} does not have; engine=\"pymunk\" runs it")
    if engine == AUTO:
        return choose_engine(AUTO, scenes)
    for scene in scenes:
        refuse(engine, scene, settle=scene.slider.track == "free")
    return engine


def _batched_outcomes(form: BatchedRun, todo: list, engine: str, quantities) -> Iterator[Outcome]:
    """:class:`~.engine.Outcome` of every run of ``todo`` on ``engine``, in order, batch by batch
    (each run's wall time: its batch's, shared)."""
    for start in range(0, len(todo), BATCH_CALLS):
        part = todo[start:start + BATCH_CALLS]
        began = time.perf_counter()
        raw = form.runs([(dict(spec.params), spec.seed) for spec in part], engine)
        wall = (time.perf_counter() - began) / len(part)
        for k, value in enumerate(raw):
            index = start + k
            try:
                if isinstance(value, Exception):
                    raise value
                yield Outcome(index, "done", run_values(value, quantities), wall_time=wall)
            except Exception as exc:  # a failed run is data (the engine's failure contract)
                yield Outcome(index, "failed", error=f"{type(exc).__name__}: {exc}", wall_time=wall, exception=exc)


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
    engine: str = "auto",
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
    engine : str, default "auto"
        The asperity engine of a run function that has a batched form (:class:`BatchedRun`, its
        attribute ``batched``): ``"auto"`` runs the study on the batched engine, in this process,
        where Numba is installed and that engine runs every unfinished run's scene
        (``asperity2d.engine.registry.choose_engine``), and says so in ``executor``
        (``"in-process, engine: batched (Numba)"``); otherwise, and for every other run
        function, the executors as above. ``"pymunk"`` or ``"batched"`` choose it.

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
    fn = resolve_run(study.run)  # fail fast on a bad dotted path, before any process starts
    start = time.perf_counter()
    with _locked(store):
        store.check_study(study)
        specs = study.runs()
        finished = store.records(study)
        if retry_failed:
            finished = {k: r for k, r in finished.items() if r.status == "done"}
        todo = [spec for spec in specs if spec.key not in finished]
        chosen = _study_engine(engine, fn, todo)
        done = sum(r.status == "done" for r in finished.values())
        failed = len(finished) - done
        executed: list[str] = []
        # what a run costs, from the runs this store already timed (None: the engine times one)
        walls = sorted(r.wall_time for r in finished.values() if r.status == "done" and r.wall_time >= 0)
        cost = walls[len(walls) // 2] if walls else None
        report = {"executor": executor.description if executor is not None else
                  ("local processes (decided by cost)" if workers is None and scheduler is None else
                   f"dask ({scheduler})" if scheduler is not None else f"local processes ({workers})")}
        if chosen != "pymunk":
            from ..engine.registry import engine_label

            report["executor"] = f"in-process, engine: {engine_label(chosen)}"
        bar, cluster = None, None
        try:
            if todo and chosen == "pymunk" and executor is None and scheduler not in (None, "local"):
                # reach the cluster before the progress bar: one that cannot be reached is one line
                executor = cluster = DaskExecutor(scheduler=scheduler)
                scheduler = None
            store.begin_session(study, executor=report["executor"] if todo else "none")
            bar = Progress(total=len(specs), done=done, failed=failed, label=study.name,
                           enabled=progress)
            if todo:
                if chosen != "pymunk":
                    outcomes = _batched_outcomes(fn.batched, todo, chosen, study.quantities)
                else:
                    jobs = jobs_for(study.run, todo, study.quantities)
                    where = {"executor": executor} if executor is not None else \
                        {"workers": workers, "scheduler": scheduler, "cost": cost}
                    outcomes = run_calls(execute_run, jobs, report=report, **where)
                for outcome in outcomes:
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
