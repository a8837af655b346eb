"""The run loop against a bare pymunk loop of the same scene with the same drive.

    python benchmarks/bench_core.py [--quick] [--json]

What a user would otherwise write is a hand-written pymunk loop: read the
slider's position and velocity, set the spring-drive force, ``space.step``.
For N = 10, 100, 1000 lower asperities (slider with max(3, N/25) tips, seed
000's fixed-track set-up, spring drive, static > kinetic friction) both loops
start from the same state, forked from one run with the slider engaged on the
surface, and step the same number of steps:

* ``bare``: that hand-written loop on a copy of the space (the same physics
  minus our stick/slip switch and track projection);
* ``run``: :meth:`asperity2d.run.Run.advance` recording every 10th step
  (what :func:`asperity2d.simulate` does).

CPU time (``time.process_time``), interleaved repeats; the ratio ``run / bare`` of each
interleaved pair, its median (the headline; targets: <= 2 at N = 10, <= 1.5 at N = 100 and
1000) and range. The steel scene is measured the same way, per step of the run proper (no
build or settling), in both set-ups exactly as ``scenes/steel_table1.py`` builds them
(``build_scene(setup=...)``: the fixed track with 24 lower / 4 upper asperities, the free
slider with 8 / 4 under 4 mN; Table 1 steel, drive sped up x2000).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import statistics
import time
from pathlib import Path

import asperity2d as a
from asperity2d.run import Run

TARGETS = {10: 2.0, 100: 1.5, 1000: 1.5, "steel": 2.0}


def engaged_run(scene) -> Run:
    """A run of ``scene`` advanced until every slider tip is over the lower surface."""
    run = Run(scene, max_steps=10**8)  # N = 1000: the run-up is 2.3e5 steps of 52 step-equivalents each
    if scene.slider.track == "free":
        run.settle()
    span = scene.slider.tips()[-1] + 2 * scene.base
    run.advance(span / scene.drive.velocity, record_every=1000)
    return run


def _bare(run: Run, steps: int) -> float:
    """CPU seconds of a hand-written pymunk loop with the same spring drive, from ``run``'s state."""
    engine = run.fork().engine
    space, body = engine.layout.space, engine.layout.slider  # the benchmark reaches into the adapter
    d, dt, load, s0 = engine.drive, engine.dt_internal, engine.load_internal, engine.step_count
    k, c, v, origin = d.k, d.c, d.v, d.origin
    t0 = time.process_time()
    for i in range(steps):
        vx = body.velocity.x
        x_end = body.position.x + vx * dt
        body.force = (k * (origin + v * (s0 + i + 1) * dt - x_end) + c * (v - vx), -load)
        space.step(dt)
    return time.process_time() - t0


def _run_loop(run: Run, steps: int) -> float:
    fork = run.fork()
    t0 = time.process_time()
    fork.advance(steps * fork.dt, record_every=10)
    return time.process_time() - t0


def compare(run: Run, steps: int, repeats: int) -> dict:
    bare, loop = [], []
    for _ in range(repeats):  # interleaved, so load changes hit both
        bare.append(_bare(run, steps))
        loop.append(_run_loop(run, steps))
    b, r = statistics.median(bare), statistics.median(loop)
    pairs = [x / y for x, y in zip(loop, bare)]
    return {"steps": steps, "bare_us_per_step": 1e6 * b / steps, "run_us_per_step": 1e6 * r / steps,
            "ratio": statistics.median(pairs), "ratio_min": min(pairs), "ratio_max": max(pairs),
            "repeats": repeats}


def steel_scene(setup: str):
    """``scenes/steel_table1.py``'s ``build_scene(setup=setup)``, exactly as the script runs it."""
    path = Path(__file__).resolve().parent.parent / "scenes" / "steel_table1.py"
    spec = importlib.util.spec_from_file_location("steel_table1", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod.build_scene(setup=setup)


def run(quick: bool = False) -> dict:
    sizes = (10, 100) if quick else (10, 100, 1000)
    repeats = 3 if quick else 7
    rows = []
    for n in sizes:
        scene = a.make_scene(lower_count=n, upper_count=max(3, n // 25), track="fixed")
        steps = {10: 6000, 100: 3000, 1000: 600}[n] // (3 if quick else 1)
        row = compare(engaged_run(scene), steps, repeats)
        row.update(N=n, upper=scene.slider.count, target=TARGETS[n])
        rows.append(row)
    steel = {}
    for setup in ("fixed", "free"):
        scene = steel_scene(setup)
        row = compare(engaged_run(scene), 4000 // (3 if quick else 1), repeats)
        row.update(N=f"scenes/steel_table1.py {setup} set-up ({scene.lower.count}/{scene.slider.count}, x2000)",
                   target=TARGETS["steel"])
        steel[setup] = row
    return {"rows": rows, "steel": steel}


def headline(res):
    out = [(f"run loop / bare pymunk + drive, make_scene(lower_count={r['N']}, upper_count={r['upper']}) "
            f"(range {r['ratio_min']:.2f}-{r['ratio_max']:.2f})", r["ratio"], f"<= {r['target']}")
           for r in res["rows"]]
    for s in res["steel"].values():
        out.append((f"run loop / bare pymunk + drive, {s['N']} (range {s['ratio_min']:.2f}-{s['ratio_max']:.2f})",
                    s["ratio"], f"<= {s['target']}"))
        out.append((f"{s['N']}: run loop, us per step", s["run_us_per_step"], "stated"))
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
    for label, value, target in headline(out):
        print(f"{label:<58} {value:8.3f}  {target}")
    for r in out["rows"] + list(out["steel"].values()):
        print(f"  N={r['N']}: bare {r['bare_us_per_step']:.1f} us/step, run {r['run_us_per_step']:.1f} us/step")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
