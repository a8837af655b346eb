"""Stick-slip under a spring drive
===============================

From E. Ooten, *Precision Motion Control at Low Velocities in the Presence of
Friction* (senior thesis, Texas A&M University, 1997-98).

Spring-driven slider on regular asperities: stick-slip (Ooten's thesis, figure 13 drive).

Ooten's Working Model set-up (the slider on a fixed-height track, its tips
a quarter of the asperity height into the lower surface), pulled by a spring
whose far end moves at constant speed. The drive force builds while the
slider sticks and drops when it slips: the sawtooth Ooten's thesis could not get
from a constant force in Working Model. On a regular surface every tip meets
its lower asperity at once, so the largest stick force of the pass is the
quasi-static flank law for all of them together: n k delta tan(45 deg + atan
mu_s) (n tips, track stiffness k, interference delta). Writes a GIF, a
time-series plot and summary.json.

Run::

    python scenes/stick_slip.py            # or: asperity2d run scenes/stick_slip.py
"""

from __future__ import annotations

import math

import asperity2d as a
from asperity2d._format import si
from asperity2d import scripting


def build_scene(quick: bool = False, **overrides):
    params = dict(lower_count=8 if quick else 16, upper_count=3 if quick else 4)
    params.update(overrides)
    return a.make_scene(spacing="regular", drive="spring", **params)


def main(argv=None) -> int:
    args = scripting.parser(scripting.title(__doc__)).parse_args(argv)
    out = scripting.out_dir(args, __file__)
    scene = build_scene(args.quick)
    result = a.simulate(scene)
    result.save(out / "run.npz")
    from asperity2d.analysis import (breakaway_force, event_statistics, mean_stick_force,
                                     peak_stick_force, stick_slip_events)
    from asperity2d.renderers import render

    events = stick_slip_events(result)
    render(result, out / "timeseries.png", events=events)
    if not args.no_gif:
        render(result, out / "run.gif", frames=args.frames or (40 if args.quick else 120))
    stats = event_statistics(events)
    flank = math.tan(math.radians(scene.lower.profile.flank_angle) + math.atan(scene.contact.mu_static))
    all_tips = scene.slider.count * scene.lower.stiffness[0] * scene.slider.interference * flank
    summary = {**result.summary(), "first_breakaway_force_N": breakaway_force(result),
               "peak_stick_force_N": peak_stick_force(result), "mean_stick_force_N": mean_stick_force(result),
               "flank_law_all_tips_N": all_tips, "events": stats}
    lines = [f"{scene.name}: {result.status} after {si(result.t[-1], 's', 3)}, {stats['count']} stick-slip events",
             f"first breakaway (front tip entering) {summary['first_breakaway_force_N'] * 1e3:.4g} mN",
             f"peak stick force over the pass {summary['peak_stick_force_N'] * 1e3:.4g} mN "
             f"(flank law for all {scene.slider.count} tips at once, n k delta tan(45 deg + atan mu_s) = "
             f"{all_tips * 1e3:.4g} mN)"]
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
