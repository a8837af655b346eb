"""Benchmark the sweep machinery: per-run overhead, throughput, parallel efficiency.

    python benchmarks/bench_sweep.py [--quick]

What is measured (medians over repeats, each repeat in a fresh store):

* **overhead**: (study wall time - time spent inside the run functions) / runs,
  relative to the mean run time, for ~1 s runs that are CPU-bound (a pure-Python
  logistic map, deterministic) and that sleep. In-process (``workers=1``) it is
  store + hashing + progress; through a one-worker spawn pool it adds pickling
  and IPC, with the pool started beforehand ("warm") or inside the study ("cold",
  includes worker start-up).
* **throughput** (runs/s) with 1 and 2 workers of an already started pool
  (start-up is reported separately, paid once per study) and the parallel efficiency
  ``T1 / (2 T2)``; for CPU-bound runs compared with the same two runs launched
  as bare processes without any sweep code ("hardware"), which shows how much
  of the loss is the machine (2 shared cores) and how much is the executor. An efficiency
  above 1 (two workers more than twice as fast as one) cannot be true of 2 cores; on a
  shared machine it only says the load changed between the two measurements, so it is
  refused (reported as None, with the measured value beside it), never printed as a result.

Local workers are kept warm for the life of a process now (one pool per worker count,
:func:`asperity2d.sweep.executors.shared_pool`): the "cold" rows discard the pool first.
"""

from __future__ import annotations

import argparse
import multiprocessing
import statistics
import sys
import tempfile
import time
from pathlib import Path

if __name__ == "__main__":  # run functions must be importable by workers as bench_sweep:*
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    _MODULE = "bench_sweep"
else:
    _MODULE = __name__


def cpu_work(*, iterations: int, seed: int) -> dict[str, float]:
    """Deterministic CPU-bound run: ``iterations`` steps of the logistic map."""
    x = 0.1 + 0.8 * (seed % 997) / 997
    for _ in range(iterations):
        x = 3.9 * x * (1.0 - x)
    return {"x": x}


def sleep_work(*, duration: float, seed: int) -> dict[str, float]:
    """Run that only sleeps ``duration`` seconds (no CPU)."""
    time.sleep(duration)
    return {"x": float(seed)}


def calibrate(seconds: float) -> int:
    """Logistic-map iterations that take about ``seconds`` here."""
    n = 200_000
    while True:
        start = time.perf_counter()
        cpu_work(iterations=n, seed=0)
        elapsed = time.perf_counter() - start
        if elapsed > 0.2:
            return max(1, int(n * seconds / elapsed))
        n *= 4


def _study(name, fn, fixed, runs):
    from asperity2d.sweep import Study

    return Study(name=name, run=f"{_MODULE}:{fn}", seeds=range(runs), fixed=fixed)


def _overhead(study, *, executor=None, workers=None):
    """(per-run overhead s, relative overhead, wall s) of one study in a fresh store."""
    from asperity2d.sweep import ResultStore, run_study

    with tempfile.TemporaryDirectory() as tmp:
        kw = {"executor": executor} if executor is not None else {"workers": workers}
        summary = run_study(study, store=tmp, progress=False, **kw)
        inside = [r.wall_time for r in ResultStore(tmp).records(study).values()]
    n_par = 1 if workers in (None, 1) else workers
    per_run = (summary.wall_time - sum(inside) / n_par) / len(inside)
    return per_run, per_run / statistics.mean(inside), summary.wall_time


def _warm(executor, workers):
    """Start the pool's worker processes with trivial runs (not timed as throughput)."""
    from asperity2d.sweep import run_study

    with tempfile.TemporaryDirectory() as tmp:
        run_study(_study("warm", "cpu_work", {"iterations": 1000}, 2 * workers), store=tmp,
                  executor=executor, progress=False)


def _median(values):
    return statistics.median(values)


def _bare_pair(iterations):
    """Wall time of two cpu_work runs launched together as plain processes."""
    ctx = multiprocessing.get_context("spawn")
    with ctx.Pool(2) as pool:
        pool.apply(cpu_work, (), {"iterations": 1000, "seed": 0})  # start both workers first
        pool.apply(cpu_work, (), {"iterations": 1000, "seed": 0})
        start = time.perf_counter()
        pool.starmap(_cpu_positional, [(iterations, 0), (iterations, 1)])
        return time.perf_counter() - start


def _cpu_positional(iterations, seed):
    return cpu_work(iterations=iterations, seed=seed)


