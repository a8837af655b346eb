"""Where runs execute: in-process, a local process pool, or a Dask cluster.

Every executor has one method, :meth:`map_unordered`, which submits
``fn(*args)`` for each argument tuple and yields ``(index, result)`` as runs
complete, in completion order. The caller (the parent process) writes each
result as it arrives, so nothing waits on anything but the runs themselves.

``fn`` here is always :func:`execute_run`: it imports the study's run function
by its dotted path inside the worker, calls it, and turns any exception into a
"failed" outcome, so one bad run never stops a study. Runs are deterministic
given their seed, so the executor never changes the numbers.
"""

from __future__ import annotations

import concurrent.futures as cf
import importlib
import multiprocessing
import os
import sys
import time
import traceback
import uuid
from functools import lru_cache
from typing import Any, Callable, Iterable, Iterator, Mapping, Sequence

from ..errors import SceneError


@lru_cache(maxsize=32)
def resolve_run(path: str) -> Callable[..., Mapping[str, float]]:
    """Import ``"package.module:function"`` and return the function."""
    module_name, _, attr = path.partition(":")
    try:
        module = importlib.import_module(module_name)
    except ImportError as exc:
        raise SceneError(f"`run` module {module_name!r} cannot be imported: {exc}") from None
    fn = getattr(module, attr, None)
    if not callable(fn):
        raise SceneError(f"`run` {path!r}: module {module_name!r} has no function {attr!r}")
    return fn


def execute_run(
    run: str, params: Mapping[str, Any], seed: int, quantities: Sequence[str] | None
) -> dict[str, Any]:
    """Call the run function once and return its outcome as a plain dict.

    The outcome has ``status`` ("done" or "failed"), ``quantities`` (name ->
    float, done runs), ``error`` and ``traceback`` (text, failed runs) and
    ``wall_time`` (s, time spent in the run function).
    """
    start = time.perf_counter()
    try:
        raw = resolve_run(run)(**params, seed=seed)
        if not isinstance(raw, Mapping):
            raise TypeError(f"run function must return a mapping, got {type(raw).__name__}")
        values = {str(name): float(value) for name, value in raw.items()}
        missing = [q for q in (quantities or ()) if q not in values]
        if missing:
            raise KeyError(f"run function did not return quantities {missing}")
    except Exception as exc:  # a failed run is data, not a crash of the study
        return {
            "status": "failed",
            "quantities": {},
            "error": f"{type(exc).__name__}: {exc}",
            "traceback": traceback.format_exc(),
            "wall_time": time.perf_counter() - start,
        }
    return {
        "status": "done",
        "quantities": values,
        "error": None,
        "traceback": None,
        "wall_time": time.perf_counter() - start,
    }


def _check_workers(workers: int | None) -> int:
    if workers is None:
        return os.cpu_count() or 1
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise SceneError(f"`workers` must be an int >= 1, got {workers!r}")
    return workers


def _check_main_importable() -> None:
    """Spawned workers re-import the main script; fail clearly when they cannot."""
    main = sys.modules.get("__main__")
    path = getattr(main, "__file__", None)
    if getattr(main, "__spec__", None) is None and path and not os.path.isfile(path):
        raise SceneError(
            f"`workers` > 1 needs a main script that worker processes can import, got {path!r} "
            "(run from a file with an `if __name__ == '__main__':` guard, or use workers=1)"
        )


class LocalExecutor:
    """Runs on this machine: in-process for one worker, else a process pool.

    Parameters
    ----------
    workers : int, optional
        Number of worker processes (default ``os.cpu_count()``). ``1`` runs in
        the calling process, which is the easiest to debug.
    in_process : bool, optional
        Override: ``False`` uses a pool even for one worker (benchmarks).
    """

    def __init__(self, *, workers: int | None = None, in_process: bool | None = None):
        self.workers = _check_workers(workers)
        self.in_process = self.workers == 1 if in_process is None else bool(in_process)
        self._pool: cf.ProcessPoolExecutor | None = None

    @property
    def description(self) -> str:
        return "in-process" if self.in_process else f"local processes ({self.workers})"

    def map_unordered(self, fn: Callable, jobs: Sequence[tuple]) -> Iterator[tuple[int, Any]]:
        """Yield ``(index, fn(*jobs[index]))`` as each run completes."""
        if self.in_process:
            for index, args in enumerate(jobs):
                yield index, fn(*args)
            return
        if self._pool is None:
            _check_main_importable()
            # spawn: workers start clean (no inherited threads, RNGs or engine state)
            self._pool = cf.ProcessPoolExecutor(
                max_workers=self.workers, mp_context=multiprocessing.get_context("spawn")
            )
        # keep a bounded window in flight so huge studies do not queue everything at once
        window = 2 * self.workers
        pending = iter(enumerate(jobs))
        in_flight: dict[cf.Future, int] = {}

        def fill() -> None:
            while len(in_flight) < window:
                nxt = next(pending, None)
                if nxt is None:
                    return
                in_flight[self._pool.submit(fn, *nxt[1])] = nxt[0]

        fill()
        while in_flight:
            done, _ = cf.wait(in_flight, return_when=cf.FIRST_COMPLETED)
            for future in done:
                index = in_flight.pop(future)
                try:
                    result = future.result()
                except cf.process.BrokenProcessPool as exc:
                    raise RuntimeError(
                        f"a sweep worker process died ({exc}); finished runs are saved, "
                        "run the study again to resume. (A script that starts a sweep "
                        "with workers > 1 needs an `if __name__ == '__main__':` guard.)"
                    ) from None
                yield index, result
            fill()

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None

    def __enter__(self) -> "LocalExecutor":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def _import_distributed():
    try:
        import distributed
    except ImportError as exc:
        raise SceneError(
            "`scheduler` needs dask.distributed, which is not installed "
            f"(pip install 'asperity2d[cluster]'): {exc}"
        ) from None
    return distributed


