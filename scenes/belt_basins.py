"""Basins of the three-mass chain: a transient, and chaos beside a cycle
=====================================================================

From the thesis *Vibration Analysis of Multi Degree of Freedom Self-excited
Systems* (no author named in the copy used here), called the multi-DOF belt
thesis below.

The multi-DOF belt thesis' 3-DOF base case (Table 2): initial-condition basins, stability, and its sound.

Run::

    python scenes/belt_basins.py [--quick] [--grid N] [--workers auto|N] [-o DIR] [--json]

* a basin map over mass 1's initial displacement and velocity (x1, v1), the
  other coordinates at eq 3.12, each run 100 s with the exact solver and
  classified rest / pure slip / stick-slip period-n / irregular
  (:func:`asperity2d.studies.mdof_belt.motion_class`), kept in a resumable sweep store;
* a sample of the points classed irregular run again four times longer
  (does the class hold, or was it a long transient?), and the largest
  Lyapunov exponent of a few that stay irregular (chaos or not?);
* the same map for a contrast chain with static friction 0.4 above the
  kinetic 0.2 (the thesis uses one coefficient, so the base case has no
  static excess);
* the Floquet multipliers of the contrast chain's limit cycle from eq 3.12,
  and the largest Lyapunov exponent (Benettin) of both chains from eq 3.12;
* ``base_x1_acceleration.wav``: mass 1's acceleration over a long run, its
  lowest mode heard at 440 Hz, with its spectrogram.
"""

# %%
# The lesson is made of the package's public calls: the belt chains of ``asperity2d.belt``, the
# Floquet multipliers and Lyapunov exponents of ``asperity2d.dynamics``, the basin maps of
# ``asperity2d.studies.mdof_belt``, the WAV through :func:`asperity2d.render`, and matplotlib
# for the maps.

import numpy as np
from matplotlib.colors import ListedColormap
from matplotlib.figure import Figure
from matplotlib.patches import Patch

import asperity2d as a
from asperity2d import scripting
from asperity2d.belt import presets, simulate_chain
from asperity2d.dynamics import chain_lyapunov, floquet
from asperity2d.studies import mdof_belt as S

X_RANGE = (-0.3, 0.9)  # m: around mass 1's equilibrium under kinetic friction, 0.294 m
V_RANGE = (-0.6, 0.6)  # m/s


# %%
# 1. What a map holds
# -------------------
#
# :func:`asperity2d.studies.mdof_belt.initial_state_basins` runs the chain from every (x1, v1) of
# the grid (the other coordinates at eq 3.12) and classes each run's last quarter: rest, pure
# slip, stick-slip of period n, or irregular. Points classed irregular are run again longer
# (:func:`asperity2d.studies.mdof_belt.recheck_irregular`): a long transient changes class, chaos
# does not, and its largest Lyapunov exponent is positive.

def basin_summary(bm) -> dict:
    """A map's record: its ``to_dict()``, each class's fraction of the runs that finished, and the
    10th and 90th percentiles of the last stick onset."""
    out = bm.to_dict()
    total = int(np.sum(bm.values["label"] >= 0))
    out["fractions"] = {k: v / max(total, 1) for k, v in out["counts"].items() if k != "failed"}
    last = bm.values["last_stick"][bm.values["label"] >= 0]
    if last.size:
        out["last_stick_s"]["p10"], out["last_stick_s"]["p90"] = (float(q) for q in np.percentile(last, [10, 90]))
    return out


def basin_map(name: str, chain: dict, size: int, quick: bool, out, workers, progress: bool) -> dict:
    """One chain's map over (x1, v1): its record, its picture and the long re-runs of its
    irregular points."""
    bm = S.initial_state_basins(chain, np.linspace(*X_RANGE, size), np.linspace(*V_RANGE, size),
                                store=out / f"{name}.runs", workers=workers, progress=progress)
    title = ("Table 2 base case (mu = 0.2, c = 0)" if name == "base" else
             "contrast: mu_s = 0.4 > mu_k = 0.2") + f", {size} x {size} runs of {chain['t_end']:g} s"
    detail = "last_stick" if name == "base" else "stick_fraction"
    return {**basin_summary(bm),
            "plot": draw_basins(bm, out / f"basins_{name}.png", detail, title),
            "irregular_rechecked": S.recheck_irregular(bm, chain, 2 if quick else 4, 2 if quick else 20,
                                                       1 if quick else 3, 10 if quick else 150)}


