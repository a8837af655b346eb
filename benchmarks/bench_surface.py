"""Profile -> asperities -> scene at 100,000 points: reading, extracting, building the scene.

Issue 14's speed target: building a scene from a 100,000-point profile takes
well under a second. Measured here, in CPU time (``time.process_time``),
median of interleaved repeats:

* ``read``: ``read_profile`` of a 100,000-line two-column CSV (a self-affine
  trace, H = 0.8, written in micrometres with a header);
* ``extract``: ``find_asperities`` on it (summits, absorption, overlap rule,
  Table 1 stiffness and Appendix A masses), summits >= 1 % of the rms height;
* ``scene``: the whole ``make_scene(lower_surface="trace.csv", modulus=...,
  density=...)`` (read, detrend, extract, per-asperity shapes, validation);
* ``scene_many``: ``make_scene`` from a rougher 100,000-point profile held in
  memory (H = 0.5, summits >= 1 % of the rms height: ~1,900 asperities), the
  per-asperity parts' worst case here; and ``space``: building that scene's
  pymunk space (units, scale checks, one body per asperity), stated;
* ``cold``: ``make_scene`` from the file in a fresh Python process, with the
  interpreter start and the imports reported apart (``scipy.signal``, which
  pulls in ``scipy.stats``, costs ~0.7 s CPU here on its own): what a first
  ``make_scene(lower_surface="trace.csv")`` in a new process pays.

Targets: read + extract <= 0.25 s warm; a whole scene <= 0.25 s warm (both
profiles) and < 1 s as the first call of a fresh process; the start-up and
imports are stated beside it (no target: they are SciPy's, paid once per
process by anything that uses scipy.signal).

Run: ``python benchmarks/bench_surface.py [--quick]``.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from asperity2d import make_scene
from asperity2d.engine.space import build
from asperity2d.run import default_dt
from asperity2d.surface import find_asperities, read_profile, self_affine_profile
from asperity2d.units import Units, check_scales

POINTS = 100_000
CHILD = """
import time, sys
import scipy.signal  # what find_asperities imports on first use
from asperity2d import make_scene
start_and_imports = time.process_time()
scene = make_scene(lower_surface=sys.argv[1], min_prominence=float(sys.argv[2]), modulus=1.86e10,
                   density=7850.0)
print(start_and_imports, time.process_time() - start_and_imports, scene.lower.count)
"""
MATERIAL = dict(modulus=1.86e10, density=7850.0)


def _write_trace(path: Path) -> float:
    profile = self_affine_profile(n=POINTS, length=1e-3, rms_height=1e-6, hurst=0.8, seed=0)
    np.savetxt(path, np.column_stack([profile.x * 1e6, profile.z * 1e6]), fmt="%.6f",
               delimiter=",", header="unit: um\nx_um,z_um", comments="# ")
    return 0.01 * 1e-6  # min_prominence: 1 % of the rms height


def _space(scene) -> None:
    units = Units.for_scene(scene)
    check_scales(scene, units)
    build(scene, units, default_dt(scene) / units.time, iterations=20, friction=0.2)


def run(quick: bool = False) -> dict:
    repeats, cold_repeats = (3, 1) if quick else (7, 3)
    rough = self_affine_profile(n=POINTS, length=1e-4, rms_height=1e-7, hurst=0.5, seed=0)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "trace.csv"
        prominence = _write_trace(path)
        profile = read_profile(path, unit="um")
        find_asperities(profile, min_prominence=prominence, **MATERIAL)  # warm up
        many = make_scene(lower_surface=rough, min_prominence=1e-9, **MATERIAL)
        reads, extracts, scenes, scenes_many, spaces = [], [], [], [], []
        for _ in range(repeats):  # interleaved
            t0 = time.process_time()
            profile = read_profile(path, unit="um")
            t1 = time.process_time()
            found = find_asperities(profile, min_prominence=prominence, **MATERIAL)
            t2 = time.process_time()
            scene = make_scene(lower_surface=str(path), min_prominence=prominence, **MATERIAL)
            t3 = time.process_time()
            many = make_scene(lower_surface=rough, min_prominence=1e-9, **MATERIAL)
            t4 = time.process_time()
            _space(many)
            t5 = time.process_time()
            reads.append(t1 - t0)
            extracts.append(t2 - t1)
            scenes.append(t3 - t2)
            scenes_many.append(t4 - t3)
            spaces.append(t5 - t4)
        cold_imports, cold_work = [], []
        for _ in range(cold_repeats):
            out = subprocess.run([sys.executable, "-c", CHILD, str(path), repr(prominence)],
                                 capture_output=True, text=True, check=True)
            imports, work, _count = out.stdout.split()
            cold_imports.append(float(imports))
            cold_work.append(float(work))
    read_s, extract_s = statistics.median(reads), statistics.median(extracts)
    return {"points": POINTS, "asperities": found.count, "absorbed": found.absorbed,
            "trimmed": found.trimmed, "repeats": repeats, "read_s": read_s,
            "extract_s": extract_s, "warm_total_s": read_s + extract_s,
            "scene_s": statistics.median(scenes), "scene_asperities": scene.lower.count,
            "scene_many_s": statistics.median(scenes_many), "many_asperities": many.lower.count,
            "space_many_s": statistics.median(spaces),
            "cold_start_and_imports_s": statistics.median(cold_imports),
            "cold_work_s": statistics.median(cold_work),
            "cold_process_s": statistics.median(np.add(cold_imports, cold_work))}


def headline(res: dict):
    return [("surface: read + extract, 100k points, warm (s)", res["warm_total_s"], "<= 0.25"),
            ("surface: make_scene from a 100k-point file, warm (s)", res["scene_s"], "<= 0.25"),
            (f"surface: make_scene, 100k points, {res['many_asperities']} asperities, warm (s)",
             res["scene_many_s"], "<= 0.25"),
            (f"surface: its pymunk space, {res['many_asperities']} bodies (s)", res["space_many_s"],
             "stated"),
            ("surface: make_scene from the file, first call in a fresh process (s)",
             res["cold_work_s"], "< 1"),
            ("surface: that process's start + imports, scipy.signal included (s)",
             res["cold_start_and_imports_s"], "stated")]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats")
    res = run(quick=parser.parse_args(argv).quick)
    print(f"{res['points']} points -> {res['asperities']} asperities from find_asperities on the raw trace "
          f"({res['absorbed']} summits absorbed, {res['trimmed']} trimmed); CPU time, median of "
          f"{res['repeats']}")
    print(f"  read_profile     {1e3 * res['read_s']:8.1f} ms")
    print(f"  find_asperities  {1e3 * res['extract_s']:8.1f} ms")
    print(f"  make_scene (file, {res['scene_asperities']} asperities) {1e3 * res['scene_s']:8.1f} ms")
    print(f"  make_scene (profile, {res['many_asperities']} asperities) {1e3 * res['scene_many_s']:8.1f} ms,"
          f" its space {1e3 * res['space_many_s']:.1f} ms")
    print(f"  fresh process: start + imports {1e3 * res['cold_start_and_imports_s']:.0f} ms, "
          f"make_scene {1e3 * res['cold_work_s']:.0f} ms")
    for label, value, target in headline(res):
        print(f"{label}: {value:.3f} (target {target})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
