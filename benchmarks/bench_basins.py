"""Basin-map benchmark: the cost of one grid point of the multi-DOF belt thesis' 3-DOF base case, and of the map.

Run ``python benchmarks/bench_basins.py [--quick]``; ``run(quick=False) -> dict``.

Target (issue 15): a 100 x 100 basin map of the Table 2 chain over 100 s per run in a few
minutes on 2 cores, i.e. the exact solver at a few ms per run.

1. **Per-run cost**, CPU time (``time.process_time``) of one grid point -- the exact solver over
   100 s plus the classification -- on a spread sample of the 100 x 100 grid of
   ``scenes/belt_basins.py`` (x1 in [-0.3, 0.9] m, v1 in [-0.6, 0.6] m/s), for the base case and
   for the static-friction contrast (mu_s = 0.4 > mu_k = 0.2, sustained stick-slip: many more
   events). Median, mean and the split solver / classifier; the events per run.
2. **Sweep overhead**: a small map through ``chain_basins`` on 2 worker processes (pool start-up
   included, as a user pays it), wall time against the CPU time inside the runs.
3. **The 100 x 100 map** (not with ``--quick``; ~4-5 minutes on 2 cores): run it through the
   CLI's code path and time it, wall clock, as a user waits for it. The map's time is only
   ever this measurement, never the per-run cost multiplied up.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time

import numpy as np

from asperity2d.belt import presets, simulate_chain
from asperity2d.dynamics.basins import chain_basins, classify_chain, with_initial

X_RANGE, V_RANGE, T_END = (-0.3, 0.9), (-0.6, 0.6), 100.0
N_SAMPLES = int(20 * T_END) + 1  # as scenes/belt_basins.py


def grid_sample(count, size=100):
    """``count`` (x1, v1) points spread over the size x size grid (a deterministic stride)."""
    xs, vs = np.linspace(*X_RANGE, size), np.linspace(*V_RANGE, size)
    idx = np.linspace(0, size * size - 1, count).round().astype(int)
    return [(float(xs[i // size]), float(vs[i % size])) for i in idx]


def per_run(chain, points):
    solve, classify, events, failed = [], [], [], 0
    for x1, v1 in points:
        kw = with_initial(with_initial(chain, "x1", x1), "v1", v1)
        t0 = time.process_time()
        try:
            r = simulate_chain(**kw)
        except Exception:  # noqa: BLE001 -- a failing grid point is counted, not timed
            failed += 1
            continue
        t1 = time.process_time()
        classify_chain(r)
        t2 = time.process_time()
        solve.append(t1 - t0)
        classify.append(t2 - t1)
        events.append(len(r.events))
    total = [a + b for a, b in zip(solve, classify)]
    return {"runs": len(total), "failed": failed,
            "ms_per_run_median": 1e3 * statistics.median(total), "ms_per_run_mean": 1e3 * statistics.mean(total),
            "ms_solver_mean": 1e3 * statistics.mean(solve), "ms_classifier_mean": 1e3 * statistics.mean(classify),
            "events_median": statistics.median(events), "events_max": max(events),
            "ms_per_event": 1e3 * sum(solve) / max(sum(events), 1)}


def sweep_overhead(chain, size, workers=2):
    xs, vs = np.linspace(*X_RANGE, size), np.linspace(*V_RANGE, size)
    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        bm = chain_basins(chain, x=("x1", xs), y=("v1", vs), store=tmp, workers=workers, progress=False)
        wall = time.perf_counter() - start
    runs = size * size - bm.failed
    # bm.wall_time sums the wall time spent inside the run functions (as the sweep records it)
    return {"grid": [size, size], "workers": workers, "wall_s": wall, "wall_in_runs_s": bm.wall_time,
            "failed": bm.failed, "wall_per_run_ms": 1e3 * wall / (size * size),
            "parallel_speedup": bm.wall_time / wall, "run_wall_ms_mean": 1e3 * bm.wall_time / max(runs, 1)}


def full_map(chain, workers=2):
    xs, vs = np.linspace(*X_RANGE, 100), np.linspace(*V_RANGE, 100)
    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        bm = chain_basins(chain, x=("x1", xs), y=("v1", vs), store=tmp, workers=workers, progress=True)
        wall = time.perf_counter() - start
    return {"wall_minutes": wall / 60, "workers": workers, "counts": bm.counts(),
            "run_wall_ms_mean": 1e3 * bm.wall_time / max(1e4 - bm.failed, 1)}


def run(quick: bool = False, full: bool | None = None) -> dict:
    """Per-run CPU (medians), the sweep's parallel speed-up and -- unless ``quick`` -- the
    whole 100 x 100 map of the base case, timed (never extrapolated from the per-run cost)."""
    full = not quick if full is None else full
    base = presets.preset("table2-3dof", t_end=T_END, n_samples=N_SAMPLES)
    contrast = presets.preset("table2-3dof", mu_s=0.4, t_end=T_END, n_samples=N_SAMPLES)
    points = grid_sample(12 if quick else 60)
    out = {"t_end_s": T_END, "n_samples": N_SAMPLES,
           "per_run": {"base": per_run(base, points), "contrast_mu_s_0.4": per_run(contrast, points[::3])},
           "sweep": sweep_overhead(base, 4 if quick else 10)}
    if full:
        out["full_map"] = full_map(base)
    return out


def headline(res) -> list:
    """Rows for ``benchmarks/run_all.py --only basins``: (figure, value, target)."""
    rows = []
    for name, r in res["per_run"].items():
        rows.append((f"basin grid point, {name}: ms CPU per 100 s run", r["ms_per_run_median"], "a few ms"))
    rows.append(("basin sweep: time in runs / wall, 2 workers", res["sweep"]["parallel_speedup"], "close to 2"))
    if "full_map" in res:
        rows.append(("basin map 100x100 measured (min)", res["full_map"]["wall_minutes"], "a few minutes"))
    return rows


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    args = p.parse_args(argv)
    res = run(quick=args.quick)
    for name, r in res["per_run"].items():
        print(f"{name}: {r['ms_per_run_median']:.1f} ms per run (median; mean {r['ms_per_run_mean']:.1f}: "
              f"solver {r['ms_solver_mean']:.1f} + classifier {r['ms_classifier_mean']:.1f}), "
              f"{r['events_median']:.0f} events, {r['ms_per_event']:.2f} ms/event, {r['failed']} failed "
              f"[target: a few ms per run]")
    s = res["sweep"]
    print(f"sweep {s['grid'][0]}x{s['grid'][1]} on {s['workers']} workers: {s['wall_per_run_ms']:.1f} ms wall per "
          f"grid point, {s['run_wall_ms_mean']:.1f} ms inside each run, (time in runs) / (wall) "
          f"{s['parallel_speedup']:.2f} (includes pool start-up) [target: close to 2]")
    if "full_map" in res:
        f = res["full_map"]
        print(f"100 x 100 map measured: {f['wall_minutes']:.1f} min on {f['workers']} workers, {f['counts']} "
              f"[target: a few minutes]")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
