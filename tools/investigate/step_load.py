"""Investigation (issue 25 item 5): the critical force from rest against the step-load law
n k delta tan(theta + phi) / 2 on the regular fixed track, over mu and damping."""
import json, math, warnings
from pathlib import Path
import asperity2d as a
from asperity2d.critical import critical_force_bracket
from asperity2d.studies.ooten import STUDY_SIZE
warnings.simplefilter("ignore")
out = {}
for zeta in (0.1, 0.0):
    for kind in ("mu", "mu_static"):
        for mu in (0.0, 0.1, 0.2, 0.3, 0.5):
            if kind == "mu_static" and mu == 0.0:
                continue
            sc = a.make_scene(drive="force", damping_ratio=zeta, **STUDY_SIZE, **{kind: mu})
            b = critical_force_bracket(sc)
            n, k, d = sc.slider.count, sc.lower.stiffness[0], sc.slider.interference
            law_s = n * k * d * math.tan(math.radians(45) + math.atan(sc.contact.mu_static)) / 2
            law_k = n * k * d * math.tan(math.radians(45) + math.atan(sc.contact.mu_kinetic)) / 2
            key = f"zeta={zeta} {kind}={mu}"
            out[key] = {"critical_N": b.value, "law_static_N": law_s, "law_kinetic_N": law_k, "band": b.band}
            print(key, f"F={b.value*1e3:.3f} mN  /law(mu_s)={b.value/law_s:.3f}  /law(mu_k)={b.value/law_k:.3f} band={b.band}", flush=True)
Path("renders/measures/step_load.json").write_text(json.dumps(out, indent=1))
