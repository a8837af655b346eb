"""Parameter studies of the three-mass chain (Tables 3-7)
======================================================

From the thesis *Vibration Analysis of Multi Degree of Freedom Self-excited
Systems* (no author named in the copy used here), called the multi-DOF belt
thesis below.

The thesis varies one parameter of its base case (Table 2) at a time: stiffness (Table 3), damping
(Table 4), mass (Table 5), belt speed (Table 6) and the friction coefficient (Table 7), Figures
6-14, and states how the motion changes. The lesson: run each variant exactly, measure amplitude,
oscillations and stick time, and judge each stated trend by a criterion fixed beforehand.

Run::

    python scenes/belt_parameters.py [--quick] [--plots] [--only stiffness|damping|mass|speed|friction]
                                     [-o DIR] [--json]

The per-table scripts ``belt_stiffness.py`` ... run one table each. Writes ``summary.json`` (the
claims and each run's measures) and, unless ``--quick`` without ``--plots``, a plot per variant.
"""

# %%
# The lesson is made of the package's public calls: the belt chains of ``asperity2d.belt``, the
# thesis' measures and claim records of ``asperity2d.studies.mdof_belt``, the claim record of
# ``asperity2d.experiments.verdicts`` and ``asperity2d.scripting`` for the command line.

import numpy as np

import asperity2d as a
from asperity2d import scripting
from asperity2d.belt import classify
from asperity2d.experiments.verdicts import claim
from asperity2d.studies import mdof_belt as S

DEC = lambda v: bool(np.all(np.diff(v) < 0))  # noqa: E731
INC = lambda v: bool(np.all(np.diff(v) > 0))  # noqa: E731

# %%
# 1. The tables
# -------------
#
# Each table: the parameter varied, the presets of ``asperity2d.belt.presets`` (the base case
# first) and the parameter's values.

TABLES = {
    "stiffness": ("k", ["table2-3dof", "table3-k20", "table3-k30"], [10, 20, 30]),
    "damping": ("c", ["table2-3dof", "table4-c0.5", "table4-c2"], [0, 0.5, 2]),
    "mass": ("m", ["table2-3dof", "table5-m1.5", "table5-m2.5"], [1, 1.5, 2.5]),
    "speed": ("v_belt", ["table2-3dof", "table6-v0.4", "table6-v0.7"], [0.1, 0.4, 0.7]),
    "friction": ("mu0", ["table2-3dof", "table7-mu0.4"], [0.2, 0.4]),
}
UNITS = {"k": "N/m", "c": "N s/m", "m": "kg", "v_belt": "m/s", "mu0": ""}


# %%
# 2. The measures and the trends
# ------------------------------
#
# Amplitude: half the peak-to-peak displacement over the last half of the 10 s run, averaged over
# the masses; oscillations: upward crossings of the mean position, summed over the masses; stick:
# the total stick time, summed. Each trend the thesis states is a claim judged as stated
# (strictly decreasing, strictly increasing, within 20 %).

