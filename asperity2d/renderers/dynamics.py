"""Figures of the dynamics tools: spectra, basin maps, Poincaré sections (matplotlib, lazily).

Each function writes one file (``.png``, ``.svg``, ``.pdf``) atomically and
returns its path, like :mod:`asperity2d.renderers.plots`.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..errors import SceneError
from .plots import figure, save
from ..dynamics.basins import LABELS

#: class colours of a basin map: rest, pure slip, stick-slip period 1, 2, >=3, irregular; failed runs grey
_CLASS_COLORS = ("#4c72b0", "#8fbc8f", "#dd8452", "#c44e52", "#8172b3", "#222222")


def plot_spectra(spectra, path: str | os.PathLike, *, unit: str = "", title: str = "", f_max: float | None = None,
                 dpi: int = 120) -> Path:
    """PSD (log scale) against frequency for ``spectra``: a list of (label, Spectrum), up to ``f_max`` (Hz).

    The dominant frequency and its harmonics are marked on each curve.
    """
    fig, axes = figure(1, width=7.5, height=3.6)
    ax = axes[0]
    for label, sp in spectra:
        keep = (sp.frequency > 0) & (sp.frequency <= (f_max if f_max else np.inf))
        line, = ax.semilogy(sp.frequency[keep], sp.power[keep], lw=0.9,
                            label=f"{label}: {sp.dominant:.4g} Hz, THD {sp.thd:.2f}")
        marks = [h.frequency for h in sp.harmonics if np.isfinite(h.power) and h.power > 0
                 and h.frequency <= (f_max if f_max else np.inf)]
        ax.plot(marks, np.interp(marks, sp.frequency, sp.power), "o", ms=3, color=line.get_color())
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel(f"PSD ({unit}²/Hz)" if unit else "PSD")
    ax.legend(fontsize=7, loc="upper right")
    ax.set_title(title or "power spectra (dots: dominant frequency and its harmonics)", fontsize=9)
    return save(fig, path, dpi)


DETAILS = {"last_stick": "time of the last stick onset (s)", "period": "period of the limit cycle (s)",
           "stick_fraction": "largest stuck fraction of a mass, last half",
           "amplitude": "amplitude over the last quarter", "pitches_per_cycle": "drive advance per cycle (pitches)"}


def plot_basins(basins, path: str | os.PathLike, *, detail: str = "last_stick", title: str = "",
                dpi: int = 120) -> Path:
    """Basin map: the class of every grid point (left), and the quantity ``detail`` (right, a key of
    ``basins.values``: by default the time of the last stick onset, i.e. how long the transient lasts)."""
    from matplotlib.colors import ListedColormap

    lab, mult = basins.values["label"], basins.values["multiplicity"]
    code = np.full(lab.shape, np.nan)
    code[lab == 0], code[lab == 1], code[lab == 3] = 0, 1, 5
    stick = lab == 2
    code[stick] = np.clip(mult[stick] + 1, 2, 4)  # period 1 -> 2, period 2 -> 3, period >= 3 -> 4
    fig, axes = figure(1, width=10.0, height=4.2)
    fig.clear()
    ax1, ax2 = fig.subplots(1, 2)
    extent = _extent(basins.x_values, basins.y_values)
    ax1.set_facecolor("#bbbbbb")  # failed runs show as grey
    ax1.imshow(code.T, origin="lower", aspect="auto", extent=extent, cmap=ListedColormap(_CLASS_COLORS),
               vmin=-0.5, vmax=5.5, interpolation="nearest")
    names = ["rest", "pure slip", "stick-slip period-1", "stick-slip period-2", "stick-slip period >= 3",
             "irregular"]
    counts = [int(np.sum(code == i)) for i in range(6)]
    handles = [_patch(c, f"{n} ({k})") for c, n, k in zip(_CLASS_COLORS, names, counts) if k]
    if basins.failed:
        handles.append(_patch("#bbbbbb", f"failed ({basins.failed})"))
    ax1.legend(handles=handles, fontsize=7, loc="upper right", framealpha=0.85)
    ax1.set_title(f"long-run motion after {basins.t_end:g} s", fontsize=9)
    if detail not in basins.values:
        raise SceneError(f"`detail` must be one of {', '.join(sorted(basins.values))}, got {detail!r}")
    shown = np.where(lab >= 0, basins.values[detail], np.nan)
    im = ax2.imshow(shown.T, origin="lower", aspect="auto", extent=extent, cmap="viridis", interpolation="nearest")
    fig.colorbar(im, ax=ax2, label=DETAILS.get(detail, detail))
    ax2.set_title("transient: last stick onset (0: never sticks)" if detail == "last_stick" else
                  DETAILS.get(detail, detail), fontsize=9)
    for ax in (ax1, ax2):
        ax.set_xlabel(_axis_label(basins.x_name))
        ax.set_ylabel(_axis_label(basins.y_name))
    if title:
        fig.suptitle(title, fontsize=10)
    return save(fig, path, dpi)


def plot_section(section, path: str | os.PathLike, *, x: int = 0, y: int = 1, title: str = "",
                 dpi: int = 120) -> Path:
    """Scatter of a Poincaré section's coordinates ``x`` and ``y`` (indices), coloured by time."""
    fig, axes = figure(1, width=5.0, height=4.2)
    ax = axes[0]
    sc = ax.scatter(section.points[:, x], section.points[:, y], c=section.t, s=6, cmap="viridis")
    fig.colorbar(sc, ax=ax, label="time (s)")
    ax.set_xlabel(_axis_label(section.names[x]))
    ax.set_ylabel(_axis_label(section.names[y]))
    ax.set_title(title or f"Poincaré section: {section.description}", fontsize=9)
    return save(fig, path, dpi)


def _extent(xs, ys):
    dx = (xs[-1] - xs[0]) / max(len(xs) - 1, 1) if len(xs) > 1 else 1.0
    dy = (ys[-1] - ys[0]) / max(len(ys) - 1, 1) if len(ys) > 1 else 1.0
    return (xs[0] - dx / 2, xs[-1] + dx / 2, ys[0] - dy / 2, ys[-1] + dy / 2)


def _axis_label(name: str) -> str:
    if name[:1] == "x" and name[1:].isdigit():
        return f"initial x{name[1:]} (m)"
    if name[:1] == "v" and name[1:].isdigit():
        return f"initial v{name[1:]} (m/s)"
    return {"drive_preload": "drive preload (N)", "seed": "spacing seed"}.get(name, name)


def _patch(color, label):
    from matplotlib.patches import Patch

    return Patch(facecolor=color, label=label)


__all__ = ["plot_spectra", "plot_basins", "plot_section", "LABELS"]
