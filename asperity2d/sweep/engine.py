"""The ensemble engine: call one function on many argument sets -- in this process, in local
worker processes or on a Dask cluster -- with one failure contract.

Every ensemble of the package goes through :func:`run_calls`: sweeps into a results store
(:func:`asperity2d.sweep.run_study`, and through it the basin maps), comparisons over seeds
(:func:`asperity2d.experiments.compare.compare`) and the scene scripts' parallel runs
(:func:`map_calls`)::

    for outcome in run_calls(fn, [(a1,), (a2,)], workers=2):    # as they complete
        outcome.index, outcome.status, outcome.value, outcome.error
    values = map_calls(fn, [{"seed": 0}, {"seed": 1}], workers=2)  # in order, or raise

The failure contract, the same on every executor:

* every call yields exactly one :class:`Outcome`, in completion order;
* a call that raises -- here, in a local worker or on a Dask worker -- is an outcome with
  ``status == "failed"``, its ``error`` (``"TypeName: message"``), ``traceback`` (text) and,
  when it can be pickled back, the ``exception`` itself; the engine does not raise for it;
* a call whose worker process died (a crash, a kill, Dask's ``KilledWorker``) is a failed
  outcome too, its error naming the death; the other calls are not lost with it (a local pool
  that breaks is started again and the calls it held are re-run one at a time, so only the
  one that kills its worker fails; a pool that breaks ``MAX_BREAKS`` times in a row with no
  call finished fails every call left: a script without an ``if __name__ == "__main__":``
  guard, a worker that cannot start);
* what stops the engine itself: bad arguments (``SceneError``, before anything starts), a
  Dask scheduler that cannot be reached (``SceneError``) and ``KeyboardInterrupt`` (calls not
  started are cancelled).

Front ends that need every value (:func:`map_calls`, ``compare``) raise the first failed call's
own exception as it arrives (a :class:`CallFailed` when it did not come back: a dead worker, an
exception that does not pickle), with a note naming the call, and cancel the rest.

Runs are deterministic given their arguments, so the executor never changes the values.
How many local workers an ensemble gets is decided in one place, :func:`decide_workers`: as
many as asked, or (``workers=None``, the default, or ``"auto"``) from what the calls cost --
in this process when parallel would not pay for starting workers, every core when it would.
What a call costs is measured, not guessed: without a ``cost`` estimate and without a warm
pool, the first call runs here (a pilot) and its time decides for the rest. Local workers are
kept warm for the life of the process (:func:`asperity2d.sweep.executors.shared_pool`), so only
the first parallel ensemble of a process pays for starting them.
"""

from __future__ import annotations

import math
import os
import pickle
import threading
import time
import traceback
from dataclasses import dataclass, field
from typing import Any, Callable, Iterator, Mapping, Sequence

from ..errors import SceneError

#: Wall time (s) to start a pool of spawned workers and import, in each, what the package's
#: calls need (the interpreter, NumPy, SciPy, pymunk, asperity2d): measured ~0.6-1.0 s on the
#: project's 2-core machine under load (0.3 s of it the interpreter alone); a warm pool costs 0.
STARTUP_S = 1.0
#: Wall time (s) per call of sending it to a warm worker and its result back (pickling a scene
#: and a float: ~1 ms measured).
DISPATCH_S = 2e-3
#: Parallel is chosen when its predicted wall time is at most this fraction of serial's (a
#: margin for a shared machine, whose second core is not always free).
PAYS = 0.8
#: A first call (the pilot) still running after this many seconds is costly enough that the
#: rest will likely go to workers: they are started then, beside it, so their start-up is
#: hidden behind the pilot instead of added after it (a pool that turns out not to pay stays
#: warm for the process's next ensemble).
SPECULATE_AFTER = 0.25


class CallFailed(RuntimeError):
    """A call failed and its own exception did not come back (a dead worker, or an exception
    that could not be pickled); the message is the error text.

    See Also
    --------
    asperity2d.sweep.Outcome.raise_failure, asperity2d.sweep.map_calls

    Examples
    --------
    >>> from asperity2d import sweep
    >>> issubclass(sweep.CallFailed, RuntimeError)
    True
    """


