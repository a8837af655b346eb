"""Investigation (issue 25 item 1): how the stick forces of one spring-driven pass move with
dt, with a perturbation of the drive speed at the 1e-4 level, with the sampling and with the
contact stick speed. Writes renders/measures/pass_sensitivity.json."""
import json, sys, time
from pathlib import Path
import numpy as np
import asperity2d as a
from asperity2d import analysis
from asperity2d.run import default_dt
from asperity2d.studies.ooten import STUDY_SIZE

OUT = Path("renders/measures/pass_sensitivity.json")
seeds = [int(s) for s in sys.argv[1:]] or [7301, 7302, 7303, 7304]
data = json.loads(OUT.read_text()) if OUT.exists() else {}

def one(scene, **kw):
    r = a.simulate(scene, progress=False, **kw)
    ev = analysis.stick_slip_events(r)
    return {"peaks_N": [e.force_peak for e in ev], "x_slip_m": [float(np.interp(e.t_slip, r.t, r.x)) for e in ev],
            "status": r.status}

for seed in seeds:
    base = dict(spacing="random", seed=seed, **STUDY_SIZE)
    for f in (1.0, 0.5, 0.25):
        for j in range(6):
            key = f"{seed}/dt{f}/eps{j}"
            if key in data:
                continue
            sc = a.make_scene(**base, drive_velocity=20.0 * (1 + 1e-4 * j))
            t0 = time.process_time()
            data[key] = one(sc, dt=default_dt(sc) * f)
            print(key, round(time.process_time() - t0, 1), [round(p * 1e3, 2) for p in data[key]["peaks_N"]], flush=True)
            OUT.write_text(json.dumps(data))
    sc = a.make_scene(**base)
    for key, kw, scene in ((f"{seed}/record1", {"record_every": 1}, sc),
                           (f"{seed}/stick_speed_x0.5", {}, a.make_scene(**base, stick_speed=0.5e-4 * sc.base * (37200 / 2.88e-16) ** 0.5)),
                           (f"{seed}/stick_speed_x2", {}, a.make_scene(**base, stick_speed=2e-4 * sc.base * (37200 / 2.88e-16) ** 0.5))):
        if key not in data:
            data[key] = one(scene, **kw)
            print(key, [round(p * 1e3, 2) for p in data[key]["peaks_N"]], flush=True)
            OUT.write_text(json.dumps(data))
