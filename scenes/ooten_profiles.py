"""Full against half triangles (Ooten's figures 9-10)
==================================================

From E. Ooten, *Precision Motion Control at Low Velocities in the Presence of
Friction* (senior thesis, Texas A&M University, 1997-98).

Ooten's figures 9-10: full vs half triangles (half triangles need a larger force).

A half triangle is Ooten's: the full triangle cut through its apex (same
height and 45° flank, half the base, one vertical face). Both surfaces carry
the same profile with every tip in the same place (regular pitch, or the same
random draws: see ``HALF``); on the fixed track the tips run the same 0.125 µm
into the lower surface. Ooten's explanation: with full triangles
the lower spring's restoring force pushes the slider on along the back flank
once a tip is past an apex; a half triangle's vertical back face loses
contact. Each set-up is run with static > kinetic friction (mu_s 0.3, mu_k
0.2, the default) and with mu_s = mu_k = 0.3, which separates that back-flank
push (geometry) from the static/kinetic friction switch (the free slider: the
default pair only). Per run:

* the critical force (N) from every start: from rest on the surface (a step
  load), from rest against the first flank (``entry``) and with the builder's
  run-up (a momentum threshold, what figure 10's slider had);
* the quasi-static breakaway (N): a slowly ramped force from rest;
* figure 10 itself: the travel (m) under one constant force, 0.9 x the half
  triangles' run-up critical force of that seed, for both profiles;
* from one spring-driven pass: the first breakaway, the peak and mean stick
  force (one pass: chaotic, see :mod:`asperity2d.experiments.measures`), the
  force to keep the slider moving (work / distance from the first breakaway
  on, N), and the contact work books
  (``asperity2d.engine.energy.ContactWork``): the work of contacts
  pushing the slider on (J) against the work of those resisting it.

Regular spacing gives one deterministic half/full ratio; random spacing (both
surfaces) is paired by seed (same seed, same draws) and judged by a one-sided
paired Wilcoxon test (half > full, holds if p < 0.01 and the change is at least 1 %). The free slider's
half triangles can fall through the 0.75 µm gaps between lower asperities
onto the floor guard (the floor does work on the slider): such runs are left
out (counted as missing); the free slider is also compared with full-base
half triangles (``half_shape="full-base"``: the full base and flank angle,
twice the height), which cannot fall through. ``--quick`` runs the first
friction pair only.

The lesson: pairing two variants seed by seed (the same random draws) and
judging a one-sided claim with its effect size; then the mechanism behind it
in the runs' own energy books.

Run::

    python scenes/ooten_profiles.py [--seeds 24] [--workers auto|N]
"""

# %%
# The steps are functions made of the package's public calls; ``main`` at the bottom reads the
# command line, runs them and prints. The gallery runs it with ``--quick`` (4 lower and 2 upper
# asperities, 2 seeds, the first friction pair, no slow ramp): its verdicts read "not testable",
# because a one-sided signed-rank test over n seeds cannot give p below 1/2**n (0.25 for 2
# seeds); a verdict needs 7 seeds or more (the default run uses 24).

from __future__ import annotations

import math

import numpy as np

import asperity2d as a
from asperity2d import stats
from asperity2d.experiments.compare import Comparison
from asperity2d.experiments.measures import measure_label
from asperity2d import scripting
from asperity2d.experiments import verdicts
from asperity2d.studies import ooten as studies
from asperity2d.sweep import map_calls

ALPHA = 0.01
FRICTIONS = {"mu_s > mu_k": {"mu_static": 0.3, "mu_kinetic": 0.2},
             "mu_s = mu_k": {"mu_static": 0.3, "mu_kinetic": 0.3}}
