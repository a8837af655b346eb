"""Quickstart: one stick-slip run as a GIF, then regular vs random spacing over seeds.

1. Simulates the default scene (16 regular lower asperities, a slider with 4
   tips under a 10 mN load, pulled through a spring whose far end moves at
   constant speed) and writes ``run.gif`` and ``timeseries.png``.
2. Measures the breakaway force (drive force at the first stick-to-slip
   transition) for regular spacing and for random spacing over several seeds
   and prints the comparison: mean, 95 % CI, Mann-Whitney U and a one-sample
   Wilcoxon test of the random values against the (deterministic) regular one.

    python scenes/quickstart.py [--seeds 10] [--workers 2]
"""

from __future__ import annotations

import os

import asperity2d as a
from asperity2d import scripting
from asperity2d.render.plots import plot_comparison
from asperity2d.studies import breakaway_force_of


def main(argv=None) -> int:
    p = scripting.parser(__doc__.splitlines()[0])
    p.add_argument("--seeds", type=int, default=10)
    p.add_argument("--workers", type=int, default=min(2, os.cpu_count() or 1))
    args = p.parse_args(argv)
    if args.seeds < 2:
        p.error(f"`seeds` must be >= 2, got {args.seeds}")
    out = scripting.out_dir(args, __file__)
    base = {"lower_count": 8, "upper_count": 3} if args.quick else {}

    scene = a.make_scene(**base)
    result = a.simulate(scene, progress=not args.json)
    events = a.stick_slip_events(result)
    a.render(result, out / "timeseries.png", events=events)
    if not args.no_gif:
        a.render(result, out / "run.gif", frames=args.frames or (40 if args.quick else 120))

    comparison = a.compare(breakaway_force_of, {"regular": {"spacing": "regular"},
                                                "random": {"spacing": "random"}},
                           seeds=range(args.seeds), base=base, progress=not args.json,
                           workers=args.workers)
    comparison.save(out / "breakaway_comparison.json")
    plot_comparison(comparison, out / "breakaway_comparison.png")
    stats = comparison.summary()
    regular = stats["regular"]["mean"]
    random_ = stats["random"]
    summary = {
        "run": result.summary(), "events": a.event_statistics(events),
        "breakaway_force_N": a.breakaway_force(result),
        "breakaway": stats,
        "random_minus_regular_N": random_["mean"] - regular,
        "random_over_regular": random_["mean"] / regular,
        "mann_whitney_p": comparison.mann_whitney("regular", "random"),
        "wilcoxon_random_vs_regular_p": comparison.one_sample("random", regular),
    }
    lines = [
        f"run: {result.status} after {result.t[-1] * 1e6:.3g} us, {len(events)} stick-slip events, "
        f"breakaway {summary['breakaway_force_N'] * 1e3:.3f} mN -> {out / 'run.gif'}",
        f"breakaway force over {args.seeds} seeds (mN):",
        f"  regular  {regular * 1e3:.3f} (deterministic)",
        f"  random   {random_['mean'] * 1e3:.3f}  95 % CI [{random_['ci_low'] * 1e3:.3f}, "
        f"{random_['ci_high'] * 1e3:.3f}]  std {random_['std'] * 1e3:.3f}",
        f"  random / regular = {summary['random_over_regular']:.3f}; "
        f"Wilcoxon vs regular p = {summary['wilcoxon_random_vs_regular_p']:.3g}; "
        f"Mann-Whitney p = {summary['mann_whitney_p']:.3g}",
    ]
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    raise SystemExit(main())
