"""Every core where it pays: the main job and a 20-seed comparison, wall time, as a user runs them.

    python benchmarks/bench_parallel.py [--quick] [--rounds N] [--json]

Two figures of issue 28, each measured in one run with interleaved rounds (so a change of the
machine's load hits both sides), wall time of a fresh process (``time.perf_counter`` around
``subprocess.run``: start-up, imports and worker start-up included, as the user waits):

* **the main job**, ``python scenes/quickstart.py`` (its defaults: the GIF, the player, 10 seeds
  of both comparisons on both set-ups), with the previous release's code (``BASELINE``,
  exported from git: its scripts already ran each comparison on ``--workers 2``, a new pool
  of spawned workers per comparison) against this code (``--workers auto``: the first run
  timed here, one warm pool for the process). Target: now / before <= 0.6.
* **a 20-seed comparison**, ``asperity2d compare --seeds 20`` (the command line's default
  measure, the critical force from rest, regular against random spacing on Ooten's
  16/4 scene) with ``--workers 1``, ``--workers 2`` and the default ``auto``.
  Target: workers 1 / workers 2 >= 1.7.

Each ratio is the median of the per-round ratios, with their range. The machine is shared
(several engineers run tests on its 2 cores): the load average is recorded with every
round; a second core that is busy with someone else's work cannot speed anything up.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
#: The code before this round (main, after the re-layering of issue 24).
BASELINE = "b81a83e"


def _tree(tmp: Path) -> Path:
    tmp.mkdir(parents=True, exist_ok=True)
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", BASELINE, "asperity2d", "scenes"],
                             capture_output=True, check=True).stdout
    subprocess.run(["tar", "-x", "-C", str(tmp)], input=archive, check=True)
    return tmp


def _wall(argv, tree: Path, out: Path) -> dict:
    env = {**os.environ, "PYTHONPATH": str(tree), "ASPERITY2D_RENDERS": str(out), "OPENBLAS_NUM_THREADS": "1"}
    load = os.getloadavg()[0]
    start = time.perf_counter()
    proc = subprocess.run([sys.executable, *argv], cwd=str(tree), env=env, capture_output=True, text=True)
    wall = time.perf_counter() - start
    if proc.returncode:
        raise RuntimeError(f"{argv} failed: {proc.stderr[-2000:]}")
    return {"wall_s": wall, "load_before": load, "load_after": os.getloadavg()[0], "stdout": proc.stdout[-600:]}


def _ratios(a, b):
    r = [x["wall_s"] / y["wall_s"] for x, y in zip(a, b)]
    return {"median": statistics.median(r), "min": min(r), "max": max(r), "rounds": len(r)}


def run(quick: bool = False, rounds: int | None = None) -> dict:
    rounds = rounds or (1 if quick else 2)
    seeds = ["--seeds", "2", "--quick"] if quick else []
    out = {"baseline": BASELINE, "rounds": rounds, "cpus": os.cpu_count()}
    with tempfile.TemporaryDirectory() as tmp:
        old_tree = _tree(Path(tmp) / "old")
        renders = Path(tmp) / "renders"
        main = {"before": [], "now": []}
        for _ in range(rounds):
            for side, tree in (("before", old_tree), ("now", ROOT)):
                main[side].append(_wall(["scenes/quickstart.py", *seeds, "-o", str(renders / side)], tree, renders))
                shutil.rmtree(renders, ignore_errors=True)
        out["main_job"] = {"command": "python scenes/quickstart.py" + (" --quick --seeds 2" if quick else ""),
                           "runs": main, "now_over_before": _ratios(main["now"], main["before"]),
                           "before_s": statistics.median(r["wall_s"] for r in main["before"]),
                           "now_s": statistics.median(r["wall_s"] for r in main["now"])}
        n = "3" if quick else "20"
        cmp = {"workers 1": [], "workers 2": [], "auto": []}
        for _ in range(rounds + 1):
            for label, extra in (("workers 1", ["--workers", "1"]), ("workers 2", ["--workers", "2"]),
                                 ("auto", [])):
                cmp[label].append(_wall(["-m", "asperity2d", "compare", "--seeds", n, "--json", *extra], ROOT,
                                        renders))
        out["compare"] = {"command": f"asperity2d compare --seeds {n}", "runs": cmp,
                          "w1_over_w2": _ratios(cmp["workers 1"], cmp["workers 2"]),
                          "w1_over_auto": _ratios(cmp["workers 1"], cmp["auto"]),
                          **{f"{k}_s": statistics.median(r["wall_s"] for r in v) for k, v in cmp.items()}}
    return out


def headline(res):
    m, c = res["main_job"], res["compare"]
    return [(f"main job ({m['command']}) wall, now / before (range "
             f"{m['now_over_before']['min']:.2f}-{m['now_over_before']['max']:.2f})", m["now_over_before"]["median"],
             "<= 0.6"),
            (f"{c['command']} wall, workers 1 / workers 2 (range {c['w1_over_w2']['min']:.2f}-"
             f"{c['w1_over_w2']['max']:.2f})", c["w1_over_w2"]["median"], ">= 1.7"),
            (f"{c['command']} wall, workers 1 / auto (the default)", c["w1_over_auto"]["median"], "stated")]


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    p.add_argument("--rounds", type=int)
    p.add_argument("--json", action="store_true")
    args = p.parse_args(argv)
    res = run(args.quick, args.rounds)
    if args.json:
        print(json.dumps(res))
        return 0
    for label, value, target in headline(res):
        print(f"{label:<100} {value:6.3f}  {target}")
    m, c = res["main_job"], res["compare"]
    print(f"main job: before {m['before_s']:.1f} s, now {m['now_s']:.1f} s; compare: workers 1 {c['workers 1_s']:.1f} s, "
          f"workers 2 {c['workers 2_s']:.1f} s, auto {c['auto_s']:.1f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