#: Ooten's half triangle. Random gaps are drawn as base + min_gap + U x 2 (pitch - base -
#: min_gap): with half the base, ``min_gap`` = half a base keeps every tip where the full
#: triangles' are (same seed, same U), so random spacing is as irregular for both profiles
#: (without it the half-triangle surfaces would be three times as irregular).
HALF = {"profile": "half", "min_gap": 0.5e-6}
#: Figure 10's force: this fraction of the half triangles' critical force with a run-up.
TRAVEL_FACTOR = 0.9
FULL_BASE_HALF = {"profile": "half", "half_shape": "full-base"}
#: Per set-up: the half triangles compared with the full ones.
HALVES = {"fixed": {"half": HALF}, "free": {"half": HALF, "half (full-base)": FULL_BASE_HALF}}
#: Measure -> (key of the run's numbers, label with unit).
MEASURES = {
    "critical": ("critical_rest_N", f"{measure_label('critical')} (N)"),
    "critical-entry": ("critical_entry_N", "critical force from rest at the entry (N)"),
    "critical-run-up": ("critical_run_up_N", f"{measure_label('critical-run-up')} (N)"),
    "quasi-static-breakaway": ("quasi_static_N", f"{measure_label('quasi-static-breakaway')} (N)"),
    "travel": ("travel_m", "travel under 0.9 x the half triangles' run-up critical force (m)"),
    "peak-stick": ("peak_stick_force_N", "peak stick force of one pass (N)"),
    "mean-stick": ("mean_stick_force_N", "mean stick force of one pass (N)"),
    "keep-moving": ("keep_moving_force_N", "force to keep the slider moving, work / distance (N)"),
    "first-breakaway": ("first_breakaway_N", f"{measure_label('first-breakaway')} (N)"),
}


# %%
# 2. Measure both profiles over seeds
# -----------------------------------
#
# One job per scene, run on worker processes by :func:`asperity2d.sweep.map_calls`:
# ``studies.measures_run`` takes the critical force from every start
# (:func:`asperity2d.critical_force_bracket`) and the quasi-static breakaway;
# ``studies.spring_pass_run`` one spring-driven pass with its contact-work books;
# ``studies.travel_run`` figure 10's travel under one constant force. A free slider whose half
# triangles fell between two lower asperities onto the floor guard is left out.

def measure(setup: str, friction: str, *, size: dict, seeds: list[int], workers: int | None,
            quasi_static: bool = True) -> dict:
    """{profile: {"regular": row, "random": [row per seed]}} of one set-up and friction pair;
    a row holds the critical force and the spring pass's numbers (with contact work)."""
    base = {**size, **studies.SETUPS[setup], **FRICTIONS[friction]}
    profiles = {"full": {"profile": "full"}, **HALVES[setup]}
    cases = [("regular", 0)] + [("random", s) for s in seeds]
    jobs = [dict(base, **shape, spacing=spacing, seed=seed) for shape in profiles.values() for spacing, seed in cases]
    forces = map_calls(studies.measures_run, [dict(j, starts=("rest", "entry", "run-up"), passes=0,
                                                   quasi_static=quasi_static) for j in jobs], workers=workers)
    passes = map_calls(studies.spring_pass_run, [dict(j, contact_work=True) for j in jobs], workers=workers)
    # figure 10: one force per case for every profile, 0.9 x the half triangles' run-up critical force
    half_rows = forces[list(profiles).index("half") * len(cases):][:len(cases)]
    push = [TRAVEL_FACTOR * r["critical_run_up_N"] for r in half_rows]
    travel = map_calls(studies.travel_run, [dict(j, force=push[i % len(cases)]) for i, j in enumerate(jobs)],
                       workers=workers)
    rows = [{**f, **p, **{k: v for k, v in t.items() if k != "force_N"}, "travel_force_N": t["force_N"],
             "fell_through": float(fell_through(p))} for f, p, t in zip(forces, passes, travel)]
    for row in rows:
        if row["fell_through"]:  # no longer a contact of two surfaces: measure nothing
            row.update({key: math.nan for key, _ in MEASURES.values()})
    n = len(seeds) + 1
    return {name: {"regular": rows[i * n], "random": rows[i * n + 1:(i + 1) * n]}
            for i, name in enumerate(profiles)}


def fell_through(row: dict) -> bool:
    """Did the slider's tips fall through the lower surface onto the floor guard (the floor
    did work on it) during the spring pass?"""
    return row["floor_work_J"] != 0.0


