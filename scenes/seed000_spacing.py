"""Seed 000 figure 11: regular vs random asperity spacing, free slider and fixed track.

Three variants (seed 000's three Working Model runs): regular/regular,
random upper on a regular lower surface ("random-upper"), random on both
surfaces ("random"). For each, over ``--seeds`` seeds (random spacings only;
regular is deterministic):

* the critical constant force (N, smallest constant push that carries the
  slider across the whole lower surface, 1 % bisection);
* the spring-drive force (N): on the free slider the breakaway force (drive
  force at the first stick-to-slip transition); on the fixed track the largest
  stick-to-slip force of a full pass (its first breakaway happens while only
  the front tip has entered the surface, so it measures the entry, not the
  spacing).

Each random variant is tested against the deterministic regular value with a
one-sample Wilcoxon signed-rank test (one-sided, "lower"); "random on both is
the smallest" with a paired Wilcoxon test of random/random against
random-upper (same seed, same upper spacing). A verdict "holds" needs p < 0.01
in the claimed direction. Both set-ups are run: the free slider under a
normal load (package default) and seed 000's fixed-height horizontal track.

    python scenes/seed000_spacing.py [--seeds 20] [--workers 2]
"""

from __future__ import annotations

import numpy as np

import asperity2d as a
from asperity2d import scripting, studies
from asperity2d.render.plots import plot_comparison

VARIANTS = {"regular": {"spacing": "regular"}, "random-upper": {"spacing": "random-upper"},
            "random": {"spacing": "random"}}
ALPHA = 0.01


def measure_setup(setup: str, *, size: dict, seeds: list[int], workers: int) -> dict:
    """Critical force and spring-drive force comparisons (:class:`Comparison`) for one set-up."""
    base = {**size, **studies.SETUPS[setup]}
    spring_measure = studies.breakaway_force_of if setup == "free" else studies.peak_spring_force_of
    out = {}
    for key, measure, drive in (("critical_force", studies.critical_force_of, "force"),
                                ("spring_force", spring_measure, "spring")):
        randoms = {k: v for k, v in VARIANTS.items() if k != "regular"}
        comparison = a.compare(measure, randoms, seeds=seeds, base={**base, "drive": drive},
                               progress=False, workers=workers)
        regular = float(measure(a.make_scene(spacing="regular", drive=drive, **base)))
        values = {"regular": (regular,) * len(seeds), **comparison.values}
        out[key] = a.Comparison(values=values, seeds=comparison.seeds, variants=VARIANTS,
                                base={**base, "drive": drive}, measure=measure.__name__)
    return out


def claims_for(setup: str, comparisons: dict) -> list[dict]:
    """Seed-000 figure-11 claims for one set-up, with numbers and tests."""
    from scipy import stats

    claims = []
    labels = {"critical_force": "critical constant force",
              "spring_force": "spring-drive breakaway force" if setup == "free"
              else "spring-drive peak stick force over a full pass"}
    for key, comparison in comparisons.items():
        regular = comparison.values["regular"][0]
        tests = {}
        for name in ("random-upper", "random"):
            numbers = studies.versus_reference(comparison.values[name], regular, alternative="less")
            tests[name] = numbers
            holds = numbers["mean"] < regular and numbers["p_wilcoxon"] < ALPHA
            claims.append(studies.claim(
                f"random spacing ({name}) lowers the {labels[key]} below regular/regular "
                "(figure 11)", holds, numbers,
                f"one-sample Wilcoxon signed-rank vs regular value, one-sided (lower), "
                f"p = {numbers['p_wilcoxon']:.3g}; holds if p < {ALPHA}", setup=setup))
        both = np.asarray(comparison.values["random"])
        upper = np.asarray(comparison.values["random-upper"])
        diff = both - upper
        ok = np.isfinite(diff)
        p_pair = float(stats.wilcoxon(diff[ok], alternative="less").pvalue) if np.any(diff[ok]) else 1.0
        smallest = (tests["random"]["mean"] < tests["random-upper"]["mean"] < regular
                    or tests["random"]["mean"] < min(tests["random-upper"]["mean"], regular))
        holds = bool(smallest and p_pair < ALPHA and tests["random"]["p_wilcoxon"] < ALPHA)
        claims.append(studies.claim(
            f"random on both surfaces needs the smallest {labels[key]} (figure 11)", holds,
            {"mean_regular": regular, "mean_random_upper": tests["random-upper"]["mean"],
             "mean_random": tests["random"]["mean"],
             "mean_paired_difference_random_minus_random_upper": float(np.nanmean(diff)),
             "p_paired_wilcoxon": p_pair, "p_random_vs_regular": tests["random"]["p_wilcoxon"]},
            f"paired Wilcoxon signed-rank random/random - random-upper (same seeds), one-sided "
            f"(lower), p = {p_pair:.3g}, and random/random below regular; holds if both p < {ALPHA}",
            setup=setup))
    return claims


def main(argv=None) -> int:
    args = scripting.study_args(__doc__.splitlines()[0], argv, default_seeds=20, minimum_seeds=2)
    n_seeds = args.seeds
    out = scripting.out_dir(args, __file__)
    size = studies.QUICK_SIZE if args.quick else studies.STUDY_SIZE
    seeds = list(range(n_seeds))
    summary = {"size": size, "seeds": n_seeds, "setups": studies.SETUPS, "alpha": ALPHA,
               "results": {}, "claims": []}
    lines = []
    for setup in studies.SETUPS:
        comparisons = measure_setup(setup, size=size, seeds=seeds, workers=args.workers)
        summary["results"][setup] = {}
        for key, comparison in comparisons.items():
            comparison.save(out / f"{setup}_{key}.json")
            plot_comparison(comparison, out / f"{setup}_{key}.png", label=f"{key} (N), {setup} slider")
            summary["results"][setup][key] = comparison.summary()
        claims = claims_for(setup, comparisons)
        summary["claims"] += claims
        for c in claims:
            n = c["numbers"]
            effect = (f"mean {n['mean'] * 1e3:.4g} mN vs regular {n['reference'] * 1e3:.4g} mN, "
                      f"diff {n['relative_difference'] * 100:+.1f} %, d = {n['effect_size_d']:.2f}, "
                      f"p = {n['p_wilcoxon']:.2g}") if "reference" in n else \
                f"paired p = {n['p_paired_wilcoxon']:.2g}"
            lines.append(f"[{setup}] {c['claim']}: {c['verdict'].upper()} ({effect})")
    if not args.no_gif:
        base = {**size, **studies.SETUPS["fixed"]}
        result = a.simulate(a.make_scene(spacing="random", seed=0, **base))
        a.render(result, out / "random_fixed_spring.gif", frames=args.frames or (30 if args.quick else 100))
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    raise SystemExit(main())
