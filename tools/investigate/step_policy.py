"""Investigation: the step policy of the stick-force measures, settled on hundreds of seeds with
the batched engine.

    python tools/investigate/step_policy.py run FIRST_SEED COUNT [--tracks fixed,free] [--chunk 16]
    python tools/investigate/step_policy.py table [--tracks fixed,free] [--store PATH]

``run``: Ooten's 10/3 scenes (``asperity2d.studies.ooten``: ``STUDY_SIZE``, both ``SETUPS``),
random spacing, seeds FIRST_SEED .. FIRST_SEED+COUNT-1, each scene's 3-pass ``stick_forces`` and
its critical forces from rest and with a run-up (``critical_force_brackets``) at dt, dt/2 and dt/4
(dt = ``default_dt``) on ``engine="batched"``. Seeds run in chunks of
``--chunk``; after each chunk the store (renders/measures/step_policy.json, key
"track/seed/factor") is rewritten atomically, so a stopped run keeps every finished chunk and
a rerun skips what is stored. The runs behind the findings page's table are kept in
docs/data/measures/step_policy_runs.json (``--store`` reads or extends it). A scene the engine refuses or that fails is stored with its
one-line reason and left out of the table (the table counts them).

``table``: per track and measure (first-breakaway: the nominal-speed pass, the measure's own
single pass; peak-stick and mean-stick: the 3-pass means, as the measures take them; critical and
critical-run-up: the critical force from rest and with a run-up), the shift of dt and dt/2 against dt/4:
the mean over seeds of the per-seed relative shift with its 95 % interval (t over seeds), the
ratio of the ensemble means with its 95 % bootstrap interval (seeds resampled, 2,000 draws, seed
0), and the two-sided Wilcoxon signed-rank p; written atomically to
docs/data/measures/step_policy.json and printed as the findings page's Markdown table. Same
store, same table, bit for bit.
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

import asperity2d as a
from asperity2d._io import atomic_write_text
from asperity2d.critical import critical_force_brackets
from asperity2d.experiments.measures import stick_forces_of
from asperity2d.run import default_dt
from asperity2d.studies.ooten import SETUPS, STUDY_SIZE

STORE = Path("renders/measures/step_policy.json")
TABLE = Path("docs/data/measures/step_policy.json")
FACTORS = (1.0, 0.5, 0.25)
#: The named measures' own ensemble (``measures.PASSES``): 3 passes at V (1 + 2e-4 (j - 1)). A
#: record of 5 passes (V (1 + 2e-4 (j - 2))) holds them as its middle three, and is read so.
#: Fewer passes buy more seeds at the same precision of the step shift: the surface's part of a
#: seed's value is the same at every step and cancels in its shift, the passes' part falls as
#: 1 / passes while the cost grows as passes.
PASSES = 3
ENGINE = "batched"


def _middle(values, k: int = PASSES) -> list:
    cut = (len(values) - k) // 2
    return list(values)[cut:cut + k]


#: measure name -> how its value is read from one scene's StickForces record
MEASURES = {
    "first-breakaway": lambda r: _middle(r["first_breakaway"], 1)[0],  # the nominal-speed pass
    "peak-stick": lambda r: _mean(_middle(r["peak"])),
    "mean-stick": lambda r: _mean(_middle(r["mean"])),
    "critical": lambda r: r.get("critical", {}).get("rest", math.nan),
    "critical-run-up": lambda r: r.get("critical", {}).get("run-up", math.nan),
}
#: The critical forces' starts, by the name of their measure.
STARTS = {"rest": "critical", "run-up": "critical-run-up"}


def _mean(values) -> float:
    v = [x for x in values if x is not None and math.isfinite(x)]
    return float(np.mean(v)) if v else math.nan


def scene(track: str, seed: int):
    return a.make_scene(spacing="random", seed=seed, **STUDY_SIZE, **SETUPS[track])


def _load() -> dict:
    return json.loads(STORE.read_text()) if STORE.exists() else {}


def _save(data: dict) -> None:
    STORE.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(STORE, json.dumps(data, indent=0, sort_keys=True))


def _critical(data: dict, track: str, seeds, f: float) -> None:
    """The critical forces of the stored seeds at dt x ``f`` that have none yet (stored beside
    their stick forces)."""
    todo = [s for s in seeds if "error" not in data[f"{track}/{s}/{f}"]
            and set(data[f"{track}/{s}/{f}"].get("critical", {})) != set(STARTS)]
    if not todo:
        return
    scenes = [scene(track, s) for s in todo]
    t0 = time.perf_counter()
    for start in STARTS:
        try:
            values = [b.value for b in critical_force_brackets(scenes, start=start, dt=f * default_dt(scenes[0]),
                                                               engine=ENGINE)]
        except (a.SceneError, a.SimulationError):  # one by one: who failed (stored as NaN, counted out)
            values = []
            for sc in scenes:
                try:
                    values.append(critical_force_brackets([sc], start=start, dt=f * default_dt(sc), engine=ENGINE)[0].value)
                except (a.SceneError, a.SimulationError):
                    values.append(math.nan)
        for s, v in zip(todo, values):
            data[f"{track}/{s}/{f}"].setdefault("critical", {})[start] = v
    _save(data)
    print(f"{track} seeds {todo[0]}-{todo[-1]} dt x {f}: critical forces {time.perf_counter() - t0:.1f} s wall",
          flush=True)


def run(first: int, count: int, tracks, chunk: int) -> None:
    data = _load()
    for track in tracks:
        for start in range(first, first + count, chunk):
            seeds = range(start, min(start + chunk, first + count))
            for f in FACTORS:
                todo = [s for s in seeds if f"{track}/{s}/{f}" not in data]
                if not todo:
                    continue
                scenes = [scene(track, s) for s in todo]
                t0, c0 = time.perf_counter(), time.process_time()
                try:
                    got = stick_forces_of(scenes, passes=PASSES, dt=f * default_dt(scenes[0]), engine=ENGINE)
                except (a.SceneError, a.SimulationError) as exc:  # the chunk again one by one: who failed
                    got = []
                    for sc in scenes:
                        try:
                            got.append(stick_forces_of([sc], passes=PASSES, dt=f * default_dt(sc), engine=ENGINE)[0])
                        except (a.SceneError, a.SimulationError) as one:
                            got.append(str(one).splitlines()[0])
                    del exc
                wall, cpu = time.perf_counter() - t0, time.process_time() - c0
                for s, r in zip(todo, got):
                    data[f"{track}/{s}/{f}"] = ({"error": r} if isinstance(r, str) else
                                                {**dataclasses.asdict(r), "wall_s": wall / len(todo),
                                                 "cpu_s": cpu / len(todo)})
                _save(data)
                print(f"{track} seeds {todo[0]}-{todo[-1]} dt x {f}: {wall:.1f} s wall, {cpu:.1f} s CPU",
                      flush=True)
            for f in FACTORS:
                _critical(data, track, seeds, f)


def _interval_t(x: np.ndarray) -> tuple[float, float, float]:
    from scipy import stats

    m = float(np.mean(x))
    se = float(np.std(x, ddof=1) / math.sqrt(len(x)))
    q = float(stats.t.ppf(0.975, len(x) - 1))
    return m, m - q * se, m + q * se


def _interval_ratio(x: np.ndarray, ref: np.ndarray) -> tuple[float, float, float]:
    rng = np.random.default_rng(0)
    idx = rng.integers(0, len(x), size=(2000, len(x)))
    boot = x[idx].mean(axis=1) / ref[idx].mean(axis=1) - 1.0
    lo, hi = np.percentile(boot, [2.5, 97.5])
    return float(x.mean() / ref.mean() - 1.0), float(lo), float(hi)


def table(tracks) -> dict:
    from scipy import stats

    data = _load()
    out = {"engine": ENGINE, "passes": PASSES, "factors": list(FACTORS), "scenes": "Ooten 10/3, random spacing",
           "rows": []}
    for track in tracks:
        seeds = sorted({int(k.split("/")[1]) for k in data if k.startswith(track + "/")})
        complete = [s for s in seeds if all(f"{track}/{s}/{f}" in data for f in FACTORS)]
        failed = [s for s in complete if any("error" in data[f"{track}/{s}/{f}"] for f in FACTORS)]
        ok = [s for s in complete if s not in failed]
        for name, read in MEASURES.items():
            vals = {f: np.array([read(data[f"{track}/{s}/{f}"]) for s in ok]) for f in FACTORS}
            finite = np.all([np.isfinite(v) for v in vals.values()], axis=0)
            ref = vals[0.25][finite]
            for f in FACTORS[:-1]:
                x = vals[f][finite]
                shift = x / ref - 1.0
                m, lo, hi = _interval_t(shift)
                r, rlo, rhi = _interval_ratio(x, ref)
                p = float(stats.wilcoxon(x, ref).pvalue) if np.any(x != ref) else 1.0
                out["rows"].append({"track": track, "measure": name, "factor": f, "seeds": int(finite.sum()),
                                    "seeds_failed": len(failed), "seed_range": [min(seeds), max(seeds)] if seeds else None,
                                    "shift_mean": m, "shift_ci95": [lo, hi],
                                    "ratio_of_means": r, "ratio_ci95": [rlo, rhi], "p_wilcoxon": p,
                                    "per_seed_sd": float(np.std(shift, ddof=1)),
                                    "mean_N_at_dt4": float(ref.mean())})
    TABLE.parent.mkdir(parents=True, exist_ok=True)
    atomic_write_text(TABLE, json.dumps(out, indent=1, sort_keys=True) + "\n")
    return out


def markdown(out: dict) -> str:
    lines = ["| track | measure | step | seeds | per-seed shift vs dt/4 (95 % CI) | ratio of means - 1 (95 % CI) | Wilcoxon p |",
             "|---|---|---|---|---|---|---|"]
    for r in out["rows"]:
        step = {1.0: "dt", 0.5: "dt/2"}[r["factor"]]
        lines.append(f"| {r['track']} | {r['measure']} | {step} | {r['seeds']} | "
                     f"{100 * r['shift_mean']:+.2f} % ({100 * r['shift_ci95'][0]:+.2f}, {100 * r['shift_ci95'][1]:+.2f}) | "
                     f"{100 * r['ratio_of_means']:+.2f} % ({100 * r['ratio_ci95'][0]:+.2f}, {100 * r['ratio_ci95'][1]:+.2f}) | "
                     f"{r['p_wilcoxon']:.2g} |")
    return "\n".join(lines)


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("what", choices=("run", "table"))
    p.add_argument("first", nargs="?", type=int)
    p.add_argument("count", nargs="?", type=int)
    p.add_argument("--tracks", default="fixed,free")
    p.add_argument("--chunk", type=int, default=16)
    p.add_argument("--store", default=str(STORE), help="the per-run store (default %(default)s)")
    args = p.parse_args()
    STORE = Path(args.store)
    tracks = args.tracks.split(",")
    if args.what == "run":
        if args.first is None or args.count is None:
            sys.exit("run needs FIRST_SEED COUNT")
        run(args.first, args.count, tracks, args.chunk)
    else:
        print(markdown(table(tracks)))