# %%
# 3. Half against full, seed by seed
# ----------------------------------
#
# Each measure becomes a :class:`asperity2d.Comparison` of the profiles over the random seeds.
# Half and full triangles of one seed share their draws, so :meth:`asperity2d.Comparison.versus`
# pairs them (paired Wilcoxon, one-sided: half needs more); the Hodges-Lehmann ratio half / full
# (:func:`asperity2d.stats.relative_effect`) gives the effect and
# :func:`asperity2d.experiments.verdicts.judge` the verdict. Regular spacing gives one
# deterministic ratio, reported beside it.

def compare_profiles(data: dict, seeds: list[int]) -> dict[str, Comparison]:
    """Per measure: every profile over the random seeds (paired by seed)."""
    first = next(iter(data.values()))["regular"]
    return {name: Comparison(values={p: tuple(r[key] for r in d["random"]) for p, d in data.items()},
                             seeds=tuple(seeds), measure=name)
            for name, (key, _) in MEASURES.items() if key in first}


def _ratio(a_value: float, b_value: float) -> float:
    return a_value / b_value if b_value and math.isfinite(a_value) and math.isfinite(b_value) else math.nan


# %%
# 1. Two profiles, the same tips
# ------------------------------
#
# :func:`asperity2d.make_scene` with ``profile="half"`` cuts every triangle through its apex.
# With ``min_gap`` half a base (``HALF``) a random surface of half triangles draws the same
# gaps as the full one of the same seed, so every tip stays where it was: only the shape
# changes. This checks it on the scenes' own geometry.

def check_same_tips(size: dict, seed: int = 1) -> None:
    """Every half-triangle variant puts its tips where the full triangles' are (random spacing)."""
    def tips(scene):
        return [surface.spacing.tips(*surface.profile.runs(upper=upper))
                for surface, upper in ((scene.lower, False), (scene.slider, True))]

    full = tips(a.make_scene(spacing="random", seed=seed, **size))
    for shape in (HALF, FULL_BASE_HALF):
        for mine, theirs in zip(tips(a.make_scene(spacing="random", seed=seed, **size, **shape)), full):
            if not np.allclose(mine, theirs, rtol=0.0, atol=1e-15):
                raise AssertionError(f"{shape}: tips differ from the full triangles'")


def claims_for(setup: str, friction: str, data: dict, comparisons: dict) -> list[dict]:
    """Per half shape and measure: half triangles need a larger force (random seeds, paired
    Wilcoxon); the regular ratio is reported beside it. Runs whose slider fell through the
    lower surface count as missing (``numbers["missing"]``)."""
    out = []
    for half in HALVES[setup]:
        shape = "half triangles" + (" (full base, twice as tall)" if half != "half" else "")
        for name, (key, label) in MEASURES.items():
            if name == "first-breakaway" or name not in comparisons:
                continue  # reported, not claimed: on the fixed track the front tip entering alone
            travel = name == "travel"  # figure 10: at one force the half triangles travel less
            direction = "less" if travel else "greater"
            values = comparisons[name].values
            pair = {half: values[half], "full": tuple(f if math.isfinite(h) else math.nan
                                                      for f, h in zip(values["full"], values[half]))}
            numbers = Comparison(values=pair, seeds=comparisons[name].seeds, measure=name).versus(
                half, "full", alternative=direction)
            e = stats.relative_effect(pair[half], pair["full"])
            numbers.update(ratio_hl=e["ratio"], ratio_ci_low=1 + e["ci_low"], ratio_ci_high=1 + e["ci_high"],
                           above=int(np.sum(np.asarray(pair[half]) > np.asarray(pair["full"]))))
            regular = {"full": data["full"]["regular"][key], "half": data[half]["regular"][key]}
            numbers["regular_half_over_full"] = _ratio(regular["half"], regular["full"])
            numbers["regular_N"] = regular
            numbers["random_half_over_full"] = _ratio(numbers["mean"], numbers["reference"])
            verdict = verdicts.judge(numbers, ALPHA, direction=direction)
            text = (f"at one constant force full triangles travel farther than {shape} (figure 10), {friction}"
                    if travel else f"{shape} need a larger {label.rsplit(' (', 1)[0]} than full triangles "
                                   f"(figures 9-10), {friction}")
            out.append(verdicts.claim(
                text, verdict, numbers,
                f"{numbers['test']}, half vs full over random seeds, one-sided ({direction}): "
                f"p = {numbers['p_wilcoxon']:.3g}; holds if p < {ALPHA} and the change is at least "
                f"{100 * verdicts.MIN_EFFECT:g} %; {numbers['missing']} seeds missing (slider fell through). Regular "
                f"spacing (deterministic): half / full = {numbers['regular_half_over_full']:.3f}", setup=setup)
                | {"measure": name, "friction": friction, "half": half})
    return out


