"""Regular against random spacing (Ooten's figure 11)
==================================================

From E. Ooten, *Precision Motion Control at Low Velocities in the Presence of
Friction* (senior thesis, Texas A&M University, 1997-98), figure 11: does random
asperity spacing lower the force that breaks the slider loose?

The lesson: measure three spacings over many seeds with every named breakaway
measure, turn each measure into a :class:`asperity2d.Comparison`, judge each claim
with :meth:`asperity2d.Comparison.verdict` (a one-sided Wilcoxon test against the
regular value, with the Hodges-Lehmann ratio and its 95 % interval), and plot it
with :func:`asperity2d.render`.

Three variants (Ooten's three Working Model runs): regular/regular, random
upper on a regular lower surface ("random-upper"), random on both surfaces
("random"). Regular spacing does not depend on the seed and is measured once.
The measures (:mod:`asperity2d.experiments.measures`):

* critical force from rest (the headline): the smallest constant force that
  carries the slider, at rest on the surface with every tip against its
  flank, across the whole surface -- a step load; Ooten's "force required to
  move the top surface over the bottom surface";
* critical force with a run-up: the same force applied a tenth of a base
  before the surface (a momentum threshold);
* quasi-static breakaway: a slowly ramped force from rest (the barrier);
* over an ensemble of spring-driven passes (their mean: one pass is chaotic):
  the peak stick force (the headline breakaway measure), the mean stick force,
  and the first breakaway (on the fixed track the front tip entering alone: the
  same for every spacing by construction, reported to show it).

A verdict "holds" needs p < 0.01 in the claimed direction and a change of at
least 1 %; "random on both is the smallest" is a paired Wilcoxon test of
random/random against random-upper (same seed). Both set-ups are run: Ooten's
fixed-height track and the free slider under a 10 mN load.

Run::

    python scenes/ooten_spacing.py [--seeds 24] [--workers auto|N]
"""

# %%
# The steps are functions made of the package's public calls; ``main`` at the bottom reads the
# command line, runs them and prints. The gallery runs it with ``--quick`` (4 lower and 2 upper
# asperities, 2 seeds, one spring-driven pass, no slow ramp): its verdicts read "not testable",
# because a one-sided signed-rank test over n seeds cannot give p below 1/2**n (0.25 for 2
# seeds); a verdict needs 7 seeds or more (the default run uses 24).

from __future__ import annotations

import math

import numpy as np

import asperity2d as a
from asperity2d import scripting, stats
from asperity2d.experiments import verdicts
from asperity2d.experiments.measures import measure_label
from asperity2d.studies import ooten as studies
from asperity2d.sweep import map_calls

#: The three spacings of figure 11, as :func:`asperity2d.make_scene` arguments.
VARIANTS = {"regular": {"spacing": "regular"}, "random-upper": {"spacing": "random-upper"},
            "random": {"spacing": "random"}}
ALPHA = 0.01
#: Measures: name -> key of studies.measures_run's output.
MEASURES = {"critical": "critical_rest_N", "critical-run-up": "critical_run_up_N",
            "quasi-static-breakaway": "quasi_static_N", "peak-stick": "peak_stick_N",
            "mean-stick": "mean_stick_N", "first-breakaway": "first_breakaway_N"}
HEADLINE = ("critical", "peak-stick")


# %%
# 1. One measure over seeds: ``compare``
# --------------------------------------
#
# :func:`asperity2d.compare` is the whole idea in one call: it makes every variant's scene on
# every seed (:func:`asperity2d.make_scene` with ``spacing=`` and ``seed=``), measures it (here
# the critical force from rest, :func:`asperity2d.critical_force`) and returns a
# :class:`asperity2d.Comparison`. ``studies.SETUPS`` holds the two set-ups' arguments
# (``track="fixed"`` with Ooten's interference, or ``track="free"``).

def critical_over_seeds(setup: str, size: dict, seeds, workers) -> a.Comparison:
    """The critical force from rest of every variant on ``seeds`` (N), by :func:`asperity2d.compare`."""
    return a.compare("critical", VARIANTS, seeds, base={**size, **studies.SETUPS[setup]},
                     progress=False, workers=workers)


