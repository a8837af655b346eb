"""Forces against the spread of the asperity heights
=================================================

Critical force and mean stick force against the spread of the asperity heights.

The surfaces of E. Ooten, *Precision Motion Control at Low Velocities in the
Presence of Friction* (senior thesis, Texas A&M University, 1997-98): 10 lower /
3 upper 45° full triangles on a 1 µm base, 1.25 µm pitch, Table 1 steel, with
Gaussian random heights on both surfaces: every asperity keeps its 1 µm base and gets its own height about 0.5 µm with
standard deviation sigma, so sigma / base = 0 (today's surfaces) to 0.2; the
spacing stays regular. Both set-ups: the free slider under 10 mN, and seed
000's fixed track whose deepest upper tip runs 0.125 µm below the tallest
lower tip. Per (set-up, sigma, seed) one scene (``asperity2d.studies.rough.rough_run``):
its critical constant force and, from a spring-driven pass, the mean drive
force at the stick-to-slip transitions (``mean_stick_force``), the asperities
touched, the most contacts at once and the steepest lower flank touched.
sigma = 0 is deterministic: one run stands for all seeds. ``--quick`` is a
smoke test (3 / 1 asperities, sigma / base 0 and 0.2, one seed, a 5x faster
drive), not a measurement.

Claims tested (Spearman rank correlation over all runs, two-sided, p < 0.05,
unless stated):

* free slider: both forces rise with the spread; mechanism: taller asperities
  have steeper flanks (theta = atan(2 h / b) on a fixed base) and the slider,
  riding on the tallest, must climb them: the critical force follows the
  flank law L tan(theta* + atan mu_k) of the steepest lower flank it touches
  (their ratio has no trend with sigma), and the contact angle the breakaway
  forces imply, atan(F / N) - atan(mu_s), rises with sigma;
* fixed track: both forces fall with the spread, and any spread puts them
  below the uniform surface's (one-sided Wilcoxon against it); mechanism:
  with the track set by the tallest lower tip, fewer lower asperities reach
  the upper tips and fewer pairs engage at once; with a spread, steeper
  flanks of the engaged asperities raise the stick force again.

Sanity counts in the summary: runs in which an upper tip reached the guard
floor or a lower asperity the bottom of its track (both must be 0), and runs
that did not pass.

Run::

    python scenes/rough_height_spread.py [--quick] [--seeds 8] [--workers auto|N] [--json] [-o DIR]
"""

from __future__ import annotations

import math

import numpy as np

from asperity2d import stats
from asperity2d.scene import OOTEN_DEFAULTS, kinetic_default
from asperity2d import scripting
from asperity2d.experiments.verdicts import HOLDS, UNTESTABLE, claim, judge, verdict_line
from asperity2d.studies.rough import rough_run, spearman, trend_claim
from asperity2d.sweep import map_calls

# %%
# The settings
# ------------
#
# The height spreads sigma / base tried, the surfaces' sizes and the two set-ups; the quick
# setting (the one the documentation ran) is a smoke test whose claims cannot be tested.

SPREADS = (0.0, 0.05, 0.1, 0.15, 0.2)  # sigma / base
QUICK_SPREADS = (0.0, 0.2)
BASE = 1e-6  # m
SIZE = dict(lower_count=10, upper_count=3)
QUICK_SIZE = dict(lower_count=3, upper_count=1, drive_velocity=100.0)  # a smoke test: 5x faster drive
SETUPS = {"free": {"track": "free"}, "fixed": {"track": "fixed", "interference": 0.125e-6}}
QUANTITIES = ("critical_force_N", "mean_stick_force_N", "touched_fraction", "max_contacts",
              "steepest_touched_flank_deg", "steepest_upper_flank_deg", "breakaway_angle_deg")
LOAD, MU_K = OOTEN_DEFAULTS["normal_load"], kinetic_default(OOTEN_DEFAULTS["mu_static"])  # N; the free slider's
ALPHA = 0.05


# %%
# 1. The runs
# -----------
#
# ``height_std`` in :func:`asperity2d.make_scene` gives every asperity its own Gaussian height;
# :func:`asperity2d.sweep.map_calls` runs :func:`asperity2d.studies.rough.rough_run` (the
# critical force and one spring-driven pass) for every spread and seed, on the workers.