# %%
# 4. Why: the back-flank push
# ---------------------------
#
# Ooten's explanation: past an apex, a full triangle's lower spring pushes the slider on along
# the back flank; a half triangle's vertical face cannot. The contact-work books of the spring
# passes weigh that push against the resisting work, and the two friction pairs separate it
# from the static/kinetic switch. On the free slider the regular critical force is compared
# with the flank laws under its load, L tan(45° + atan mu).

def contact_books(rows: list[dict]) -> dict:
    """Contact work of some runs: pushing / resisting (fraction) and the mean pushing force (N)."""
    push = np.array([r["contact_work_pushing_J"] for r in rows])
    resist = np.array([r["contact_work_resisting_J"] for r in rows])
    return {"pushing_J": stats.describe(push), "resisting_J": stats.describe(resist),
            "pushing_share": stats.describe(push / np.where(resist > 0, resist, np.nan)),
            "pushing_force_mean_N": stats.describe([r["pushing_force_mean_N"] for r in rows])}


def verdict_line(record: dict) -> str:
    """``[setup] claim: verdict (random x1.05, 8/10 seeds above, p = 0.004; regular x1.000)``."""
    n = record["numbers"]
    if not n["n"]:  # not a seed-count problem: every run was left out
        return f"[{record['setup']}] {record['claim']}: not testable, every run's slider fell through"
    return (f"[{record['setup']}] {record['claim']}: {record['verdict']} (random half/full x{n['ratio_hl']:.3f} "
            f"[{n['ratio_ci_low']:.3f}, {n['ratio_ci_high']:.3f}], {n['above']}/{n['n']} seeds above, Wilcoxon "
            f"p = {n['p_wilcoxon']:.2g}; regular x{n['regular_half_over_full']:.3f})")


def flank_laws(friction: str, critical: dict) -> dict:
    """The free slider's flank laws under its load L: pushed up 45° flanks from rest against
    mu_s, L tan(45° + atan mu_s), or kept sliding from flank to flank at mu_k,
    L tan(45° + atan mu_k) (N); and each regular critical force over both."""
    load = a.make_scene(**studies.SETUPS["free"]).slider.normal_load
    laws = {kind: load * math.tan(math.radians(45.0) + math.atan(FRICTIONS[friction][f"mu_{kind}"]))
            for kind in ("static", "kinetic")}
    return {"static_N": laws["static"], "kinetic_N": laws["kinetic"],
            "static_over_kinetic": laws["static"] / laws["kinetic"],
            "regular_critical_over_law": {p: {k: _ratio(c, law) for k, law in laws.items()}
                                          for p, c in critical.items()}}


