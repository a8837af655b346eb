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
   11), two measures of the force that breaks the slider loose: the
   critical force from rest (the smallest constant force that moves the
   slider, at rest on the surface, all the way across) and the peak stick
   force of spring-driven passes (the mean of three passes whose drive
   speeds differ by 0.02 %: which positions one pass sticks at is chaotic),
   on the fixed track and, beside it, on the free slider under a 10 mN
   load. Seeds are added in stages of 10 until each verdict is decided, up
   to ``--max-seeds`` (30): it *holds* (a one-sided Wilcoxon test against
   the regular value and a change of at least 1 %, twice the model's force
   resolution), there is *no effect* (the ratio random / regular is shown
   to lie within 1 % of 1), or it *does not hold* (shown the other way);
   otherwise it is *undecided*, with the seeds that would decide it. Each
   line says how many seeds its verdict took.

Run::

    python scenes/quickstart.py [--seeds auto|N] [--max-seeds 30] [--workers auto|N]
"""

# %%
# The lesson is in three functions, each made only of the package's public calls; ``main`` at
# the bottom reads the command line and prints. The gallery ran it with ``--quick`` (8 lower and
# 3 upper asperities, 2 seeds), so its verdicts below say "not testable": a one-sided
# signed-rank test over n seeds cannot give p below 1/2**n, and 2 seeds give at best 0.25; the
# claim needs 7 seeds or more. The default run adds seeds in stages of 10, up to 30, until
# each verdict is decided.

from __future__ import annotations

import math

import asperity2d as a
from asperity2d import scripting
from asperity2d.experiments.measures import MEASURES as NAMED, measure_label
from asperity2d.experiments.verdicts import outcome_text, verdict_line

MEASURES = ("critical", "peak-stick")
ALPHA = NAMED["critical"].rule.alpha  # every measure's verdict rule: p < 0.01
#: The seed budget of the default run: three stages of 10. The fixed-track lines decide at the
#: first stage; the free slider's critical force, a change of about 1-2 % against a 1.7 % per-seed
#: spread, needs more.
MAX_SEEDS = 30


# %%
# 1. One stick-slip run
# ---------------------
#
# :func:`asperity2d.make_scene` with no arguments is Ooten's set-up; :func:`asperity2d.simulate`
# runs it until the slider has passed, :func:`asperity2d.stick_slip_events` cuts the motion
# into stick-slip cycles, and :func:`asperity2d.render` picks a picture by the file's extension.
# On a regular surface every tip meets its asperity at once, so the largest force before a
# slip is the flank law for all n tips: n k delta tan(theta + atan mu_s).

def stick_slip_run(out, size: dict, frames: int | None, progress: bool):
    """The run, its events and pictures, and the flank law for all tips (N)."""
    scene = a.make_scene(**size)
    result = a.simulate(scene, progress=progress)
    events = a.stick_slip_events(result)
    a.render(result, out / "timeseries.png", events=events)
    if frames:
        a.render(result, out / "run.gif", frames=frames)
    a.render(result, out / "run.html")
    flank = math.tan(math.radians(scene.lower.profile.flank_angle) + math.atan(scene.contact.mu_static))
    all_tips = scene.slider.count * scene.lower.stiffness[0] * scene.slider.interference * flank
    return scene, result, events, all_tips


# %%
# 2. Regular against random spacing, over seeds
# ---------------------------------------------
#
# :func:`asperity2d.compare` measures each variant on each seed: the critical force from rest
# under a constant force, and the peak stick force of spring-driven passes, on Ooten's fixed
# track and on the free slider under a 10 mN load. With ``seeds="auto"`` it adds seeds in
# stages until the verdict against the regular surface is decided, under a sequential design
# that keeps the chance of a false verdict at 0.01 despite looking after every stage.
# ``engine="auto"``: where Numba is installed (the ``[batch]`` extra), the comparisons the batched
# engine covers (every one here: the critical forces and the peak stick forces, on both set-ups)
# run on it, every run of a stage in one batch, and
# the summary says so; everything else, and every run without Numba, runs on pymunk.

def spacing_comparison(measure: str, setup: str, size: dict, seeds: int | str, workers, progress: bool,
                       max_seeds: int = MAX_SEEDS):
    """Regular against random spacing: one ``measure`` per variant and seed."""
    variants = {"regular": {"spacing": "regular"}, "random": {"spacing": "random"}}
    drive = NAMED[measure].drive  # the drive the measure needs, from its registry entry
    auto = seeds == "auto"
    return a.compare(measure, variants, "auto" if auto else range(seeds), progress=progress,
                     base={**size, "track": setup, "drive": drive}, workers=workers,
                     max_seeds=max_seeds if auto else None, engine="auto")


# %%
# 3. The verdict
# --------------
#
# Each measure carries its verdict rule (``asperity2d.experiments.measures.MEASURES``):
# a one-sided Wilcoxon test of the random values against the regular one, and the
# Hodges-Lehmann ratio random / regular with its 95 % interval. The claim holds if p < 0.01 and
# the change is at least 1 % (twice the model's force resolution); there is no effect if the
# ratio's 98 % interval lies within 1 % of 1; it does not hold if shown the other way; it is
# undecided otherwise (with the seeds that would decide it), and not testable when even every
# seed below could not reach p < 0.01. Seeds added in stages are judged at each stage's
# stricter level. :meth:`asperity2d.Comparison.verdict` applies it.

def verdict(comparison, setup: str) -> dict:
    """The claim record: the statement, its verdict and the numbers behind it."""
    return comparison.verdict("random", "regular", subject="random spacing", setup=setup)


# %%
# The command line
# ----------------
#
# ``main`` reads the options (``--quick``, ``--seeds``, ``--workers``, ``-o``, ``--json``), runs
# the three steps and prints the summary.

def main(argv=None) -> int:
    si = scripting.si
    args = scripting.study_args(scripting.title(__doc__), argv, default_seeds="auto", minimum_seeds=2,
                                auto=True, default_max_seeds=MAX_SEEDS)
    out = scripting.out_dir(args, __file__)
    size = {"lower_count": 8, "upper_count": 3} if args.quick else {}
    frames = None if args.no_gif else args.frames or (40 if args.quick else 120)
    scene, result, events, all_tips = stick_slip_run(out, size, frames, progress=not args.json)

    summary = {"run": result.summary(), "events": a.event_statistics(events),
               "peak_stick_force_N": a.peak_stick_force(result), "flank_law_all_tips_N": all_tips,
               "seeds": args.seeds, "alpha": ALPHA, "comparisons": {}, "claims": []}
    if args.seeds == "auto":
        summary["max_seeds"] = args.max_seeds
    verdicts, engines = {}, {}
    for setup in ("fixed", "free"):
        for name in MEASURES:
            comparison = spacing_comparison(name, setup, size, args.seeds, args.workers, not args.json,
                                            max_seeds=getattr(args, "max_seeds", MAX_SEEDS))
            comparison.save(out / f"{setup}_{name}.json")
            a.render(comparison, out / f"{setup}_{name}.png",
                     label=f"{measure_label(name)} (mN), {setup} set-up")
            record = verdict(comparison, setup)
            summary["comparisons"][f"{setup}/{name}"] = comparison.summary()
            summary["claims"].append(record)
            verdicts[setup, name] = record
            engines[f"{setup}/{name}"] = comparison.engine

    lines = [
        f"stick-slip run on Ooten's set-up ({scene.lower.count} regular lower asperities, a slider with "
        f"{scene.slider.count} tips on a fixed-height track, spring drive): {len(events)} stick-slip events; "
        f"the peak stick force {si(summary['peak_stick_force_N'], 'N')} is the flank law for all "
        f"{scene.slider.count} tips at once ({si(all_tips, 'N')}) -> {out / 'run.gif'}, {out / 'run.html'}",
        f"Does random spacing lower the force that breaks the slider loose? "
        + (f"Seeds added in stages of 10 until decided (at most {args.max_seeds})" if args.seeds == "auto"
           else f"{args.seeds} seeds") + ", Ooten's fixed track; the free slider under a 10 mN load beside it:",
    ]
    for name in MEASURES:
        fixed, free = verdicts["fixed", name], verdicts["free", name]
        lines.append(f"  {verdict_line({**fixed, 'setup': None})}"
                     f"  | free slider: {outcome_text(free['verdict'], free['numbers'])}")
    batched = [key for key, engine in engines.items() if engine != "pymunk"]
    if batched:  # said only when it happened: without Numba the summary is as it always was
        summary["engines"] = engines
        lines.append(f"engine: {engines[batched[0]]} (Numba) for {', '.join(batched)}; "
                     "pymunk (the reference) for the rest and the stick-slip run")
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
