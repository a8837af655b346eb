"""Does regularity enhance stick-slip? (Ooten's abstract)
======================================================

From E. Ooten, *Precision Motion Control at Low Velocities in the Presence of
Friction* (senior thesis, Texas A&M University, 1997-98).

Ooten's abstract: regular asperities enhance stick-slip, random ones reduce or remove it.

Spring-driven passes over regular/regular and random/random surfaces at three
drive-spring stiffnesses spanning a decade (default 1 176, 3 720 and
11 760 N/m: the package default x 10^-0.5, 1, 10^0.5), for both set-ups
(Ooten's fixed-height track first, then the free slider under load). Per
run (``asperity2d.studies.ooten.spring_pass_run``): the number of
stick-slip events, the stick-slip amplitude -- the mean force drop per slip
(N) -- the spread of the drops (std, N) and the regularity of the events
(coefficient of variation of the intervals between slips; 0 = periodic).

Claim tested per set-up and stiffness: the random surfaces' mean force drop
per slip is below the deterministic regular value (one-sample Wilcoxon
signed-rank test over the random seeds, one-sided "lower"; holds if p < 0.01,
:func:`asperity2d.experiments.verdicts.judge`). A pass with no complete slip (one
slip carried the slider across) has no force drop and counts as missing.
Whether the verdict changes with the drive stiffness is reported as
``drive_dependent``.

The lesson: a distribution over random seeds against one deterministic value,
repeated along a parameter (the drive stiffness), and whether the verdict
depends on it.

Run::

    python scenes/ooten_stickslip.py [--seeds 20] [--workers auto|N]
"""

# %%
# The steps are in ``main`` below, made of the package's public calls; it reads the command
# line, runs them and prints. The gallery runs it with ``--quick`` (4 lower and 2 upper
# asperities, 2 seeds, the softest and stiffest spring): a one-sided signed-rank test over n
# seeds cannot give p below 1/2**n, so its verdicts read "not testable"; a verdict needs 7 seeds
# or more (the default run uses 20).

from __future__ import annotations

import math

import numpy as np
from matplotlib.figure import Figure

import asperity2d as a
from asperity2d import stats
from asperity2d import scripting
from asperity2d.experiments import verdicts
from asperity2d.studies import ooten as studies
from asperity2d.sweep import map_calls

STIFFNESSES = (1_176.0, 3_720.0, 11_760.0)  # N/m
ALPHA = 0.01
METRICS = ("events", "force_drop_mean_N", "force_drop_std_N", "regularity")
AMPLITUDE = "stick-slip amplitude (mean force drop per slip)"


# %%
# 1. The picture
# --------------
#
# The mean force drop per slip against the drive stiffness: the regular surface's single value
# and the random surfaces' mean with its 95 % interval, drawn with matplotlib.

def plot_amplitudes(results: dict, path) -> None:
    """Mean force drop against drive stiffness, regular (line) and random (mean, 95 % CI)."""
    fig = Figure(figsize=(7.0, 3.2), layout="constrained")
    axes = fig.subplots(1, len(results), squeeze=False)[0]
    for ax, (setup, per_k) in zip(axes, results.items()):
        ks = [float(k) for k in per_k]
        reg = [per_k[k]["regular"]["force_drop_mean_N"] * 1e3 for k in per_k]
        rnd = [per_k[k]["random"]["force_drop_mean_N"] for k in per_k]
        ax.plot(ks, reg, "o-", label="regular")
        mean = np.array([r["mean"] for r in rnd]) * 1e3
        err = np.array([[r["mean"] - r["ci_low"], r["ci_high"] - r["mean"]] for r in rnd]).T * 1e3
        ax.errorbar(ks, mean, yerr=np.nan_to_num(err), fmt="s--", capsize=3, label="random (95 % CI)")
        ax.set_xscale("log")
        ax.set_xlim(min(ks) / 1.6, max(ks) * 1.6)
        for k, r, m in zip(ks, reg, mean):  # a pass that one slip carried across has no force drop
            if not (np.isfinite(r) or np.isfinite(m)):
                ax.text(k, 0.5, "no complete\nslip", transform=ax.get_xaxis_transform(), ha="center",
                        va="center", fontsize=8, color="0.4")
        ax.set_xlabel("drive stiffness (N/m)")
        ax.set_ylabel("mean force drop per slip (mN)")
        ax.set_title(f"{setup} slider", fontsize=9)
        ax.legend(fontsize=8)
    fig.savefig(path, dpi=110)


# %%
# 2. Passes, statistics, verdicts
# -------------------------------
#
# For each set-up and stiffness: one spring-driven pass per surface (``studies.spring_pass_run``:
# :func:`asperity2d.make_scene` with ``drive="spring"`` and ``drive_stiffness=``, then
# :func:`asperity2d.simulate`, :func:`asperity2d.stick_slip_events` and
# :func:`asperity2d.event_statistics`), run on worker processes by
# :func:`asperity2d.sweep.map_calls`; the random seeds against the regular value with
# :func:`asperity2d.stats.versus_reference` and :func:`asperity2d.stats.relative_effect`, judged
# by :func:`asperity2d.experiments.verdicts.judge`. Last, a regular pass on the softest spring,
# rendered as a GIF and a time series (:func:`asperity2d.render`).

