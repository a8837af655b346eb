"""Investigation: Ooten's figure-10 travel (0.9 x the half triangles' run-up critical force,
fixed track, mu_s > mu_k) at dt, dt/2, dt/4, dt/8 on seeds the studies never used.
python tools/investigate/travel_dt.py SEED... ; appends to renders/measures/travel_dt.json"""
import json, sys, time
from pathlib import Path

import asperity2d as a
from asperity2d.critical import critical_force
from asperity2d.experiments.measures import travel_under_force
from asperity2d.run import default_dt
from asperity2d.studies.ooten import SETUPS, STUDY_SIZE
from asperity2d.sweep.engine import map_calls

OUT = Path("renders/measures/travel_dt.json")
FACTORS = (1.0, 0.5, 0.25, 0.125)
PROFILES = {"full": {"profile": "full"}, "half": {"profile": "half", "min_gap": 0.5e-6}}


def scene(seed, profile):
    spacing = "regular" if seed == 0 else "random"
    return a.make_scene(spacing=spacing, seed=seed, drive="force", **STUDY_SIZE, **SETUPS["fixed"],
                        mu_static=0.3, mu_kinetic=0.2, **PROFILES[profile])


def one_seed(seed):
    t0 = time.process_time()
    force = 0.9 * critical_force(scene(seed, "half"), start="run-up")
    out = {"force_N": force, "critical_cpu_s": time.process_time() - t0}
    for profile in PROFILES:
        sc = scene(seed, profile)
        for f in FACTORS:
            t0 = time.process_time()
            travel, status = travel_under_force(sc, force=force, dt=f * default_dt(sc))
            out[f"{profile}/{f}"] = {"travel_m": travel, "status": status, "cpu_s": time.process_time() - t0}
    return out


if __name__ == "__main__":
    data = json.loads(OUT.read_text()) if OUT.exists() else {}
    seeds = [int(s) for s in sys.argv[1:] if str(int(s)) not in data]
    for seed, row in zip(seeds, map_calls(one_seed, [{"seed": s} for s in seeds], workers=1)):
        data[str(seed)] = row
        OUT.write_text(json.dumps(data, indent=1))
        print(seed, json.dumps(row), flush=True)
