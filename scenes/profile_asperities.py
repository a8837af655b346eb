"""A measured-style profile turned into asperities
===============================================

A measured-style surface profile turned into triangular asperities, with its statistics: the
lesson reads a profile, levels it, fits its Hurst exponent, and turns its summits into the
asperities a scene is made of. The stiffness and mass rules are those of E. Ooten,
*Precision Motion Control at Low Velocities in the Presence of Friction* (senior thesis, Texas
A&M University, 1997-98), Table 1 and Appendix A.

Reads ``scenes/data/measured_style_profile.csv`` (a SYNTHETIC self-affine
trace with instrument-like noise and tilt, made by
``scenes/data/make_measured_profile.py``; not a measurement), removes the
tilt, and reports the rms height, rms slope and the Hurst exponent fitted to
the power spectrum between the wavelengths length / 8 (6.25 µm; the longest
ones are few and smeared by the window) and 0.2 µm (above the noise floor);
the recipe asked for H = 0.8 between 10 µm and 0.1 µm (the quick run's quarter trace is too
short for the fit to find it: it reports its own H with its error). The summits with prominence
>= 20 nm (ten times the noise) and width at half prominence >= 0.1 µm become
triangular asperities by the rule of ``asperity2d.surface.asperities``;
track stiffness from Ooten's Table 1's rule K = 2 E b with its printed
E = 1.86e10 Pa (37,200 N/m at b = 1 µm, the package default), mass from the
Appendix A pyramid rho b^2 h / 3 with steel's 7850 kg/m^3 (Ooten's
printed 8 kg/m^3 is a thousand times low).

Outputs: ``profile_asperities.png`` (whole trace), ``profile_zoom.png``
(first 10 µm), ``spectrum.png``, ``asperities.json`` (the record), and
``summary.json``.

Run::

    python scenes/profile_asperities.py [--quick] [--json] [-o DIR] [--profile FILE --unit um]
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

import asperity2d as a
from asperity2d import scripting
from asperity2d import surface

# %%
# The settings
# ------------
#
# The shipped trace, the rule that decides which summits become asperities (prominence and
# width, above the trace's noise), and Ooten's rules for each asperity's track stiffness and mass.

DATA = Path(__file__).resolve().parent / "data" / "measured_style_profile.csv"
MIN_PROMINENCE = 20e-9  # m: ten times the 2 nm rms noise of the shipped trace
MIN_WIDTH = 0.1e-6  # m, width at half prominence
MODULUS = 1.86e10  # Pa, Ooten's Table 1 as printed
DENSITY = 7850.0  # kg/m^3, steel
SHORTEST_FIT_WAVELENGTH = 0.2e-6  # m


# %%
# 1. Read and level the profile
# -----------------------------
#
# :func:`asperity2d.surface.read_profile` reads a two-column file (or an instrument's file) in
# the unit it is given; :meth:`~asperity2d.surface.SurfaceProfile.detrended` removes the tilt.
# The quick setting (the one the documentation ran) keeps the first quarter of the trace.

def load_profile(path, unit: str, quick: bool):
    """The levelled profile of the file ``path`` (the first quarter of it if ``quick``)."""
    measured = surface.read_profile(path, unit=unit)
    if quick:  # the first quarter of the trace
        keep = slice(0, max(64, measured.count // 4))
        measured = surface.SurfaceProfile(measured.x[keep], measured.z[keep], name=measured.name,
                                          metadata={**measured.metadata, "cropped": "first quarter"})
    return measured.detrended()


# %%
# 2. Its spectrum and Hurst exponent
# ----------------------------------
#
# :func:`asperity2d.surface.power_spectrum` gives C(q); a self-affine surface has
# C(q) ~ q^-(1 + 2H). :func:`asperity2d.surface.fit_hurst` fits H over a band of wavenumbers:
# from 8 times the longest wavelength's q (the longest ones are few and smeared by the window)
# to the shortest wavelength above the noise floor.

def hurst_fit(profile):
    """The profile's power spectrum and the Hurst fit over the band the text explains."""
    spectrum = surface.power_spectrum(profile)
    fit = surface.fit_hurst(spectrum, q_min=8 * float(spectrum.q[0]),
                            q_max=2 * math.pi / SHORTEST_FIT_WAVELENGTH)
    return spectrum, fit


# %%
# 3. Summits into asperities
# --------------------------
#
# :func:`asperity2d.surface.find_asperities` keeps the summits of enough prominence and width
# and makes each a triangle (its feet, apex and base level); with ``modulus`` and ``density`` it
# gives each its track stiffness K = 2 E b and its mass rho b^2 h / 3.