class DaskExecutor:
    """Runs on a Dask distributed cluster.

    Parameters
    ----------
    scheduler : str
        ``"tcp://host:port"`` (or any address Dask accepts) to connect to a
        running cluster, or ``"local"`` to start a ``LocalCluster`` of worker
        processes here (closed again by :meth:`close`). The workers must be
        able to import asperity2d and the study's run function.
    workers : int, optional
        Worker processes for ``scheduler="local"`` (default ``os.cpu_count()``).
    """

    def __init__(self, *, scheduler: str, workers: int | None = None):
        check_executor_args(workers=workers, scheduler=scheduler)
        distributed = _import_distributed()
        self.scheduler = scheduler
        self._cluster = None
        if scheduler == "local":
            n = _check_workers(workers)
            self._cluster = distributed.LocalCluster(
                n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None
            )
            address = self._cluster.scheduler_address
        else:
            address = scheduler
        try:
            # connect timeout: dask config `distributed.comm.timeouts.connect`
            self._client = distributed.Client(address, set_as_default=False)
        except (OSError, TimeoutError) as exc:
            self._close_cluster()
            raise SceneError(f"`scheduler` {scheduler!r} could not be reached: {exc}") from None

    @property
    def description(self) -> str:
        return f"dask ({self.scheduler})"

    def map_unordered(self, fn: Callable, jobs: Sequence[tuple]) -> Iterator[tuple[int, Any]]:
        """Yield ``(index, fn(*jobs[index]))`` as each run completes on the cluster."""
        distributed = _import_distributed()
        token = uuid.uuid4().hex[:8]
        futures = {}
        for index, args in enumerate(jobs):
            future = self._client.submit(fn, *args, key=f"asperity2d-run-{token}-{index}", pure=False)
            futures[future.key] = (future, index)
        try:
            for future in distributed.as_completed(
                [f for f, _ in futures.values()], loop=self._client.loop
            ):
                index = futures[future.key][1]
                try:
                    result = future.result()
                except Exception as exc:  # the worker died running it (KilledWorker, ...)
                    result = {
                        "status": "failed",
                        "quantities": {},
                        "error": f"{type(exc).__name__}: {exc}",
                        "traceback": "".join(traceback.format_exception(exc)),
                        "wall_time": float("nan"),
                    }
                future.release()
                yield index, result
        finally:  # stopped early (error, Ctrl-C): do not leave runs queued on the cluster
            for future, _ in futures.values():
                if not future.done():
                    future.cancel()

    def _close_cluster(self) -> None:
        if self._cluster is not None:
            self._cluster.close()
            self._cluster = None

    def close(self) -> None:
        self._client.close()
        self._close_cluster()

    def __enter__(self) -> "DaskExecutor":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def check_executor_args(*, workers: int | None = None, scheduler: str | None = None) -> None:
    """Validate ``workers`` / ``scheduler`` without starting anything (SceneError if bad)."""
    if workers is not None:
        _check_workers(workers)
    if scheduler is None:
        return
    if not isinstance(scheduler, str) or not scheduler:
        raise SceneError(f"`scheduler` must be an address or 'local', got {scheduler!r}")
    if scheduler != "local" and workers is not None:
        raise SceneError("`workers` applies only to scheduler='local'; a cluster has its own")


def make_executor(
    *, workers: int | None = None, scheduler: str | None = None
) -> LocalExecutor | DaskExecutor:
    """A :class:`DaskExecutor` if ``scheduler`` is given, else a :class:`LocalExecutor`."""
    check_executor_args(workers=workers, scheduler=scheduler)
    if scheduler is None:
        return LocalExecutor(workers=workers)
    return DaskExecutor(scheduler=scheduler, workers=workers)


def _call(fn: Callable, kwargs: Mapping[str, Any]) -> Any:
    return fn(**kwargs)


def map_calls(fn: Callable, kwargs_list: Sequence[Mapping[str, Any]], *, workers: int | None = 1,
              scheduler: str | None = None) -> list:
    """``[fn(**kw) for kw in kwargs_list]`` on an executor (in-process, local processes or
    Dask), returned in order. ``fn`` must be a module-level function to run in worker
    processes; an exception in a run is raised here."""
    jobs = [(fn, dict(kw)) for kw in kwargs_list]
    out: list = [None] * len(jobs)
    with make_executor(workers=workers, scheduler=scheduler) as executor:
        for index, value in executor.map_unordered(_call, jobs):
            if isinstance(executor, DaskExecutor) and isinstance(value, dict) and value.get("status") == "failed":
                raise RuntimeError(f"{value.get('error')} (call {index} of {fn.__name__})")
            out[index] = value
    return out


def jobs_for(run: str, specs: Iterable, quantities: Sequence[str] | None) -> list[tuple]:
    """Argument tuples of :func:`execute_run` for run specs."""
    q = None if quantities is None else tuple(quantities)
    return [(run, dict(spec.params), spec.seed, q) for spec in specs]
