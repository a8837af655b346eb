"""Regular against random spacing (Ooten's figure 11)
==================================================

From E. Ooten, *Precision Motion Control at Low Velocities in the Presence of
Friction* (senior thesis, Texas A&M University, 1997-98).

Ooten's figure 11: regular vs random asperity spacing, on the fixed track and the free slider.

Three variants (Ooten's three Working Model runs): regular/regular, random
upper on a regular lower surface ("random-upper"), random on both surfaces
("random"). For each, over ``--seeds`` seeds (regular spacing does not depend
on the seed and is measured once):

* critical force from rest (the headline): the smallest constant force that
  moves the slider, at rest on the surface with every tip against its flank,
  over the whole surface -- Ooten's "force required to move the top
  surface over the bottom surface";
* critical force with a run-up: the same force applied a tenth of a base
  before the surface, so the slider meets the first flank with momentum;
* from one spring-driven pass: the peak stick force over the pass (the
  headline breakaway measure: the force that breaks the engaged slider loose
  at its worst position), the mean stick force, and the first breakaway
  (on the fixed track the front tip entering alone: the same for every
  spacing by construction, reported to show it).

Each random variant is tested against the regular value with a one-sample
Wilcoxon signed-rank test (one-sided, "lower"); "random on both is the
smallest" with a paired Wilcoxon test of random/random against random-upper
(same seed). A verdict "holds" needs p < 0.01 in the claimed direction. Both
set-ups are run: Ooten's fixed-height track (default) and the free slider
under a normal load.

Run::

    python scenes/ooten_spacing.py [--seeds 20] [--workers 2]
"""

from __future__ import annotations

import asperity2d as a
from asperity2d.cli import scripting
from asperity2d.experiments.compare import Comparison, measure_label
from asperity2d.renderers.plots import plot_comparison
from asperity2d.studies import claims
from asperity2d.studies import ooten as studies
from asperity2d.sweep.engine import map_calls

VARIANTS = {"regular": {"spacing": "regular"}, "random-upper": {"spacing": "random-upper"},
            "random": {"spacing": "random"}}
ALPHA = 0.01
#: Measures: name -> key of studies.spring_pass_run's output (pass measures) or None (compare).
MEASURES = {"critical": None, "critical-run-up": None, "peak-stick": "peak_stick_force_N",
            "mean-stick": "mean_stick_force_N", "first-breakaway": "first_breakaway_N"}
HEADLINE = ("critical", "peak-stick")


def measure_setup(setup: str, *, size: dict, seeds: list[int], workers: int) -> dict[str, Comparison]:
    """Every measure's :class:`Comparison` of the three variants on one set-up."""
    base = {**size, **studies.SETUPS[setup]}
    out = {}
    for name in ("critical", "critical-run-up"):
        out[name] = a.compare(name, VARIANTS, seeds, base={**base, "drive": "force"}, progress=False,
                              workers=workers)
    # one spring-driven pass per scene gives all three pass measures
    jobs = [(variant, seed) for variant in VARIANTS for seed in (seeds[:1] if variant == "regular" else seeds)]
    rows = map_calls(studies.spring_pass_run, [{**base, **VARIANTS[v], "seed": s} for v, s in jobs],
                     workers=workers)
    for name, key in MEASURES.items():
        if key is None:
            continue
        values = {v: tuple(r[key] for (w, _), r in zip(jobs, rows) if w == v) for v in VARIANTS}
        values["regular"] = values["regular"] * len(seeds)
        out[name] = Comparison(values=values, seeds=tuple(seeds), variants=VARIANTS,
                               base={**base, "drive": "spring"}, measure=name)
    return out


def claims_for(setup: str, comparisons: dict[str, Comparison]) -> list[dict]:
    """Ooten's figure 11 claims for one set-up, with numbers and tests."""
    out = []
    for name, comparison in comparisons.items():
        label = measure_label(name)
        for variant in ("random-upper", "random"):
            numbers = comparison.versus(variant, "regular", alternative="less")
            out.append(claims.claim(
                f"random spacing ({variant}) lowers the {label}", claims.judge(numbers, ALPHA), numbers,
                f"{numbers['test']}, one-sided (lower): p = {numbers['p_wilcoxon']:.3g}; holds if p < {ALPHA} and the change is at least {100 * claims.MIN_EFFECT:g} %",
                setup=setup) | {"measure": name, "variant": variant})
        both = comparison.versus("random", "random-upper", alternative="less")
        verdict = claims.judge(both, ALPHA)
        if verdict == claims.HOLDS and both["mean"] >= comparison.summary()["regular"]["mean"]:
            verdict = claims.FAILS  # smallest of the three, not just below random-upper
        out.append(claims.claim(
            f"random on both surfaces needs the smallest {label} (figure 11)", verdict, both,
            f"paired Wilcoxon random/random - random-upper (same seeds), one-sided (lower): "
            f"p = {both['p_wilcoxon']:.3g}, and below regular; holds if p < {ALPHA} and the change is at least {100 * claims.MIN_EFFECT:g} %",
            setup=setup) | {"measure": name, "variant": "random vs random-upper"})
    return out


def main(argv=None) -> int:
    args = scripting.study_args(scripting.title(__doc__), argv, default_seeds=20, minimum_seeds=2)
    out = scripting.out_dir(args, __file__)
    size = studies.QUICK_SIZE if args.quick else studies.STUDY_SIZE
    seeds = list(range(args.seeds))
    summary = {"size": size, "seeds": args.seeds, "setups": studies.SETUPS, "alpha": ALPHA,
               "headline_measures": HEADLINE, "results": {}, "claims": []}
    lines = []
    for setup in studies.SETUPS:
        comparisons = measure_setup(setup, size=size, seeds=seeds, workers=args.workers)
        summary["results"][setup] = {}
        for name, comparison in comparisons.items():
            comparison.save(out / f"{setup}_{name}.json")
            plot_comparison(comparison, out / f"{setup}_{name}.png",
                            label=f"{measure_label(name)} (mN), {setup} set-up")
            summary["results"][setup][name] = comparison.summary()
        setup_claims = claims_for(setup, comparisons)
        summary["claims"] += setup_claims
        lines += [claims.verdict_line(c) for c in setup_claims if c["measure"] in HEADLINE or args.quick]
    if not args.no_gif:
        result = a.simulate(a.make_scene(spacing="random", seed=0, **size, **studies.SETUPS["fixed"]))
        a.render(result, out / "random_fixed_spring.gif", frames=args.frames or (30 if args.quick else 100))
    held = [c for c in summary["claims"] if c["verdict"] == claims.HOLDS]
    lines.append(f"{len(held)} of {len(summary['claims'])} claims hold; every claim with its numbers in summary.json")
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
