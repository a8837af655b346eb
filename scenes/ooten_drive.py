"""Constant force against a spring drive (Ooten's Working Model runs)
==================================================================

From E. Ooten, *Precision Motion Control at Low Velocities in the Presence of
Friction* (senior thesis, Texas A&M University, 1997-98).

Ooten's thesis: constant force vs spring drive (Working Model's constant push never gave stick-slip).

Regular spacing, full 45° triangles, both set-ups (Ooten's fixed-height
track first, then the free slider under load). The critical force from rest
is bisected (the slider at rest on the surface, every tip against its flank:
:func:`asperity2d.critical_force`); the slider is then pushed from that same
rest with 0.95 x and 1.05 x that force (it should stop on a flank, or run
away over the whole surface), and pulled by the default drive spring (far
end at constant speed), which should give stick-slip: the drive force builds
while the slider sticks and drops when it slips. The spring pass reports the
first breakaway (on the fixed track the front tip entering alone), the peak
and mean stick force over the pass and the force drops (N).

A *restart* of a constant-force run is a return to forward motion (speed
above 10 % of sqrt(F b / M), b the base, M the slider mass) after a stick:
a stop (speed below 1 % of it) lasting at least the scene's slowest natural
period -- what stick-slip under a constant force would need. Momentary stops
(bounces off a flank) are counted separately. Writes the
positions plot (seed figure 10 style), the spring run's time series and a GIF.

The lesson: the two drives of :func:`asperity2d.make_scene` (``drive="force"``,
``drive="spring"``), the critical force as a threshold, and stick-slip events.

Run::

    python scenes/ooten_drive.py
"""

# %%
# The steps are functions made of the package's public calls; ``main`` at the bottom reads the
# command line, runs them and prints. Nothing here is random (regular spacing): the verdicts are
# direct checks of single runs, so ``--quick`` (4 lower and 2 upper asperities) gives them too.

from __future__ import annotations

import math

import asperity2d as a
from asperity2d import scripting
from asperity2d.experiments import verdicts
from asperity2d.experiments.verdicts import claim
from asperity2d.studies import ooten as studies

FACTORS = {"below": 0.95, "above": 1.05}


# %%
# 1. What stick-slip under a constant force would look like
# ---------------------------------------------------------
#
# A run's velocity (``result.v``) tells: the slider stops (speed under 1 % of a characteristic
# speed) for at least the scene's slowest natural period, then moves forward again. Bounces off
# a flank, where the velocity only passes through zero, are counted apart.

def restarts(result, *, min_stop: float = 0.0) -> int:
    """Times a constant-force slider moves forward again after having stopped for >= ``min_stop`` s.

    ``min_stop=0`` also counts momentary stops (bounces off a flank, where the
    velocity passes through zero).
    """
    scene = result.scene
    v_char = math.sqrt(abs(scene.drive.force) * scene.base / scene.slider.mass)
    moving, count, moved, t_stop = False, 0, False, 0.0
    for t, v in zip(result.t, result.v):
        if not moving and v > 0.1 * v_char:
            count += 1 if moved and t - t_stop >= min_stop else 0
            moving = moved = True
        elif moving and abs(v) < 0.01 * v_char:
            moving, t_stop = False, t
    return count


# %%
# 2. Either side of the threshold, and a spring
# ---------------------------------------------
#
# :func:`asperity2d.critical_force_bracket` bisects the critical force from rest on a regular
# scene (``drive="force"``); ``studies.pushed`` pushes the slider from that same rest with 0.95 x
# and 1.05 x it. :func:`asperity2d.simulate` then runs the default spring drive
# (``drive="spring"``), whose stick-slip events :func:`asperity2d.stick_slip_events` finds and
# :func:`asperity2d.event_statistics` sums up. Each claim is a record of
# :func:`asperity2d.experiments.verdicts.claim`.

