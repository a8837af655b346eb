"""The batched engine against the pymunk path: stick-force passes over seeds, memory, cost model.

    python benchmarks/bench_batched.py [--quick] [--json]

* **peak-stick**: ``stick_forces_of`` (3 passes per seed at the step policy's dt/2) of the default
  scene with random spacing on ``seeds`` seeds, on ``engine="batched"`` (every pass of every seed
  in one batch, the engine's threads on every core) and on ``engine="pymunk"`` for the first
  ``pymunk_seeds`` of them (one process; its CPU per scene-pass, times the passes, is what the
  pymunk path costs, which on P cores at perfect efficiency takes that over P of wall time). The
  ratio is that ideal pymunk wall time over the batched wall time, both on this machine in this
  run; the per-seed values of the seeds both ran are compared.
* **load**: the first call in this process (Numba loads the compiled loop from its cache; the
  first call after an install compiles it, a one-time cost stated separately by ``compile_s``
  when the cache was empty).
* **memory**: the arrays of one batch of 1,000 default scenes: its state and geometry, and its
  record for a full pass at dt/2 (the record dominates; :func:`asperity2d.engine.batched.run`
  splits a call into batches of at most ``CHUNK_BYTES``).
* **cost model**: CPU per scene-step while the slider crosses a regular surface, for batch sizes
  B and lower counts N, fitted as c(N) = a + b N (per scene-step, at the largest B).

CPU time is ``time.process_time`` (every thread of the process); wall time ``perf_counter``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import numpy as np  # noqa: E402

import asperity2d as a  # noqa: E402
from asperity2d.engine import batched  # noqa: E402
from asperity2d.experiments.measures import PASSES, STICK_DT_FRACTION, stick_forces_of  # noqa: E402
from asperity2d.run import default_dt, default_duration  # noqa: E402

TARGETS = {"peak_stick_ratio": 30.0, "memory_1000_MB": 1024.0}
SEED0 = 9401


def _timed(fn):
    w, c = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - w, time.process_time() - c


def _load() -> dict:
    cache = Path(batched.__file__).parent / "__pycache__"
    cold = not any(cache.glob("batched_kernel*.nbi")) if cache.exists() else True
    scene = a.make_scene(lower_count=4, upper_count=2)
    _, wall, _ = _timed(lambda: a.simulate(scene, 1e-9, engine="batched"))
    return {("compile_s" if cold else "load_s"): wall}


def _peak_stick(seeds: int, pymunk_seeds: int) -> dict:
    scenes = [a.make_scene(spacing="random", seed=SEED0 + s) for s in range(seeds)]
    got, b_wall, b_cpu = _timed(lambda: stick_forces_of(scenes, engine="batched"))
    ref, p_wall, p_cpu = _timed(lambda: stick_forces_of(scenes[:pymunk_seeds], engine="pymunk"))
    cores = os.cpu_count() or 1
    per_pass = p_cpu / (pymunk_seeds * PASSES)
    pymunk_ideal_wall = per_pass * seeds * PASSES / cores
    diffs = [abs(g.average("peak") / r.average("peak") - 1.0) for g, r in zip(got, ref)]
    return {"seeds": seeds, "passes": PASSES, "pymunk_seeds": pymunk_seeds, "cores": cores,
            "batched_wall_s": b_wall, "batched_cpu_s": b_cpu,
            "pymunk_cpu_per_scene_pass_s": per_pass, "pymunk_ideal_wall_s": pymunk_ideal_wall,
            "ratio_wall": pymunk_ideal_wall / b_wall,
            "ratio_cpu": per_pass * seeds * PASSES / b_cpu,
            "max_relative_difference_per_seed": max(diffs) if diffs else math.nan}


def _memory() -> dict:
    scene = a.make_scene()
    dt = STICK_DT_FRACTION * default_dt(scene)
    samples = int(default_duration(scene) / dt) // 10
    state = batched.Batch([scene] * 1000, [dt] * 1000, samples=1)
    arrays = [v for v in vars(state).values() if isinstance(v, np.ndarray)]
    state_bytes = sum(v.nbytes for v in arrays) - state.rec.nbytes
    record_bytes = 1000 * 9 * 8 * samples
    return {"scenes": 1000, "state_MB": state_bytes / 2**20, "record_MB_full_pass": record_bytes / 2**20,
            "samples_per_pass": samples, "chunk_MB": batched.CHUNK_BYTES / 2**20,
            "estimate_MB": batched.Batch.nbytes_for(1000, 16, 4, samples) / 2**20}


def _cost(quick: bool) -> dict:
    rows = []
    sizes = (1, 8) if quick else (1, 8, 64)
    counts = (8, 16) if quick else (8, 16, 32, 64)
    steps = 2000 if quick else 10000
    for n in counts:
        scene = a.make_scene(lower_count=n, upper_count=4, track="fixed")
        dt = default_dt(scene)
        for B in sizes:
            batch = batched.Batch([scene] * B, [dt] * B, samples=steps // 10 + 1)
            batch.advance([int(0.3e-6 / dt)] * B)  # the slider onto the surface first
            _, wall, cpu = _timed(lambda: batch.advance([steps] * B))
            rows.append({"N": n, "B": B, "cpu_us_per_scene_step": cpu / (B * steps) * 1e6,
                         "wall_us_per_scene_step": wall / (B * steps) * 1e6})
    big = [r for r in rows if r["B"] == max(sizes)]
    b, a0 = np.polyfit([r["N"] for r in big], [r["cpu_us_per_scene_step"] for r in big], 1)
    return {"rows": rows, "fit_cpu_us": {"a": float(a0), "b_per_N": float(b)}}


def run(quick: bool = False) -> dict:
    out = {"load": _load()}
    out["peak_stick"] = _peak_stick(8 if quick else 64, 1 if quick else 2)
    out["memory"] = _memory()
    out["cost"] = _cost(quick)
    out["targets"] = TARGETS
    return out


def headline(res: dict) -> list[tuple[str, float, str]]:
    p, m = res["peak_stick"], res["memory"]
    return [(f"batched / pymunk, {p['seeds']} seeds x {p['passes']} peak-stick passes (wall, {p['cores']} cores)",
             p["ratio_wall"], ">= 30"),
            ("batched: largest per-seed peak-stick difference to pymunk", p["max_relative_difference_per_seed"], "< 0.01"),
            ("batched: 1,000 scenes' state (MB)", m["state_MB"], "< 1024"),
            ("batched: 1,000 scenes' state + full-pass record (MB)", m["state_MB"] + m["record_MB_full_pass"], "< 1024")]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    res = run(args.quick)
    if args.json:
        print(json.dumps(res, indent=1))
    else:
        for name, value, target in headline(res):
            print(f"{name:80s} {value:10.4g}  target {target}")
        print(json.dumps(res, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
