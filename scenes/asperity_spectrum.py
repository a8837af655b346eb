"""The spectrum of asperity stick-slip: regular against random spacing
===================================================================

From E. Ooten, *Precision Motion Control at Low Velocities in the Presence of
Friction* (senior thesis, Texas A&M University, 1997-98).

The asperity stick-slip spectrum: regular against random spacing, and a drive-preload scan.

Run: ``python scenes/asperity_spectrum.py [--quick] [--workers auto|N] [-o DIR] [--json]``.

Ooten's set-up on the fixed-height track (``make_scene(track="fixed")``)
with a spring drive, at two drive stiffnesses: the default 3 720 N/m over
120 lower asperities (the slider slips several pitches at a time, so a run
needs many asperities to show several cycles) and a tenfold stiffer
37 200 N/m (the lower asperities' own stiffness) over 40. For regular and
random (seed 0) spacing the friction force and the drive force are analysed
over the part of the run where the slider is on the surface (15-90 % of the
run, ``asperity2d.dynamics.ASPERITY_WINDOW``):

* periodogram, dominant frequency in units of drive speed / mean pitch;
* ``line_fraction``: the share of the force's variance (above 0.2 V/pitch)
  within ±2 bins of the harmonics k·V/pitch, k = 1..5 -- near 1 for a
  spectrum of sharp lines at the pitch frequency, small when smeared;
* the slip sequence's class (``asperity2d.dynamics.classify_asperity``).

Then a scan over the drive preload (the initial condition the public API
offers: ``asperity2d.dynamics.asperity_basins`` says why the spacing
offset is not one) on the regular surface, and a WAV of the regular run's
friction force (its pitch frequency heard at 110 Hz) with its spectrogram.
"""

import itertools

import numpy as np
from matplotlib.figure import Figure

from asperity2d import make_scene, render, simulate
from asperity2d.dynamics import signal, spectrum
from asperity2d.dynamics import ASPERITY_WINDOW as WINDOW, BASIN_LABELS as LABELS, asperity_basins, classify_asperity
from asperity2d import scripting

# %%
# The settings
# ------------
#
# Two drive stiffnesses (N/m) and the number of lower asperities each needs to show several
# stick-slip cycles; the quick setting (the one the documentation ran) uses the stiff drive over
# 10 asperities only, so its spectra have few lines and coarse bins.

DRIVES = {"default": (3_720.0, 120), "stiff": (37_200.0, 40)}  # N/m, lower asperities


# %%
# 1. A run and its spectrum
# -------------------------
#
# :func:`asperity2d.make_scene` and :func:`asperity2d.simulate` make the run;
# :func:`asperity2d.dynamics.signal` takes a named series out of it and
# :func:`asperity2d.dynamics.spectrum` its periodogram, over the part of the run where the slider
# is on the surface. Frequencies are read in units of the pitch frequency, drive speed / mean
# pitch: a regular surface should show sharp lines at its harmonics.

def line_fraction(sp, f_pitch, harmonics=5):
    """Share of the PSD above 0.2 f_pitch that lies within ±2 bins of k·f_pitch, k = 1..harmonics."""
    f, p = sp.frequency, sp.power
    above = f > 0.2 * f_pitch
    near = np.zeros_like(above)
    for k in range(1, harmonics + 1):
        near |= np.abs(f - k * f_pitch) <= 2 * sp.resolution
    return float(p[above & near].sum() / p[above].sum())


def run_and_spectra(spacing: str, stiffness: float, count: int):
    """One run on the fixed track with a spring drive, and the spectra of its friction and drive
    forces in the window: ``(result, row of numbers, friction force Spectrum)``."""
    scene = make_scene(spacing=spacing, seed=0, track="fixed", drive="spring", lower_count=count,
                       drive_stiffness=stiffness)
    result = simulate(scene)
    f_pitch = scene.drive.velocity / scene.lower.spacing.mean_pitch
    t = result.t
    w = (t >= t[0] + WINDOW[0] * (t[-1] - t[0])) & (t <= t[0] + WINDOW[1] * (t[-1] - t[0]))
    row = {"drive_stiffness_N_m": stiffness, "lower_count": count, "status": result.status,
           "duration_s": float(t[-1]), "pitch_frequency_hz": f_pitch}
    friction = None
    for name in ("friction_force", "drive_force"):
        tt, y = signal(result, name)
        sp = spectrum(tt[w], y[w], method="periodogram")
        row[name] = {"dominant_over_pitch_frequency": sp.dominant / f_pitch,
                     "resolution_over_pitch_frequency": sp.resolution / f_pitch,
                     "line_fraction": line_fraction(sp, f_pitch), "thd": sp.thd,
                     "peaks_over_pitch_frequency": [q.frequency / f_pitch for q in sp.peaks[:5]]}
        if name == "friction_force":
            friction = sp
    return result, row, friction


# %%
# 2. The slip sequence's class
# ----------------------------
#
# ``classify_asperity`` sorts the run by its slips in the window: rest, pure slip, stick-slip
# (the slips repeat, with a period of so many pitches) or irregular.