def run(quick: bool = False) -> dict:
    """Run the benchmark and return its numbers (seconds, ratios)."""
    from asperity2d.sweep import LocalExecutor
    from asperity2d.sweep.executors import discard_pool

    seconds = 0.25 if quick else 1.0
    repeats = 1 if quick else 3
    n_over, n_thru = (3, 4) if quick else (5, 6)
    iterations = calibrate(seconds)
    cpu = {"iterations": iterations}
    slp = {"duration": seconds}
    out = {"run_seconds": seconds, "repeats": repeats, "iterations": iterations,
           "overhead": {}, "throughput": {}}

    for label, fn, fixed in (("cpu", "cpu_work", cpu), ("sleep", "sleep_work", slp)):
        rows = {"in-process": [], "pool1-warm": [], "pool1-cold": []}
        for r in range(repeats):
            study = _study(f"over-{label}-{r}", fn, fixed, n_over)
            rows["in-process"].append(_overhead(study, workers=1))
            discard_pool()  # cold: no warm pool of this process
            with LocalExecutor(workers=1, in_process=False) as ex:
                rows["pool1-cold"].append(_overhead(study, executor=ex))
                rows["pool1-warm"].append(_overhead(study, executor=ex))  # same pool, started
        out["overhead"][label] = {
            k: {"per_run_ms": 1e3 * _median([v[0] for v in vals]),
                "relative": _median([v[1] for v in vals])}
            for k, vals in rows.items()
        }

    for label, fn, fixed in (("cpu", "cpu_work", cpu), ("sleep", "sleep_work", slp)):
        walls = {1: [], 2: []}
        for r in range(repeats):
            study = _study(f"thru-{label}-{r}", fn, fixed, n_thru)
            for w in (1, 2):
                with LocalExecutor(workers=w, in_process=False) as ex:
                    _warm(ex, w)
                    walls[w].append(_overhead(study, executor=ex)[2])
        t1, t2 = _median(walls[1]), _median(walls[2])
        rounds = [a / (2 * b) for a, b in zip(walls[1], walls[2])]  # interleaved pairs
        efficiency = _median(rounds)
        out["throughput"][label] = {"runs_per_s_1": n_thru / t1, "runs_per_s_2": n_thru / t2,
                                    "efficiency_measured": efficiency, "efficiency_rounds": rounds,
                                    "efficiency": efficiency if efficiency <= 1.0 else None}
        if efficiency > 1.0:
            out["throughput"][label]["refused"] = (f"{efficiency:.2f} > 1 cannot be true of 2 cores: the load "
                                                   "changed between the measurements")
    starts = []
    for r in range(repeats):
        discard_pool()
        with LocalExecutor(workers=2, in_process=False) as ex:
            start = time.perf_counter()
            _warm(ex, 2)
            starts.append(time.perf_counter() - start)
    out["pool_start_2_workers_s"] = _median(starts)
    single = _median([_overhead(_study(f"one-{r}", "cpu_work", cpu, 1), workers=1)[2]
                      for r in range(repeats)])
    pair = _median([_bare_pair(iterations) for _ in range(repeats)])
    out["throughput"]["cpu"]["hardware_efficiency"] = single / pair
    return out


def _print(res: dict) -> None:
    s = res["run_seconds"]
    print(f"sweep benchmark: runs of ~{s:g} s, medians of {res['repeats']} repeat(s)\n")
    print(f"{'per-run overhead':<22}{'cpu ms':>9}{'cpu %':>8}{'sleep ms':>10}{'sleep %':>9}")
    for k in ("in-process", "pool1-warm", "pool1-cold"):
        c, z = res["overhead"]["cpu"][k], res["overhead"]["sleep"][k]
        print(f"{k:<22}{c['per_run_ms']:>9.1f}{100 * c['relative']:>8.2f}"
              f"{z['per_run_ms']:>10.1f}{100 * z['relative']:>9.2f}")
    print(f"\n2-worker spawn pool start-up (once per study): {res['pool_start_2_workers_s']:.2f} s")
    print(f"\n{'throughput, warm pool':<22}{'1 worker':>10}{'2 workers':>11}{'efficiency':>12}")
    for k in ("cpu", "sleep"):
        t = res["throughput"][k]
        eff = "refused" if t["efficiency"] is None else f"{t['efficiency']:.2f}"
        print(f"{k + ' (runs/s)':<22}{t['runs_per_s_1']:>10.3f}{t['runs_per_s_2']:>11.3f}{eff:>12}"
              f"  (measured {t['efficiency_measured']:.2f})")
    hw = res["throughput"]["cpu"]["hardware_efficiency"]
    print(f"\nhardware: two bare CPU-bound processes at once reach efficiency {hw:.2f} "
          f"(1.00 = two full cores)")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="short runs, one repeat")
    _print(run(quick=parser.parse_args().quick))
