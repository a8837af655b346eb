"""Regular against random spacing (Ooten's figure 11)
==================================================

From E. Ooten, *Precision Motion Control at Low Velocities in the Presence of
Friction* (senior thesis, Texas A&M University, 1997-98).

Ooten's figure 11: regular vs random asperity spacing, on the fixed track and the free slider.

Three variants (Ooten's three Working Model runs): regular/regular, random
upper on a regular lower surface ("random-upper"), random on both surfaces
("random"). Every named measure (:mod:`asperity2d.experiments.measures`) of
every scene, over ``--seeds`` seeds (regular spacing does not depend on the
seed and is measured once):

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

Each random variant is tested against the regular value with a one-sample
Wilcoxon signed-rank test (one-sided, "lower"); "random on both is the
smallest" with a paired Wilcoxon test of random/random against random-upper
(same seed). A verdict "holds" needs p < 0.01 in the claimed direction and a
change of at least 1 %. Every claim states its effect as a ratio with the
Hodges-Lehmann 95 % interval of the per-seed ratios
(:func:`asperity2d.stats.relative_effect`). Both set-ups are run: Ooten's
fixed-height track (default) and the free slider under a normal load.

Run::

    python scenes/ooten_spacing.py [--seeds 24] [--workers auto|N]
"""

from __future__ import annotations

import math

import numpy as np

import asperity2d as a
from asperity2d import stats
from asperity2d import scripting
from asperity2d.experiments.compare import Comparison
from asperity2d.experiments.measures import measure_label
from asperity2d.experiments import verdicts
from asperity2d.studies import ooten as studies
from asperity2d.sweep import map_calls

VARIANTS = {"regular": {"spacing": "regular"}, "random-upper": {"spacing": "random-upper"},
            "random": {"spacing": "random"}}
ALPHA = 0.01
#: Measures: name -> key of studies.measures_run's output.
MEASURES = {"critical": "critical_rest_N", "critical-run-up": "critical_run_up_N",
            "quasi-static-breakaway": "quasi_static_N", "peak-stick": "peak_stick_N",
            "mean-stick": "mean_stick_N", "first-breakaway": "first_breakaway_N"}
HEADLINE = ("critical", "peak-stick")


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


def comparisons(rows: dict, seeds: list[int], setup: str) -> dict[str, Comparison]:
    """Per measure the rows carry: every variant over the seeds."""
    return {name: Comparison(values={v: tuple(r[key] for r in rows[v]) for v in VARIANTS}, seeds=tuple(seeds),
                             variants=VARIANTS, base=dict(studies.SETUPS[setup]), measure=name)
            for name, key in MEASURES.items() if key in rows["regular"][0]}


def with_effect(numbers: dict, values, reference) -> dict:
    """``numbers`` plus the Hodges-Lehmann ratio and its 95 % interval (``ratio_hl``,
    ``ratio_ci_low``, ``ratio_ci_high``) of ``values`` against ``reference`` (a value or
    per-seed values)."""
    e = stats.relative_effect(values, reference)
    return {**numbers, "ratio_hl": e["ratio"], "ratio_ci_low": 1 + e["ci_low"], "ratio_ci_high": 1 + e["ci_high"],
            "ci_level": e["level"]}


def claims_for(setup: str, found: dict[str, Comparison]) -> list[dict]:
    """Ooten's figure 11 claims for one set-up, with numbers, effect sizes and tests."""
    out = []
    for name, comparison in found.items():
        label = measure_label(name)
        regular = comparison.values["regular"][0]
        for variant in ("random-upper", "random"):
            numbers = with_effect(comparison.versus(variant, "regular", alternative="less"),
                                  comparison.values[variant], regular)
            out.append(verdicts.claim(
                f"random spacing ({variant}) lowers the {label}", verdicts.judge(numbers, ALPHA), numbers,
                f"{numbers['test']}, one-sided (lower): p = {numbers['p_wilcoxon']:.3g}; holds if p < {ALPHA} "
                f"and the change is at least {100 * verdicts.MIN_EFFECT:g} %", setup=setup)
                | {"measure": name, "variant": variant})
        both = with_effect(comparison.versus("random", "random-upper", alternative="less"),
                           comparison.values["random"], comparison.values["random-upper"])
        verdict = verdicts.judge(both, ALPHA)
        if verdict == verdicts.HOLDS and both["mean"] >= comparison.summary()["regular"]["mean"]:
            verdict = verdicts.FAILS  # smallest of the three, not just below random-upper
        means = {v: s["mean"] for v, s in comparison.summary().items()}
        both["smallest_variant"] = min(means, key=lambda v: means[v] if math.isfinite(means[v]) else math.inf)
        out.append(verdicts.claim(
            f"random on both surfaces needs the smallest {label} (figure 11)", verdict, both,
            f"paired Wilcoxon random/random - random-upper (same seeds), one-sided (lower): "
            f"p = {both['p_wilcoxon']:.3g}, and below regular; holds if p < {ALPHA} and the change is at least "
            f"{100 * verdicts.MIN_EFFECT:g} %", setup=setup) | {"measure": name, "variant": "random vs random-upper"})
    return out


def bands(rows: dict) -> dict:
    """How many critical forces of each variant found passing non-monotone (a band)."""
    out = {}
    for start in ("rest", "run_up"):
        key = f"critical_{start}_band_low_N"
        out[start] = {v: int(sum(np.isfinite(r[key]) for r in rs)) for v, rs in rows.items()}
    return out


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
            a.render(comparison, out / f"{setup}_{name}.png",
                            label=f"{measure_label(name)} (mN), {setup} set-up")
            summary["results"][setup][name] = comparison.summary()
        setup_claims = claims_for(setup, found)
        summary["claims"] += setup_claims
        lines += [verdicts.verdict_line(c) for c in setup_claims if c["measure"] in HEADLINE or args.quick]
    if not args.no_gif:
        result = a.simulate(a.make_scene(spacing="random", seed=0, **size, **studies.SETUPS["fixed"]))
        a.render(result, out / "random_fixed_spring.gif", frames=args.frames or (30 if args.quick else 100))
    held = [c for c in summary["claims"] if c["verdict"] == verdicts.HOLDS]
    lines.append(f"{len(held)} of {len(summary['claims'])} claims hold; every claim with its numbers in summary.json")
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
