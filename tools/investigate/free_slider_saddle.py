"""Investigation: why a free slider on a random surface passes below the kinetic flank law.

The free slider (``track="free"``, the main job's 16/4 set-up under 10 mN) is pushed from rest at
its critical force. For each seed this script records, at the settled start, every contact
(which lower asperity, which upper tip, front or back flank, its vertical force and the lower
spring's compression, how far the tip is from the apex it must pass) and compares the measured
critical force with a quasi-static energy estimate built from that geometry alone:

    the slider's height is set by the lower springs carrying L between them; moving it on by s
    presses each front-flank asperity down by s and lets each back-flank asperity up by s, so
    the load passes from the back contacts to the front ones while the slider hardly rises; a
    front contact resists with tan(45 deg + atan mu_k) times its vertical force, a back contact
    pushes on with tan(45 deg - atan mu_k) times its own. A constant force F from rest carries
    the slider over the first apex when its work F s is never less than the resisting work
    integral_0^s R, so F_c = max_s (1/s) integral_0^s R(s') ds'.

With one contact (a regular surface) R = L tan(45 deg + atan mu_k) throughout: the flank law.

python tools/investigate/free_slider_saddle.py [--size 16/4] SEED... ; prints one line per seed
and adds it to renders/measures/free_slider_saddle.json (seed -1: the regular surface); copied to
docs/data/measures/ for the findings page. ``--summary [FILE]`` prints the numbers the page quotes;
``--figure [SIZE/SEED ...]`` draws R(s) and its running mean against the measured force.
Measured: ``--size 16/4 -1 7636 0..7 7601..7624`` and ``--size 10/3 -1 0..23``.
"""
from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

import asperity2d as a
from asperity2d.critical import critical_force_bracket, measure_dt, passes, settled_run

OUT = Path("renders/measures/free_slider_saddle.json")


def scene_of(seed: int, size: str = "16/4"):
    lower, upper = (int(n) for n in size.split("/"))
    spacing = "regular" if seed < 0 else "random"
    return a.make_scene(track="free", spacing=spacing, seed=max(seed, 0), lower_count=lower,
                        upper_count=upper, drive="force")


def rest_contacts(scene) -> tuple[object, list[dict]]:
    """The settled run from rest and its contacts: lower index, upper tip, flank, forces (N),
    the lower spring's compression (m) and the tip's horizontal distance to that apex (m)."""
    run = settled_run(scene, start="rest", dt=measure_dt(scene, "rest"))
    e = run.engine
    u = e.units
    force = u.mass * u.length / u.time ** 2
    x = e.slider_state()[0]
    apex = np.asarray(scene.lower.tips(), dtype=float)
    tips = x + np.asarray(scene.slider.tips(), dtype=float)
    out = []
    for i, fx, fy in e.arbiters_internal().slider_forces(e.dt_internal):
        if i < 0:
            continue
        # a front contact (pushing the slider back) is the nearest tip behind the apex, a back
        # contact the nearest one past it
        front = fx < 0
        gap = (apex[i] - tips) if front else (tips - apex[i])
        j = int(np.argmin(np.where(gap >= -0.05 * scene.base, gap, np.inf)))
        out.append({"lower": int(i), "upper": j, "flank": "front" if front else "back",
                    "fx": fx * force, "fy": fy * force, "apex_minus_tip": float(apex[i] - tips[j])})
    return run, out


def _compressions(run, scene, contacts) -> None:
    """Each contact's lower spring compression (m): its vertical force over the track stiffness
    (at rest the spring carries the contact's vertical force; the damper is idle)."""
    for c in contacts:
        c["k"] = float(scene.lower.stiffness[c["lower"]])
        c["compression"] = c["fy"] / c["k"]


