"""Critical force and a 20-seed comparison, against the previous release's code, in one run.

    python benchmarks/bench_studies.py [--quick] [--json]

What a user of the previous code ran: ``critical_force(scene)`` and
``asperity2d compare --measure critical --seeds 20`` at the command line's
default size (16 lower / 4 upper asperities, regular vs random spacing). The
previous code is checked out from git (``BASELINE``, the last commit before
this round) into a temporary folder; both run the same scene in separate
interpreters, interleaved, and report CPU time (``time.process_time``) of the
measurement alone, one worker, each after the same warm-up (a critical force
of a 3/1 scene, so first-use imports are outside the clock on both sides). Like with like: the previous critical force
started from the builder's position (the run-up), so against it the new code is timed
with ``start="run-up"`` -- which is not the default. The default from rest, and either start
against a bare pymunk loop of its own runs, is ``bench_critical.py``; this script gives it the
critical force's code (``_CODE``: ``what`` = "critical-rest" / "critical").
The previous code settled a free slider again in every bisection run and
measured the seed-independent regular scene once per seed.

Both set-ups: the free slider (the previous default, where settling cost
57-59 % of a critical force) and Ooten's fixed track (the new default).
Target (issue 13): at least 2.5x faster.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BASELINE = "5c72af9"  # the previous round's last commit
TARGET = 2.5

_CODE = r"""
import json, sys, time
import asperity2d as a
setup, what, seeds, new = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4] == "new"
size = {"lower_count": 16, "upper_count": 4, "track": setup}
try:  # imports outside the clock (lazy now; the previous code had no experiments/ package)
    import asperity2d.experiments.compare, asperity2d.critical, asperity2d.run
except ImportError:
    import asperity2d.compare, asperity2d.critical, asperity2d.simulate
# Warm-up outside the clock, the same call on both sides: a critical force of a 3/1 scene (first-use
# imports such as tqdm.auto and first calls into pymunk are paid here, as timeit's warm-up would).
tiny = a.make_scene(drive="force", lower_count=3, upper_count=1, track=setup)
a.critical_force(tiny, start="run-up") if new else a.critical_force(tiny)
runs = []  # (internal force, steps) of each run of the new code, for the zero-overhead bound
if new and what in ("critical", "critical-rest"):
    from asperity2d.run import Run
    _advance = Run.advance
    def counted(self, duration, **kw):
        n0 = self.engine.step_count
        try:
            return _advance(self, duration, **kw)
        finally:
            runs.append((self.engine.drive.force, self.engine.step_count - n0))
    Run.advance = counted
t0 = time.process_time()
start = "rest" if what == "critical-rest" else "run-up"
if what in ("critical", "critical-rest"):
    scene = a.make_scene(drive="force", **size)
    value = a.critical_force(scene, start=start) if new else a.critical_force(scene)
else:
    variants = {"regular": {"spacing": "regular"}, "random": {"spacing": "random"}}
    base = {**size, "drive": "force"}
    if new:
        c = a.compare("critical-run-up", variants, range(seeds), base=base, progress=False, workers=1)
    else:
        from asperity2d.studies import critical_force_of
        c = a.compare(critical_force_of, variants, range(seeds), base=base, progress=False)
    value = sum(c.values["random"]) / seeds
cpu = time.process_time() - t0
out = {"cpu_s": cpu, "value": value}
if runs:
    # The same runs stepped by a bare public-API pymunk loop (force set, space.step; no switch,
    # projection, record or stops) from the same settled state, plus the settling steps: the CPU
    # time of a run loop with no overhead at all.
    from asperity2d.critical import settled_run
    base = settled_run(scene, start=start)
    bare = 0.0
    for force, n in runs + [(0.0, round(base.settle_time / base.dt))]:
        e = base.fork().engine
        space, body, load, dt = e.layout.space, e.layout.slider, e.load_internal, e.dt_internal
        t1 = time.process_time()
        for _ in range(n):
            body.force = (force, -load)
            space.step(dt)
        bare += time.process_time() - t1
    out.update(bare_cpu_s=bare, steps=sum(n for _, n in runs) + round(base.settle_time / base.dt))
