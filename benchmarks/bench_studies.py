"""Benchmark a 20-seed regular-vs-random comparison at the seed-000 study settings.

    python benchmarks/bench_studies.py [--quick]

Issue 4's target: a 20-seed regular-vs-random comparison at default settings
finishes in under two minutes on this 2-core machine. Measured here with
:func:`asperity2d.compare` at the study size (10 lower / 3 upper asperities,
free slider under 10 mN, the package defaults otherwise), for the critical
constant force (1 % bisection) and the spring-drive breakaway force, with
``workers=1`` and ``workers=2``. The regular variant is run for every seed too,
as a plain ``compare`` call does (it is deterministic; the study scripts run it
once). Wall times are single measurements on a shared machine: the load at the
time is printed alongside.
"""

from __future__ import annotations

import argparse
import os
import time

import asperity2d as a
from asperity2d import studies

TARGET_S = 120.0


def run(quick: bool = False) -> dict:
    """Wall time (s) per measure and worker count; ``quick``: 3 seeds instead of 20."""
    seeds = range(3 if quick else 20)
    variants = {"regular": {"spacing": "regular"}, "random": {"spacing": "random"}}
    rows = {}
    for measure, drive in ((studies.critical_force_of, "force"), (studies.breakaway_force_of, "spring")):
        for workers in (1, 2):
            load = os.getloadavg()[0]
            start = time.perf_counter()
            comparison = a.compare(measure, variants, seeds=seeds, progress=False, workers=workers,
                                   base={**studies.STUDY_SIZE, "drive": drive})
            wall = time.perf_counter() - start
            rows[f"{measure.__name__}/workers={workers}"] = {
                "wall_s": wall, "runs": 2 * len(seeds), "per_run_s": wall / (2 * len(seeds)),
                "load_before": load, "random_mean_N": comparison.mean("random"),
                "under_target": wall < TARGET_S}
    return {"seeds": len(seeds), "target_s": TARGET_S, "rows": rows}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="3 seeds instead of 20")
    args = p.parse_args(argv)
    out = run(quick=args.quick)
    print(f"{out['seeds']} seeds x 2 variants, study size {studies.STUDY_SIZE} (target < {TARGET_S:.0f} s)")
    print(f"{'measure / workers':40s} {'wall s':>8s} {'s/run':>7s} {'load':>5s}  target")
    for name, r in out["rows"].items():
        print(f"{name:40s} {r['wall_s']:8.1f} {r['per_run_s']:7.2f} {r['load_before']:5.1f}  "
              f"{'ok' if r['under_target'] else 'MISSED'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
