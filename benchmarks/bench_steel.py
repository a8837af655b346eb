"""Steel (seed 000 Table 1) scene: steps per second and wall time per micrometre of sliding.

Real time (5e-3 m/s) is estimated from a short run's step rate; accelerated
runs are timed end to end (drive factor 2000 and 1000, as scenes/steel_table1.py).

    python benchmarks/bench_steel.py [--quick]
"""

from __future__ import annotations

import importlib.util
import sys
import time
from pathlib import Path

from asperity2d import quasistatic as qs


def _scene():
    path = Path(__file__).resolve().parent.parent / "scenes" / "steel_table1.py"
    spec = importlib.util.spec_from_file_location("steel_table1", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod.build_scene()


def run(quick: bool = False) -> dict:
    scene = _scene()
    rows = {"real_time": qs.real_time_rate(scene, steps=5_000 if quick else 20_000)}
    for factor in ((2000.0,) if quick else (2000.0, 1000.0)):
        clock = time.perf_counter()
        out, result = qs.run_measures(qs.accelerated(scene, factor=factor))
        wall = time.perf_counter() - clock
        distance = float(result.x[-1] - result.x[0])
        rows[f"x{factor:g}"] = {"drive_velocity_m_per_s": factor * qs.SEED_DRIVE_VELOCITY,
                                "steps": out["steps"], "steps_per_s": out["steps"] / wall,
                                "wall_time_per_um_s": wall / (distance * 1e6), "wall_time_s": wall}
    return rows


def main(argv=None) -> int:
    quick = "--quick" in (argv if argv is not None else sys.argv[1:])
    rows = run(quick=quick)
    print(f"{'run':>10} {'v (m/s)':>9} {'steps/s':>9} {'wall s/µm':>11}")
    for name, r in rows.items():
        print(f"{name:>10} {r['drive_velocity_m_per_s']:>9.3g} {r['steps_per_s']:>9.0f} "
              f"{r['wall_time_per_um_s']:>11.4g}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
