"""A scene from a measured-style profile, on both set-ups
======================================================

A scene built from the shipped measured-style profile file, run on both set-ups.

``scenes/data/measured_style_profile.csv`` is SYNTHETIC: a self-affine trace
(H = 0.8, rms 0.15 µm, 50 µm, 4096 points) with instrument-like noise, tilt and
quantisation added by ``scenes/data/make_measured_profile.py``; not a
measurement. ``make_scene(lower_surface=<that file>)`` reads it in the unit
the file states (µm), removes the tilt, and turns every summit of prominence
>= 10 % of the rms height into a triangular lower asperity with its own
height, flanks and base level (Table 1 stiffness and mass for all). The
slider carries Ooten's four 45° triangles (1 µm base, 1.25 µm pitch).

* fixed track: the deepest upper tip runs one rms height above the profile's
  mean line, or 5 % of the rms height above the profile's rigid valley floor
  between asperities where that is higher (a rigid slider cannot pass below
  it); claim: the asperities touched over a spring-driven pass are exactly
  those whose summit rises above that height;
* free slider under 0.3 mN: the critical force and the mean stick force,
  against a regular surface of the profile's median asperity (same count,
  base and height, bases touching); the contact angle the breakaway forces
  imply is reported beside the steepest flanks in contact.

Outputs: ``profile_touched.png`` (the profile, its asperities, the ones the
fixed-track pass touched and the track height), ``fixed_run.png`` and
``fixed_run.gif`` (the fixed-track pass), ``summary.json``. ``--quick`` uses
the first 8 µm of the trace and a 5x faster drive (a smoke test).

Run::

    python scenes/rough_measured.py [--quick] [--no-gif] [--json] [-o DIR]
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import asperity2d as a
from asperity2d import surface
from asperity2d import scripting
from asperity2d import stats
from asperity2d.experiments.verdicts import claim, verdict_line
from asperity2d.studies.rough import fixed_track_interference, measure, pass_measures

# %%
# The settings
# ------------
#
# The shipped trace, Ooten's four-tip slider, and the free slider's load.

DATA = Path(__file__).resolve().parent / "data" / "measured_style_profile.csv"
SLIDER = dict(upper_count=4)
#: The free slider's load: 0.3 mN pushes one 37,200 N/m track 8 nm down, a fifth of the median
#: asperity's 44 nm (the package default 10 mN would push it 0.27 µm, to the bottom of its track).
LOAD = 0.3e-3
QUICK_LENGTH = 8e-6  # m of the trace used by --quick


# %%
# 1. The profile and the scenes made from it
# ------------------------------------------
#
# :func:`asperity2d.make_scene` accepts a profile as ``lower_surface``: it levels it and turns
# every summit of prominence at least 10 % of the rms height into a lower asperity of its own
# height, flanks and base level (:func:`asperity2d.surface.find_asperities` does the same here,
# for the plot). The fixed track's height is set from the profile
# (:func:`asperity2d.studies.rough.fixed_track_interference`); the free slider is compared with
# a regular surface of the profile's median asperity, built the same way from a triangle wave.

def triangle_wave(count: int, base: float, height: float) -> tuple[np.ndarray, np.ndarray]:
    """``count`` touching isosceles triangles of ``base`` and ``height`` (m) on z = 0, sampled
    every base / 64, with half a base of flat ground at each end: ``(x, z)`` in m."""
    x = np.arange(0.0, (count + 1) * base, base / 64.0)
    u = x / base - 0.5  # in bases, from the first foot
    inside = (u >= 0) & (u <= count)
    z = np.where(inside, height * (1.0 - np.abs(2.0 * (u % 1.0) - 1.0)), 0.0)
    return x, z


def load(quick: bool) -> surface.SurfaceProfile:
    profile = surface.read_profile(DATA)
    if quick:
        keep = profile.x < profile.x[0] + QUICK_LENGTH
        profile = surface.SurfaceProfile(profile.x[keep], profile.z[keep], name=profile.name,
                                         metadata={**profile.metadata, "cropped_m": QUICK_LENGTH})
    return profile


def scenes(profile, quick: bool) -> dict:
    """The scenes of the lesson: ``probe`` (the free slider, to read the surface), ``fixed``,
    ``free`` and ``regular`` (the free slider on the median asperity's regular surface), with the
    levelled profile, its rms height, its asperity record and which way the track height was set."""
    slider = dict(SLIDER, **({"drive_velocity": 100.0} if quick else {}))
    # what make_scene extracts: the levelled profile's summits of prominence >= 10 % of its rms
    levelled = profile.detrended()
    rms = surface.rms_height(levelled)
    record = surface.find_asperities(levelled, min_prominence=0.1 * rms, stiffness=1.0, mass=1.0)
    probe = a.make_scene(lower_surface=profile, track="free", **slider)
    interference, raised = fixed_track_interference(probe.lower, rms, 0.05 * rms)
    fixed = a.make_scene(lower_surface=profile, track="fixed", interference=interference, **slider)
    free = a.make_scene(lower_surface=profile, track="free", normal_load=LOAD, **slider)
    lower = free.lower
    # the same slider on a regular surface of the median asperity, bases touching, built through
    # the same profile path from a triangle wave, with the profile's track travel (a profile scene's
    # travel is its tallest asperity; the median's own would put the stops 3-7x closer and make
    # the comparison one of travel stops, not of geometry)
    regular = a.make_scene(lower_surface=triangle_wave(lower.count, lower.profile.base, lower.profile.height),
                           surface_detrend=False, track="free", normal_load=LOAD,
                           travel_down=lower.travel_down, travel_up=lower.travel_up, **slider)
    return {"probe": probe, "fixed": fixed, "free": free, "regular": regular, "levelled": levelled,
            "rms": rms, "record": record, "raised": raised}


# %%
# 2. Run and measure
# ------------------
#
# On the fixed track, one spring-driven pass (:func:`asperity2d.studies.rough.pass_measures`:
# which asperities it touched, its stick forces) and the critical force from rest
# (:func:`asperity2d.critical_force`); on the free slider, both surfaces measured alike
# (:func:`asperity2d.studies.rough.measure`).

def run_all(made: dict):
    """The measures of every run (N, counts, degrees) and the fixed-track pass itself."""
    fixed_pass, pass_result = pass_measures(made["fixed"])
    runs = {"fixed": {"critical_force_N": a.critical_force(made["fixed"]), **fixed_pass},
            "free": measure(made["free"]), "free_regular_median": measure(made["regular"])}
    return runs, pass_result


# %%
# 3. Judge
# --------
#
# Two claims, each one realisation (one profile), so each is a direct check rather than a
# test over seeds: :func:`asperity2d.experiments.verdicts.claim` records the statement, whether
# it holds, the numbers and the test.

def judge_runs(runs: dict, count: int) -> list[dict]:
    """The claim records of the fixed track's touched set and the free slider's comparison."""
    f, r = runs["free"], runs["free_regular_median"]
    return [
        claim("fixed track: the asperities touched are exactly those whose summit is above the track",
              runs["fixed"]["touched_matches_above_level"] == 1.0,
              {"touched": runs["fixed"]["touched_count"],
               "above_level": runs["fixed"]["above_level_fraction"] * count},
              "the set touched at any step of the pass == summits above the track", setup="fixed"),
        claim("free slider: the profile needs a larger critical force than a regular surface of its "
              "median asperity", bool(f["critical_force_N"] > r["critical_force_N"]),
              {"profile_N": f["critical_force_N"], "regular_median_N": r["critical_force_N"],
               "ratio": f["critical_force_N"] / r["critical_force_N"]},
              "one realisation: direct comparison of the two critical forces", setup="free"),
    ]


# %%
# 4. Plot
# -------
#
# The profile with its asperities, those the fixed-track pass touched in blue and the track's
# height as a dashed line, and the pass itself: both with :func:`asperity2d.render`.

# %%
# The command line
# ----------------
#
# ``main`` reads the options (``--quick``, ``--no-gif``, ``-o``, ``--json``), runs the steps and
# prints the measures and the verdicts.

def main(argv=None) -> int:
    args = scripting.parser(scripting.title(__doc__)).parse_args(argv)
    out = scripting.out_dir(args, __file__)
    profile = load(args.quick)
    made = scenes(profile, args.quick)
    probe, fixed, lower = made["probe"], made["fixed"], made["free"].lower
    shapes, rms = lower.shapes, made["rms"]
    runs, pass_result = run_all(made)
    touched = pass_result.lower_contact.any(axis=1)
    a.render(made["record"], out / "profile_touched.png", profile=made["levelled"], highlight=touched,
             level=probe.lower.top - fixed.slider.interference)
    a.render(pass_result, out / "fixed_run.png")
    outputs = ["profile_touched.png", "fixed_run.png"]
    if not (args.no_gif or args.quick):
        a.render(pass_result, out / "fixed_run.gif", frames=args.frames or 120)
        outputs.append("fixed_run.gif")

    claims = judge_runs(runs, lower.count)
    angles = np.degrees(np.arctan2(shapes.heights, np.asarray(shapes.left_runs)))
    summary = {
        "profile": {"file": str(DATA), "synthetic": True, "points": profile.count,
                    "length_m": profile.length, "rms_height_m": rms,
                    "cropped": bool(args.quick)},
        "asperities": {"count": lower.count, "height_m": stats.describe(shapes.heights),
                       "base_m": stats.describe(shapes.bases), "summit_m": stats.describe(shapes.summits),
                       "left_flank_deg": stats.describe(angles), "mean_pitch_m": lower.spacing.mean_pitch},
        "track_height_m": probe.lower.top - fixed.slider.interference,
        "track_set_by": "the rigid valley floor" if made["raised"] else "one rms above the mean line", "runs": runs,
        "claims": claims, "outputs": outputs}
    lines = [f"{profile.name}: {lower.count} asperities over {profile.length * 1e6:.1f} µm, heights "
             f"{np.mean(shapes.heights) * 1e9:.0f} ± {np.std(shapes.heights) * 1e9:.0f} nm, flanks "
             f"{np.mean(angles):.1f}° (max {np.max(angles):.1f}°)"]
    for name, m in runs.items():
        if np.isfinite(m["mean_stick_force_N"]):
            stick = (f"mean stick {m['mean_stick_force_N'] * 1e3:.3g} mN, touched {m['touched_count']:.0f}, "
                     f"breakaway angle {m['breakaway_angle_deg']:.1f}°")
        else:  # the quick run's drive is 5x faster: the slider slides through without sticking
            stick = (f"touched {m['touched_count']:.0f}, no stick-slip event over the pass (so no mean stick force or "
                     f"breakaway angle{': the quick run drives 5x faster' if args.quick else ''})")
        lines.append(f"{name}: critical {m['critical_force_N'] * 1e3:.3g} mN, {stick}")
    lines += [verdict_line(c) for c in claims]
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
