"""Spectra of the three-mass chain across belt speed
=================================================

From the thesis *Vibration Analysis of Multi Degree of Freedom Self-excited
Systems* (no author named in the copy used here), called the multi-DOF belt
thesis below.

Spectra of the multi-DOF belt thesis' 3-DOF chain across belt speed: where the stick-slip sawtooth goes.

Run::

    python scenes/belt_spectra.py [--quick] [-o DIR] [--json]

The multi-DOF belt thesis (Figures 5, 12, 13) sees stick-slip at 0.1 m/s fade as the belt
speeds up, into "quasi-harmonic oscillation with a constant amplitude and
period" at 0.7 m/s. For every belt speed this script runs the Table 2 chain
from eq 3.12 with the exact solver and measures mass 1's displacement
spectrum (periodogram) in two windows -- the thesis' first 10 s, and the
steady state (the last half of a long run) -- with its dominant frequency,
harmonic distortion (THD) and stick fraction, and the run's class
(:func:`asperity2d.studies.mdof_belt.motion_class`). The same for a contrast
chain with static friction 0.4 above the kinetic 0.2, which keeps a
stick-slip cycle. The undamped chain's normal modes, f = sqrt(k (2 - 2 cos(jπ/4)) / m) / 2π,
are printed beside them. Writes spectra plots, THD / stick fraction against
speed, two WAVs (base case and contrast at 0.1 m/s) and ``summary.json``.

Resolution caveat: a 10 s window has 0.1 Hz bins, too coarse to tell the
second mode (0.712 Hz) from the second harmonic of the first (0.770 Hz), so
in that window a pure-slip motion still shows a THD of about 0.3; the
steady window (0.005 Hz bins at 400 s) separates them.
"""

# %%
# The lesson is made of the package's public calls: the belt chains of ``asperity2d.belt``, the
# signals and spectra of ``asperity2d.dynamics``, the run's class from
# ``asperity2d.studies.mdof_belt``, the WAV through :func:`asperity2d.render`, and matplotlib for
# the plots.

import numpy as np
from matplotlib.figure import Figure

import asperity2d as a
from asperity2d import scripting
from asperity2d.belt import presets, simulate_chain
from asperity2d.dynamics import signal, spectrum
from asperity2d.studies import mdof_belt as S

SPEEDS = (0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 1.0)
QUICK_SPEEDS = (0.1, 0.7)
#: The undamped chain's normal modes (Hz): sqrt(k (2 - 2 cos(j pi / 4)) / m) / 2 pi.
MODES_HZ = [float(np.sqrt(10.0 * (2 - 2 * np.cos(j * np.pi / 4)) / 1.0) / (2 * np.pi)) for j in (1, 2, 3)]


# %%
# 1. A spectrum of one window of a run
# ------------------------------------
#
# :func:`asperity2d.dynamics.signal` takes a named series out of a run (mass 1's displacement),
# :func:`asperity2d.dynamics.spectrum` its periodogram with the dominant frequency, its harmonics
# and the harmonic distortion (THD). Beside it: the largest fraction of the window any mass spends
# stuck.

def stick_fraction(result, a, b):
    """Largest fraction of [a, b] any mass spends stuck."""
    return max(sum(max(0.0, min(e, b) - max(s, a)) for s, e in per) / (b - a) for per in result.stick_intervals)


def measure(result, a, b):
    """The spectrum of x1 over [a, b] s and its numbers."""
    t, x = signal(result, "x", mass=0)
    w = (t >= a) & (t <= b)
    sp = spectrum(t[w], x[w], method="periodogram")
    return sp, {"window_s": [a, b], "dominant_hz": sp.dominant, "resolution_hz": sp.resolution, "thd": sp.thd,
                "peaks_hz": [p.frequency for p in sp.peaks[:4]], "stick_fraction": stick_fraction(result, a, b)}


# %%
# 2. Across belt speed, two chains
# --------------------------------
#
# The thesis' chain (mu0 = 0.2) and a contrast with static friction 0.4, each run exactly from
# eq 3.12 at every belt speed; each run's class, and the spectra of its first 10 s and of its
# steady state (the last half).

def sweep(speeds, t_end: float):
    """Rows of measures per chain and speed, and the spectra by (chain, speed)."""
    chains, spectra = {}, {}
    for chain, mu_s in (("base", 0.2), ("contrast_mu_s_0.4", 0.4)):
        rows = []
        for v in speeds:
            r = simulate_chain(**presets.preset("table2-3dof", v_belt=v, mu_s=mu_s, t_end=t_end,
                                                n_samples=int(100 * t_end) + 1))
            cls = S.motion_class(r)
            sp_first, first = measure(r, 0.0, 10.0)
            sp_steady, steady = measure(r, t_end / 2, t_end)
            spectra[(chain, v)] = (sp_first, sp_steady)
            rows.append({"v_belt": v, "class": cls["class"], "multiplicity": cls["multiplicity"],
                         "period_s": cls["period_s"], "last_stick_s": cls["last_stick_s"],
                         "first_10s": first, "steady": steady})
        chains[chain] = rows
    return chains, spectra