def main(argv=None) -> int:
    args = scripting.study_args(scripting.title(__doc__), argv, default_seeds=20, minimum_seeds=2)
    n_seeds = args.seeds
    out = scripting.out_dir(args, __file__)
    size = studies.QUICK_SIZE if args.quick else studies.STUDY_SIZE
    stiffnesses = (STIFFNESSES[0], STIFFNESSES[-1]) if args.quick else STIFFNESSES
    summary = {"size": size, "seeds": n_seeds, "stiffnesses_N_per_m": stiffnesses,
               "setups": studies.SETUPS, "results": {}, "claims": [], "drive_dependent": {}}
    lines = []
    for setup in studies.SETUPS:
        base = {**size, **studies.SETUPS[setup]}
        jobs = [dict(base, drive_stiffness=k, spacing=sp, seed=s) for k in stiffnesses
                for sp, s in [("regular", 0)] + [("random", s) for s in range(n_seeds)]]
        rows = map_calls(studies.spring_pass_run, jobs, workers=args.workers)
        per_k, judged = {}, {}
        for i, k in enumerate(stiffnesses):
            block = rows[i * (n_seeds + 1):(i + 1) * (n_seeds + 1)]
            regular, randoms = block[0], block[1:]
            described = {m: stats.describe([r[m] for r in randoms]) for m in METRICS}
            per_k[str(k)] = {"regular": {m: regular[m] for m in METRICS}, "random": described}
            amp = stats.versus_reference([r["force_drop_mean_N"] for r in randoms],
                                           regular["force_drop_mean_N"], alternative="less")
            e = stats.relative_effect([r["force_drop_mean_N"] for r in randoms], regular["force_drop_mean_N"])
            amp.update(ratio_hl=e["ratio"], ratio_ci_low=1 + e["ci_low"], ratio_ci_high=1 + e["ci_high"])
            verdict = verdicts.judge(amp, ALPHA) if math.isfinite(regular["force_drop_mean_N"]) else verdicts.FAILS
            judged[str(k)] = verdict
            numbers = {"drive_stiffness_N_per_m": k, "force_drop": amp,
                       "regular": per_k[str(k)]["regular"], "random": described,
                       "fraction_random_seeds_with_fewer_events":
                           float(np.mean([r["events"] < regular["events"] for r in randoms]))}
            record = verdicts.claim(
                f"random spacing lowers the {AMPLITUDE} (abstract: regularity enhances stick-slip), "
                f"drive stiffness {k:g} N/m", verdict, numbers,
                f"one-sample Wilcoxon signed-rank of the random passes' mean force drop per slip vs the "
                f"regular value, one-sided (lower), p = {amp['p_wilcoxon']:.3g}; holds if p < {ALPHA}; "
                f"{amp['missing']} passes without a complete slip left out", setup=setup)
            summary["claims"].append(record | {"measure": "force_drop_mean_N",
                                               "drive_stiffness_N_per_m": k})
            lines.append(verdicts.verdict_line({**record, "numbers": amp}))
            lines.append(
                f"    regular {regular['events']:.0f} events, drop {regular['force_drop_mean_N'] * 1e3:.3g} mN "
                f"(std {regular['force_drop_std_N'] * 1e3:.3g}, CV {regular['regularity']:.2f}); random "
                f"{described['events']['mean']:.1f} events, drop {amp['mean'] * 1e3:.3g} mN (d = "
                f"{amp['effect_size_d']:.2f}, std {described['force_drop_std_N']['mean'] * 1e3:.3g}, "
                f"CV {described['regularity']['mean']:.2f})")
        summary["results"][setup] = per_k
        summary["drive_dependent"][setup] = {"verdicts": judged,
                                             "depends_on_drive": len(set(judged.values()) - {verdicts.UNTESTABLE}) > 1}
        lines.append(f"[{setup}] verdict depends on the drive stiffness: "
                     f"{summary['drive_dependent'][setup]['depends_on_drive']}")
    if 0.5 ** n_seeds >= ALPHA:
        lines.append(f"not testable here: {n_seeds} seeds cannot give p < {ALPHA} (a one-sided signed-rank "
                     f"test over n seeds reaches at best 1/2**n); the claims need "
                     f"{math.ceil(math.log2(1 / ALPHA))} seeds or more")
    plot_amplitudes(summary["results"], out / "force_drop_vs_stiffness.png")
    if not args.no_gif:
        result = a.simulate(a.make_scene(spacing="regular", drive_stiffness=stiffnesses[0], **size,
                                         **studies.SETUPS["fixed"]))
        a.render(result, out / "regular_soft_spring.gif", frames=args.frames or (30 if args.quick else 120))
        a.render(result, out / "regular_soft_spring.png")
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