def resisting_force(scene, contacts, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Quasi-static resisting force R(s) (N) and the slider's rise (m) after moving on by s (m),
    with the contacts at rest kept (each front contact until its apex, then on the back flank)."""
    mu = scene.contact.mu_kinetic
    up, down = math.tan(math.pi / 4 + math.atan(mu)), math.tan(math.pi / 4 - math.atan(mu))
    load = scene.slider.normal_load
    k = np.array([c["k"] for c in contacts])
    c0 = np.array([c["compression"] for c in contacts])
    d = np.array([c["apex_minus_tip"] if c["flank"] == "front" else -abs(c["apex_minus_tip"]) for c in contacts])
    R, rise = np.empty_like(s), np.empty_like(s)
    for n, sn in enumerate(s):
        # a front contact presses its asperity down until the tip reaches the apex, then lets it up
        press = np.where(sn <= d, sn, 2 * np.maximum(d, 0.0) - sn)
        press = np.where(d < 0, -sn, press)
        carried = lambda dy: float(np.sum(k * np.maximum(c0 + press - dy, 0.0))) - load  # noqa: E731
        dy = brentq(carried, -1e-5, 1e-5, xtol=1e-15)
        f = k * np.maximum(c0 + press - dy, 0.0)
        climbing = (d >= 0) & (sn <= d)
        R[n] = float(np.sum(np.where(climbing, up * f, -down * f)))
        rise[n] = dy
    return R, rise


def estimate(scene, contacts, points: int = 2000) -> dict:
    fronts = [c["apex_minus_tip"] for c in contacts if c["flank"] == "front"]
    if not fronts:
        return {"estimate_N": float("nan")}
    s = np.linspace(0.0, max(fronts), points + 1)[1:]
    R, rise = resisting_force(scene, contacts, s)
    work = np.concatenate(([0.0], np.cumsum(0.5 * (R[1:] + R[:-1]) * np.diff(s))))
    work += R[0] * s[0]
    mean = work / s
    k = int(np.argmax(mean))
    return {"estimate_N": float(mean[k]), "at_m": float(s[k]), "rise_at_apex_m": float(rise[-1]),
            "climb_m": float(max(fronts)), "R_max_N": float(R.max()), "R_start_N": float(R[0])}


def one_seed(seed: int, size: str = "16/4") -> dict:
    scene = scene_of(seed, size)
    load, mu_k = scene.slider.normal_load, scene.contact.mu_kinetic
    law = load * math.tan(math.pi / 4 + math.atan(mu_k))
    bracket = critical_force_bracket(scene)
    run, contacts = rest_contacts(scene)
    _compressions(run, scene, contacts)
    est = estimate(scene, contacts)
    return {"seed": seed, "size": size, "critical_N": bracket.value, "law_N": law,
            "ratio": bracket.value / law, "contacts": contacts, **est,
            "estimate_ratio": est["estimate_N"] / bracket.value}


def summary(path: Path) -> None:
    """The figures the findings page quotes, per size: how often and by how much the random
    surfaces pass below the kinetic flank law, and how well the estimate follows them."""
    data = json.loads(path.read_text())
    for size in sorted({k.split("/")[0] + "/" + k.split("/")[1] for k in data}, reverse=True):
        rows = [v for k, v in data.items() if k.startswith(size + "/") and v["seed"] >= 0]
        ratio = np.array([v["ratio"] for v in rows])
        est = np.array([v["estimate_N"] / v["law_N"] for v in rows])
        climb = np.array([v["climb_m"] for v in rows])
        back = np.array([any(c["flank"] == "back" for c in v["contacts"]) for v in rows])
        print(f"{size}: {len(rows)} random seeds; critical / kinetic flank law median {np.median(ratio):.3f}, "
              f"range {ratio.min():.3f}-{ratio.max():.3f}; below 0.99: {(ratio < 0.99).sum()}, below 0.95: "
              f"{(ratio < 0.95).sum()}, below 0.90: {(ratio < 0.9).sum()}; a back-flank contact at rest: "
              f"{back.sum()}/{len(rows)}")
        print(f"  estimate / measured: mean {np.mean(est / ratio):.3f}, range {np.min(est / ratio):.3f}-"
              f"{np.max(est / ratio):.3f}; correlation {np.corrcoef(ratio, est)[0, 1]:.2f}; "
              f"correlation with the front tip's climb {np.corrcoef(ratio, climb)[0, 1]:.2f}")
        for v in sorted(rows, key=lambda v: v["ratio"])[:3]:
            print(f"  seed {v['seed']}: {v['critical_N'] * 1e3:.2f} mN = {v['ratio']:.3f} x law, estimate "
                  f"{v['estimate_N'] * 1e3:.2f} mN, climb {v['climb_m'] * 1e9:.0f} nm")


def figure(keys: list[str], path: Path, data_path: Path = OUT) -> Path:
    """R(s) of the estimate, its running mean (the force that carries the slider that far) and
    the measured critical force, for the recorded seeds ``keys`` ("16/4/7636", "16/4/-1")."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    data = json.loads(data_path.read_text())
    fig, axes = plt.subplots(1, len(keys), figsize=(5.2 * len(keys), 3.6), squeeze=False)
    for ax, key in zip(axes[0], keys):
        rec = data[key]
        size, seed = key.rsplit("/", 1)
        scene = scene_of(int(seed), size)
        fronts = [c["apex_minus_tip"] for c in rec["contacts"] if c["flank"] == "front"]
        s = np.linspace(0.0, max(fronts), 1001)[1:-1]  # up to the apex, not over it
        R, _ = resisting_force(scene, rec["contacts"], s)
        mean = np.cumsum(0.5 * (R + np.concatenate(([R[0]], R[:-1]))) * np.diff(np.concatenate(([0.0], s)))) / s
        ax.plot(s * 1e9, R * 1e3, label="resisting force R(s), quasi-static")
        ax.plot(s * 1e9, mean * 1e3, label="its running mean (the force needed from rest)")
        ax.axhline(rec["law_N"] * 1e3, color="0.5", ls="--", label="kinetic flank law")
        ax.axhline(rec["critical_N"] * 1e3, color="k", ls=":", label="measured critical force")
        ax.set_xlabel("slider travel s (nm)")
        ax.set_ylabel("force (mN)")
        ax.set_title("regular surface" if int(seed) < 0 else f"seed {seed}", fontsize=10)
    axes[0][0].legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    return path


def main(argv: list[str]) -> int:
    if argv[:1] == ["--figure"]:
        print(figure(argv[1:] or ["16/4/7636", "16/4/-1"], OUT.with_suffix(".png")))
        return 0
    if argv[:1] == ["--summary"]:
        summary(Path(argv[1]) if len(argv) > 1 else OUT)
        return 0
    size = "16/4"
    if argv[:1] == ["--size"]:
        size, argv = argv[1], argv[2:]
    data = json.loads(OUT.read_text()) if OUT.exists() else {}
    for seed in (int(s) for s in argv):
        out = one_seed(seed, size)
        data[f"{size}/{seed}"] = out
        flanks = " ".join(f"{c['flank'][0]}{c['lower']}/{c['upper']}:{c['fy'] * 1e3:.2f}mN,d={c['apex_minus_tip'] * 1e9:.0f}nm"
                          for c in out["contacts"])
        print(f"{size} seed {seed}: critical {out['critical_N'] * 1e3:.3f} mN = {out['ratio']:.3f} x law; "
              f"estimate {out['estimate_N'] * 1e3:.3f} mN ({out['estimate_ratio']:.3f}); {flanks}", flush=True)
        OUT.parent.mkdir(parents=True, exist_ok=True)
        OUT.write_text(json.dumps(data, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