# %%
# 2. The picture
# --------------
#
# Left: the class of every grid point (stick-slip by its period); right: how long the transient
# lasts (the last stick onset) or how much of the last half a mass spends stuck.

COLOURS = ("#4c72b0", "#8fbc8f", "#dd8452", "#c44e52", "#8172b3", "#222222")
CLASSES = ("rest", "pure slip", "stick-slip period-1", "stick-slip period-2", "stick-slip period >= 3", "irregular")
DETAILS = {"last_stick": "transient: last stick onset (s; 0: never sticks)",
           "stick_fraction": "largest stuck fraction of a mass, last half"}


def draw_basins(bm, path, detail: str, title: str) -> str:
    """Draw basin map ``bm`` to ``path``; the file's name."""
    lab, mult = bm.values["label"], bm.values["multiplicity"]
    code = np.full(lab.shape, np.nan)
    code[lab == 0], code[lab == 1], code[lab == 3] = 0, 1, 5
    stick = lab == 2
    code[stick] = np.clip(mult[stick] + 1, 2, 4)  # period 1 -> 2, period 2 -> 3, period >= 3 -> 4
    xs, ys = bm.x_values, bm.y_values
    dx, dy = (xs[-1] - xs[0]) / max(len(xs) - 1, 1), (ys[-1] - ys[0]) / max(len(ys) - 1, 1)
    extent = (xs[0] - dx / 2, xs[-1] + dx / 2, ys[0] - dy / 2, ys[-1] + dy / 2)
    fig = Figure(figsize=(10.0, 4.4), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2)
    ax1.set_facecolor("#bbbbbb")  # failed runs show as grey
    ax1.imshow(code.T, origin="lower", aspect="auto", extent=extent, cmap=ListedColormap(COLOURS),
               vmin=-0.5, vmax=5.5, interpolation="nearest")
    counts = [int(np.sum(code == i)) for i in range(6)]
    handles = [Patch(color=c, label=f"{n} ({k})") for c, n, k in zip(COLOURS, CLASSES, counts) if k]
    if bm.failed:
        handles.append(Patch(color="#bbbbbb", label=f"failed ({bm.failed})"))
    ax1.legend(handles=handles, fontsize=7, loc="upper right", framealpha=0.85)
    ax1.set_title(f"long-run motion after {bm.t_end:g} s", fontsize=9)
    shown = np.where(lab >= 0, bm.values[detail], np.nan)
    im = ax2.imshow(shown.T, origin="lower", aspect="auto", extent=extent, cmap="viridis", interpolation="nearest")
    fig.colorbar(im, ax=ax2, label=DETAILS[detail])
    ax2.set_title(DETAILS[detail], fontsize=9)
    for ax in (ax1, ax2):
        ax.set_xlabel("x1 at t = 0 (m)")
        ax.set_ylabel("v1 at t = 0 (m/s)")
    fig.suptitle(title, fontsize=10)
    fig.savefig(path, dpi=120)
    return path.name


# %%
# 3. Stability: a cycle, or chaos?
# --------------------------------
#
# The contrast chain reaches a stick-slip limit cycle from eq 3.12: its Floquet multipliers
# (:func:`asperity2d.dynamics.floquet`; stable if every non-trivial one lies inside the unit
# circle). The largest Lyapunov exponent of both chains from eq 3.12
# (:func:`asperity2d.dynamics.chain_lyapunov`, Benettin): positive for chaos.

def stability(quick: bool):
    """The contrast cycle's Floquet multipliers (or why there are none) and both Lyapunov exponents."""
    long = 120.0 if quick else 300.0
    try:
        fl = floquet(presets.preset("table2-3dof", mu_s=0.4, t_end=long, n_samples=int(100 * long) + 1)).to_dict()
    except Exception as exc:  # noqa: BLE001 -- a run without a cycle is a result, reported as such
        fl = {"error": str(exc)}
    steps = 10 if quick else 150
    lyapunov = {
        "base": chain_lyapunov(presets.preset("table2-3dof"), steps=steps, interval=2.0).to_dict(),
        "contrast_mu_s_0.4": chain_lyapunov(presets.preset("table2-3dof", mu_s=0.4), steps=steps,
                                            interval=2.0).to_dict(),
    }
    return fl, lyapunov