def claims_for(which, labels, res):
    """The claim records of one table: ``labels`` name the variants, ``res`` their runs."""
    amp = [np.mean(S.amplitude(r)) for r in res]
    stick = [sum(S.total_stick(r)) for r in res]
    osc = [sum(S.oscillations(r)) for r in res]
    first = [S.first_stick(r, 0) for r in res]
    first_len = [(f[1] - f[0]) if f else 0.0 for f in first]
    T = S.trend_claim
    if which == "stiffness":
        return [T("amplitude decreases with stiffness (Figs 6-7)", labels, amp, DEC, "mean amplitude strictly decreasing", "m"),
                T("stick-slip decreases with stiffness", labels, stick, DEC, "total stick time strictly decreasing", "s")]
    if which == "damping":
        return [T("number of oscillations decreases as damping rises 0.5 -> 2 (Figs 8-9)", labels[1:], osc[1:],
                  DEC, "oscillation count lower at c = 2"),
                T("stick phenomenon decreases as damping rises 0.5 -> 2", labels[1:], stick[1:], DEC,
                  "total stick time lower at c = 2", "s")]
    if which == "mass":
        change = np.abs(np.array(amp) / amp[0] - 1)
        return [T("amplitude has no considerable change with mass (Figs 10-11)", labels, amp,
                  lambda v: bool(np.all(change <= 0.2)), "mean amplitude within 20 % of the m = 1 kg case", "m"),
                T("number of oscillations decreases with mass", labels, osc, DEC, "count strictly decreasing"),
                T("stick period becomes larger with mass", labels, first_len, INC,
                  "first stick interval of m1 strictly longer", "s")]
    if which == "speed":
        regime = [classify(r) for r in res]
        return [T("stick-slip starts to vanish at 0.4 m/s (Fig 12)", labels, stick, DEC,
                  "total stick time strictly decreasing with belt speed", "s"),
                claim("quasi-harmonic oscillation with constant amplitude and period at 0.7 m/s (Fig 13)",
                      regime[-1] == "quasi-harmonic", {"thesis": "quasi-harmonic", "computed": regime[-1]},
                      "regime classifier on the second half of the run"),
                T("amplitude increases with belt speed", labels, amp, INC, "mean amplitude strictly increasing", "m"),
                T("number of oscillations increases with belt speed", labels, osc, INC, "count strictly increasing")]
    return [T("long stick interval at the outset when mu0 rises 0.2 -> 0.4 (Fig 14)", labels, first_len, INC,
              "first stick interval of m1 longer at mu0 = 0.4", "s"),
            T("increasing the friction coefficient reduces the number of oscillations (conclusion)", labels, osc,
              DEC, "oscillation count lower at mu0 = 0.4")]


# %%
# 3. Run the tables
# -----------------
#
# Every variant is one exact run (:func:`asperity2d.studies.mdof_belt.run` simulates a preset;
# ``quick`` keeps fewer output samples, the events are the same).

def study(quick: bool, only: str | None = None):
    """The claims and measures of the tables (``only`` one of them), and the runs to plot:
    preset name -> (plot title, run)."""
    summary = {"study": "3-DOF parameter studies, initial conditions eq 3.12", "claims": [], "cases": {}}
    results = {}
    for which, (param, names, labels) in TABLES.items():
        if only and which != only:
            continue
        res = [S.run(n, quick=quick) for n in names]
        summary["claims"] += claims_for(which, [f"{param}={v}" for v in labels], res)
        for name, r, value in zip(names, res, labels):
            summary["cases"][name] = S.case_summary(r)
            if name != "table2-3dof":
                results[name] = (f"{which}: {param} = {value:g} {UNITS[param]}".rstrip() + f" (preset {name})", r)
    summary["measures"] = ("amplitude: half peak-to-peak displacement over the last half of the 10 s run, "
                           "averaged over the masses; oscillations: upward crossings of the mean position, "
                           "summed over masses; stick: total stick time summed over masses")
    return summary, results


# %%
# The command line
# ----------------
#
# ``main`` reads the options (``--only`` one table), runs the tables, plots each variant with
# :func:`asperity2d.render` (displacement, velocity and phase portrait per mass, stick intervals
# shaded), writes ``summary.json`` and prints each claim. The per-table scripts call it with
# ``only`` and their own file, so their outputs go to ``renders/belt_<table>``.

def main(argv=None, only: str | None = None, script: str | None = None) -> int:
    p = scripting.parser(scripting.title(__doc__))
    p.add_argument("--plots", action="store_true", help="write the plots with --quick too")
    if only is None:
        p.add_argument("--only", choices=list(TABLES), default=None, help="run one table")
    args = p.parse_args(argv)
    only = only or args.only
    out = scripting.out_dir(args, script or __file__)
    summary, results = study(args.quick, only)
    summary["solver"] = S.SOLVER
    summary["verdict_rule"] = S.VERDICT_RULE
    if not args.quick or args.plots:
        summary["plots"] = summary["outputs"] = [
            a.render(r, out / f"{name}.png", title=title).name for name, (title, r) in results.items()]
    return scripting.finish(args, summary, out, S.claim_lines(summary["claims"]))


if __name__ == "__main__":
    scripting.run(main)
