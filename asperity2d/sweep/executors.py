"""Where calls execute: in-process, a local process pool, or a Dask cluster (the transport of
:mod:`asperity2d.sweep.engine`, which holds the failure contract).

Every executor has one method, :meth:`map_unordered`, which submits
``fn(*args)`` for each argument tuple and yields ``(index, result)`` as calls
complete, in completion order. ``fn`` is always the engine's
:func:`~.engine.guarded`, which never raises, so a result is always its
outcome tuple; a call whose worker died is reported as the same tuple
(:func:`died`) by both executors. The caller (the parent process)
handles each result as it arrives, so nothing waits on anything but the calls.

:func:`execute_run` is what a study's run executes in the worker: it imports
the study's run function by its dotted path, calls it and checks what it
returned. Runs are deterministic given their seed, so the executor never
changes the numbers.

Local worker processes live as long as the process that started them (one warm pool per worker
count, ``shared_pool``: a spawned worker pays ~0.3 s of CPU to start and more to import
what its calls need, so an ensemble after the first pays neither) and no longer: each worker
asks the kernel to kill it when its parent dies (Linux ``prctl(PR_SET_PDEATHSIG)``) and watches
its parent besides (a thread that exits the worker once it has been re-parented), so a sweep
killed with SIGKILL leaves no worker behind; the resource tracker that multiprocessing started
exits with them (its pipe closes when its last writer is gone).
"""

from __future__ import annotations

import atexit
import concurrent.futures as cf
import importlib
import multiprocessing
import os
import math
import re
import sys
import threading
import time
import traceback
import uuid
from functools import lru_cache
from typing import Any, Callable, Iterable, Iterator, Mapping, Sequence

import contextlib
import logging

from ..errors import SceneError, SimulationError


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


def execute_run(run: str, params: Mapping[str, Any], seed: int, quantities: Sequence[str] | None
                ) -> dict[str, float]:
    """Call a study's run function once (``run`` a dotted path) and return its quantities
    (name -> float); raise if it raises, returns something else than a mapping of numbers, or
    lacks one of ``quantities`` (the engine records the failure).

    Parameters
    ----------
    run : str
        ``"module:function"``.
    params : mapping
        Keyword arguments.
    seed : int
        Passed as ``seed=``.
    quantities : sequence of str, optional
        Names the result must hold.

    Returns
    -------
    dict of str to float

    Raises
    ------
    Exception
        The run's own, or a ``SceneError`` for a result that is not a mapping of numbers.

    See Also
    --------
    asperity2d.sweep.run_study : calls it for every run.

    Examples
    --------
    >>> from asperity2d import sweep
    >>> values = sweep.execute_run('asperity2d.studies.ooten:critical_force_run', {'lower_count': 4, 'upper_count': 2}, 0,
    ...                          ['critical_force_N'])
    >>> f"{values['critical_force_N'] * 1e3:.3g} mN"
    '7.61 mN'
    """
    return run_values(resolve_run(run)(**params, seed=seed), quantities)


def run_values(raw, quantities: Sequence[str] | None) -> dict[str, float]:
    """A run function's result as its quantities (name -> float); raise for a result that is not
    a mapping of numbers or lacks one of ``quantities`` (the engine records the failure)."""
    if not isinstance(raw, Mapping):
        raise TypeError(f"run function must return a mapping, got {type(raw).__name__}")
    values = {str(name): float(value) for name, value in raw.items()}
    missing = [q for q in (quantities or ()) if q not in values]
    if missing:
        raise KeyError(f"run function did not return quantities {missing}")
    return values


def died(exc: BaseException) -> tuple:
    """The outcome tuple of :func:`asperity2d.sweep.engine.guarded` for a call whose worker
    died with ``exc`` (both executors report a death this way)."""
    hint = ""
    if type(exc).__name__ == "BrokenProcessPool":
        hint = (" (a script that runs an ensemble with workers > 1 needs an "
                "`if __name__ == '__main__':` guard)")
    return ("failed", None, f"worker died: {type(exc).__name__}: {exc}{hint}",
            "".join(traceback.format_exception(exc)), math.nan, None)


def _check_workers(workers: int | None) -> int:
    if workers is None:
        return os.cpu_count() or 1
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise SceneError(f"`workers` must be an int >= 1, got {workers!r}")
    return workers


