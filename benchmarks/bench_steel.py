"""Steel (seed 000 Table 1) scene: cost per step of the run proper, and per micrometre of sliding.

    python benchmarks/bench_steel.py [--quick] [--json]

Only the stepping is timed (``Run.advance``, CPU time, median of repeats):
building the space and settling are done before the clock starts and no
analysis is included. A micrometre of drive travel at speed v takes
1e-6 / (v dt) steps, so the wall time per micrometre follows from the measured
cost per step for the real drive (5e-3 m/s, seed 000) and the sped-up one
(x2000, scenes/steel_table1.py). The run-loop-against-bare-pymunk ratio of the
same scene is in ``bench_core.py``.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import statistics
import time
from pathlib import Path

from asperity2d.experiments import quasistatic as qs
from asperity2d.run import Run


def _scene(**overrides):
    path = Path(__file__).resolve().parent.parent / "scenes" / "steel_table1.py"
    spec = importlib.util.spec_from_file_location("steel_table1", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod.build_scene(**overrides)


def _cpu_per_step(scene, steps: int, repeats: int) -> float:
    run = Run(scene)
    if scene.slider.track == "free":
        run.settle()
    run.advance(steps * run.dt)  # into contact: the timed runs step the engaged slider
    times = []
    for _ in range(repeats):
        fork = run.fork()
        t0 = time.process_time()
        fork.advance(steps * fork.dt)
        times.append(time.process_time() - t0)
    return statistics.median(times) / steps, run.dt


def run(quick: bool = False) -> dict:
    steps, repeats = (2_000, 3) if quick else (10_000, 5)
    rows = {}
    for setup in ("fixed", "free"):
        scene = qs.accelerated(_scene(track=setup), factor=2000.0)
        per_step, dt = _cpu_per_step(scene, steps, repeats)
        for label, velocity in (("x2000", 2000.0 * qs.SEED_DRIVE_VELOCITY), ("real time", qs.SEED_DRIVE_VELOCITY)):
            steps_per_um = 1e-6 / (velocity * dt)
            rows[f"{setup}/{label}"] = {"drive_velocity_m_per_s": velocity, "us_per_step": 1e6 * per_step,
                                        "steps_per_um": steps_per_um, "cpu_s_per_um": steps_per_um * per_step}
    return rows


def headline(res):
    return [(f"steel {key}: CPU s per um of sliding", r["cpu_s_per_um"], "") for key, r in res.items()] + \
        [(f"steel {key}: us per step (run proper)", r["us_per_step"], "") for key, r in res.items()
         if key.endswith("x2000")]


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    p.add_argument("--json", action="store_true")
    args = p.parse_args(argv)
    rows = run(quick=args.quick)
    if args.json:
        print(json.dumps(rows))
        return 0
    print(f"{'run':>16} {'v (m/s)':>9} {'us/step':>8} {'steps/um':>10} {'CPU s/um':>10}")
    for name, r in rows.items():
        print(f"{name:>16} {r['drive_velocity_m_per_s']:>9.3g} {r['us_per_step']:>8.1f} "
              f"{r['steps_per_um']:>10.3g} {r['cpu_s_per_um']:>10.4g}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
