"""A run of 1e8 steps in bounded memory: the steel scene at Ooten's real drive speed, streamed.

    python benchmarks/bench_long_run.py [--quick] [--steps N] [--json]

The scene is ``scenes/steel_table1.py``'s free set-up exactly as that script builds it
(``build_scene(setup="free")``: Table 1 steel, 8 lower / 4 upper asperities, the slider under
4 mN, the 3,720 N/m drive spring) with the drive at Ooten's own 5e-3 m/s instead of the
script's x2000 (1.8e7 steps per micrometre of drive travel). It runs
``simulate(scene, duration=N dt, record_every=100, record_to=DIR, max_steps=...)`` in a fresh
process, so the resident memory measured is the run's alone:

* RSS (``/proc/self/statm``) sampled by an observer along the run, and the peak
  (``VmHWM``) at the end: a flat line means memory does not grow with the run;
* wall and CPU time of the whole run (settling included), CPU per step and per micrometre of
  drive travel, measured, not extrapolated;
* what the record holds: samples, bytes on disk, stick-slip events (read back lazily).

The machine is shared: CPU time is the figure to trust; wall time says what a user waited.
``--quick`` runs 1e6 steps.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RECORD_EVERY = 100


def _scene():
    spec = importlib.util.spec_from_file_location("steel_table1", ROOT / "scenes" / "steel_table1.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    from asperity2d.experiments.quasistatic import SEED_DRIVE_VELOCITY

    return mod.build_scene(setup="free", drive_velocity=SEED_DRIVE_VELOCITY)


def _rss() -> int:
    with open("/proc/self/statm") as fh:
        return int(fh.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def child(steps: int, directory: str) -> dict:
    import asperity2d as a
    from asperity2d.run import default_dt

    scene = _scene()
    dt = default_dt(scene)
    trace = []  # (samples, rss bytes) every 1 % of the run
    every = max(1, steps // RECORD_EVERY // 100)
    count = [0]

    def watch(probe):
        if count[0] % every == 0:
            trace.append((count[0], _rss()))
        count[0] += 1

    rss_start = _rss()
    wall, cpu = time.perf_counter(), time.process_time()
    result = a.simulate(scene, (steps - 0.5) * dt, record_every=RECORD_EVERY, record_to=directory,
                        max_steps=2 * steps, observers=[watch], progress=False)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    # VmHWM, the process's own peak (ru_maxrss carries over execve from whoever spawned it)
    peak = 1024 * int(next(line.split()[1] for line in open("/proc/self/status") if line.startswith("VmHWM:")))
    events = a.stick_slip_events(result)
    travel = float(result.drive_x[-1] - result.drive_x[0])
    disk = sum(f.stat().st_size for f in Path(directory).iterdir())
    rss = [r for _, r in trace]
    return {
        "scene": "scenes/steel_table1.py build_scene(setup='free'), drive 5e-3 m/s (Ooten's thesis, real time)",
        "steps": result.meta["steps"], "settle_time_s": result.meta["settle_time"], "dt_s": dt,
        "record_every": RECORD_EVERY, "samples": len(result), "bytes_on_disk": disk,
        "status": result.status, "wall_s": wall, "cpu_s": cpu, "us_per_step_cpu": 1e6 * cpu / steps,
        "drive_travel_m": travel, "cpu_s_per_um_of_drive": cpu / (travel * 1e6),
        "stick_slip_events": len(events),
        "rss_at_start_MB": rss_start / 1e6, "rss_along_run_MB": [r / 1e6 for r in rss],
        "rss_at_10pc_MB": rss[len(rss) // 10] / 1e6, "rss_last_MB": rss[-1] / 1e6,
        # the first block (4 MB at most) is touched as it fills; after that nothing grows
        "rss_growth_10_to_100pc_MB": (rss[-1] - rss[len(rss) // 10]) / 1e6, "peak_rss_MB": peak / 1e6,
        "in_memory_record_would_be_MB": len(result) * (88 + 17 * scene.lower.count) / 1e6,
    }


def run(quick: bool = False, steps: int | None = None) -> dict:
    steps = steps or (1_000_000 if quick else 100_000_000)
    directory = tempfile.mkdtemp(prefix="asperity2d-long-")
    try:
        load = os.getloadavg()
        out = subprocess.run([sys.executable, __file__, "--child", str(steps), directory],
                             capture_output=True, text=True, check=True)
        res = json.loads(out.stdout.strip().splitlines()[-1])
        res["load_average_before"], res["load_average_after"] = load, os.getloadavg()
        return res
    finally:
        shutil.rmtree(directory, ignore_errors=True)


def headline(res):
    return [(f"{res['steps']:.3g}-step run streamed (steel, real drive speed): peak RSS (MB)", res["peak_rss_MB"],
             "bounded"),
            ("... RSS growth from 10 % to 100 % of the run (MB)", res["rss_growth_10_to_100pc_MB"], "~0"),
            ("... wall time (h)", res["wall_s"] / 3600, "stated"),
            ("... CPU s per um of drive travel at 5e-3 m/s, measured", res["cpu_s_per_um_of_drive"], "stated")]


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    p.add_argument("--steps", type=int)
    p.add_argument("--json", action="store_true")
    p.add_argument("--child", nargs=2, help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.child:
        sys.path.insert(0, str(ROOT))
        print(json.dumps(child(int(args.child[0]), args.child[1])))
        return 0
    res = run(args.quick, args.steps)
    if args.json:
        print(json.dumps(res))
        return 0
    for label, value, target in headline(res):
        print(f"{label:<78} {value:10.4g}  {target}")
    print(f"  {res['samples']} samples, {res['bytes_on_disk'] / 1e6:.1f} MB on disk, "
          f"{res['stick_slip_events']} stick-slip events, drive travel {res['drive_travel_m'] * 1e6:.2f} um")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