def _missing_main_file() -> str | None:
    """The path a main module gives as its ``__file__`` when no file is there (a notebook downloaded
    away from its script, whose first cell set ``__file__`` beside it), else None."""
    main = sys.modules.get("__main__")
    path = getattr(main, "__file__", None)
    if getattr(main, "__spec__", None) is None and path and not os.path.isfile(path):
        return str(path)
    return None


def _from_main(value, depth: int = 2) -> str | None:
    """The name of a function or class defined in ``__main__`` found in ``value`` (a call's function
    or argument, looked into through dicts, lists and tuples ``depth`` levels deep), else None."""
    if getattr(value, "__module__", None) == "__main__" and callable(value):
        return getattr(value, "__qualname__", repr(value))
    if depth and isinstance(value, Mapping):
        value = list(value.values())
    if depth and isinstance(value, (list, tuple)):
        for item in value:
            found = _from_main(item, depth - 1)
            if found:
                return found
    return None


def _check_main_importable(fn=None, jobs=()) -> bool:
    """Spawned workers re-import the main script; fail clearly when they must and cannot.

    A main module whose ``__file__`` is not on disk (a notebook kernel) is no obstacle when
    nothing the workers run lives in ``__main__`` -- the package's measures and run functions are
    imported by name: then the workers are started without it, and this returns True. A function
    defined in the notebook itself cannot reach them: that is the one-line error."""
    path = _missing_main_file()
    if path is None:
        return False
    found = _from_main(fn) or next((name for args in jobs[:1] for name in [_from_main(list(args))] if name), None)
    if found:
        raise SceneError(
            f"`workers` > 1 needs a main script that worker processes can import, got {path!r}, "
            f"which is not on disk, and `{found}` is defined there (define it in a module the workers "
            "can import, run from a file with an `if __name__ == '__main__':` guard, or use workers=1)"
        )
    return True


@contextlib.contextmanager
def _main_file_hidden(hide: bool):
    """While the pool spawns workers, hide a ``__file__`` of ``__main__`` that is not on disk:
    a spawned worker would try to run that file first, and die."""
    main = sys.modules.get("__main__")
    if not hide or main is None or "__file__" not in vars(main):
        yield
        return
    path = vars(main).pop("__file__")
    try:
        yield
    finally:
        vars(main).setdefault("__file__", path)


# -- plain scripts ---------------------------------------------------------------------------
def _is_main_test(test) -> bool:
    """True for the test ``__name__ == "__main__"`` (either way round)."""
    import ast

    if not (isinstance(test, ast.Compare) and len(test.ops) == 1 and isinstance(test.ops[0], ast.Eq)):
        return False
    sides = [test.left, test.comparators[0]]
    return (any(isinstance(s, ast.Name) and s.id == "__name__" for s in sides)
            and any(isinstance(s, ast.Constant) and s.value == "__main__" for s in sides))


def guarded_line(source: str, line: int) -> bool:
    """True if ``line`` of the module ``source`` lies in the body of an ``if __name__ ==
    "__main__":`` block (False also for source that does not parse)."""
    import ast

    try:
        tree = ast.parse(source)
    except (SyntaxError, ValueError):
        return False
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and _is_main_test(node.test) and node.body:
            if node.body[0].lineno <= line <= (node.body[-1].end_lineno or node.body[-1].lineno):
                return True
    return False


def unguarded_main_call(frame=None) -> str | None:
    """``"path:line"`` of the main script's statement if the ensemble is started from its top-level code outside an
    ``if __name__ == "__main__":`` block, else None.

    A spawned worker process (local pools, a Dask ``LocalCluster``) starts by running the main
    script again, as ``__mp_main__``: code under the guard is skipped there, code outside it
    runs again -- and starts its own ensemble inside the worker, which fails (one traceback per
    worker). Python's ``multiprocessing`` does not re-run a main module named ``__main__`` or
    ``pkg.__main__`` (``python -m asperity2d``), nor an interactive session or notebook (no file).
    """
    main = sys.modules.get("__main__")
    if main is None:
        return None
    spec_name = getattr(getattr(main, "__spec__", None), "name", None)
    if spec_name is not None and (spec_name == "__main__" or spec_name.endswith(".__main__")):
        return None
    path = getattr(main, "__file__", None)
    if not path or not os.path.isfile(path):
        return None
    frame = sys._getframe(1) if frame is None else frame
    while frame is not None and not (frame.f_globals is vars(main) and frame.f_code.co_name == "<module>"):
        frame = frame.f_back
    if frame is None:  # not called from the main script's top level (a function it called later)
        return None
    try:
        with open(path, encoding="utf-8") as fh:
            source = fh.read()
    except (OSError, UnicodeDecodeError):
        return None
    return None if guarded_line(source, frame.f_lineno) else f"{path}:{frame.f_lineno}"


