"""Which asperities carry load on a rough surface
==============================================

Which asperities carry load: the fraction touched over a pass against the fixed track's height.

A Greenwood-Williamson question on Ooten's fixed track. The lower surface
has 24 asperities on a 1 µm base at regular 1.25 µm pitch, their heights drawn
about 0.5 µm with standard deviation 0.1 µm (Gaussian, and uniform with the
same mean and spread); the slider carries one 45° tip and runs on a fixed
track with that tip at height L above the lower base line, pulled through a
spring over the whole surface. Every step is recorded, and an asperity counts
as carrying load if it touches the slider at any step. L goes from
mean - 1.5 std to mean + 1.5 std (the interference below the tallest tip is
set per realisation to put the track at L; a realisation whose tallest summit
is below L has no asperity to touch and is counted as 0 without a run; one
whose tallest summit is less than 2e-3 base (2 nm) above L needs an
interference below the engine's resolution and is left out at that level,
listed in ``left_out_unresolved``).

Claims tested:

* per realisation, exactly: the asperities touched are those whose summit is
  above L (a rigid track sweeps a fixed height; nothing else reaches it), but
  for summits above L by less than the slider's travel in the step a tip
  crossed them: pymunk detects contacts at the steps only, and a slip at
  3-4 km/s moves the slider 30-45 nm per step at the default dt, so a summit
  a few nm above L can pass between two steps. Those are counted
  (``summits_missed_within_one_step``) and the raw comparison is kept
  (``realisations_differing_from_the_geometry``);
* over realisations: the fraction touched is the fraction of summit heights
  above L, the closed form ``asperity2d.surface.fraction_above`` (Gaussian
  tail Q((L - mean) / std), a linear ramp for uniform heights), within three
  binomial standard errors at every level (pooled over seeds: each level has
  24 x seeds i.i.d. asperities).

``--quick`` is a smoke test (6 asperities, two levels, one seed, a 5x faster
drive), not a measurement.

Run::

    python scenes/rough_contact_fraction.py [--quick] [--seeds 6] [--workers auto|N] [--json] [-o DIR]
"""

from __future__ import annotations

import math

import numpy as np

from asperity2d import make_scene
from asperity2d import scripting
from asperity2d.experiments.verdicts import claim, verdict_line
from asperity2d.studies.rough import MIN_LENGTH_RATIO, rough_run
from asperity2d.sweep import map_calls
from asperity2d.surface import fraction_above

# %%
# The settings
# ------------
#
# The heights' mean and spread, the track heights L tried (in standard deviations about the mean)
# and the surfaces' sizes; the quick setting (the one the documentation ran) is a smoke test.

MEAN, STD, BASE = 0.5e-6, 0.1e-6, 1e-6  # m
LEVELS = (-1.5, -1.0, -0.5, 0.0, 0.5, 1.0, 1.5)  # (L - mean) / std
QUICK_LEVELS = (-0.5, 0.5)
SIZE = dict(lower_count=24, upper_count=1)
QUICK_SIZE = dict(lower_count=6, upper_count=1, drive_velocity=100.0)  # a smoke test: 5x faster drive
DISTRIBUTIONS = ("gaussian", "uniform")


# %%
# 1. The runs
# -----------
#
# :func:`asperity2d.make_scene` draws the heights (``lower_height_std``,
# ``height_distribution``); the fixed track's interference below the tallest tip puts the tip at
# height L. :func:`asperity2d.sweep.map_calls` runs :func:`asperity2d.studies.rough.rough_run`
# (one spring-driven pass, every step recorded) for every seed and level, on the workers.

def scene_kw(size: dict, distribution: str) -> dict:
    return dict(size, track="fixed", height=MEAN, lower_height_std=STD, height_distribution=distribution)


def jobs_for(size: dict, distribution: str, levels, seeds) -> tuple[list, list[dict], list[dict]]:
    """Runs to make, the realisations with no summit above the level (no run needed), and those
    whose tallest summit is too close above the level for the engine (left out)."""
    jobs, empty, unresolved = [], [], []
    for seed in seeds:
        top = make_scene(seed=seed, **scene_kw(size, distribution)).lower.top
        for k in levels:
            level = MEAN + k * STD
            row = {"distribution": distribution, "seed": seed, "level_std": k, "level_m": level}
            if level >= top:
                empty.append({**row, "touched_count": 0.0, "above_level_fraction": 0.0,
                              "touched_fraction": 0.0, "touched_matches_above_level": 1.0,
                              "touched_matches_resolvable": 1.0, "missed_within_step": 0.0,
                              "simulated": False})
            elif top - level < MIN_LENGTH_RATIO * BASE:
                # the tallest summit within 2 nm of the track: an interference the engine cannot
                # resolve (under its collision slop); this (seed, level) is left out and counted
                unresolved.append(row)
            else:
                jobs.append((row, dict(scene_kw(size, distribution), seed=seed, critical=False,
                                       interference=top - level)))
    return jobs, empty, unresolved


# %%
# 2. Compare with the closed form
# -------------------------------
#
# :func:`asperity2d.surface.fraction_above` is the fraction of heights above L (the Gaussian tail,
# or a linear ramp for uniform heights); the fraction touched, pooled over seeds, must match it
# within three binomial standard errors, and each realisation must touch exactly its summits above
# L (:func:`asperity2d.experiments.verdicts.claim` records each check).

