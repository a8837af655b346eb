"""Forces against the Hurst exponent of a self-affine surface
==========================================================

Critical force and mean stick force against the Hurst exponent H at fixed rms height.

The lower surface is a self-affine profile (``asperity2d.surface.self_affine_profile``,
one realisation per seed): 16 µm long, 2048 points, rms height 0.15 µm, power
between the wavelengths 4 µm (a roll-off plateau above) and 0.25 µm, H = 0.3
to 0.9; its summits of prominence >= 10 % of the rms height become the lower
asperities (``make_scene(lower_surface=profile)``, Table 1 stiffness and mass
for all). The slider carries Ooten's three 45° triangles (1 µm base,
1.25 µm pitch). Both set-ups: the free slider under 1 mN, and a fixed track
whose deepest upper tip runs one rms height (0.15 µm) above the profile's
mean line (a fixed separation of the mean planes, as in Greenwood-Williamson),
raised to 5 % of the rms above the profile's rigid valley floor between its
asperities where that floor is higher (a rigid slider cannot pass below it;
``level_raised`` counts those runs).

At fixed rms, a smaller H puts more of the height variance at short
wavelengths: more, smaller and steeper summits (the rms slope grows). Claims
tested (Spearman rank correlation over all runs, two-sided, p < 0.05):

* free slider: the critical force and the mean stick force fall as H grows;
  mechanism: the steepest lower flank the slider touches falls with H, and the
  critical force follows its flank law L tan(theta* + atan mu_k);
* fixed track: the forces fall as H grows; mechanism: fewer summits rise above
  the track at a fixed separation, with gentler flanks; the asperities touched
  are exactly those above the track.

A fixed-track run whose track would lie above every summit is left out
(``valid_runs`` in the summary).
``--quick`` is a smoke test (a 5 µm profile, H = 0.3 and 0.9, one seed, one
upper tip, a 5x faster drive), not a measurement.

Run::

    python scenes/rough_hurst.py [--quick] [--seeds 5] [--workers auto|N] [--json] [-o DIR]
"""

from __future__ import annotations

import math

import numpy as np

from asperity2d import stats
from asperity2d.scene import OOTEN_DEFAULTS, kinetic_default
from asperity2d import scripting
from asperity2d.experiments.verdicts import UNTESTABLE, claim, verdict_line
from asperity2d.studies.rough import self_affine_run, spearman, trend_claim
from asperity2d.sweep import map_calls

# %%
# The settings
# ------------
#
# The Hurst exponents tried, the profiles (fixed rms height), the slider and the two set-ups;
# the quick setting (the one the documentation ran) is a smoke test whose trends cannot be tested.

HURSTS, QUICK_HURSTS = (0.3, 0.5, 0.7, 0.9), (0.3, 0.9)
RMS = 0.15e-6  # m
PROFILE = dict(rms_height=RMS, length=16e-6, points=2048, shortest=0.25e-6, longest=4e-6)
QUICK_PROFILE = dict(rms_height=RMS, length=5e-6, points=640, shortest=0.25e-6, longest=2.5e-6)
#: The free slider's load: 1 mN (10 mN, the package default, would push one of these 0.1-0.2 µm
#: asperities 0.27 µm down its 37,200 N/m track, past its height).
SETUPS = {"free": {"track": "free", "normal_load": 1e-3}, "fixed": {"track": "fixed", "separation": RMS}}
SLIDER, QUICK_SLIDER = dict(upper_count=3), dict(upper_count=1, drive_velocity=100.0)
QUANTITIES = ("critical_force_N", "mean_stick_force_N", "lower_count", "rms_slope", "touched_count",
              "above_level_fraction", "steepest_touched_flank_deg", "breakaway_angle_deg", "max_contacts")
MU_K = kinetic_default(OOTEN_DEFAULTS["mu_static"])
ALPHA = 0.05