def measure(setup: str, spreads, seeds, size, workers: int | None) -> list[dict]:
    """One row per (spread, seed); a spread of 0 is deterministic: one run."""
    keys = [(s, seed) for s in spreads for seed in (seeds if s else seeds[:1])]
    jobs = [dict(size, **SETUPS[setup], seed=seed, **({"height_std": s * BASE} if s else {}))
            for s, seed in keys]
    rows = map_calls(rough_run, jobs, workers=workers)
    return [{**r, "spread": s, "seed": seed} for r, (s, seed) in zip(rows, keys)]


# %%
# 2. Judge the trends
# -------------------
#
# :func:`asperity2d.studies.rough.trend_claim` judges a rise or fall with the spread by a Spearman
# rank correlation; the comparison with the uniform surface is a one-sided Wilcoxon test
# (:func:`asperity2d.stats.versus_reference`) judged by :func:`asperity2d.experiments.verdicts.judge`.

def _below_uniform(text: str, rows: list[dict], q: str, spreads, setup: str) -> dict:
    """Every spread's values below the uniform surface's: one-sided Wilcoxon against it at each."""
    uniform = next(r[q] for r in rows if r["spread"] == 0.0)
    per = {f"{s:g}": stats.versus_reference([r[q] for r in rows if r["spread"] == s], uniform)
           for s in spreads[1:]}
    verdicts = [judge(n, ALPHA) for n in per.values()]
    verdict = (UNTESTABLE if UNTESTABLE in verdicts else
               all(v == HOLDS for v in verdicts))
    return claim(text, verdict, {"uniform_value": uniform, "per_spread": per},
                 f"one-sided Wilcoxon signed-rank against the uniform surface's value at every spread; "
                 f"holds if every mean is below it with p < {ALPHA:g}", setup=setup)


def analyse(setup: str, rows: list[dict], spreads) -> tuple[dict, list[dict]]:
    per_spread = {f"{s:g}": {q: stats.describe([r[q] for r in rows if r["spread"] == s]) for q in QUANTITIES}
                  for s in spreads}
    spread = [r["spread"] for r in rows]
    col = {q: [r[q] for r in rows] for q in rows[0]}
    sanity = {"floor_touched_runs": int(np.nansum(col["floor_touched"])),
              "track_bottomed_runs": int(np.nansum(col["track_bottomed"])),
              "not_passed_runs": int(len(rows) - np.nansum(col["passed"]))}
    if setup == "free":
        law = np.array([LOAD * math.tan(math.radians(t) + math.atan(MU_K))
                        for t in col["steepest_touched_flank_deg"]])
        ratio = np.array(col["critical_force_N"]) / law
        rho, p = spearman(spread, ratio)
        angle = np.array(col["breakaway_angle_deg"])
        sanity["breakaway_within_3deg_of"] = {
            "steepest_lower_flank_touched": float(np.mean(np.abs(angle - col["steepest_touched_flank_deg"]) < 3)),
            "steepest_upper_flank": float(np.mean(np.abs(angle - col["steepest_upper_flank_deg"]) < 3))}
        claims = [
            trend_claim("free slider: the critical force rises with the height spread", spread,
                        col["critical_force_N"], 1, setup=setup),
            trend_claim("free slider: the mean stick force rises with the height spread", spread,
                        col["mean_stick_force_N"], 1, setup=setup),
            trend_claim("free slider, mechanism: the contact angle the breakaway forces imply "
                        "(atan(F / N) - atan mu_s) rises with the spread", spread, col["breakaway_angle_deg"],
                        1, setup=setup),
            claim("free slider, mechanism: the critical force follows the flank law "
                  "L tan(theta* + atan mu_k) of the steepest lower flank it touches",
                  UNTESTABLE if not math.isfinite(p) else bool(not p < ALPHA),
                  {"ratio": stats.describe(ratio), "spearman_rho": rho, "p": p},
                  f"no Spearman trend of F_c / flank law with sigma (p >= {ALPHA:g})", setup=setup)]
    else:
        rough = [r for r in rows if r["spread"] > 0]
        claims = [
            trend_claim("fixed track: the critical force falls with the height spread", spread,
                        col["critical_force_N"], -1, setup=setup),
            trend_claim("fixed track: the mean stick force falls with the height spread", spread,
                        col["mean_stick_force_N"], -1, setup=setup),
            _below_uniform("fixed track: any height spread lowers the critical force below the uniform "
                           "surface's", rows, "critical_force_N", spreads, setup),
            _below_uniform("fixed track: any height spread lowers the mean stick force below the uniform "
                           "surface's", rows, "mean_stick_force_N", spreads, setup),
            trend_claim("fixed track, mechanism: fewer lower asperities are touched as the spread grows",
                        spread, col["touched_fraction"], -1, setup=setup),
            trend_claim("fixed track, mechanism: fewer pairs engage at once as the spread grows", spread,
                        col["max_contacts"], -1, setup=setup),
            trend_claim("fixed track, mechanism: with a spread, the mean stick force rises with the "
                        "steepest lower flank touched", [r["steepest_touched_flank_deg"] for r in rough],
                        [r["mean_stick_force_N"] for r in rough], 1, setup=setup)]
    observed = {q: dict(zip(("spearman_rho", "p"), spearman(spread, col[q]))) for q in QUANTITIES}
    return {"per_spread": per_spread, "sanity": sanity, "spearman_vs_spread": observed}, claims