# %%
# 4. The sound
# ------------
#
# :func:`asperity2d.render` writes a run to ``.wav``: mass 1's acceleration over a long run, its
# lowest mode heard at 440 Hz, with its spectrogram beside it.

def sound(out, quick: bool) -> dict:
    """The base case, heard."""
    sound_t = 100.0 if quick else 3000.0
    run = simulate_chain(**presets.preset("table2-3dof", t_end=sound_t, n_samples=int(50 * sound_t) + 1))
    wav = a.render(run, out / "base_x1_acceleration.wav", signal="acceleration", mass=0)
    return {"path": str(wav), "spectrogram": str(wav.with_name(wav.stem + ".spectrogram.png"))}


# %%
# In words
# --------

def _counts(counts: dict) -> str:
    """``"pure slip 4 (44 %), irregular 5 (56 %)"``: the classes that occurred."""
    total = sum(counts.values()) or 1
    return ", ".join(f"{k} {v} ({100 * v / total:.0f} %)" for k, v in counts.items() if v) or "none"


def _recheck(record: dict) -> str:
    """The long re-runs of irregular points in words."""
    if not record.get("checked"):
        return "none to check"
    text = f"{record['checked']} checked over {record['t_end_s']:g} s: {_counts(record['classes'])}"
    lyap = record.get("lyapunov_of_still_irregular") or []
    if lyap:
        text += "; largest Lyapunov exponents of those still irregular " + ", ".join(
            f"{r['lyapunov_per_s']:+.3f} 1/s" for r in lyap)
    return text



# %%
# The command line
# ----------------
#
# ``main`` reads the options (``--quick``: 3 x 3 grids of 20 s runs), makes both maps, re-runs
# their irregular points, measures the contrast cycle's stability and both chains' Lyapunov
# exponents, writes the sound and prints what it found.

def main(argv=None) -> int:
    p = scripting.parser(scripting.title(__doc__))
    p.add_argument("--grid", type=int, default=None, help="points per axis (default 60, quick 3)")
    scripting.add_workers(p)
    args = p.parse_args(argv)
    out = scripting.out_dir(args, __file__)
    quick = args.quick
    grid = args.grid or (3 if quick else 60)
    t_end = 20.0 if quick else 100.0
    samples = int(20 * t_end) + 1  # 20 per second: the classifier reads velocities over the last quarter
    base = presets.preset("table2-3dof", t_end=t_end, n_samples=samples)
    contrast = presets.preset("table2-3dof", mu_s=0.4, t_end=t_end, n_samples=samples)
    summary = {"grid": [grid, grid], "t_end_s": t_end, "axes": {"x1_m": X_RANGE, "v1_m_s": V_RANGE},
               "fixed": "x2, x3, v2, v3 from eq 3.12 (0.06 m, 0.07 m, 0.03 m/s, 0.05 m/s)"}
    for name, chain, size in (("base", base, grid), ("contrast_mu_s_0.4", contrast, max(2, grid // 2))):
        summary[name] = basin_map(name, chain, size, quick, out, args.workers, not args.json)
    summary["floquet_contrast_eq312"], summary["lyapunov_eq312"] = stability(quick)
    summary["sound"] = sound(out, quick)
    b, c = summary["base"], summary["contrast_mu_s_0.4"]
    lines = [f"base case, {grid} x {grid} initial states over {t_end:g} s: {_counts(b['counts'])}",
             f"  last stick onset: median {b['last_stick_s']['median']:.3g} s, max {b['last_stick_s']['max']:.3g} s",
             f"  irregular points run again longer: {_recheck(b['irregular_rechecked'])}",
             f"contrast mu_s = 0.4: {_counts(c['counts'])}"
             + (f", cycle periods {', '.join(f'{p:.4g} s' for p in c['periods_s'][:6])}" if c["periods_s"] else ""),
             f"  irregular points run again longer: {_recheck(c['irregular_rechecked'])}"]
    fl = summary["floquet_contrast_eq312"]
    if "moduli" in fl:
        lines.append(f"contrast cycle from eq 3.12: period {fl['period_s']:.6g} s (period-{fl['multiplicity']}), "
                     f"|multipliers| {', '.join(f'{m:.4g}' for m in fl['moduli'])}, "
                     f"{'stable' if fl['stable'] else 'unstable'}")
    lines.append("largest Lyapunov exponents (1/s): " + ", ".join(
        f"{k} {v['value_per_s']:.2g}" for k, v in summary["lyapunov_eq312"].items()))
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
