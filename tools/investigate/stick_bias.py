"""Investigation: the 5-pass stick forces at dt, dt/2, dt/4 on seeds the studies never used
(Ooten's 10/3 scenes, random spacing), to measure their step bias and their per-pass spread.
python tools/investigate/stick_bias.py SETUP FIRST_SEED COUNT [WORKERS] ; appends to
renders/measures/stick_bias.json (key "setup/seed/factor") as each run finishes, so a stopped
run keeps what it measured. SETUP "fixed-regular" / "free-regular": the regular surface (one
scene, whatever the seed: python tools/investigate/stick_bias.py fixed-regular 0 1)."""
import dataclasses, json, sys, time
from pathlib import Path

import asperity2d as a
from asperity2d.experiments.measures import stick_forces
from asperity2d.run import default_dt
from asperity2d.studies.ooten import SETUPS, STUDY_SIZE
from asperity2d.sweep.engine import run_calls

OUT = Path("renders/measures/stick_bias.json")
FACTORS = (1.0, 0.5, 0.25)
PASSES = 5


def one(setup, seed, factor):
    base, _, spacing = setup.partition("-")
    scene = a.make_scene(spacing=spacing or "random", seed=seed, **STUDY_SIZE, **SETUPS[base])
    t0 = time.process_time()
    sf = stick_forces(scene, passes=PASSES, dt=factor * default_dt(scene))
    return {**dataclasses.asdict(sf), "cpu_s": time.process_time() - t0}


if __name__ == "__main__":
    setup, first, count = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    workers = int(sys.argv[4]) if len(sys.argv) > 4 else 1
    data = json.loads(OUT.read_text()) if OUT.exists() else {}
    calls = [(setup, seed, f) for seed in range(first, first + count) for f in FACTORS
             if f"{setup}/{seed}/{f}" not in data]
    for outcome in run_calls(one, calls, workers=workers, cost=30.0):
        key = "/".join(map(str, calls[outcome.index]))
        if not outcome.ok:
            print(key, "failed", outcome.error, flush=True)
            continue
        data = json.loads(OUT.read_text()) if OUT.exists() else {}
        data[key] = outcome.value
        OUT.write_text(json.dumps(data, indent=1))
        print(key, round(outcome.value["cpu_s"], 1), outcome.value["events"], flush=True)