_warned_scripts: set[str] = set()


def main_from_stdin() -> bool:
    """True when the main script was read from standard input (``python - < script.py``): a
    spawned worker would have to import it again, and there is no file to import."""
    main = sys.modules.get("__main__")
    return (main is not None and getattr(main, "__spec__", None) is None
            and getattr(main, "__file__", None) == "<stdin>")


def plain_script_fallback() -> bool:
    """True (and, once per script, a warning saying how to get the workers) if worker processes
    would re-run the main script's unguarded top-level code: the ensemble then runs here."""
    import warnings

    if main_from_stdin():
        if "<stdin>" not in _warned_scripts:
            _warned_scripts.add("<stdin>")
            frame, main = sys._getframe(1), vars(sys.modules["__main__"])
            while frame is not None and frame.f_globals is not main:
                frame = frame.f_back
            warnings.warn_explicit(  # one line, "<stdin>:LINE: RuntimeWarning: ...", at the script's call
                "asperity2d runs these calls in this process, without worker processes: the main script "
                "came from standard input, which a worker process cannot import again (save it to a file "
                "to get the workers)", RuntimeWarning, "<stdin>", frame.f_lineno if frame else 0,
                module="__main__")
        return True
    where = unguarded_main_call(sys._getframe(1))
    if where is None:
        return False
    script, _, line = where.rpartition(":")
    if script not in _warned_scripts:
        _warned_scripts.add(script)
        warnings.warn_explicit(
            "asperity2d runs these calls in this process, without worker processes: the script starts "
            "them outside an `if __name__ == \"__main__\":` block, and each worker would run the script "
            "again. Put the script's calls under that block to get the workers.",
            RuntimeWarning, script, int(line), module="__main__")
    return True


# -- the warm pools ----------------------------------------------------------------------------
#: How often a worker checks that its parent is alive (s), besides the kernel's death signal.
WATCH_INTERVAL = 0.2
_PR_SET_PDEATHSIG = 1
_pools: dict[int, cf.ProcessPoolExecutor] = {}
_pools_lock = threading.Lock()


@contextlib.contextmanager
def _sigint_deferred():
    """Hold a Ctrl-C back while this (main) thread starts worker processes, and keep it from them.

    A terminal's Ctrl-C goes to the whole process group: a worker still starting its interpreter
    would die of it with a traceback of its own, and its pool would break under the parent's
    cancelled calls. So SIGINT is blocked in this thread while it spawns: a spawned worker inherits
    the mask through its ``exec``, holds a Ctrl-C pending until its initializer ignores the signal
    (which discards it) and then ignores it for life; the parent alone stops the run and ends them.
    The parent's own Ctrl-C is noted meanwhile (any thread may take it: numerical libraries'
    threads do not block it) and raised once the workers are started.

    Multiprocessing's resource tracker is started first: starting it unblocks SIGINT. Ignoring the
    signal instead (it survives ``exec`` too) lost the parent's Ctrl-C: the command ran on to its
    end. Outside the main thread the mask is set the same way and the handler is left alone
    (Python lets only the main thread set handlers). Without ``pthread_sigmask`` (Windows) the
    main thread's spawn ignores the signal.
    """
    import signal

    main = threading.current_thread() is threading.main_thread()
    mask = getattr(signal, "pthread_sigmask", None)
    if mask is None:  # pragma: no cover - not POSIX
        old = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
        try:
            yield
        finally:
            if main:
                signal.signal(signal.SIGINT, old)
        return
    from multiprocessing import resource_tracker

    resource_tracker.ensure_running()
    caught = []
    before = mask(signal.SIG_BLOCK, {signal.SIGINT})
    old = signal.signal(signal.SIGINT, lambda *_: caught.append(True)) if main else None
    try:
        yield
    finally:
        if main:
            signal.signal(signal.SIGINT, old)
        mask(signal.SIG_SETMASK, before)  # one held in this thread goes to the handler now
    if caught:
        signal.raise_signal(signal.SIGINT)