def mechanism(setup: str, results: dict) -> dict:
    """What makes half and full triangles differ, in numbers: per friction pair, the contact work
    books of every profile (the back-flank push), the full slider's mean push against the
    half-minus-full difference of the keep-moving force, and the half / full ratios; across
    the two pairs, ``switch_effect``: how much the static/kinetic switch adds to each ratio."""
    out = {}
    for friction, res in results.items():
        data, comparisons = res["data"], res["comparisons"]
        push = np.array([r["pushing_force_mean_N"] for r in data["full"]["random"]])
        entry = {"contact_work": {p: {"regular": contact_books([d["regular"]]),
                                      "random": contact_books(d["random"])} for p, d in data.items()},
                 "full_pushing_force_mean_N": stats.describe(push)}
        for half in HALVES[setup]:
            km = comparisons["keep-moving"].values
            diff = np.asarray(km[half]) - np.asarray(km["full"])
            entry[half] = {
                "keep_moving_difference_half_minus_full_N": stats.describe(diff),
                "push_over_difference": _ratio(float(np.nanmean(push)), float(np.nanmean(diff)))
                if np.isfinite(diff).any() else math.nan,
                "half_over_full": {c["measure"]: {"regular": c["numbers"]["regular_half_over_full"],
                                                  "random": c["numbers"]["random_half_over_full"]}
                                   for c in res["claims"] if c["half"] == half}}
        if setup == "free":
            entry["flank_law"] = flank_laws(friction, {p: d["regular"]["critical_rest_N"] for p, d in data.items()})
        out[friction] = entry
    if set(FRICTIONS) <= set(out):
        out["switch_effect"] = {}
        for half in HALVES[setup]:
            s_, k_ = out["mu_s > mu_k"][half]["half_over_full"], out["mu_s = mu_k"][half]["half_over_full"]
            out["switch_effect"][half] = {name: {sp: s_[name][sp] - k_[name][sp] for sp in ("regular", "random")}
                                          for name in s_}
    return out


def mechanism_lines(setup: str, mech: dict) -> list[str]:
    lines = []
    for friction in FRICTIONS:
        if friction not in mech:
            continue
        m = mech[friction]
        books = m["contact_work"]
        share = {p: 100 * b["random"]["pushing_share"]["mean"] for p, b in books.items()}
        lines.append(
            f"[{setup}] {friction}: contacts pushing the slider on return "
            + ", ".join(f"{v:.2g} % ({p})" for p, v in share.items())
            + f" of the resisting work (random seeds; regular full {100 * books['full']['regular']['pushing_share']['mean']:.2g} %); "
            f"the full slider's mean push is {1e3 * m['full_pushing_force_mean_N']['mean']:.3g} mN against a "
            "keep-moving difference (half - full) of "
            + ", ".join(f"{1e3 * m[h]['keep_moving_difference_half_minus_full_N']['mean']:.3g} mN ({h})"
                        for h in HALVES[setup]))
        if "flank_law" in m:
            law = m["flank_law"]
            lines.append(f"[{setup}] {friction}: regular critical force from rest over the flank laws "
                         f"(static {1e3 * law['static_N']:.3g} mN, kinetic {1e3 * law['kinetic_N']:.3g} mN, ratio "
                         f"{law['static_over_kinetic']:.3f}): " + ", ".join(
                             f"{p} x{r['static']:.3f} static / x{r['kinetic']:.3f} kinetic"
                             for p, r in law["regular_critical_over_law"].items()))
    return lines


# %%
# 5. Figure 10: one force, two profiles
# -------------------------------------
#
# One constant force, 0.9 x the half triangles' critical force with a run-up, pushes both
# sliders of one random seed (``studies.pushed``); their travel against time
# (``studies.plot_positions``) shows the half-triangle slider stopping first.

def figure10(size: dict, seed: int, force_fraction: float, path) -> dict:
    """Figure 10 analogue: one constant force, full vs half triangles, with the builder's run-up
    (fixed track, random spacing seed ``seed``): ``force_fraction`` x the half-triangle
    slider's critical force with a run-up, at that measure's step."""
    from asperity2d.experiments.measures import measure_step

    base = {**size, **studies.SETUPS["fixed"], "spacing": "random", "seed": seed, "drive": "force"}
    scenes = {"full": a.make_scene(**base), "half": a.make_scene(**base, **HALF)}
    force = force_fraction * a.critical_force(scenes["half"], start="run-up")
    runs = {p: studies.pushed(sc, force, start="run-up", dt=measure_step("critical-run-up", sc)) for p, sc in scenes.items()}
    studies.plot_positions(list(runs.values()), [f"{p} triangles, {force * 1e3:.3g} mN with a run-up ({r.status})"
                                          for p, r in runs.items()], path)
    return {"force_N": force, "seed": seed,
            **{f"travel_{p}_m": float(r.x[-1] - r.x[0]) for p, r in runs.items()},
            **{f"status_{p}": r.status for p, r in runs.items()}}


