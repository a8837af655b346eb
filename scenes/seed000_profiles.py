"""Seed 000 figures 9-10: full vs half triangles (half triangles need a larger force).

Both surfaces carry the same profile, 45° flanks and the same base (a half
triangle is then twice as tall as a full one); on the fixed track the
interference is the same 0.125 µm for both. For each profile and set-up (free
slider under load; seed 000's fixed-height track):

* ``critical_force_N``: smallest constant push that carries the slider across
  (start from rest, 1 % bisection);
* ``keep_moving_force_N``: force needed to keep the slider moving once it
  moves: the displacement-weighted mean drive force (work / distance) of a
  slow spring-driven pass, counted from the first breakaway on;
* ``mean_drive_force_N``: the time-averaged spring-drive force over the same
  part of the pass;
* ``spring_force_N``: spring-drive breakaway force (free slider) or the
  largest stick-to-slip force of the pass (fixed track, whose first breakaway
  is the entry of the front tip alone).

Ratios half/full are per seed over random-spacing seeds (same seed: same
spacing) with a 95 % t-interval; regular spacing is deterministic. Which
flank limits: the work of the net horizontal contact force on the slider,
split into resisting work (tips climbing the lower asperities' rising flanks)
and forward-pushing work (full triangles: the upper back flank sliding down
the lower front flank as the lower spring recovers; half triangles have a
vertical back face, so there is none).

    python scenes/seed000_profiles.py [--seeds 10] [--workers 2]
"""

from __future__ import annotations

import numpy as np

import asperity2d as a
from asperity2d import stats
from asperity2d.studies import scripting
from asperity2d.studies.claims import claim
from asperity2d.studies import seed000 as studies
from asperity2d.sweep.executors import map_calls
from asperity2d.render.plots import plot_positions

PROFILES = ("full", "half")
QUANTITIES = ("critical_force_N", "keep_moving_force_N", "mean_drive_force_N", "spring_force_N")


def measure(setup: str, *, size: dict, seeds: list[int], workers: int) -> dict:
    """Per profile: the regular values and one value per random seed of every quantity."""
    base = {**size, **studies.SETUPS[setup]}
    jobs = [dict(base, profile=prof, spacing=spacing, seed=seed)
            for prof in PROFILES for spacing, seed in [("regular", 0)] + [("random", s) for s in seeds]]
    critical = map_calls(studies.critical_force_run, jobs, workers=workers)
    passes = map_calls(studies.spring_pass_run, jobs, workers=workers)
    rows = []
    for c, s in zip(critical, passes):
        rows.append({**c, **s, "spring_force_N": s["first_breakaway_N" if setup == "free" else "peak_stick_force_N"],
                     "back_flank_share": s["back_flank_work_J"] / s["front_flank_work_J"]})
    n = len(seeds) + 1
    return {prof: {"regular": rows[i * n], "random": rows[i * n + 1:(i + 1) * n]}
            for i, prof in enumerate(PROFILES)}


