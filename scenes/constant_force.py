"""A constant force: the slider stops on a flank or runs away
=============================================================

From E. Ooten, *Precision Motion Control at Low Velocities in the Presence of
Friction* (senior thesis, Texas A&M University, 1997-98), figures 10 and 12.

With a constant push the slider never shows stick-slip: it either stops on a
flank or runs away over the whole surface. This script finds the critical force
from rest by bisection (the slider settled at rest on the surface, every tip
against its flank, the force then applied at once: :func:`asperity2d.critical_force`)
and pushes the slider **from that same rest** with 0.95 x and 1.05 x that force:
the first stops on a flank, the second passes. It writes the two position traces
(Ooten's figure 10 analogue), a GIF of the run that passes, and summary.json.

The closed form printed beside it is the set-up's flank law. On the free slider
(``--track free``) the slider climbs one flank under its load L, and the critical
force from rest is the kinetic flank law L tan(45 deg + atan mu_k). On Ooten's
fixed track (the default) every tip must push its lower spring down by the
interference delta: a slow push needs the static flank law for all n tips,
n k delta tan(45 deg + atan mu_s) (the peak stick force of a spring-driven pass
reaches it), but the critical force from rest, a force applied at once, is a
dynamic threshold well below it with no closed form: the ratio is printed.

Run::

    python scenes/constant_force.py        # or: asperity2d run scenes/constant_force.py
"""

from __future__ import annotations

import math

from matplotlib.figure import Figure

import asperity2d as a
from asperity2d import scripting
from asperity2d.studies.ooten import pushed


# %%
# 1. The scene
# ------------
#
# Ooten's set-up with regular spacing and a constant-force drive. The quick setting (the one
# the documentation ran) uses 6 lower asperities and 2 tips instead of 12 and 3;
# ``track="free"`` swaps the fixed-height track for the free slider under its load.

def build_scene(quick: bool = False, **overrides):
    """Regular spacing under a constant force (fewer asperities if ``quick``)."""
    params = dict(lower_count=6 if quick else 12, upper_count=2 if quick else 3)
    params.update(overrides)
    return a.make_scene(spacing="regular", drive="force", **params)


# %%
# 2. The critical force from rest, by bisection
# ---------------------------------------------
#
# :func:`asperity2d.critical_force_bracket` settles the slider at rest on the surface, applies
# a force at once and halves the bracket between a force that stops and one that passes until
# it is 1 % wide. Then :func:`asperity2d.studies.ooten.pushed` pushes from that same rest with
# 5 % less and 5 % more: the first run stops on a flank, the second passes.

def critical_and_pushes(scene):
    """The bracket of the critical force from rest and the runs at 0.95 x and 1.05 x it."""
    bracket = a.critical_force_bracket(scene, rel_tol=0.01)  # from rest (the default start)
    runs = {label: pushed(scene, factor * bracket.value, start="rest")
            for label, factor in (("below", 0.95), ("above", 1.05))}
    return bracket, runs


# %%
# 3. The closed form beside it
# ----------------------------
#
# The free slider climbs one flank under its load L: the kinetic flank law
# L tan(theta + atan mu_k) is its critical force. On the fixed track a slow push needs the
# static flank law for all n tips, n k delta tan(theta + atan mu_s); a force applied at once
# undercuts it, and the ratio says by how much.

def flank_law(scene) -> tuple[float, str]:
    """The set-up's flank law (N) and its formula in words (see the module docstring)."""
    angle = math.radians(scene.lower.profile.flank_angle)
    if scene.slider.track == "free":
        law = scene.slider.normal_load * math.tan(angle + math.atan(scene.contact.mu_kinetic))
        return law, "the free slider's kinetic flank law L tan(45 deg + atan mu_k), which it should match"
    n, k, delta = scene.slider.count, scene.lower.stiffness[0], scene.slider.interference
    law = n * k * delta * math.tan(angle + math.atan(scene.contact.mu_static))
    return law, (f"what a slow push needs on the fixed track, the static flank law for all {n} tips "
                 f"n k delta tan(45 deg + atan mu_s), a bound a force applied at once undercuts")


# %%
# 4. Plot the two runs
# --------------------
#
# The slider's travel against time for both pushes (Ooten's figure 10): a plateau is where
# the slider stopped on a flank. A plain matplotlib figure, from the runs' ``t`` and ``x``.

def plot_travel(runs: dict, path) -> None:
    """Travel (µm) against time (µs, or ns for a run shorter than 1 µs) of the runs below and
    above the critical force."""
    longest = max(float(run.t[-1]) for run in runs.values())
    scale, unit = (1e6, "µs") if longest >= 1e-6 else (1e9, "ns")
    fig = Figure(figsize=(7.0, 3.2), layout="constrained")
    ax = fig.add_subplot()
    for label, factor in (("below", 0.95), ("above", 1.05)):
        run = runs[label]
        ax.plot(run.t * scale, (run.x - run.x[0]) * 1e6, label=f"{factor:.2f} x critical ({run.status})")
    ax.set_xlabel(f"time ({unit})")
    ax.set_ylabel("slider travel (µm)")
    ax.legend(loc="best", fontsize="small")
    fig.savefig(path, dpi=120)


# %%
# The command line
# ----------------
#
# ``main`` reads the options (``--quick``, ``--track``, ``-o``, ``--json``, ``--no-gif``),
# runs the steps, draws the run that passes with :func:`asperity2d.render` and prints.

def main(argv=None) -> int:
    si = scripting.si
    p = scripting.parser(scripting.title(__doc__))
    p.add_argument("--track", choices=("fixed", "free"), default="fixed",
                   help="Ooten's fixed track (default) or the free slider under its load")
    args = p.parse_args(argv)
    out = scripting.out_dir(args, __file__)
    scene = build_scene(args.quick, track=args.track)
    bracket, runs = critical_and_pushes(scene)
    plot_travel(runs, out / "positions.png")
    if not args.no_gif:
        a.render(runs["above"], out / "run.gif", frames=args.frames or (40 if args.quick else 100))
    law, law_words = flank_law(scene)
    summary = {
        "track": scene.slider.track, "start": "rest",
        "critical_force_N": bracket.value, "bracket_N": [bracket.stops, bracket.passes],
        "runs_used": bracket.runs, "flank_law_N": law, "flank_law": law_words,
        "below": runs["below"].summary(), "above": runs["above"].summary(),
    }
    lines = [f"critical force from rest {si(bracket.value, 'N', 4)} (the slider stops at "
             f"{si(bracket.stops, 'N', 4)} and passes at {si(bracket.passes, 'N', 4)}; {bracket.runs} runs); "
             f"{law_words} = {si(law, 'N', 4)} (ratio {bracket.value / law:.3f})"]
    for label, factor in (("below", 0.95), ("above", 1.05)):
        run = runs[label]
        lines.append(f"pushed from the same rest with {factor:.2f} x = {si(factor * bracket.value, 'N', 4)}: "
                     f"{run.status} after {si(summary[label]['distance_m'], 'm', 3)}")
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