# %%
# 3. The plots
# ------------
#
# The spectra on a log scale with the dominant frequency and its harmonics marked, and THD and
# stick fraction against belt speed.

def plot_spectra(curves, path, title: str):
    """PSD of x1 against frequency (up to 3 Hz), one curve per (label, spectrum)."""
    fig = Figure(figsize=(7.5, 3.6), layout="constrained")
    ax = fig.add_subplot()
    for label, sp in curves:
        keep = (sp.frequency > 0) & (sp.frequency <= 3.0)
        line, = ax.semilogy(sp.frequency[keep], sp.power[keep], lw=0.9,
                            label=f"{label}: {sp.dominant:.4g} Hz, THD {sp.thd:.2f}")
        marks = [h.frequency for h in sp.harmonics if np.isfinite(h.power) and h.power > 0 and h.frequency <= 3.0]
        ax.plot(marks, np.interp(marks, sp.frequency, sp.power), "o", ms=3, color=line.get_color())
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("PSD (m²/Hz)")
    ax.legend(fontsize=7, loc="upper right")
    ax.set_title(title, fontsize=9)
    fig.savefig(path, dpi=120)
    return path.name


def plot_trends(chains, path):
    """THD and stick fraction of both windows against belt speed."""
    fig = Figure(figsize=(7.0, 5.2), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    for chain, rows in chains.items():
        v = [r["v_belt"] for r in rows]
        for key, style in (("first_10s", "--"), ("steady", "-")):
            ax1.plot(v, [r[key]["thd"] for r in rows], style, marker="o", ms=3, label=f"{chain}, {key}")
            ax2.plot(v, [r[key]["stick_fraction"] for r in rows], style, marker="o", ms=3, label=f"{chain}, {key}")
    ax1.set_ylabel("THD of x1")
    ax2.set_ylabel("stick fraction")
    ax2.set_xlabel("belt speed (m/s)")
    ax1.legend(fontsize=7)
    ax1.set_title("harmonic distortion and sticking against belt speed", fontsize=9)
    fig.savefig(path, dpi=120)
    return path.name


# %%
# 4. The sound
# ------------
#
# :func:`asperity2d.render` writes a run to ``.wav``: mass 1's acceleration, its lowest mode heard
# at 440 Hz, with a spectrogram beside it (``<name>.spectrogram.png``).

def sounds(out, t_end: float) -> dict:
    """The base case and the contrast at 0.1 m/s, heard."""
    found = {}
    for chain, mu_s in (("base", 0.2), ("contrast_mu_s_0.4", 0.4)):
        r = simulate_chain(**presets.preset("table2-3dof", v_belt=0.1, mu_s=mu_s, t_end=t_end,
                                            n_samples=int(50 * t_end) + 1))
        path = a.render(r, out / f"{chain}_v0.1_x1_acceleration.wav")
        found[chain] = {"path": str(path), "spectrogram": str(path.with_name(path.stem + ".spectrogram.png"))}
    return found


# %%
# The command line
# ----------------
#
# ``main`` reads the options (``--quick``: two speeds, 40 s runs), runs the steps and prints a
# row per chain and speed.

def main(argv=None) -> int:
    args = scripting.parser(scripting.title(__doc__)).parse_args(argv)
    out = scripting.out_dir(args, __file__)
    speeds = QUICK_SPEEDS if args.quick else SPEEDS
    t_end = 40.0 if args.quick else 400.0
    chains, spectra = sweep(speeds, t_end)
    summary = {"modes_hz": MODES_HZ, "t_end_s": t_end, "signal": "x1 (m), mass 1's displacement",
               "chains": chains}
    picks = [v for v in (0.1, 0.4, 0.7) if v in speeds]
    modes = ", ".join(f"{f:.3f}" for f in MODES_HZ)
    plots = []
    for chain in chains:
        for k, window in ((0, "first 10 s"), (1, "steady state")):
            plots.append(plot_spectra([(f"{v:g} m/s", spectra[(chain, v)][k]) for v in picks],
                                      out / f"spectra_{chain}_{'first10s' if k == 0 else 'steady'}.png",
                                      f"{chain}: x1 spectra, {window} (modes {modes} Hz)"))
    plots.append(plot_trends(chains, out / "thd_vs_speed.png"))
    summary["plots"] = plots
    summary["sounds"] = sounds(out, 100.0 if args.quick else 2000.0)
    lines = [f"modes of the undamped chain: {', '.join(f'{f:.4f}' for f in MODES_HZ)} Hz"]
    for chain, rows in chains.items():
        lines.append(f"{chain}:")
        for row in rows:
            f10, st = row["first_10s"], row["steady"]
            lines.append(f"  {row['v_belt']:4.2f} m/s: {row['class']:10s} | first 10 s: stick "
                         f"{f10['stick_fraction']:.2f}, THD {f10['thd']:.2f}, f {f10['dominant_hz']:.3f} Hz | steady: stick "
                         f"{st['stick_fraction']:.3f}, THD {st['thd']:.3f}, f {st['dominant_hz']:.4f} Hz")
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