def slip_class(result) -> dict:
    """The class of the run's slip sequence, its slip count and pitches per cycle."""
    cls = classify_asperity(result)
    return {"class": LABELS[int(cls["label"])], "slip_events_in_window": int(cls["events"]),
            "pitches_per_cycle": cls["pitches_per_cycle"]}


# %%
# 3. Plot the spectra
# -------------------
#
# The friction force's periodograms on one axis (a plain matplotlib figure), the dominant
# frequency and its harmonics marked.

def plot_spectra(curves, path, *, f_max: float, title: str) -> str:
    """The friction force's PSD (N²/Hz, log scale) of each (label, Spectrum) up to ``f_max`` (Hz),
    its dominant frequency and harmonics marked by dots."""
    fig = Figure(figsize=(7.5, 3.6), layout="constrained")
    ax = fig.add_subplot()
    for label, sp in curves:
        keep = (sp.frequency > 0) & (sp.frequency <= f_max)
        line, = ax.semilogy(sp.frequency[keep] / 1e6, sp.power[keep], lw=0.9,
                            label=f"{label}: {sp.dominant / 1e6:.4g} MHz, THD {sp.thd:.2f}")
        marks = [h.frequency for h in sp.harmonics if np.isfinite(h.power) and h.power > 0 and h.frequency <= f_max]
        ax.plot(np.divide(marks, 1e6), np.interp(marks, sp.frequency, sp.power), "o", ms=3, color=line.get_color())
    ax.set_xlabel("frequency (MHz)")
    ax.set_ylabel("PSD (N²/Hz)")
    ax.legend(fontsize=7, loc="upper right")
    ax.set_title(title, fontsize=9)
    fig.savefig(path, dpi=120)
    return str(path)


# %%
# The command line
# ----------------
#
# ``main`` reads the options (``--quick``, ``--workers``, ``-o``, ``--json``), runs both spacings
# at each drive, scans the drive preload on the regular surface (``asperity_basins`` runs one
# scene per preload through the sweep machinery), writes the regular run's friction force as a
# WAV with :func:`asperity2d.render` (its pitch frequency heard at 110 Hz) and prints.

def main(argv=None) -> int:
    si = scripting.si
    p = scripting.parser(scripting.title(__doc__))
    scripting.add_workers(p)
    args = p.parse_args(argv)
    out = scripting.out_dir(args, __file__)
    drives = {"stiff": (DRIVES["stiff"][0], 10)} if args.quick else DRIVES
    summary = {"scene": {"track": "fixed", "drive": "spring", "upper_count": 4, "pitch_m": 1.25e-6,
                         "drive_velocity_m_s": 20.0}, "window": list(WINDOW), "runs": {}}
    curves, regular = [], None
    for (drive, (stiffness, count)), spacing in itertools.product(drives.items(), ("regular", "random")):
        result, row, friction = run_and_spectra(spacing, stiffness, count)
        if spacing == "regular" and drive == "stiff":
            regular = result
        curves.append((f"{spacing}, {drive} drive", friction))
        row.update(slip_class(result))
        summary["runs"][f"{spacing}_{drive}"] = row
    summary["plot"] = plot_spectra(curves, out / "friction_spectra.png", f_max=6 * 16e6,
                                   title="friction force spectra, fixed track (V/pitch = 16 MHz); "
                                         "dots: dominant frequency and its harmonics")
    summary["notes"] = "scan and sound use the stiff drive (many slips on a 40-asperity surface)"
    preloads = (0.0, 0.01) if args.quick else (0.0, 0.005, 0.01, 0.02, 0.03)
    stiffness, count = drives["stiff"]
    scan_kw = dict(track="fixed", drive="spring", lower_count=count, drive_stiffness=stiffness)
    scan = asperity_basins(scan_kw, preloads, store=out / "preload.runs", workers=args.workers,
                           progress=not args.json)
    summary["preload_scan"] = {"preloads_N": list(preloads), "scene": scan_kw,
                               "classes": [LABELS[int(c)] if c >= 0 else "failed" for c in scan.values["label"][:, 0]],
                               "slip_events": scan.values["events"][:, 0].tolist(), **scan.to_dict()}
    f_pitch = regular.scene.drive.velocity / regular.scene.lower.spacing.mean_pitch
    wav = render(regular, out / "regular_friction.wav", signal="friction_force", time_scale=110.0 / f_pitch)
    summary["sound"] = {"path": str(wav), "spectrogram": str(wav.with_name(wav.stem + ".spectrogram.png")),
                        "signal": "friction_force", "time_scale": 110.0 / f_pitch}
    lines = []
    for name, row in summary["runs"].items():
        fr = row["friction_force"]
        lines.append(f"{name}: dominant {fr['dominant_over_pitch_frequency']:.4f} V/pitch (bin "
                     f"{fr['resolution_over_pitch_frequency']:.3f}), line fraction {fr['line_fraction']:.2f}, "
                     f"slips {row['slip_events_in_window']} -> {row['class']}"
                     + (f", {row['pitches_per_cycle']:.3g} pitches/cycle" if row['pitches_per_cycle'] == row['pitches_per_cycle'] else ""))
    lines.append("drive preload scan: " + ", ".join(
        f"{si(p, 'N', 3, trim=True)} -> {c}" for p, c in zip(preloads, summary["preload_scan"]["classes"])))
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
