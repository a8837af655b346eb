"""Investigation (issue 25 item 1): the deterministic measures at dt and dt/2 on rule-picked
random seeds (SeedSequence(ENTROPY)), fixed track and free slider, 10/3. Appends to
renders/measures/deterministic_dt.json."""
import json, sys, time, warnings
from pathlib import Path
import numpy as np
import asperity2d as a
from asperity2d.critical import critical_force_bracket
from asperity2d.experiments.measures import quasi_static_breakaway, travel_under_force, stick_forces
from asperity2d.run import default_dt
from asperity2d.studies.ooten import STUDY_SIZE, SETUPS

warnings.simplefilter("ignore")
OUT = Path("renders/measures/deterministic_dt.json")
data = json.loads(OUT.read_text()) if OUT.exists() else {}
entropy, n = int(sys.argv[1]), int(sys.argv[2])
seeds = [int(s) for s in np.random.SeedSequence(entropy).generate_state(n, dtype=np.uint32)]
for setup in ("fixed", "free"):
    for seed in seeds:
        sc = a.make_scene(spacing="random", seed=seed, drive="force", **STUDY_SIZE, **SETUPS[setup])
        for f in (1.0, 0.5):
            key = f"{setup}/{seed}/dt{f}"
            if key in data:
                continue
            dt = default_dt(sc) * f
            t0 = time.process_time()
            row = {}
            for start in ("rest", "run-up"):
                b = critical_force_bracket(sc, start=start, dt=dt)
                row[f"critical_{start}"] = b.value
                row[f"band_{start}"] = b.band
                row[f"runs_{start}"] = b.runs
            q = quasi_static_breakaway(sc, dt=dt)
            row["quasi_static"], row["quasi_static_change"] = q.force, q.rate_change
            force = 0.9 * data.get(f"{setup}/{seed}/dt1.0", row)["critical_run-up"]  # the same force at both dt
            travel, status = travel_under_force(sc, force=force, dt=dt)
            row["travel_force"], row["travel_0.9"], row["travel_status"] = force, travel, status
            sf = stick_forces(sc, passes=1, dt=dt)
            row["first_breakaway"] = sf.first_breakaway[0]
            row["cpu_s"] = time.process_time() - t0
            data[key] = row
            print(key, {k: (round(v * 1e3, 4) if isinstance(v, float) and k not in ("travel_0.9",) else v) for k, v in row.items()}, flush=True)
            OUT.write_text(json.dumps(data))
