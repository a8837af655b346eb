"""Core simulator benchmarks: recording overhead and scaling in N.

    python benchmarks/bench_core.py [--quick]

For N = 10, 100, 1000 lower asperities (slider with N/4 tips, spring drive,
static > kinetic friction) it times, side by side and interleaved, medians
of several repeats of:

* ``space``: a raw ``space.step`` loop on the same pymunk space (no drive, no
  friction switching, no track projection: not the same physics, a floor);
* ``engine``: the engine's own step (drive force, stick/slip switching,
  track projection) with no recording;
* ``simulate``: the run loop recording every 10th step.

``simulate / engine`` is the recording overhead (target >= 0.9);
``engine / space`` is what the per-step physics done in Python costs.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time

import asperity2d as a
from asperity2d.engine import Engine
from asperity2d.simulate import _Recorder


def _scene(n: int):
    return a.make_scene(lower_count=n, upper_count=max(1, n // 4))


def _engine(scene):
    dt = scene.shortest_period() / 50
    engine = Engine(scene, dt)
    engine.settle(10 * scene.slowest_period() / engine.units.time)
    return engine, dt


def _time_space(scene, steps):
    engine, _ = _engine(scene)
    space, dt = engine.space, engine.dt
    t0 = time.perf_counter()
    for _ in range(steps):
        space.step(dt)
    return time.perf_counter() - t0


def _time_engine(scene, steps):
    engine, _ = _engine(scene)
    t0 = time.perf_counter()
    engine.step(steps)
    return time.perf_counter() - t0


def _time_simulate(scene, steps):
    engine, dt = _engine(scene)
    recorder = _Recorder(engine, steps * dt, dt, 10)
    t0 = time.perf_counter()
    recorder.run([], progress=False, meta={})
    return time.perf_counter() - t0


def run(quick: bool = False) -> dict:
    sizes = (10, 100) if quick else (10, 100, 1000)
    repeats = 3 if quick else 5
    rows = []
    for n in sizes:
        scene = _scene(n)
        steps = 2000 if n >= 1000 else 4000
        if quick:
            steps //= 4
        times = {"space": [], "engine": [], "simulate": []}
        for _ in range(repeats):  # interleaved so drifts in machine load hit all three
            times["space"].append(_time_space(scene, steps))
            times["engine"].append(_time_engine(scene, steps))
            times["simulate"].append(_time_simulate(scene, steps))
        med = {k: statistics.median(v) for k, v in times.items()}
        rows.append({
            "N": n, "steps": steps,
            "space_steps_per_s": steps / med["space"],
            "engine_steps_per_s": steps / med["engine"],
            "simulate_steps_per_s": steps / med["simulate"],
            "recording_ratio": med["engine"] / med["simulate"],
            "engine_vs_space_ratio": med["space"] / med["engine"],
            "us_per_asperity_step": 1e6 * med["simulate"] / steps / n,
        })
    first, last = rows[0], rows[-1]
    growth = (last["N"] / first["N"]) / (first["simulate_steps_per_s"] / last["simulate_steps_per_s"])
    return {"rows": rows, "linear_scaling_margin": growth}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    p.add_argument("--json", action="store_true")
    args = p.parse_args(argv)
    out = run(args.quick)
    if args.json:
        print(json.dumps(out))
        return 0
    print(f"{'N':>5} {'space st/s':>11} {'engine st/s':>12} {'simulate st/s':>14} "
          f"{'sim/engine':>10} {'engine/space':>12} {'us/asp-step':>11}")
    for r in out["rows"]:
        print(f"{r['N']:>5} {r['space_steps_per_s']:>11.0f} {r['engine_steps_per_s']:>12.0f} "
              f"{r['simulate_steps_per_s']:>14.0f} {r['recording_ratio']:>10.3f} "
              f"{r['engine_vs_space_ratio']:>12.3f} {r['us_per_asperity_step']:>11.3f}")
    print(f"cost grew {1 / out['linear_scaling_margin']:.3f} x as fast as N "
          "(<= 1 means no worse than linear)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