def prepare_workers() -> None:
    """Start multiprocessing's resource tracker now, from the main thread: a Ctrl-C while it starts
    then interrupts the command where it stands (the tracker protects itself from the signal)."""
    from multiprocessing import resource_tracker

    resource_tracker.ensure_running()


def _die_with(parent: int, death_signal: bool) -> None:
    """Worker initializer: ignore SIGINT (the parent handles a Ctrl-C: :func:`_sigint_deferred`)
    and exit as soon as process ``parent`` is gone.

    ``death_signal``: ask the kernel for SIGKILL when the parent dies (Linux; the signal follows
    the *thread* that spawned the worker, so the pool asks for it only when it spawns every
    worker from the main thread at once). Always: a daemon thread that polls ``os.getppid()``
    (a worker is re-parented when its parent dies) and exits the worker.
    """
    if death_signal and sys.platform.startswith("linux"):
        try:
            import ctypes
            import signal

            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        except (OSError, AttributeError):  # pragma: no cover - no prctl: the watchdog remains
            pass
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)  # discards a Ctrl-C held since the spawn
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
    # tqdm's default lock holds a multiprocessing RLock, which in a spawned process is a named
    # semaphore registered with the resource tracker; a worker killed mid-run (a Ctrl-C ends
    # them so) never unregisters it, and the tracker's "leaked semaphore objects" warning lands
    # under the command's one line. A spawned worker's RLock is its own anyway (a spawn shares
    # no lock with its siblings), so a thread lock is the same exclusion without the semaphore.
    from tqdm import tqdm

    tqdm.set_lock(threading.RLock())
    if os.getppid() != parent:  # the parent died before the signal was asked for
        os._exit(1)

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(WATCH_INTERVAL)
        os._exit(1)

    threading.Thread(target=watch, name="asperity2d-parent-watch", daemon=True).start()


def shared_pool(workers: int) -> cf.ProcessPoolExecutor:
    """The process's pool of ``workers`` spawned workers, started on first use and kept warm
    until the process exits (or the pool breaks: :func:`discard_pool`)."""
    with _pools_lock:
        pool = _pools.get(workers)
        if pool is not None:
            return pool
        # spawn: workers start clean (no inherited threads, RNGs or engine state)
        main = threading.current_thread() is threading.main_thread()
        launch = getattr(cf.ProcessPoolExecutor, "_launch_processes", None)
        pool = None
        try:
            with _sigint_deferred():
                pool = cf.ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn"),
                                              initializer=_die_with,
                                              initargs=(os.getpid(), main and launch is not None))
                if main and launch is not None:
                    launch(pool)  # every worker now, from this thread (the death signal follows it)
        except BaseException:  # a Ctrl-C held while they started: end them (not yet listed)
            if pool is not None:
                _end(pool)
            raise
        _pools[workers] = pool
        return pool


def warm_pools() -> set[int]:
    """The worker counts of the pools this process keeps warm (empty: none is running)."""
    with _pools_lock:
        return set(_pools)


def discard_pool(pool: cf.ProcessPoolExecutor | None = None) -> None:
    """Shut down ``pool`` (every pool if None) and forget it: a broken pool, or the process's
    exit (registered with :mod:`atexit`). Calls queued in it are cancelled."""
    with _pools_lock:
        chosen = [(n, p) for n, p in _pools.items() if pool is None or p is pool]
        for n, _ in chosen:
            del _pools[n]
    if pool is not None and not chosen:
        chosen = [(0, pool)]
    for _, p in chosen:
        p.shutdown(wait=True, cancel_futures=True)


def kill_pool(pool: cf.ProcessPoolExecutor) -> None:
    """End ``pool`` now, its workers killed mid-call (a Ctrl-C: nobody waits for their results).

    Its calls are left as they are, not cancelled: the pool's manager thread marks them broken
    when it sees the workers gone, and on Python 3.11 it raises ``InvalidStateError`` in that
    thread for any call that was cancelled first."""
    with _pools_lock:
        for n, p in list(_pools.items()):
            if p is pool:
                del _pools[n]
    _end(pool)


