"""Quickstart: a stick-slip run, then regular against random spacing
=================================================================

From E. Ooten, *Precision Motion Control at Low Velocities in the Presence of
Friction* (senior thesis, Texas A&M University, 1997-98).

The package's main job, on Ooten's own Working Model set-up (the package default): 16
regular lower asperities on spring-damper tracks, a slider with 4 tips on a
fixed-height horizontal track.

1. A spring whose far end moves at constant speed pulls the slider over the
   surface: it sticks and slips. Writes ``run.gif`` (the scene with its
   meters, slips in slow motion), ``run.html`` (the same run in an
   interactive player: open it in a browser) and ``timeseries.png``.
2. Regular against random spacing (both surfaces random, Ooten's figure
   11) over ``--seeds`` seeds, two measures of the force that breaks the
   slider loose: the critical force from rest (the smallest constant force
   that moves the slider, at rest on the surface, all the way across) and
   the peak stick force of spring-driven passes (the mean of three passes
   whose drive speeds differ by 0.02 %: which positions one pass sticks at
   is chaotic). Each is judged by a one-sided Wilcoxon test against the
   regular value (holds if p < 0.01 and the change is at least 1 %, twice
   the model's force resolution), with the ratio random / regular and its
   95 % interval, on the fixed track and, beside it, on the free slider
   under a 10 mN load.

Run::

    python scenes/quickstart.py [--seeds 8] [--workers auto|N]
"""

from __future__ import annotations

import math

import asperity2d as a
from asperity2d._format import si
from asperity2d.cli import scripting
from asperity2d.experiments.measures import MEASURES as NAMED, measure_label
from asperity2d.renderers.plots import plot_comparison
from asperity2d.studies import claims

MEASURES = ("critical", "peak-stick")
ALPHA = NAMED["critical"].rule.alpha  # every measure's rule: p < 0.01


def main(argv=None) -> int:
    args = scripting.study_args(scripting.title(__doc__), argv, default_seeds=8, minimum_seeds=2)
    out = scripting.out_dir(args, __file__)
    size = {"lower_count": 8, "upper_count": 3} if args.quick else {}

    scene = a.make_scene(**size)
    result = a.simulate(scene, progress=not args.json)
    events = a.stick_slip_events(result)
    a.render(result, out / "timeseries.png", events=events)
    if not args.no_gif:
        a.render(result, out / "run.gif", frames=args.frames or (40 if args.quick else 120))
    a.render(result, out / "run.html")
    flank = math.tan(math.radians(scene.lower.profile.flank_angle) + math.atan(scene.contact.mu_static))
    all_tips = scene.slider.count * scene.lower.stiffness[0] * scene.slider.interference * flank

    variants = {"regular": {"spacing": "regular"}, "random": {"spacing": "random"}}
    summary = {"run": result.summary(), "events": a.event_statistics(events),
               "peak_stick_force_N": a.peak_stick_force(result), "flank_law_all_tips_N": all_tips,
               "seeds": args.seeds, "alpha": ALPHA, "comparisons": {}, "claims": []}
    verdicts = {}
    for setup in ("fixed", "free"):
        for name in MEASURES:
            drive = NAMED[name].drive
            comparison = a.compare(name, variants, range(args.seeds), progress=not args.json,
                                   base={**size, "track": setup, "drive": drive}, workers=args.workers)
            comparison.save(out / f"{setup}_{name}.json")
            plot_comparison(comparison, out / f"{setup}_{name}.png",
                            label=f"{measure_label(name)} (mN), {setup} set-up")
            # the measure's own rule: one-sided Wilcoxon, holds if p < 0.01 and the change >= 1 %
            record = comparison.verdict("random", "regular", subject="random spacing", setup=setup)
            summary["comparisons"][f"{setup}/{name}"] = comparison.summary()
            summary["claims"].append(record)
            verdicts[setup, name] = record

    lines = [
        f"stick-slip run on Ooten's set-up ({scene.lower.count} regular lower asperities, a slider with "
        f"{scene.slider.count} tips on a fixed-height track, spring drive): {len(events)} stick-slip events; "
        f"the peak stick force {si(summary['peak_stick_force_N'], 'N')} is the flank law for all "
        f"{scene.slider.count} tips at once ({si(all_tips, 'N')}) -> {out / 'run.gif'}, {out / 'run.html'}",
        f"Does random spacing lower the force that breaks the slider loose? {args.seeds} seeds, "
        f"Ooten's fixed track; the free slider under a 10 mN load beside it:",
    ]
    for name in MEASURES:
        fixed, free = verdicts["fixed", name], verdicts["free", name]
        lines.append(f"  {claims.verdict_line({**fixed, 'setup': None})}"
                     f"  | free slider: {free['verdict']} ({claims.effect(free['numbers'])})")
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