# %%
# 1. Judge the trends
# -------------------
#
# Each run (in ``main`` below) is :func:`asperity2d.studies.rough.self_affine_run`: a seeded
# :func:`asperity2d.surface.self_affine_profile` made into a scene by
# ``make_scene(lower_surface=profile)`` and measured, mapped over the workers with
# :func:`asperity2d.sweep.map_calls`. The trends with H are judged by a Spearman rank
# correlation (:func:`asperity2d.studies.rough.trend_claim`).

def analyse(setup: str, rows: list[dict], hursts, load: float) -> tuple[dict, list[dict]]:
    valid = [r for r in rows if r.get("valid") == 1.0]
    per_h = {f"{h:g}": {q: stats.describe([r[q] for r in valid if r["hurst"] == h]) for q in QUANTITIES}
             for h in hursts}
    hs = [r["hurst"] for r in valid]
    col = {q: [r[q] for r in valid] for q in (valid[0] if valid else {})}
    sanity = {"runs": len(rows), "valid_runs": len(valid),
              "floor_touched_runs": int(np.nansum(col.get("floor_touched", []))),
              "track_bottomed_runs": int(np.nansum(col.get("track_bottomed", []))),
              "not_passed_runs": int(len(valid) - np.nansum(col.get("passed", []))),
              "level_raised_runs": int(np.nansum([r.get("level_raised", 0.0) for r in rows]))}
    if not valid:
        return {"per_hurst": per_h, "sanity": sanity}, []
    claims = [trend_claim("rms slope falls as H grows at fixed rms height (the profiles' premise)", hs,
                          col["rms_slope"], -1, setup=setup)]
    for q, text in (("critical_force_N", "critical force"), ("mean_stick_force_N", "mean stick force")):
        claims.append(trend_claim(f"{setup}: the {text} falls as H grows (fixed rms)", hs, col[q], -1,
                                  setup=setup))
    claims.append(trend_claim(f"{setup}, mechanism: the steepest lower flank touched falls as H grows",
                              hs, col["steepest_touched_flank_deg"], -1, setup=setup))
    if setup == "free":
        law = np.array([load * math.tan(min(math.radians(t) + math.atan(MU_K), math.radians(89.0)))
                        for t in col["steepest_touched_flank_deg"]])
        ratio = np.array(col["critical_force_N"]) / law
        rho, p = spearman(hs, ratio)
        claims.append(claim("free, mechanism: the critical force follows the flank law "
                            "L tan(theta* + atan mu_k) of the steepest lower flank touched",
                            UNTESTABLE if not math.isfinite(p) else bool(not p < ALPHA),
                            {"ratio": stats.describe(ratio), "spearman_rho": rho, "p": p},
                            f"no Spearman trend of F_c / flank law with H (p >= {ALPHA:g})", setup=setup))
    else:
        claims.append(trend_claim("fixed, mechanism: fewer summits rise above the track as H grows", hs,
                                  col["above_level_fraction"], -1, setup=setup))
        claims.append(claim("fixed: the asperities touched are exactly those above the track",
                            bool(all(v == 1.0 for v in col["touched_matches_above_level"])),
                            {"runs": len(valid)}, "every run: touched set == summits above the track",
                            setup=setup))
    observed = {q: dict(zip(("spearman_rho", "p"), spearman(hs, col[q]))) for q in QUANTITIES}
    return {"per_hurst": per_h, "sanity": sanity, "spearman_vs_hurst": observed}, claims


# %%
# 2. Plot
# -------
#
# The forces and the steepest flank touched against H, each seed a point and the mean a line
# (a plain matplotlib figure).