# %%
# 3. Plot
# -------
#
# Both forces against the spread, each seed a point and the mean a line (a plain matplotlib figure).

def plot(results: dict, path) -> None:
    from matplotlib.figure import Figure  # a user's own figure (no pyplot)

    fig = Figure(figsize=(9.0, 2 * 3.0), layout="constrained")
    axes = fig.subplots(2, 1, sharex=True)
    for ax, q, label in ((axes[0], "critical_force_N", "critical force (mN)"),
                         (axes[1], "mean_stick_force_N", "mean stick force (mN)")):
        for i, (setup, rows) in enumerate(results.items()):
            s = np.array([r["spread"] for r in rows])
            v = np.array([r[q] for r in rows]) * 1e3
            ax.plot(s + 0.004 * (i - 0.5), v, "o", ms=3, alpha=0.5, color=f"C{i}")
            xs = sorted(set(s))
            means = [stats.describe(v[s == x])['mean'] for x in xs]
            ax.plot(xs, means, "-", color=f"C{i}", label=f"{setup}: mean")
        ax.set_yscale("log")
        ax.set_ylabel(label)
        ax.legend(fontsize=8)
    axes[1].set_xlabel("height spread sigma / base")
    axes[0].set_title("random heights, regular spacing; points: seeds", fontsize=9)
    fig.savefig(path, dpi=120)


# %%
# The command line
# ----------------
#
# ``main`` reads the options (``--quick``, ``--seeds``, ``--workers``, ``-o``, ``--json``), runs
# the steps, draws and prints the numbers and the verdicts.

def main(argv=None) -> int:
    args = scripting.study_args(scripting.title(__doc__), argv, default_seeds=8, minimum_seeds=1,
                                quick_seeds=1)
    out = scripting.out_dir(args, __file__)
    spreads, size = (QUICK_SPREADS, QUICK_SIZE) if args.quick else (SPREADS, SIZE)
    seeds = list(range(args.seeds))
    results = {setup: measure(setup, spreads, seeds, size, args.workers) for setup in SETUPS}
    summary = {"spreads_sigma_over_base": list(spreads), "seeds": args.seeds, "size": size,
               "setups": {k: {"parameters": v} for k, v in SETUPS.items()}, "claims": []}
    for setup, rows in results.items():
        numbers, claims = analyse(setup, rows, spreads)
        summary["setups"][setup].update(numbers)
        summary["setups"][setup]["runs"] = rows
        summary["claims"] += claims
    plot(results, out / "forces_vs_spread.png")
    summary["outputs"] = ["forces_vs_spread.png"]
    lines = []
    for setup in SETUPS:
        for s in spreads:
            n = summary["setups"][setup]["per_spread"][f"{s:g}"]
            lines.append(f"{setup} sigma/base {s:g}: critical {n['critical_force_N']['mean'] * 1e3:.3g} mN, "
                         f"mean stick {n['mean_stick_force_N']['mean'] * 1e3:.3g} mN, touched "
                         f"{n['touched_fraction']['mean']:.2f}, contacts at once {n['max_contacts']['mean']:.2g}")
    lines += [verdict_line(c) for c in summary["claims"]]
    untestable = sum(c["verdict"] == UNTESTABLE for c in summary["claims"])
    if untestable:
        runs = 1 + (len(spreads) - 1) * args.seeds  # sigma = 0 is one run
        needed = next(n for n in range(1, 64) if 0.5 ** n < ALPHA)  # one-sided Wilcoxon: p >= 1 / 2**n
        lines.append(f"{untestable} claims not testable: {len(spreads)} spreads x {args.seeds} seed(s) give "
                     f"{runs} runs per set-up; a rank correlation needs 3 or more, and the comparison with the "
                     f"uniform surface {needed} seeds or more to reach p < {ALPHA:g} (the full study: "
                     f"{len(SPREADS)} spreads x 8 seeds)")
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