def analyse(rows: list[dict], size: dict, levels, n_seeds: int) -> tuple[dict, list[dict]]:
    n = size["lower_count"]
    floor = MIN_LENGTH_RATIO * BASE
    table, worst = {}, {}
    for dist in DISTRIBUTIONS:
        table[dist] = {}
        for k in levels:
            sel = [r for r in rows if r["distribution"] == dist and r["level_std"] == k]
            touched = sum(r["touched_count"] for r in sel)
            total = n * len(sel)
            p = fraction_above(MEAN + k * STD, mean=MEAN, std=STD, distribution=dist, floor=floor)
            se = math.sqrt(max(p * (1 - p), 1e-12) / total)
            table[dist][f"{k:g}"] = {"level_m": MEAN + k * STD, "observed": touched / total,
                                     "closed_form": p, "binomial_se": se,
                                     "z": (touched / total - p) / se, "asperities": total}
        worst[dist] = max(abs(v["z"]) for v in table[dist].values())
    mismatched = [r for r in rows if r["touched_matches_resolvable"] != 1.0]
    claims = [claim(
        "per realisation, the asperities touched over the pass are exactly those whose summit is "
        "above the track's tip height, but for summits that rise less above it than the slider "
        "moves in one step", not mismatched,
        {"realisations": len(rows), "simulated": sum(1 for r in rows if r.get("simulated", True)),
         "mismatched": len(mismatched),
         "realisations_differing_from_the_geometry": sum(r["touched_matches_above_level"] != 1.0 for r in rows),
         "summits_missed_within_one_step": sum(r["missed_within_step"] for r in rows),
         "largest_step_m": max((r.get("max_step_travel_m", 0.0) for r in rows), default=0.0)},
        "every run: the set of lower asperities touched at any recorded step == summits above L, "
        "less those above L by less than the slider's travel in the step a tip crossed them "
        "(contacts are detected at the steps only)")]
    for dist in DISTRIBUTIONS:
        claims.append(claim(
            f"{dist} heights: the fraction touched equals the closed-form fraction of summit heights "
            "above the track height", bool(worst[dist] < 3.0), {"max_abs_z": worst[dist]},
            f"|observed - closed form| < 3 binomial SE at each of {len(levels)} levels, "
            f"{n} asperities x {n_seeds} seeds per level"))
    return table, claims


# %%
# 3. Plot
# -------
#
# The closed form against L, and the fraction touched with its two-standard-error bars (a plain
# matplotlib figure).

def plot(table: dict, path) -> None:
    from matplotlib.figure import Figure  # a user's own figure (no pyplot)

    fig = Figure(figsize=(6.5, 3.6), layout="constrained")
    ax = fig.add_subplot()
    grid = np.linspace(MEAN - 2.2 * STD, MEAN + 2.2 * STD, 200)
    for i, (dist, rows) in enumerate(table.items()):
        ax.plot(grid * 1e6, [fraction_above(g, mean=MEAN, std=STD, distribution=dist) for g in grid],
                color=f"C{i}", lw=1, label=f"{dist}: closed form")
        lv = np.array([v["level_m"] for v in rows.values()]) * 1e6
        obs = np.array([v["observed"] for v in rows.values()])
        se = np.array([v["binomial_se"] for v in rows.values()])
        ax.errorbar(lv + 0.004 * (i - 0.5), obs, yerr=2 * se, fmt="o", ms=4, color=f"C{i}",
                    capsize=2, label=f"{dist}: simulated (±2 SE)")
    ax.set_xlabel("fixed-track tip height L (µm above the lower base line)")
    ax.set_ylabel("fraction of lower asperities touched")
    ax.set_title(f"heights {MEAN * 1e6:g} ± {STD * 1e6:g} µm", fontsize=9)
    ax.legend(fontsize=7)
    fig.savefig(path, dpi=120)


# %%
# The command line
# ----------------
#
# ``main`` reads the options (``--quick``, ``--seeds``, ``--workers``, ``-o``, ``--json``), runs
# the steps, draws and prints the numbers and the verdicts.

def main(argv=None) -> int:
    args = scripting.study_args(scripting.title(__doc__), argv, default_seeds=6, minimum_seeds=1,
                                quick_seeds=1)
    out = scripting.out_dir(args, __file__)
    size, levels = (QUICK_SIZE, QUICK_LEVELS) if args.quick else (SIZE, LEVELS)
    seeds = list(range(args.seeds))
    rows, left_out = [], []
    for dist in DISTRIBUTIONS:
        jobs, empty, unresolved = jobs_for(size, dist, levels, seeds)
        measured = map_calls(rough_run, [kw for _, kw in jobs], workers=args.workers)
        rows += [{**row, **m} for (row, _), m in zip(jobs, measured)] + empty
        left_out += unresolved
    table, claims = analyse(rows, size, levels, len(seeds))
    plot(table, out / "contact_fraction.png")
    summary = {"heights_m": {"mean": MEAN, "std": STD}, "base_m": BASE, "size": size,
               "left_out_unresolved": left_out,
               "seeds": args.seeds, "levels_std": list(levels), "fraction": table, "claims": claims,
               "runs": [{k: r[k] for k in ("distribution", "seed", "level_std", "touched_count",
                                          "above_level_fraction", "touched_matches_above_level",
                                          "touched_matches_resolvable", "missed_within_step")}
                        for r in rows],
               "outputs": ["contact_fraction.png"]}
    lines = [f"{d} L = mean {float(k):+g} std: touched {v['observed']:.3f}, closed form {v['closed_form']:.3f} "
             f"(z = {v['z']:+.2f})" for d, t in table.items() for k, v in t.items()]
    lines += [verdict_line(c) for c in claims]
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
