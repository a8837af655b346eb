"""Basins of the three-mass chain: a transient, and chaos beside a cycle
=====================================================================

From the thesis *Vibration Analysis of Multi Degree of Freedom Self-excited
Systems* (no author named in the copy used here), called the multi-DOF belt
thesis below.

The multi-DOF belt thesis' 3-DOF base case (Table 2): initial-condition basins, stability, and its sound.

Run: ``python scenes/belt_basins.py [--quick] [--grid N] [--workers auto|N] [-o DIR] [--json]``
(also ``asperity2d run scenes/belt_basins.py -- ...``).

* a basin map over mass 1's initial displacement and velocity (x1, v1), the
  other coordinates at eq 3.12, each run 100 s with the exact solver and
  classified rest / pure slip / stick-slip period-n / irregular
  (``asperity2d.dynamics.basins``), kept in a resumable sweep store;
* a sample of the points classed irregular run again four times longer
  (does the class hold, or was it a long transient?), and the largest
  Lyapunov exponent of a few that stay irregular (chaos or not?);
* the same map for a contrast chain with static friction 0.4 above the
  kinetic 0.2 (the thesis uses one coefficient, so the base case has no
  static excess);
* the Floquet multipliers of the contrast chain's limit cycle from eq 3.12,
  and the largest Lyapunov exponent (Benettin) of both chains from eq 3.12;
* ``base_x1_acceleration.wav``: mass 1's acceleration over a long run, its
  lowest mode heard at 440 Hz, with its spectrogram.
"""


import numpy as np

from asperity2d import SimulationError
from asperity2d.belt import presets, simulate_chain
from asperity2d.dynamics import chain_lyapunov, floquet, flow_map
from asperity2d.dynamics.basins import (LABELS, RUN_CPU_LIMIT, chain_basins, classify_chain, cpu_limit,
                                        with_initial)
from asperity2d.renderers.dynamics import plot_basins
from asperity2d.renderers.sound import write_wav
from asperity2d import scripting

X_RANGE = (-0.3, 0.9)  # m: around mass 1's equilibrium under kinetic friction, 0.294 m
V_RANGE = (-0.6, 0.6)  # m/s


