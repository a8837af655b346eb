"""A constant force: the slider stops on a flank or runs away
==========================================================

From E. Ooten, *Precision Motion Control at Low Velocities in the Presence of
Friction* (senior thesis, Texas A&M University, 1997-98).

Constant-force slider (Working Model's set-up, Ooten's figures 10 and 12).

With a constant push the slider never shows stick-slip: it either stops on a
flank or runs away. This script finds the critical force by bisection and runs
just below and just above it, writing the position traces (Ooten's
figure 10 analogue), a GIF of the run that passes, and summary.json.

    python scenes/constant_force.py        # or: asperity2d run scenes/constant_force.py
"""

from __future__ import annotations

import asperity2d as a
from asperity2d.cli import scripting
from asperity2d.critical import critical_force_bracket


def build_scene(quick: bool = False, **overrides):
    params = dict(lower_count=6 if quick else 12, upper_count=2 if quick else 3)
    params.update(overrides)
    return a.make_scene(spacing="regular", drive="force", **params)


def main(argv=None) -> int:
    args = scripting.parser(scripting.title(__doc__)).parse_args(argv)
    out = scripting.out_dir(args, __file__)
    scene = build_scene(args.quick)
    bracket = critical_force_bracket(scene, rel_tol=0.01)
    runs = {}
    for label, factor in (("below", 0.95), ("above", 1.05)):
        force = factor * bracket.value
        runs[label] = a.simulate(scene.replace(drive=a.ConstantForce(force=force)))
    from asperity2d.renderers import render
    from asperity2d.renderers.plots import plot_positions

    plot_positions([runs["below"], runs["above"]],
                   [f"0.95 x critical ({runs['below'].status})", f"1.05 x critical ({runs['above'].status})"],
                   out / "positions.png")
    if not args.no_gif:
        render(runs["above"], out / "run.gif", frames=args.frames or (40 if args.quick else 100))
    mu_k = scene.contact.mu_kinetic
    summary = {
        "critical_force_N": bracket.value, "bracket_N": [bracket.stops, bracket.passes],
        "runs_used": bracket.runs,
        "kinetic_flank_law_N": scene.slider.normal_load * (1 + mu_k) / (1 - mu_k),
        "below": runs["below"].summary(), "above": runs["above"].summary(),
    }
    lines = [f"critical force {bracket.value:.4g} N (bracket {bracket.stops:.4g}-{bracket.passes:.4g} N, "
             f"{bracket.runs} runs); kinetic flank law L(1+mu_k)/(1-mu_k) = {summary['kinetic_flank_law_N']:.4g} N",
             f"0.95 x: {runs['below'].status} after {summary['below']['distance_m']:.3g} m",
             f"1.05 x: {runs['above'].status} after {summary['above']['distance_m']:.3g} m"]
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