def to_asperities(profile, min_prominence: float = MIN_PROMINENCE, min_width: float = MIN_WIDTH):
    """The triangular asperities of ``profile`` by the rule above."""
    return surface.find_asperities(profile, min_prominence=min_prominence, min_width=min_width,
                                   modulus=MODULUS, density=DENSITY)


# %%
# 4. Plot
# -------
#
# :func:`asperity2d.render` draws both: the asperities over their profile (``profile=``;
# ``x_range=`` zooms in) and the spectrum with the fitted line over its band (``fit=``).

def _stats(values: np.ndarray) -> dict:
    return {"mean": float(np.mean(values)), "std": float(np.std(values)),
            "min": float(np.min(values)), "max": float(np.max(values))}


# %%
# The command line
# ----------------
#
# ``main`` reads the options (``--quick``, ``--profile``, ``--unit``, ``--min-prominence``,
# ``--min-width``, ``-o``, ``--json``), runs the steps, writes the record and prints.

def main(argv=None) -> int:
    p = scripting.parser(scripting.title(__doc__))
    p.add_argument("--profile", default=str(DATA), help="two-column x, z file (or instrument file)")
    p.add_argument("--unit", default="um", help="length unit of the file's columns")
    p.add_argument("--min-prominence", type=float, default=MIN_PROMINENCE, help="m")
    p.add_argument("--min-width", type=float, default=MIN_WIDTH, help="m")
    args = p.parse_args(argv)
    out = scripting.out_dir(args, __file__)
    profile = load_profile(args.profile, args.unit, args.quick)
    spectrum, fit = hurst_fit(profile)
    asperities = to_asperities(profile, args.min_prominence, args.min_width)
    a.render(asperities, out / "profile_asperities.png", profile=profile)
    x0 = float(profile.x[0])
    a.render(asperities, out / "profile_zoom.png", profile=profile, x_range=(x0, x0 + 10e-6))
    a.render(spectrum, out / "spectrum.png", fit=fit)
    (out / "asperities.json").write_text(json.dumps(asperities.to_dict(), allow_nan=False) + "\n", encoding="utf-8")
    summary = {
        "profile": {"file": str(args.profile), "points": profile.count, "length_m": profile.length,
                    "spacing_m": profile.spacing, "synthetic": Path(args.profile) == DATA,
                    "rms_height_m": surface.rms_height(profile),
                    "rms_slope": surface.rms_slope(profile)},
        "hurst": {"value": fit.hurst, "stderr": fit.hurst_stderr, "q_min_rad_per_m": fit.q_min,
                  "q_max_rad_per_m": fit.q_max, "points": fit.points,
                  "recipe_value": 0.8 if Path(args.profile) == DATA else None},
        "rule": {"min_prominence_m": args.min_prominence, "min_width_m": args.min_width,
                 "stiffness": "K = 2 E b (Ooten's Table 1)", "modulus_Pa": MODULUS,
                 "mass": "rho b^2 h / 3 (Ooten's Appendix A pyramid)", "density_kg_m3": DENSITY},
        "asperities": {"count": asperities.count, "absorbed": asperities.absorbed, "trimmed": asperities.trimmed,
                       "base_m": _stats(asperities.bases), "height_m": _stats(asperities.heights),
                       "summit_m": _stats(asperities.summits), "left_angle_deg": _stats(asperities.left_angles),
                       "right_angle_deg": _stats(asperities.right_angles),
                       "stiffness_N_m": _stats(asperities.stiffness), "mass_kg": _stats(asperities.mass)},
        "outputs": ["profile_asperities.png", "profile_zoom.png", "spectrum.png", "asperities.json"],
    }
    lines = [
        f"{profile.name}: {profile.count} points over {profile.length * 1e6:.1f} µm, "
        f"rms height {summary['profile']['rms_height_m'] * 1e9:.1f} nm, "
        f"rms slope {summary['profile']['rms_slope']:.3f}",
        f"Hurst exponent {fit.hurst:.3f} ± {fit.hurst_stderr:.3f} over q = {fit.q_min:.3g} .. "
        f"{fit.q_max:.3g} rad/m ({fit.points} points)",
        f"{asperities.count} asperities ({asperities.absorbed} summits absorbed, {asperities.trimmed} trimmed): base "
        f"{np.mean(asperities.bases) * 1e6:.2f} ± {np.std(asperities.bases) * 1e6:.2f} µm, height "
        f"{np.mean(asperities.heights) * 1e9:.1f} ± {np.std(asperities.heights) * 1e9:.1f} nm, flank "
        f"{np.mean(asperities.left_angles):.1f}° / {np.mean(asperities.right_angles):.1f}°",
    ]
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
