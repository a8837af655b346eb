"""Sweeps and ensembles: run a function over a parameter grid and seeds, at scale.

Every ensemble runs on one engine (:mod:`.engine`: :func:`run_calls`, :func:`map_calls`,
one failure contract on every executor). A :class:`Study` names a run function by dotted
path ``"module:function"``, a grid of parameters and a list of seeds. :func:`run_study`
executes the runs that are not finished yet (locally in processes, or on a Dask cluster) and
writes each one atomically to a resumable :class:`ResultStore` (a run function with a batched
form, :class:`BatchedRun`, runs the whole study on the batched asperity engine where it is
installed and covers the scenes); :func:`summarize` turns the store into statistics per grid point
(:func:`asperity2d.renderers.sweep.plot_summary` draws them).
"""

from .engine import CallFailed, Outcome, decide_workers, map_calls, run_calls
from .executors import DaskExecutor, LocalExecutor, execute_run, make_executor
from .report import Summary, VariantStats, VariantTest, summarize
from .runner import BatchedRun, SweepSummary, run_study
from .record import CorruptRunWarning, RunRecord
from .store import ResultStore, StoreStatus
from .study import RunSpec, Study, load_study, run_key

__all__ = [
    "BatchedRun",
    "CallFailed",
    "CorruptRunWarning",
    "Outcome",
    "decide_workers",
    "map_calls",
    "run_calls",
    "DaskExecutor",
    "LocalExecutor",
    "ResultStore",
    "RunRecord",
    "RunSpec",
    "StoreStatus",
    "Study",
    "Summary",
    "SweepSummary",
    "VariantStats",
    "VariantTest",
    "execute_run",
    "load_study",
    "make_executor",
    "run_key",
    "run_study",
    "summarize",
]
