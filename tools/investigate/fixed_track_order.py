"""Investigation (issue 25 item 1): order of convergence of the fixed-track force thresholds in
dt (dt, dt/2, dt/4) on the deterministic_dt seeds, and the regular surface against its law."""
import json, math, sys, warnings
from pathlib import Path
import numpy as np
import asperity2d as a
from asperity2d.critical import critical_force_bracket
from asperity2d.experiments.measures import quasi_static_breakaway
from asperity2d.run import default_dt
from asperity2d.studies.ooten import STUDY_SIZE, SETUPS

warnings.simplefilter("ignore")
OUT = Path("renders/measures/fixed_track_order.json")
data = json.loads(OUT.read_text()) if OUT.exists() else {}
seeds = [int(s) for s in np.random.SeedSequence(2025).generate_state(4, dtype=np.uint32)]
cases = [("regular", 0)] + [("random", s) for s in seeds]
for spacing, seed in cases:
    sc = a.make_scene(spacing=spacing, seed=seed, drive="force", **STUDY_SIZE, **SETUPS["fixed"])
    for f in (1.0, 0.5, 0.25, 0.125):
        key = f"{spacing}/{seed}/dt{f}"
        if key in data or (f == 0.125 and spacing != "regular"):
            continue
        dt = default_dt(sc) * f
        row = {k: critical_force_bracket(sc, start=k, dt=dt).value for k in ("rest", "run-up")}
        row["quasi_static"] = quasi_static_breakaway(sc, dt=dt).force
        data[key] = row
        print(key, {k: round(v * 1e3, 4) for k, v in row.items()}, flush=True)
        OUT.write_text(json.dumps(data))
n, k, d = 3, 37200.0, 0.125e-6
print("law mu_s", n * k * d * math.tan(math.radians(45) + math.atan(0.3)), "step law mu_k / 2",
      n * k * d * math.tan(math.radians(45) + math.atan(0.2)) / 2)
