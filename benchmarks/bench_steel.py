"""Steel (Ooten's thesis Table 1) scene: CPU time per micrometre of drive travel, measured.

    python benchmarks/bench_steel.py [--quick] [--json]

Both set-ups exactly as ``scenes/steel_table1.py`` runs them (``build_scene(setup=...)``:
the fixed track with 24 lower / 4 upper asperities, the free slider with 8 / 4 under 4 mN;
the drive at x2000 of Ooten's 5e-3 m/s). Only the stepping is timed (``Run.advance``, CPU
time): the space is built, settled and driven into contact before the clock starts; then a
fork of that run is advanced until the drive's far end has moved one whole micrometre (9,044
steps), three times, median and range. Nothing is extrapolated: the seed's real drive speed
(1.8e7 steps per micrometre) is measured by ``bench_long_run.py`` (1e8 steps of the free
set-up); the fixed set-up at real speed has not been measured and has no row.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import statistics
import time
from pathlib import Path

from asperity2d.run import Run


def _scene(setup: str):
    path = Path(__file__).resolve().parent.parent / "scenes" / "steel_table1.py"
    spec = importlib.util.spec_from_file_location("steel_table1", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod.build_scene(setup=setup)


def _cpu_per_um(scene, travel: float, repeats: int) -> dict:
    run = Run(scene)
    if scene.slider.track == "free":
        run.settle()
    run.advance(2 * scene.base / scene.drive.velocity)  # into contact: the timed runs step the engaged slider
    duration = travel / scene.drive.velocity
    times = []
    for _ in range(repeats):
        fork = run.fork()
        t0 = time.process_time()
        fork.advance(duration)
        times.append(time.process_time() - t0)
    steps = fork.engine.step_count - run.engine.step_count
    per_um = [t / (travel * 1e6) for t in times]
    return {"drive_velocity_m_per_s": scene.drive.velocity, "travel_m": travel, "steps": steps,
            "us_per_step": 1e6 * statistics.median(times) / steps, "cpu_s_per_um": statistics.median(per_um),
            "cpu_s_per_um_min": min(per_um), "cpu_s_per_um_max": max(per_um), "repeats": repeats}


def run(quick: bool = False) -> dict:
    travel, repeats = (0.25e-6, 1) if quick else (1e-6, 3)
    rows = {}
    for setup in ("fixed", "free"):
        scene = _scene(setup)
        rows[f"{setup} ({scene.lower.count}/{scene.slider.count}, x2000)"] = _cpu_per_um(scene, travel, repeats)
    return rows


def headline(res):
    return [(f"scenes/steel_table1.py {key}: CPU s per um of drive travel, measured over "
             f"{r['travel_m'] * 1e6:g} um (range {r['cpu_s_per_um_min']:.3g}-{r['cpu_s_per_um_max']:.3g})",
             r["cpu_s_per_um"], "stated") for key, r in res.items() if isinstance(r, dict) and "cpu_s_per_um" in r]


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    p.add_argument("--json", action="store_true")
    args = p.parse_args(argv)
    rows = run(quick=args.quick)
    if args.json:
        print(json.dumps(rows))
        return 0
    print(f"{'set-up':>24} {'v (m/s)':>9} {'us/step':>8} {'steps':>8} {'CPU s/um':>10}")
    for name, r in rows.items():
        print(f"{name:>24} {r['drive_velocity_m_per_s']:>9.3g} {r['us_per_step']:>8.1f} "
              f"{r['steps']:>8d} {r['cpu_s_per_um']:>10.4g}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