def _end(pool: cf.ProcessPoolExecutor) -> None:
    """Kill ``pool``'s workers and shut it down without waiting (:func:`kill_pool`, unlisted)."""
    for process in list((getattr(pool, "_processes", None) or {}).values()):
        with contextlib.suppress(Exception):
            process.kill()
    pool.shutdown(wait=False, cancel_futures=False)


atexit.register(discard_pool)


#: A local pool that breaks this many times in a row, no call finishing in between, is given up:
#: every call left fails with the error (a script without an ``if __name__ == "__main__":``
#: guard, a worker that cannot start).
MAX_BREAKS = 3


class LocalExecutor:
    """Runs on this machine: in-process for one worker, else the process's warm pool of that
    many workers (``shared_pool``).

    Parameters
    ----------
    workers : int, optional
        Number of worker processes (default ``os.cpu_count()``). ``1`` runs in
        the calling process, which is the easiest to debug.
    in_process : bool, optional
        Override: ``False`` uses a pool even for one worker (benchmarks).

    See Also
    --------
    asperity2d.sweep.make_executor, asperity2d.sweep.DaskExecutor

    Examples
    --------
    >>> from asperity2d import sweep
    >>> executor = sweep.LocalExecutor(workers=1)
    >>> executor.in_process, executor.workers
    (True, 1)
    >>> executor.close()
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
        hide = _check_main_importable(fn, jobs)
        # keep a bounded window in flight so huge studies do not queue everything at once
        window = 2 * self.workers
        pending = iter(enumerate(jobs))
        in_flight: dict[cf.Future, tuple[int, tuple]] = {}
        # A worker that dies takes the whole pool, and every call in it, down with it, without
        # saying which call killed it. The calls lost that way are run again one at a time in a
        # new pool: an innocent one finishes, the culprit breaks the pool alone and fails.
        suspects: list[tuple[int, tuple]] = []

        def fill() -> None:
            while len(in_flight) < (1 if suspects else window):
                nxt = suspects.pop(0) if suspects else next(pending, None)
                if nxt is None:
                    return
                pool = self._start()
                with _sigint_deferred():  # a submit may start a worker
                    in_flight[pool.submit(fn, *nxt[1])] = nxt

        try:
            with _main_file_hidden(hide):
                yield from self._drain(fn, in_flight, fill, suspects, pending)
        except KeyboardInterrupt:  # Ctrl-C: end the workers now, mid-call, and let the caller say so
            if self._pool is not None:
                kill_pool(self._pool)
                self._pool = None
            in_flight.clear()
            raise
        finally:  # stopped early (a failure raised by the caller): drop what is queued
            for future in in_flight:
                future.cancel()

    def _drain(self, fn, in_flight, fill, suspects, pending):
        breaks = 0  # pools broken in a row with no call finished in between
        fill()
        while in_flight:
            done, _ = cf.wait(in_flight, return_when=cf.FIRST_COMPLETED)
            lost, cause = [], None
            for future in done:
                call = in_flight.pop(future)
                try:
                    result = future.result()
                except (cf.process.BrokenProcessPool, cf.CancelledError) as exc:
                    lost.append(call)
                    cause = exc
                    continue
                breaks = 0
                yield call[0], result
            if cause is not None:
                lost += in_flight.values()
                in_flight.clear()
                self._discard()
                breaks += 1
                if breaks >= MAX_BREAKS:  # the pool itself cannot run: every call left fails
                    for index, _ in [*lost, *suspects, *pending]:
                        yield index, died(cause)
                    return
                if len(lost) == 1:  # alone in its pool: this call killed its worker
                    yield lost[0][0], died(cause)
                else:
                    suspects.extend(sorted(lost, key=lambda c: c[0]))
            fill()

    def _start(self) -> cf.ProcessPoolExecutor:
        if self._pool is None:
            self._pool = shared_pool(self.workers)
        return self._pool

    def _discard(self) -> None:
        """The pool broke: shut it down; the next call starts a new one."""
        if self._pool is not None:
            discard_pool(self._pool)
            self._pool = None

    def close(self) -> None:
        """Let go of the pool; it stays warm for the process's next ensemble."""
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