def plot(results: dict, path) -> None:
    from matplotlib.figure import Figure  # a user's own figure (no pyplot)

    fig = Figure(figsize=(8.0, 3 * 2.6), layout="constrained")
    axes = fig.subplots(3, 1, sharex=True)
    for ax, q, label, scale in ((axes[0], "critical_force_N", "critical force (mN)", 1e3),
                                (axes[1], "mean_stick_force_N", "mean stick force (mN)", 1e3),
                                (axes[2], "steepest_touched_flank_deg", "steepest flank touched (°)", 1.0)):
        for i, (setup, rows) in enumerate(results.items()):
            rows = [r for r in rows if r.get("valid") == 1.0]
            h = np.array([r["hurst"] for r in rows])
            v = np.array([r[q] for r in rows]) * scale
            ax.plot(h + 0.01 * (i - 0.5), v, "o", ms=3, alpha=0.5, color=f"C{i}")
            xs = sorted(set(h))
            ax.plot(xs, [stats.describe(v[h == x])['mean'] for x in xs], "-", color=f"C{i}", label=f"{setup}: mean")
        ax.set_ylabel(label, fontsize=8)
        ax.legend(fontsize=7)
    axes[0].set_yscale("log")
    axes[1].set_yscale("log")
    axes[2].set_xlabel("Hurst exponent H (rms height fixed at 0.15 µm)")
    fig.savefig(path, dpi=120)


# %%
# The command line
# ----------------
#
# ``main`` reads the options (``--quick``, ``--seeds``, ``--workers``, ``-o``, ``--json``), runs
# the steps, draws and prints the numbers and the verdicts.

def main(argv=None) -> int:
    args = scripting.study_args(scripting.title(__doc__), argv, default_seeds=5, minimum_seeds=1,
                                quick_seeds=1)
    out = scripting.out_dir(args, __file__)
    hursts, profile, slider = ((QUICK_HURSTS, QUICK_PROFILE, QUICK_SLIDER) if args.quick
                               else (HURSTS, PROFILE, SLIDER))
    results, summary = {}, {"hursts": list(hursts), "profile": profile, "slider": slider,
                            "seeds": args.seeds, "setups": {}, "claims": []}
    for setup, params in SETUPS.items():
        jobs = [dict(profile, **slider, **params, hurst=h, seed=s) for h in hursts for s in range(args.seeds)]
        rows = map_calls(self_affine_run, jobs, workers=args.workers)
        results[setup] = [{**r, "hurst": j["hurst"], "seed": j["seed"]} for r, j in zip(rows, jobs)]
        numbers, claims = analyse(setup, results[setup], hursts, params.get("normal_load", 0.0))
        summary["setups"][setup] = {"parameters": params, **numbers, "runs": results[setup]}
        summary["claims"] += claims
    plot(results, out / "forces_vs_hurst.png")
    summary["outputs"] = ["forces_vs_hurst.png"]
    lines = []
    for setup in SETUPS:
        for h in hursts:
            n = summary["setups"][setup]["per_hurst"][f"{h:g}"]
            stick = n["mean_stick_force_N"]["mean"]
            stick = (f"mean stick {stick * 1e3:.3g} mN" if math.isfinite(stick) else
                     "no stick-slip event in any run (so no mean stick force)")
            lines.append(f"{setup} H = {h:g}: {n['lower_count']['mean']:.3g} asperities, rms slope "
                         f"{n['rms_slope']['mean']:.2f}, critical {n['critical_force_N']['mean'] * 1e3:.3g} mN, "
                         f"{stick}, steepest flank touched {n['steepest_touched_flank_deg']['mean']:.3g}°")
    lines += [verdict_line(c) for c in summary["claims"]]
    untestable = sum(c["verdict"] == UNTESTABLE for c in summary["claims"])
    if untestable:
        runs = len(hursts) * args.seeds
        lines.append(f"{untestable} claims not testable: {len(hursts)} Hurst exponents x {args.seeds} seed(s) "
                     f"give {runs} runs per set-up, and a rank correlation needs 3 or more (the full study: "
                     f"{len(HURSTS)} x 5 seeds, {len(HURSTS) * 5} runs)")
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