# %%
# 2. Every measure of a scene in one job
# --------------------------------------
#
# Six measures, each through ``compare``, would build and settle every scene six times. The
# study runs one job per (variant, seed) instead: ``studies.measures_run`` makes the scene and
# takes every measure of it (:func:`asperity2d.critical_force_bracket` from rest and with a
# run-up, the quasi-static ramp, the spring-driven passes), and :func:`asperity2d.sweep.map_calls`
# runs the jobs on worker processes. The critical forces are the ones ``compare`` gives (``main``
# checks step 1's against them); the stick forces average 5 passes (``passes``) where the named
# measures average 3. The regular scene does not depend on the seed: it is measured once.

def rows_for(setup: str, *, size: dict, seeds: list[int], workers: int | None, passes: int,
             quasi_static: bool = True) -> dict:
    """{variant: [row per seed]} of ``asperity2d.studies.ooten.measures_run`` on one set-up;
    the regular scene (seed-independent) is measured once and repeated."""
    base = {**size, **studies.SETUPS[setup], "passes": passes, "quasi_static": quasi_static}
    jobs = [(v, s) for v in VARIANTS for s in (seeds[:1] if v == "regular" else seeds)]
    rows = map_calls(studies.measures_run, [{**base, **VARIANTS[v], "seed": s} for v, s in jobs],
                     workers=workers)
    out = {v: [r for (w, _), r in zip(jobs, rows) if w == v] for v in VARIANTS}
    out["regular"] = out["regular"] * len(seeds)
    return out


def bands(rows: dict) -> dict:
    """How many critical forces of each variant found passing non-monotone (a band)."""
    out = {}
    for start in ("rest", "run_up"):
        key = f"critical_{start}_band_low_N"
        out[start] = {v: int(sum(np.isfinite(r[key]) for r in rs)) for v, rs in rows.items()}
    return out


# %%
# 3. One comparison per measure
# -----------------------------
#
# A :class:`asperity2d.Comparison` holds one value per variant and seed; named after its measure
# it knows its label, unit and verdict rule, saves to JSON and plots with
# :func:`asperity2d.render`.

def comparisons(rows: dict, seeds: list[int], setup: str) -> dict[str, a.Comparison]:
    """Per measure the rows carry: every variant over the seeds."""
    return {name: a.Comparison(values={v: tuple(r[key] for r in rows[v]) for v in VARIANTS}, seeds=tuple(seeds),
                               variants=VARIANTS, base=dict(studies.SETUPS[setup]), measure=name)
            for name, key in MEASURES.items() if key in rows["regular"][0]}


# %%
# 4. The verdicts
# ---------------
#
# :meth:`asperity2d.Comparison.verdict` judges "random spacing lowers the <measure>": a
# one-sided Wilcoxon signed-rank test of the random values against the regular one, holds if
# p < 0.01 and the mean moved by at least 1 % (twice the model's force resolution), with the
# Hodges-Lehmann ratio random / regular and its 95 % interval. Figure 11's third claim, "random
# on both surfaces is the smallest", pairs random with random-upper seed by seed
# (:meth:`asperity2d.Comparison.versus`, :func:`asperity2d.stats.relative_effect`) and judges
# it with :func:`asperity2d.experiments.verdicts.judge`.

def claims_for(setup: str, found: dict[str, a.Comparison]) -> list[dict]:
    """Ooten's figure 11 claims for one set-up, with numbers, effect sizes and tests."""
    out = []
    for name, comparison in found.items():
        label = measure_label(name)
        for variant in ("random-upper", "random"):
            record = comparison.verdict(variant, "regular", subject=f"random spacing ({variant})", setup=setup)
            out.append(record | {"measure": name, "variant": variant})
        both = comparison.versus("random", "random-upper", alternative="less")
        e = stats.relative_effect(comparison.values["random"], comparison.values["random-upper"])
        both.update(ratio_hl=e["ratio"], ratio_ci_low=1 + e["ci_low"], ratio_ci_high=1 + e["ci_high"])
        verdict = verdicts.judge(both, ALPHA)
        means = {v: d["mean"] for v, d in comparison.summary().items()}
        if verdict == verdicts.HOLDS and both["mean"] >= means["regular"]:
            verdict = verdicts.FAILS  # smallest of the three, not just below random-upper
        both["smallest_variant"] = min(means, key=lambda v: means[v] if math.isfinite(means[v]) else math.inf)
        out.append(verdicts.claim(
            f"random on both surfaces needs the smallest {label} (figure 11)", verdict, both,
            f"paired Wilcoxon random/random - random-upper (same seeds), one-sided (lower): "
            f"p = {both['p_wilcoxon']:.3g}, and below regular; holds if p < {ALPHA} and the change is at least "
            f"{100 * verdicts.MIN_EFFECT:g} %", setup=setup) | {"measure": name, "variant": "random vs random-upper"})
    return out