class OneLine(logging.Filter):
    """A log filter that writes an exception's record as one line: its message and the exception's
    type and text, without the traceback (a killed Dask worker makes its peers and the scheduler
    log a ``CommClosedError`` traceback each; the run it held is reported as failed anyway)."""

    def filter(self, record: logging.LogRecord) -> bool:
        # only Dask's (and its event loop's) records: a user's own logging keeps its tracebacks
        if record.exc_info and record.exc_info[1] is not None and record.name.split(".")[0] in DASK_LOGGERS:
            exc = record.exc_info[1]
            record.msg = f"{record.getMessage()} ({type(exc).__name__}: {exc})".replace("\n", " ")
            record.args, record.exc_info, record.exc_text = (), None, None
        return True


#: The loggers whose exception records :class:`OneLine` shortens while a Dask executor is open.
DASK_LOGGERS = ("distributed", "tornado", "asyncio")


def quiet_tracebacks(names=DASK_LOGGERS) -> Callable[[], None]:
    """Put a :class:`OneLine` filter on the handlers of loggers ``names`` (and the root's);
    return the function that takes it off again."""
    one = OneLine()
    handlers = {h for name in (*names, "") for h in logging.getLogger(name).handlers}
    for handler in handlers:
        handler.addFilter(one)

    def undo() -> None:
        for handler in handlers:
            handler.removeFilter(one)

    return undo


def dask_setup(worker=None) -> None:
    """Dask preload hook (``LocalCluster(preload=[__name__])``): the workers this package starts
    log exceptions as one line too."""
    quiet_tracebacks()


class DaskExecutor:
    """Runs on a Dask distributed cluster.

    Parameters
    ----------
    scheduler : str
        ``"tcp://host:port"`` (or any address Dask accepts) to connect to a
        running cluster, or ``"local"`` to start a ``LocalCluster`` of worker
        processes here (closed again by ``close()``). The workers must be
        able to import asperity2d and the study's run function.
    workers : int, optional
        Worker processes for ``scheduler="local"`` (default ``os.cpu_count()``).

    See Also
    --------
    asperity2d.sweep.make_executor, asperity2d.sweep.LocalExecutor

    Examples
    --------
    Skipped when the examples run: it needs a Dask scheduler listening at that address.

    >>> from asperity2d import sweep
    >>> executor = sweep.DaskExecutor(scheduler="tcp://127.0.0.1:8786")  # doctest: +SKIP
    >>> sweep.run_study("study.toml", store="results", scheduler="tcp://127.0.0.1:8786")  # doctest: +SKIP
    """

    def __init__(self, *, scheduler: str, workers: int | None = None):
        check_executor_args(workers=workers, scheduler=scheduler)
        distributed = _import_distributed()
        self.scheduler = scheduler
        self._cluster = None
        self._loud = quiet_tracebacks()
        if scheduler == "local":
            n = _check_workers(workers)
            try:
                self._cluster = distributed.LocalCluster(
                    n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
                    preload=[__name__])
            except Exception as exc:  # noqa: BLE001 - a worker killed or failing while it starts
                self._loud()
                raise SimulationError(f"`scheduler` 'local': the Dask cluster did not start "
                                      f"({type(exc).__name__}: {exc})") from None
            address = self._cluster.scheduler_address
        else:
            address = scheduler
        try:
            self._client = distributed.Client(address, set_as_default=False, timeout=CONNECT_TIMEOUT)
        except (OSError, TimeoutError, ValueError) as exc:
            self._close_cluster()
            self._loud()
            raise SceneError(f"`scheduler` {scheduler!r} could not be reached within "
                             f"{CONNECT_TIMEOUT:g} s: {exc}") from None

    @property
    def description(self) -> str:
        return f"dask ({self.scheduler})"

    def map_unordered(self, fn: Callable, jobs: Sequence[tuple]) -> Iterator[tuple[int, Any]]:
        """Yield ``(index, fn(*jobs[index]))`` as each run completes on the cluster.

        A task whose worker died (``KilledWorker``, after the scheduler's own retries) may be
        only a neighbour of the culprit, queued on the same worker: such calls are run again
        one at a time at the end, so only the call that kills its worker alone fails.
        """
        distributed = _import_distributed()
        token = uuid.uuid4().hex[:8]
        suspects: list[int] = []
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
                except (KeyboardInterrupt, SystemExit):
                    raise
                except BaseException:  # the worker died running it, or beside the one that did
                    # (KilledWorker, CommClosedError, a cancelled future: each is a death)
                    suspects.append(index)
                    future.release()
                    continue
                future.release()
                yield index, result
            for index in suspects:  # alone on the cluster now
                future = self._client.submit(fn, *jobs[index], key=f"asperity2d-rerun-{token}-{index}",
                                             pure=False)
                futures[future.key] = (future, index)
                try:
                    result = future.result()
                except Exception as exc:  # noqa: BLE001 - it kills its worker by itself
                    result = died(exc)
                future.release()
                yield index, result
        except OSError as exc:  # CommClosedError: the connection to the scheduler itself was lost
            raise SimulationError(f"`scheduler` {self.scheduler!r}: the connection to the Dask scheduler "
                                  f"closed ({type(exc).__name__}: {exc}); the runs not finished have no result"
                                  ) from None
        finally:  # stopped early (error, Ctrl-C): do not leave runs queued on the cluster
            for future, _ in futures.values():
                if not future.done():
                    future.cancel()

    def _close_cluster(self) -> None:
        if self._cluster is not None:
            with contextlib.suppress(Exception):  # a cluster whose workers were killed: gone already
                self._cluster.close()
            self._cluster = None

    def close(self) -> None:
        with contextlib.suppress(Exception):  # CommClosedError, a timeout: the connection is gone
            self._client.close()
        self._close_cluster()
        self._loud()

    def __enter__(self) -> "DaskExecutor":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