def _ratio(num: np.ndarray, den: np.ndarray) -> np.ndarray:
    """num / den, NaN where den is 0 (back-flank shares of zero)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(den != 0, num / np.where(den != 0, den, 1.0), np.nan)


def analyse(setup: str, data: dict) -> tuple[dict, list[dict]]:
    """Numbers per quantity (regular values, random means, half/full ratios) and the claims."""
    numbers, claims = {}, []
    for q in QUANTITIES + ("back_flank_share",):
        full_r, half_r = data["full"]["regular"][q], data["half"]["regular"][q]
        full = np.array([r[q] for r in data["full"]["random"]])
        half = np.array([r[q] for r in data["half"]["random"]])
        numbers[q] = {"regular_full": full_r, "regular_half": half_r,
                      "regular_ratio_half_over_full": half_r / full_r if full_r else float("nan"),
                      "random_full": stats.describe(full), "random_half": stats.describe(half),
                      "random_ratio_half_over_full": stats.describe(_ratio(half, full))}
    for q, text in (("critical_force_N", "critical constant force"),
                    ("keep_moving_force_N", "force to keep the slider moving"),
                    ("mean_drive_force_N", "mean spring-drive force"),
                    ("spring_force_N", "spring-drive breakaway (free) / peak stick (fixed) force")):
        n = numbers[q]
        ratio = n["random_ratio_half_over_full"]
        holds = n["regular_ratio_half_over_full"] > 1.0 and ratio["ci_low"] > 1.0
        claims.append(claim(
            f"half triangles need a larger {text} than full triangles (figures 9-10)", holds, n,
            f"regular: deterministic ratio {n['regular_ratio_half_over_full']:.3f}; random: 95 % "
            f"t-CI of the per-seed ratio half/full over {ratio['n']} seeds "
            f"[{ratio['ci_low']:.3f}, {ratio['ci_high']:.3f}]; holds if both are > 1", setup=setup))
    share = numbers["back_flank_share"]
    holds = (share["regular_full"] > 0.0 and share["random_full"]["mean"] > 0.0
             and share["regular_half"] <= 0.1 * share["regular_full"]
             and share["random_half"]["mean"] <= 0.1 * share["random_full"]["mean"])
    claims.append(claim(
        "with full triangles the lower spring's restoring force pushes the slider forward on the "
        "back flank once a tip is past an apex; half triangles lose contact (figure 9)", holds,
        {**share, "limiting_flank": "front flank climbing for both profiles: the slider stops "
         "with its tips on the lower asperities' rising flanks; back_flank_share is the forward "
         "work returned by back flanks per unit of front-flank (climbing) work"},
        "direct: forward (back-flank) contact work per unit climbing work > 0 for full and at most "
        "a tenth of that for half (regular, and the mean over random seeds)", setup=setup))
    return numbers, claims


def main(argv=None) -> int:
    args = scripting.study_args(__doc__.splitlines()[0], argv, default_seeds=10, minimum_seeds=2)
    n_seeds = args.seeds
    out = scripting.out_dir(args, __file__)
    size = studies.QUICK_SIZE if args.quick else studies.STUDY_SIZE
    summary = {"size": size, "seeds": n_seeds, "setups": studies.SETUPS, "results": {}, "claims": []}
    lines = []
    for setup in studies.SETUPS:
        data = measure(setup, size=size, seeds=list(range(n_seeds)), workers=args.workers)
        numbers, claims = analyse(setup, data)
        summary["results"][setup] = numbers
        summary["claims"] += claims
        for q in QUANTITIES:
            n = numbers[q]
            r = n["random_ratio_half_over_full"]
            lines.append(f"[{setup}] {q}: regular full {n['regular_full'] * 1e3:.4g} mN, half "
                         f"{n['regular_half'] * 1e3:.4g} mN (x{n['regular_ratio_half_over_full']:.3f}); "
                         f"random half/full {r['mean']:.3f} [{r['ci_low']:.3f}, {r['ci_high']:.3f}]")
        lines += [f"[{setup}] {c['claim']}: {c['verdict'].upper()}" for c in claims]
    # Figure 10 analogue: the same constant force (0.97 x the regular half-triangle critical
    # force on the fixed track) pushes a full- and a half-triangle slider.
    base = {**size, **studies.SETUPS["fixed"]}
    force = 0.97 * summary["results"]["fixed"]["critical_force_N"]["regular_half"]
    runs = [a.simulate(a.make_scene(profile=prof, drive="force", drive_force=force, **base))
            for prof in PROFILES]
    plot_positions(runs, [f"{prof} triangles, {force * 1e3:.3g} mN ({r.status})"
                          for prof, r in zip(PROFILES, runs)], out / "positions_fixed.png")
    summary["figure10_runs"] = {prof: r.summary() for prof, r in zip(PROFILES, runs)}
    if not args.no_gif:
        result = a.simulate(a.make_scene(profile="half", **base))
        a.render(result, out / "half_fixed_spring.gif", frames=args.frames or (30 if args.quick else 100))
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    raise SystemExit(main())