def recheck_irregular(bm, chain, factor, count, chaos, steps, seed=0):
    """Run up to ``count`` grid points classed irregular again, ``factor`` times longer: a long transient
    (sparse sticks on the way to pure slip) changes class, a sustained irregular motion does not. For the
    first ``chaos`` of those still irregular, the largest Lyapunov exponent (Benettin, ``steps`` x 2 s after
    a transient of t_end): positive for chaos, ~0 (to ~1e-3 1/s over 300 s) for a cycle or a torus."""
    i, j = np.nonzero(bm.values["label"] == 3)
    if i.size == 0:
        return {"checked": 0}
    pick = np.random.default_rng(seed).choice(i.size, min(count, i.size), replace=False)
    classes, exponents = [], []
    for k in pick:
        kw = with_initial(with_initial(chain, bm.x_name, bm.x_values[i[k]]), bm.y_name, bm.y_values[j[k]])
        longer = dict(kw, t_end=factor * chain["t_end"], n_samples=factor * (chain["n_samples"] - 1) + 1)
        try:
            with cpu_limit(RUN_CPU_LIMIT):
                classes.append(LABELS[int(classify_chain(simulate_chain(**longer))["label"])])
        except SimulationError:
            classes.append("failed")
        if classes[-1] == "irregular" and len(exponents) < chaos:
            s = flow_map(kw, np.concatenate([kw["x0"], kw["v0"]]), chain["t_end"])
            settled = dict(kw, x0=s[:len(s) // 2].tolist(), v0=s[len(s) // 2:].tolist())
            exponents.append({"x1": float(bm.x_values[i[k]]), "v1": float(bm.y_values[j[k]]),
                              "lyapunov_per_s": chain_lyapunov(settled, steps=steps, interval=2.0).value})
    return {"checked": len(classes), "t_end_s": factor * chain["t_end"],
            "classes": {name: classes.count(name) for name in sorted(set(classes))},
            "lyapunov_of_still_irregular": exponents}


def basin_summary(bm) -> dict:
    out = bm.to_dict()
    total = int(np.sum(bm.values["label"] >= 0))
    out["fractions"] = {k: v / max(total, 1) for k, v in out["counts"].items() if k != "failed"}
    last = bm.values["last_stick"][bm.values["label"] >= 0]
    if last.size:
        out["last_stick_s"]["p10"], out["last_stick_s"]["p90"] = (float(q) for q in np.percentile(last, [10, 90]))
    return out


def _counts(counts: dict) -> str:
    """``"pure slip 4 (44 %), irregular 5 (56 %)"``: the classes that occurred."""
    total = sum(counts.values()) or 1
    return ", ".join(f"{k} {v} ({100 * v / total:.0f} %)" for k, v in counts.items() if v) or "none"


def _recheck(record: dict) -> str:
    """The long re-runs of irregular points in words."""
    if not record.get("checked"):
        return "none to check"
    text = f"{record['checked']} checked over {record['t_end_s']:g} s: {_counts(record['classes'])}"
    lyap = record.get("lyapunov_of_still_irregular") or []
    if lyap:
        text += "; largest Lyapunov exponents of those still irregular " + ", ".join(
            f"{r['lyapunov_per_s']:+.3f} 1/s" for r in lyap)
    return text


def main(argv=None) -> int:
    p = scripting.parser(scripting.title(__doc__))
    p.add_argument("--grid", type=int, default=None, help="points per axis (default 60, quick 3)")
    scripting.add_workers(p)
    args = p.parse_args(argv)
    out = scripting.out_dir(args, __file__)
    quick = args.quick
    grid = args.grid or (3 if quick else 60)
    t_end = 20.0 if quick else 100.0
    samples = int(20 * t_end) + 1  # 20 per second: the classifier reads velocities over the last quarter
    base = presets.preset("table2-3dof", t_end=t_end, n_samples=samples)
    contrast = presets.preset("table2-3dof", mu_s=0.4, t_end=t_end, n_samples=samples)
    summary = {"grid": [grid, grid], "t_end_s": t_end, "axes": {"x1_m": X_RANGE, "v1_m_s": V_RANGE},
               "fixed": "x2, x3, v2, v3 from eq 3.12 (0.06 m, 0.07 m, 0.03 m/s, 0.05 m/s)"}
    for name, chain, size in (("base", base, grid), ("contrast_mu_s_0.4", contrast, max(2, grid // 2))):
        bm = chain_basins(chain, x=("x1", np.linspace(*X_RANGE, size)), y=("v1", np.linspace(*V_RANGE, size)),
                          store=out / f"{name}.runs", workers=args.workers, progress=not args.json)
        title = ("Table 2 base case (mu = 0.2, c = 0)" if name == "base" else
                 "contrast: mu_s = 0.4 > mu_k = 0.2") + f", {size} x {size} runs of {t_end:g} s"
        detail = "last_stick" if name == "base" else "stick_fraction"
        summary[name] = {**basin_summary(bm),
                         "plot": str(plot_basins(bm, out / f"basins_{name}.png", detail=detail, title=title)),
                         "irregular_rechecked": recheck_irregular(bm, chain, 2 if quick else 4, 2 if quick else 20,
                                                                  1 if quick else 3, 10 if quick else 150)}
    # stability of the contrast's cycle reached from eq 3.12 (the base case has none to analyse)
    long = 120.0 if quick else 300.0
    try:
        fl = floquet(presets.preset("table2-3dof", mu_s=0.4, t_end=long, n_samples=int(100 * long) + 1))
        summary["floquet_contrast_eq312"] = fl.to_dict()
    except Exception as exc:  # noqa: BLE001 -- a run without a cycle is a result, reported as such
        summary["floquet_contrast_eq312"] = {"error": str(exc)}
    steps = 10 if quick else 150
    summary["lyapunov_eq312"] = {
        "base": chain_lyapunov(presets.preset("table2-3dof"), steps=steps, interval=2.0).to_dict(),
        "contrast_mu_s_0.4": chain_lyapunov(presets.preset("table2-3dof", mu_s=0.4), steps=steps,
                                            interval=2.0).to_dict(),
    }
    sound_t = 100.0 if quick else 3000.0
    run = simulate_chain(**presets.preset("table2-3dof", t_end=sound_t, n_samples=int(50 * sound_t) + 1))
    summary["sound"] = write_wav(run, out / "base_x1_acceleration.wav", signal="acceleration", mass=0).to_dict()
    b, c = summary["base"], summary["contrast_mu_s_0.4"]
    lines = [f"base case, {grid} x {grid} initial states over {t_end:g} s: {_counts(b['counts'])}",
             f"  last stick onset: median {b['last_stick_s']['median']:.3g} s, max {b['last_stick_s']['max']:.3g} s",
             f"  irregular points run again longer: {_recheck(b['irregular_rechecked'])}",
             f"contrast mu_s = 0.4: {_counts(c['counts'])}"
             + (f", cycle periods {', '.join(f'{p:.4g} s' for p in c['periods_s'][:6])}" if c["periods_s"] else ""),
             f"  irregular points run again longer: {_recheck(c['irregular_rechecked'])}"]
    fl = summary["floquet_contrast_eq312"]
    if "moduli" in fl:
        lines.append(f"contrast cycle from eq 3.12: period {fl['period_s']:.6g} s (period-{fl['multiplicity']}), "
                     f"|multipliers| {', '.join(f'{m:.4g}' for m in fl['moduli'])}, "
                     f"{'stable' if fl['stable'] else 'unstable'}")
    lines.append("largest Lyapunov exponents (1/s): " + ", ".join(
        f"{k} {v['value_per_s']:.2g}" for k, v in summary["lyapunov_eq312"].items()))
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