@dataclass(frozen=True)
class Outcome:
    """What became of call ``index``: ``status`` ``"done"`` with its ``value``, or ``"failed"``
    with ``error``, ``traceback`` and (when it could be pickled) the ``exception``;
    ``wall_time`` (s) spent in the call (NaN when its worker died).

    See Also
    --------
    asperity2d.sweep.run_calls : yields them.

    Examples
    --------
    >>> import math
    >>> from asperity2d import sweep
    >>> [(o.index, o.status, o.value, o.error) for o in sweep.run_calls(math.sqrt, [(4.0,), (-1.0,)], workers=1)]
    [(0, 'done', 2.0, None), (1, 'failed', None, 'ValueError: math domain error')]
    """

    index: int
    status: str
    value: Any = None
    error: str | None = None
    traceback: str | None = None
    wall_time: float = math.nan
    exception: BaseException | None = field(default=None, compare=False, repr=False)

    @property
    def ok(self) -> bool:
        return self.status == "done"

    def raise_failure(self, where: str = "") -> None:
        """Raise the call's own exception (or :class:`CallFailed`), with a note naming ``where``."""
        exc = self.exception if self.exception is not None else CallFailed(self.error or "the call failed")
        if where:
            exc.add_note(f"while running {where}")
        raise exc


def guarded(fn: Callable, args: tuple) -> tuple:
    """Call ``fn(*args)`` where it executes (a worker, or here); never raises. Returns
    ``(status, value, error, traceback, wall_time, exception)`` (module level: workers
    import it)."""
    start = time.perf_counter()
    try:
        value = fn(*args)
    except Exception as exc:  # a failed call is data, not a crash of the ensemble
        try:
            pickle.dumps(exc)
            carried = exc
        except Exception:  # noqa: BLE001 - an exception that cannot travel back: its text does
            carried = None
        return ("failed", None, f"{type(exc).__name__}: {exc}", traceback.format_exc(),
                time.perf_counter() - start, carried)
    return "done", value, None, None, time.perf_counter() - start, None


def is_auto(workers) -> bool:
    """True for the worker count that is decided by cost: None or ``"auto"``."""
    return workers is None or (isinstance(workers, str) and workers == "auto")


def decide_workers(workers: int | str | None, calls: int, *, cost: float | None = None) -> int:
    """Local worker processes for an ensemble of ``calls`` calls: the one place this is decided.

    ``workers`` as given (an int >= 1; never more than there are calls: a pool of idle workers
    costs their start-up and nothing else), or, for ``None`` / ``"auto"``, from ``cost``, the
    wall time (s) of one call: every core (``os.cpu_count()``) when the predicted parallel wall
    time -- ``STARTUP_S`` unless a warm pool of that many workers is running, plus the
    calls in rounds of one per worker, plus ``DISPATCH_S`` per call -- is at most
    ``PAYS`` of the serial time, else 1 (this process). Without a ``cost``: every core.

    Parameters
    ----------
    workers : int, "auto" or None
        As asked.
    calls : int
        Number of calls.
    cost : float, optional
        Wall time of one call (s).

    Returns
    -------
    int
        Worker processes (1: in this process).

    Raises
    ------
    SceneError
        A bad ``workers``.

    See Also
    --------
    asperity2d.sweep.run_calls : uses it.

    Examples
    --------
    >>> from asperity2d import sweep
    >>> sweep.decide_workers(2, 10)
    2
    >>> sweep.decide_workers('auto', 10, cost=0.001)  # cheap calls: not worth a pool
    1
    """
    if not is_auto(workers):
        if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
            raise SceneError(f"`workers` must be an int >= 1 or 'auto', got {workers!r}")
        return max(1, min(workers, calls))
    from .executors import warm_pools

    cores = max(1, min(os.cpu_count() or 1, calls))
    if cores == 1 or cost is None:
        return cores
    if not (isinstance(cost, (int, float)) and math.isfinite(cost) and cost >= 0):
        raise SceneError(f"`cost` must be a finite time >= 0 (s), got {cost!r}")
    start = 0.0 if cores in warm_pools() else STARTUP_S
    serial = calls * cost
    parallel = start + math.ceil(calls / cores) * cost + calls * DISPATCH_S
    return cores if parallel <= PAYS * serial else 1


