"""Stick-slip under a spring drive
===============================

From E. Ooten, *Precision Motion Control at Low Velocities in the Presence of
Friction* (senior thesis, Texas A&M University, 1997-98), the drive of his figure 13.

Ooten's Working Model set-up (the slider on a fixed-height track, its tips
a quarter of the asperity height into the lower surface), pulled by a spring
whose far end moves at constant speed. The drive force builds while the
slider sticks and drops when it slips: the sawtooth Ooten's thesis could not get
from a constant force in Working Model. On a regular surface every tip meets
its lower asperity at once, so the largest stick force of the pass is the
quasi-static flank law for all of them together: n k delta tan(45 deg + atan
mu_s) (n tips, track stiffness k, interference delta). Writes a GIF, a
time-series plot, the run (``run.npz``) and summary.json.

The lesson: make a scene, run it, cut the run into stick-slip events, read the
three breakaway measures a single run gives, and check the largest against its
closed form.

Run::

    python scenes/stick_slip.py            # or: asperity2d run scenes/stick_slip.py
"""

from __future__ import annotations

import math

import asperity2d as a
from asperity2d import scripting


# %%
# 1. The scene
# ------------
#
# :func:`asperity2d.make_scene` builds Ooten's set-up; keyword arguments change one parameter
# each. Here the lower asperities are regularly spaced and a spring pulls the slider. The quick
# setting (the one the documentation ran) uses 8 lower asperities and 3 tips instead of 16 and 4.

def build_scene(quick: bool = False, **overrides):
    """Ooten's set-up with regular spacing and a spring drive (fewer asperities if ``quick``)."""
    params = dict(lower_count=8 if quick else 16, upper_count=3 if quick else 4)
    params.update(overrides)
    return a.make_scene(spacing="regular", drive="spring", **params)


# %%
# 2. Run it and find the stick-slip events
# ----------------------------------------
#
# :func:`asperity2d.simulate` runs the scene until the slider has passed the surface;
# :func:`asperity2d.stick_slip_events` cuts the motion into cycles of sticking (the slider at
# rest while the spring force builds) and slipping. :func:`asperity2d.render` draws the run:
# the file's extension picks the picture (a time-series plot, an animation).

def run_and_draw(scene, out, frames: int | None):
    """The run, its stick-slip events, ``timeseries.png`` and (if ``frames``) ``run.gif``."""
    result = a.simulate(scene)
    result.save(out / "run.npz")
    events = a.stick_slip_events(result)
    a.render(result, out / "timeseries.png", events=events)
    if frames:
        a.render(result, out / "run.gif", frames=frames)
    return result, events


# %%
# 3. Measure, and compare with the flank law
# ------------------------------------------
#
# A single run gives three breakaway measures: the first breakaway (the force at which the
# slider first slips, the front tip entering the surface), the peak stick force (the largest
# force before any slip of the pass) and the mean stick force. On a regular surface all n tips
# meet their asperities together, so the peak is the static flank law for all tips:
# n k delta tan(theta + atan mu_s), with theta the flank angle.

def flank_law_all_tips(scene) -> float:
    """n k delta tan(theta + atan mu_s) (N): the quasi-static force to push all tips up a flank."""
    flank = math.tan(math.radians(scene.lower.profile.flank_angle) + math.atan(scene.contact.mu_static))
    return scene.slider.count * scene.lower.stiffness[0] * scene.slider.interference * flank


def measures(result, events) -> dict:
    """The run's breakaway measures (N) and its event statistics."""
    return {"first_breakaway_force_N": a.breakaway_force(result),
            "peak_stick_force_N": a.peak_stick_force(result),
            "mean_stick_force_N": a.mean_stick_force(result),
            "events": a.event_statistics(events)}


# %%
# The command line
# ----------------
#
# ``main`` reads the options (``--quick``, ``-o``, ``--json``, ``--no-gif``, ``--frames``),
# runs the three steps and prints what it found.

def main(argv=None) -> int:
    si = scripting.si
    args = scripting.parser(scripting.title(__doc__)).parse_args(argv)
    out = scripting.out_dir(args, __file__)
    scene = build_scene(args.quick)
    frames = None if args.no_gif else args.frames or (40 if args.quick else 120)
    result, events = run_and_draw(scene, out, frames)
    found = measures(result, events)
    all_tips = flank_law_all_tips(scene)
    stats = found.pop("events")
    summary = {**result.summary(), **found, "flank_law_all_tips_N": all_tips, "events": stats}
    lines = [f"{scene.name}: {result.status} after {si(result.t[-1], 's', 3)}, {stats['count']} stick-slip events",
             f"first breakaway (front tip entering) {summary['first_breakaway_force_N'] * 1e3:.4g} mN",
             f"peak stick force over the pass {summary['peak_stick_force_N'] * 1e3:.4g} mN "
             f"(flank law for all {scene.slider.count} tips at once, n k delta tan(45 deg + atan mu_s) = "
             f"{all_tips * 1e3:.4g} mN)"]
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