# %%
# 6. The whole study
# ------------------
#
# For each set-up (Ooten's fixed track first, then the free slider) and friction pair: measure,
# compare, judge, save and draw each comparison (:func:`asperity2d.render`), then the mechanism
# and figure 10. ``main`` reads the options with :mod:`asperity2d.scripting`.

def main(argv=None) -> int:
    args = scripting.study_args(scripting.title(__doc__), argv, default_seeds=24, minimum_seeds=2)
    out = scripting.out_dir(args, __file__)
    size = studies.QUICK_SIZE if args.quick else studies.STUDY_SIZE
    seeds = list(range(args.seeds))
    summary = {"size": size, "seeds": args.seeds, "setups": studies.SETUPS, "frictions": FRICTIONS,
               "alpha": ALPHA, "results": {}, "mechanism": {}, "claims": []}
    check_same_tips(size)
    lines = []
    for setup in studies.SETUPS:  # fixed first: Ooten's set-up
        results = {}
        pairs = list(FRICTIONS)[:1] if args.quick or setup == "free" else list(FRICTIONS)
        for friction in pairs:
            data = measure(setup, friction, size=size, seeds=seeds, workers=args.workers,
                           quasi_static=not args.quick)
            comparisons = compare_profiles(data, seeds)
            found = claims_for(setup, friction, data, comparisons)
            results[friction] = {"data": data, "comparisons": comparisons, "claims": found}
            summary["claims"] += found
            lines += [verdict_line(c) for c in found]
            tag = friction.replace(" ", "").replace(">", "gt").replace("=", "eq")
            for name, comparison in comparisons.items():
                label = MEASURES[name][1]
                unit = "µm" if label.endswith("(m)") else "mN"
                a.render(comparison, out / f"{setup}_{tag}_{name}.png", unit=unit,
                         label=label.replace("(N)", "(mN)").replace("(m)", "(µm)") + f", {setup}, {friction}")
            summary["results"].setdefault(setup, {})[friction] = {
                "regular": {p: d["regular"] for p, d in data.items()},
                "random": {p: {k: stats.describe([r[k] for r in d["random"]]) for k in d["random"][0]}
                           for p, d in data.items()},
                "random_per_seed": {p: d["random"] for p, d in data.items()}}
            for half in HALVES[setup]:
                rows = [data[half]["regular"]] + data[half]["random"]
                fell = [r["fell_through"] for r in rows]
                summary["results"][setup][friction][f"{half}_fell_through_fraction"] = float(np.mean(fell))
                if any(fell):
                    lines.append(f"[{setup}] {friction}: the {half} triangles' slider fell through the lower "
                                 f"surface onto the floor guard in {sum(fell):.0f} of {len(fell)} runs "
                                 "(left out: no longer two surfaces in contact)")
        summary["mechanism"][setup] = mechanism(setup, results)
        lines += mechanism_lines(setup, summary["mechanism"][setup])
    summary["figure10"] = figure10(size, 0, TRAVEL_FACTOR, out / "positions_fixed.png")
    if not args.no_gif:
        result = a.simulate(a.make_scene(**HALF, **size, **studies.SETUPS["fixed"]))
        a.render(result, out / "half_fixed_spring.gif", frames=args.frames or (30 if args.quick else 100))
    if 0.5 ** args.seeds >= ALPHA:
        lines.append(f"not testable here: {args.seeds} seeds cannot give p < {ALPHA} (a one-sided signed-rank "
                     f"test over n seeds reaches at best 1/2**n); the claims need "
                     f"{math.ceil(math.log2(1 / ALPHA))} seeds or more")
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