#: A Dask scheduler address: ``[scheme://]host:port`` (the schemes Dask's TCP-like transports
#: use; IPv6 hosts in brackets), or ``inproc://...``.
_ADDRESS = re.compile(r"^(?:(?:tcp|tls|ucx|ws|wss)://)?(?:\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9_.-]+):[0-9]{1,5}$"
                      r"|^inproc://\S+$")
#: Seconds to wait for a Dask scheduler to answer before giving up (a cluster on a network
#: answers in milliseconds; a wrong address should fail fast, in one line).
CONNECT_TIMEOUT = 5.0


def check_scheduler(scheduler) -> None:
    """Refuse a ``scheduler`` that is neither ``"local"`` nor an address (SceneError naming it),
    before anything is imported or started."""
    if not isinstance(scheduler, str) or not scheduler:
        raise SceneError(f"`scheduler` must be an address or 'local', got {scheduler!r}")
    if scheduler != "local" and not _ADDRESS.match(scheduler):
        raise SceneError(f"`scheduler` must be 'local' or a Dask scheduler address like "
                         f"tcp://host:8786, got {scheduler!r}")


def check_executor_args(*, workers: int | None = None, scheduler: str | None = None) -> None:
    """Validate ``workers`` / ``scheduler`` without starting anything (SceneError if bad)."""
    if workers is not None:
        _check_workers(workers)
    if scheduler is None:
        return
    check_scheduler(scheduler)
    if scheduler != "local" and workers is not None:
        raise SceneError("`workers` applies only to scheduler='local'; a cluster has its own")


def make_executor(
    *, workers: int | None = None, scheduler: str | None = None
) -> LocalExecutor | DaskExecutor:
    """A :class:`DaskExecutor` if ``scheduler`` is given, else a :class:`LocalExecutor`.

    Parameters
    ----------
    workers : int, optional
        Local worker processes.
    scheduler : str, optional
        A Dask scheduler address, or ``"local"``.

    Returns
    -------
    LocalExecutor or DaskExecutor

    See Also
    --------
    asperity2d.sweep.LocalExecutor
    asperity2d.sweep.DaskExecutor

    Examples
    --------
    >>> from asperity2d import sweep
    >>> type(sweep.make_executor(workers=1)).__name__
    'LocalExecutor'
    """
    check_executor_args(workers=workers, scheduler=scheduler)
    if scheduler is None:
        return LocalExecutor(workers=workers)
    return DaskExecutor(scheduler=scheduler, workers=workers)


def jobs_for(run: str, specs: Iterable, quantities: Sequence[str] | None) -> list[tuple]:
    """Argument tuples of :func:`execute_run` for run specs."""
    q = None if quantities is None else tuple(quantities)
    return [(run, dict(spec.params), spec.seed, q) for spec in specs]