# %%
# 5. The whole study
# ------------------
#
# For each set-up: measure (step 2), compare (step 3), save each comparison and draw it
# (:func:`asperity2d.render` of a comparison: every seed's value, each variant's mean and 95 %
# interval, in mN), then judge (step 4); the critical forces of step 1 are checked against the
# bulk's on the first seeds. ``main`` reads the options (``--quick``, ``--seeds``,
# ``--workers``, ``-o``, ``--json``, ``--no-gif``) with :mod:`asperity2d.scripting`.

def main(argv=None) -> int:
    args = scripting.study_args(scripting.title(__doc__), argv, default_seeds=24, minimum_seeds=2)
    out = scripting.out_dir(args, __file__)
    size = studies.QUICK_SIZE if args.quick else studies.STUDY_SIZE
    passes = 1 if args.quick else 5  # --quick: a smoke test (one pass, no slow ramp)
    seeds = list(range(args.seeds))
    summary = {"size": size, "seeds": args.seeds, "passes": passes, "setups": studies.SETUPS, "alpha": ALPHA,
               "headline_measures": HEADLINE, "results": {}, "rows": {}, "bands": {}, "claims": []}
    lines = []
    for setup in studies.SETUPS:
        rows = rows_for(setup, size=size, seeds=seeds, workers=args.workers, passes=passes,
                        quasi_static=not args.quick)
        summary["rows"][setup] = rows
        summary["bands"][setup] = bands(rows)
        found = comparisons(rows, seeds, setup)
        summary["results"][setup] = {}
        for name, comparison in found.items():
            comparison.save(out / f"{setup}_{name}.json")
            a.render(comparison, out / f"{setup}_{name}.png", label=f"{measure_label(name)} (mN), {setup} set-up")
            summary["results"][setup][name] = comparison.summary()
        setup_claims = claims_for(setup, found)
        summary["claims"] += setup_claims
        lines += [verdicts.verdict_line(c) for c in setup_claims if c["measure"] in HEADLINE or args.quick]
    check = critical_over_seeds("fixed", size, seeds[:2], args.workers)
    same = all(check.values[v] == tuple(r["critical_rest_N"] for r in summary["rows"]["fixed"][v][:2]) for v in VARIANTS)
    summary["compare_check"] = {"seeds": seeds[:2], "values_N": check.values, "same_as_bulk": same}
    lines.append(f"a.compare('critical', ...) on seeds {seeds[:2]} of the fixed track gives the study's critical "
                 f"forces {'exactly' if same else 'NOT exactly (a bug)'}")
    if not args.no_gif:
        result = a.simulate(a.make_scene(spacing="random", seed=0, **size, **studies.SETUPS["fixed"]))
        a.render(result, out / "random_fixed_spring.gif", frames=args.frames or (30 if args.quick else 100))
    held = [c for c in summary["claims"] if c["verdict"] == verdicts.HOLDS]
    lines.append(f"{len(held)} of {len(summary['claims'])} claims hold; every claim with its numbers in summary.json")
    if 0.5 ** args.seeds >= ALPHA:
        need = math.ceil(math.log2(1 / ALPHA))
        lines.append(f"not testable here: {args.seeds} seeds cannot give p < {ALPHA} (a one-sided signed-rank "
                     f"test over n seeds reaches at best 1/2**n); the claims need {need} seeds or more")
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
