"""Building (and freeing) an asperity scene's pymunk space, against its size.

    python benchmarks/bench_build.py [--quick] [--json]     (or: run_all.py --only build)

For N = 1,000, 10,000 and 100,000 lower asperities (4 upper tips, Ooten's fixed-track
set-up): CPU time (``time.process_time``) of ``Run(scene)`` -- scaling, checks, building the
space --, of 20 steps, and of freeing the run (``gc.collect`` after the last reference goes).
One measurement each (a build is seconds, not microseconds; the machine may be shared, so
read the ratios between sizes, not the absolute times). Linear building shows as a time per
asperity that stays flat from 10,000 to 100,000; before issue 27 it grew with N (10,000:
2.2 s, 20,000: 9.3 s, 100,000: about 20 minutes; freeing 20,000 took 12 s).
"""

from __future__ import annotations

import argparse
import gc
import json
import time

import asperity2d as a
from asperity2d.run import Run


def measure(n: int) -> dict:
    scene = a.make_scene(lower_count=n, upper_count=4)
    t0 = time.process_time()
    run = Run(scene)
    t1 = time.process_time()
    run.advance(20 * run.dt)
    t2 = time.process_time()
    del run
    gc.collect()
    t3 = time.process_time()
    return {"N": n, "build_s": t1 - t0, "build_us_per_asperity": 1e6 * (t1 - t0) / n,
            "step_ms": 1e3 * (t2 - t1) / 20, "free_s": t3 - t2}


def run(quick: bool = False) -> dict:
    return {"rows": [measure(n) for n in ((1_000, 10_000) if quick else (1_000, 10_000, 100_000))]}


def headline(res):
    rows = res["rows"]
    out = [(f"build us per asperity, N={r['N']:,}", r["build_us_per_asperity"], "flat in N") for r in rows]
    out.append((f"build time, N={rows[-1]['N']:,} (s)", rows[-1]["build_s"], "seconds"))
    return out


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    p.add_argument("--json", action="store_true")
    args = p.parse_args(argv)
    out = run(args.quick)
    if args.json:
        print(json.dumps(out))
        return 0
    for r in out["rows"]:
        print(f"N={r['N']:>7,}: build {r['build_s']:6.2f} s ({r['build_us_per_asperity']:5.0f} us/asperity), "
              f"step {r['step_ms']:8.2f} ms, free {r['free_s']:5.2f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
