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
How many local workers an ensemble gets is decided in one place, :func:`decide_workers`.
"""

from __future__ import annotations

import math
import os
import pickle
import time
import traceback
from dataclasses import dataclass, field
from typing import Any, Callable, Iterator, Mapping, Sequence

from ..errors import SceneError


class CallFailed(RuntimeError):
    """A call failed and its own exception did not come back (a dead worker, or an exception
    that could not be pickled); the message is the error text."""


@dataclass(frozen=True)
class Outcome:
    """What became of call ``index``: ``status`` ``"done"`` with its ``value``, or ``"failed"``
    with ``error``, ``traceback`` and (when it could be pickled) the ``exception``;
    ``wall_time`` (s) spent in the call (NaN when its worker died)."""

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


def decide_workers(workers: int | None, calls: int) -> int:
    """Local worker processes for an ensemble of ``calls`` calls: the one place this is decided.

    ``workers`` as given (an int >= 1), or every core (``os.cpu_count()``) when None; never
    more than there are calls (a pool of idle workers costs their start-up and nothing else).
    """
    if workers is None:
        workers = os.cpu_count() or 1
    elif isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise SceneError(f"`workers` must be an int >= 1, got {workers!r}")
    return max(1, min(workers, calls))


def run_calls(fn: Callable, calls: Sequence[tuple], *, workers: int | None = 1,
              scheduler: str | None = None, executor=None) -> Iterator[Outcome]:
    """``fn(*args)`` for every ``args`` in ``calls``; yield an :class:`Outcome` per call as it
    completes (the module docstring's failure contract).

    ``workers`` local processes (1: in this process; None: every core, see
    :func:`decide_workers`), or a Dask ``scheduler`` address (``"local"`` starts a
    ``LocalCluster`` of ``workers`` processes; a running cluster has its own, so ``workers``
    stays at its default), or an open ``executor`` (kept open). ``fn``
    must be a module-level function to run in worker processes.
    """
    from .executors import check_executor_args, make_executor

    calls = list(calls)
    if executor is not None and (workers not in (None, 1) or scheduler is not None):
        raise SceneError("`executor` excludes `workers` and `scheduler`")
    if scheduler not in (None, "local") and workers == 1:
        workers = None  # the default; a running cluster has its own workers
    check_executor_args(workers=workers, scheduler=scheduler)
    if not calls:
        return
    jobs = [(fn, tuple(args)) for args in calls]
    owned = executor is None
    if owned:
        n = workers if scheduler is not None else decide_workers(workers, len(calls))
        executor = make_executor(workers=n, scheduler=scheduler)
    try:
        for index, result in executor.map_unordered(guarded, jobs):
            status, value, error, tb, wall, exc = result
            yield Outcome(index, status, value, error, tb, wall, exc)
    finally:
        if owned:
            executor.close()


def _call(fn: Callable, kwargs: Mapping[str, Any]) -> Any:
    return fn(**kwargs)


def map_calls(fn: Callable, kwargs_list: Sequence[Mapping[str, Any]], *, workers: int | None = 1,
              scheduler: str | None = None) -> list:
    """``[fn(**kw) for kw in kwargs_list]`` on the engine (in-process, local processes or Dask),
    returned in order. A failed call raises its own exception here (:meth:`Outcome.raise_failure`,
    noting which call), on every executor; the calls not yet finished are cancelled."""
    out: list = [None] * len(kwargs_list)
    for outcome in run_calls(_call, [(fn, dict(kw)) for kw in kwargs_list], workers=workers,
                             scheduler=scheduler):
        if not outcome.ok:
            outcome.raise_failure(f"call {outcome.index} of {getattr(fn, '__name__', fn)!s}")
        out[outcome.index] = outcome.value
    return out
