"""Investigation (issue 25 item 1): the pass ensemble's stick forces at dt, dt/2, dt/4.
python tools/investigate/ensemble_dt.py SEED... ; appends to renders/measures/ensemble_dt.json"""
import dataclasses, json, sys, time
from pathlib import Path
import asperity2d as a
from asperity2d.experiments.measures import stick_forces
from asperity2d.run import default_dt
from asperity2d.studies.ooten import STUDY_SIZE

OUT = Path("renders/measures/ensemble_dt.json")
data = json.loads(OUT.read_text()) if OUT.exists() else {}
factors = (1.0, 0.5, 0.25)
for seed in [int(s) for s in sys.argv[1:]]:
    sc = a.make_scene(spacing="random", seed=seed, **STUDY_SIZE)
    for f in factors:
        key = f"{seed}/dt{f}"
        if key in data:
            continue
        t0 = time.process_time()
        sf = stick_forces(sc, dt=default_dt(sc) * f)
        data[key] = dataclasses.asdict(sf)
        print(key, round(time.process_time() - t0, 1), "peak", [round(p * 1e3, 2) for p in sf.peak],
              "mean", [round(p * 1e3, 2) for p in sf.mean], flush=True)
        OUT.write_text(json.dumps(data))