def run_setup(setup: str, size: dict) -> tuple[dict, dict, list[dict]]:
    """Constant-force runs from rest either side of the critical force, and one spring-driven pass."""
    base = {**size, **studies.SETUPS[setup]}
    scene = a.make_scene(spacing="regular", drive="force", **base)
    bracket = a.critical_force_bracket(scene, start="rest")
    runs = {k: studies.pushed(scene, f * bracket.value, start="rest") for k, f in FACTORS.items()}
    runs["spring"] = a.simulate(a.make_scene(spacing="regular", drive="spring", **base))
    events = a.stick_slip_events(runs["spring"])
    stats = a.event_statistics(events)
    peaks = [e.force_peak for e in events]
    numbers = {"critical_force_from_rest_N": bracket.value, "bracket_N": [bracket.stops, bracket.passes]}
    for k in FACTORS:
        r = runs[k]
        numbers[k] = {"force_N": FACTORS[k] * bracket.value, "start": "rest", "status": r.status,
                      "travel_m": float(r.x[-1] - r.x[0]),
                      "restarts_after_stick": restarts(r, min_stop=scene.slowest_period()),
                      "momentary_stops_then_moving": restarts(r)}
    numbers["spring"] = {"status": runs["spring"].status, "events": stats,
                         "stick_forces_N": peaks, "force_drops_N": [e.force_drop for e in events],
                         "first_breakaway_N": peaks[0] if peaks else math.nan,
                         "peak_stick_force_N": max(peaks, default=math.nan),
                         "mean_stick_force_N": sum(peaks) / len(peaks) if peaks else math.nan}
    const_ok = (runs["below"].status == "stuck" and runs["above"].status == "passed"
                and numbers["below"]["restarts_after_stick"] == 0
                and numbers["above"]["restarts_after_stick"] == 0)
    claims = [
        claim(
            "with a constant force the slider either stops on a flank (and stays stopped) or runs "
            "away over the whole surface; no stick-slip", const_ok,
            {k: numbers[k] for k in ("critical_force_from_rest_N", "bracket_N", "below", "above")},
            "direct: run status at 0.95 x / 1.05 x the critical force from rest, pushed from that rest "
            "(stuck / passed), and no forward restart after a stop of at least the scene's slowest "
            "period (a stick); momentary stops (bounces) are counted separately", setup=setup),
        claim(
            "a spring drive (far end at constant speed) gives stick-slip: force builds while stuck "
            "and drops at each slip", stats["count"] >= 2 and stats["force_drop_mean"] > 0,
            numbers["spring"], "direct: >= 2 detected stick-slip events with positive force drops "
            "(asperity2d.stick_slip_events, default thresholds)", setup=setup),
    ]
    return numbers, runs, claims


# %%
# 3. The three runs in one picture
# --------------------------------
#
# The slider's travel against time (``studies.plot_positions``): one run stops on a flank, one runs
# away, the spring-driven one climbs in steps. :func:`asperity2d.render` draws the spring run's
# time series.

# %%
# 4. Both set-ups
# ---------------
#
# Ooten's fixed-height track first, then the free slider under its load. ``main`` reads the
# options with :mod:`asperity2d.scripting`.

def main(argv=None) -> int:
    args = scripting.parser(scripting.title(__doc__)).parse_args(argv)
    out = scripting.out_dir(args, __file__)
    size = studies.QUICK_SIZE if args.quick else studies.STUDY_SIZE
    summary = {"size": size, "setups": studies.SETUPS, "results": {}, "claims": []}
    lines = []
    for setup in studies.SETUPS:
        numbers, runs, claims = run_setup(setup, size)
        summary["results"][setup] = numbers
        summary["claims"] += claims
        fc = numbers["critical_force_from_rest_N"]
        spring = numbers["spring"]
        studies.plot_positions([runs["below"], runs["above"], runs["spring"]],
                       [f"constant {FACTORS['below']} x {fc * 1e3:.3g} mN from rest ({runs['below'].status})",
                        f"constant {FACTORS['above']} x {fc * 1e3:.3g} mN from rest ({runs['above'].status})",
                        f"spring drive ({spring['events']['count']} stick-slip events)"],
                       out / f"positions_{setup}.png")
        a.render(runs["spring"], out / f"spring_{setup}.png")
        ev = spring["events"]
        lines.append(f"[{setup}] critical force from rest {fc * 1e3:.4g} mN: 0.95 x -> {runs['below'].status}, "
                     f"1.05 x -> {runs['above'].status}; spring drive: {ev['count']} stick-slip events, first "
                     f"breakaway {spring['first_breakaway_N'] * 1e3:.3g} mN, peak stick force "
                     f"{spring['peak_stick_force_N'] * 1e3:.3g} mN, mean stick force "
                     f"{spring['mean_stick_force_N'] * 1e3:.3g} mN, mean force drop {ev['force_drop_mean'] * 1e3:.3g} mN")
        lines += [verdicts.verdict_line(c) for c in claims]
        if setup == "fixed" and not args.no_gif:  # Ooten's own set-up
            a.render(runs["spring"], out / "spring_fixed.gif", frames=args.frames or (30 if args.quick else 120))
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