def run_calls(fn: Callable, calls: Sequence[tuple], *, workers: int | str | None = None,
              scheduler: str | None = None, executor=None, cost: float | None = None,
              report: dict | None = None) -> Iterator[Outcome]:
    """``fn(*args)`` for every ``args`` in ``calls``; yield an :class:`Outcome` per call as it
    completes (the module docstring's failure contract).

    Parameters
    ----------
    fn : callable
        The function to call; a module-level function to run in worker processes.
    calls : sequence of tuple
        The positional arguments of each call.
    workers : int or "auto", optional
        Local processes (1: in this process; None or ``"auto"``, the default: decided by
        :func:`decide_workers` from ``cost``, else from the first call, run here). With
        ``scheduler="local"``, the ``LocalCluster``'s processes (every core when auto).
    scheduler : str, optional
        A Dask scheduler address, or ``"local"`` to start a ``LocalCluster`` (a running cluster
        has its own workers).
    executor : optional
        An open executor to run on (kept open); excludes ``workers`` and ``scheduler``.
    cost : float, optional
        The wall time of one call (s), if the caller knows it.
    report : dict, optional
        Receives ``"executor"``: where the calls ran, in words.

    Returns
    -------
    iterator of Outcome
        One per call, as each completes.

    See Also
    --------
    asperity2d.sweep.map_calls : the values in order.

    Examples
    --------
    >>> import math
    >>> from asperity2d import sweep
    >>> for outcome in sweep.run_calls(math.sqrt, [(4.0,), (-1.0,)], workers=1):
    ...     print(outcome.index, outcome.status, outcome.value, outcome.error)
    0 done 2.0 None
    1 failed None ValueError: math domain error
    """
    from .executors import LocalExecutor, check_executor_args, make_executor, plain_script_fallback, warm_pools

    calls = list(calls)
    if executor is not None and (not is_auto(workers) or scheduler is not None):
        raise SceneError("`executor` excludes `workers` and `scheduler`")
    if is_auto(workers):
        workers = None
    else:
        decide_workers(workers, 1)  # validates
    check_executor_args(workers=workers, scheduler=scheduler)
    if report is not None:
        report["executor"] = "none"
    if not calls:
        return
    jobs = [(fn, tuple(args)) for args in calls]
    owned, first, pilot = executor is None, 0, ""
    if owned and scheduler in (None, "local") and workers != 1 and len(jobs) > 1 and plain_script_fallback():
        workers, scheduler = 1, None  # a plain script without the main guard: in this process
    if owned and scheduler is not None:
        executor = make_executor(workers=workers, scheduler=scheduler)
    elif owned:
        cores = min(os.cpu_count() or 1, len(jobs))
        if workers is None and cost is None and cores > 1 and cores not in warm_pools():
            # what a call costs is measured: the first runs here, and its time decides the rest
            from .executors import prepare_workers, shared_pool

            prepare_workers()  # here, in the main thread, safe from a Ctrl-C (not in the timer's)
            early = threading.Timer(SPECULATE_AFTER, shared_pool, args=(cores,))
            early.daemon = True
            early.start()
            try:
                status, value, error, tb, wall, exc = guarded(*jobs[0])
            finally:
                early.cancel()
                early.join()
            first, cost = 1, wall
            pilot = f"call 0 in-process ({wall:.3g} s), then "
            yield Outcome(0, status, value, error, tb, wall, exc)
        n = decide_workers(workers, len(jobs) - first, cost=cost) if len(jobs) > first else 1
        executor = LocalExecutor(workers=n)
    if report is not None:
        report["executor"] = pilot + executor.description
    try:
        for index, result in executor.map_unordered(guarded, jobs[first:]):
            status, value, error, tb, wall, exc = result
            yield Outcome(index + first, status, value, error, tb, wall, exc)
    finally:
        if owned:
            executor.close()


def _call(fn: Callable, kwargs: Mapping[str, Any]) -> Any:
    return fn(**kwargs)


def map_calls(fn: Callable, kwargs_list: Sequence[Mapping[str, Any]], *,
              workers: int | str | None = None, scheduler: str | None = None) -> list:
    """``[fn(**kw) for kw in kwargs_list]`` on the engine (in-process, local processes or Dask;
    ``workers`` as for :func:`run_calls`, decided by cost by default), returned in order. A
    failed call raises its own exception here (:meth:`Outcome.raise_failure`, noting which
    call), on every executor; the calls not yet finished are cancelled.

    Parameters
    ----------
    fn : callable
        Called with each mapping as keyword arguments; module level for worker processes.
    kwargs_list : sequence of mappings
        One per call.
    workers : int, "auto" or None
        As for :func:`run_calls`.
    scheduler : str, optional
        A Dask scheduler address.

    Returns
    -------
    list
        The values, in the order of ``kwargs_list``.

    Raises
    ------
    Exception
        The first failed call's own exception.

    See Also
    --------
    asperity2d.sweep.run_calls : outcomes as they complete, failures included.

    Examples
    --------
    >>> from asperity2d import sweep
    >>> sweep.map_calls(complex, [{'real': 3, 'imag': 4}, {'real': 5}], workers=1)
    [(3+4j), (5+0j)]
    """
    out: list = [None] * len(kwargs_list)
    for outcome in run_calls(_call, [(fn, dict(kw)) for kw in kwargs_list], workers=workers,
                             scheduler=scheduler):
        if not outcome.ok:
            outcome.raise_failure(f"call {outcome.index} of {getattr(fn, '__name__', fn)!s}")
        out[outcome.index] = outcome.value
    return out