print(json.dumps(out))
"""


def _baseline_tree(tmp: Path) -> Path:
    """The previous code, exported from git into ``tmp`` (no checkout of the working tree)."""
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", BASELINE, "asperity2d"],
                             capture_output=True, check=True).stdout
    subprocess.run(["tar", "-x", "-C", str(tmp)], input=archive, check=True)
    return tmp


def _measure(tree: Path | None, setup: str, what: str, seeds: int, new: bool, kernel: bool = True) -> dict:
    env = {**os.environ, "PYTHONPATH": str(tree if tree is not None else ROOT)}
    if not kernel:  # the engine's Python step loop instead of the C one (the numbers are the same)
        env["ASPERITY2D_KERNEL"] = "0"
    proc = subprocess.run([sys.executable, "-c", _CODE, setup, what, str(seeds), "new" if new else "old"],
                          capture_output=True, text=True, env=env, cwd=str(tree or ROOT), check=True)
    return json.loads(proc.stdout.strip().splitlines()[-1])


def run(quick: bool = False) -> dict:
    repeats = {"critical": 1 if quick else 7, "compare": 1 if quick else 3}  # critical: ~1 s a pair
    seeds = 3 if quick else 20
    rows = {}
    with tempfile.TemporaryDirectory() as tmp:
        old_tree = _baseline_tree(Path(tmp))
        for setup in ("free", "fixed"):
            for what in ("critical", "compare"):
                old, new = [], []
                for _ in range(repeats[what]):  # interleaved
                    old.append(_measure(old_tree, setup, what, seeds, new=False))
                    new.append(_measure(None, setup, what, seeds, new=True))
                o = statistics.median(r["cpu_s"] for r in old)
                n = statistics.median(r["cpu_s"] for r in new)
                rows[f"{setup}/{what}"] = {"old_cpu_s": o, "new_cpu_s": n, "speedup": o / n, "repeats": len(old),
                                           "old_value_N": old[0]["value"], "new_value_N": new[0]["value"]}
                if "bare_cpu_s" in new[0]:  # what a loop with no overhead at all could reach
                    b = statistics.median(r["bare_cpu_s"] for r in new)
                    rows[f"{setup}/{what}"].update(bare_cpu_s=b, steps=new[0]["steps"], zero_overhead_bound=o / b,
                                                   new_over_bare=n / b)
    return {"baseline": BASELINE, "seeds": seeds, "target": TARGET, "rows": rows}


def headline(res):
    out = []
    for key, r in res["rows"].items():
        setup, what = key.split("/")
        label = ("critical force" if what == "critical" else f"{res['seeds']}-seed compare, critical") + \
            f", {setup}, run-up (as the previous code measured; not the default): previous code / now (CPU)"
        out.append((label, r["speedup"], f">= {res['target']}"))
        if "zero_overhead_bound" in r:
            out.append((f"critical force, {setup}: previous code / a bare pymunk loop of the same runs (bound)",
                        r["zero_overhead_bound"], "stated"))
    return out


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="3 seeds, one repeat")
    p.add_argument("--json", action="store_true")
    args = p.parse_args(argv)
    out = run(quick=args.quick)
    if args.json:
        print(json.dumps(out))
        return 0
    for key, r in out["rows"].items():
        print(f"{key:16s} previous {r['old_cpu_s']:7.2f} s, now {r['new_cpu_s']:7.2f} s CPU: "
              f"{r['speedup']:5.2f}x (target >= {TARGET}); values {r['old_value_N'] * 1e3:.4g} / "
              f"{r['new_value_N'] * 1e3:.4g} mN")
        if "zero_overhead_bound" in r:
            print(f"{'':16s} the same {r['steps']} steps in a bare pymunk loop {r['bare_cpu_s']:.2f} s: "
                  f"a zero-overhead loop would be {r['zero_overhead_bound']:.2f}x the previous code; "
                  f"now {r['new_over_bare']:.2f}x the bare loop")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
