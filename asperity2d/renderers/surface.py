"""Plots of a profile with its asperities, and of its power spectrum (matplotlib, lazily).

Each function writes one file (``.png``, ``.svg`` or ``.pdf``, from the
extension) atomically and returns its path. Lengths are drawn in micrometres.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..errors import SceneError
from .plots import figure, save
from ..surface.asperities import Asperities
from ..surface.profile import SurfaceProfile
from ..surface.stats import HurstFit, PowerSpectrum

UM = 1e6  # metres -> micrometres


def plot_asperities(profile: SurfaceProfile, asperities: Asperities, path: str | os.PathLike, *,
                    x_range: tuple[float, float] | None = None, highlight=None,
                    level: float | None = None, dpi: int = 120) -> Path:
    """The profile (line) with its triangular asperities laid over it (shaded, apexes marked).

    ``x_range`` (m) zooms in on a stretch; the default shows the whole trace.
    ``highlight`` (one bool per asperity) draws those asperities in a second
    colour (e.g. the ones a run touched); ``level`` (m, the profile's datum)
    draws a horizontal line (e.g. a fixed track's tip height).
    """
    from matplotlib.collections import PolyCollection

    fig, (ax,) = figure(1, width=8.0, height=2.6)
    x, z = profile.x, profile.z
    a = asperities
    if x_range is not None:
        lo, hi = x_range
        if not lo < hi:
            raise SceneError(f"`x_range` must be (low, high) with low < high, got {x_range!r}")
        shown = (x >= lo) & (x <= hi)
        x, z = x[shown], z[shown]
        a_shown = (a.right_feet >= lo) & (a.left_feet <= hi)
    else:
        a_shown = np.ones(a.count, dtype=bool)
    feet_l, feet_r, apex = a.left_feet[a_shown], a.right_feet[a_shown], a.apex_x[a_shown]
    base, top = a.base_levels[a_shown], a.summits[a_shown]
    triangles = np.stack([np.column_stack([feet_l, base]), np.column_stack([apex, top]),
                          np.column_stack([feet_r, base])], axis=1) * UM
    marked = np.zeros(a.count, dtype=bool) if highlight is None else np.asarray(highlight, dtype=bool)
    if marked.shape != (a.count,):
        raise SceneError(f"`highlight` must hold one bool per asperity ({a.count}), got shape {marked.shape}")
    marked = marked[a_shown]
    colours = np.where(marked, "tab:blue", "tab:orange")
    ax.add_collection(PolyCollection(triangles, facecolors=colours, edgecolors="tab:red",
                                     alpha=0.35, linewidths=0.8, label="asperities"))
    if highlight is not None:
        ax.plot([], [], "s", color="tab:blue", alpha=0.5, label=f"highlighted ({int(marked.sum())})")
    if level is not None:
        ax.axhline(level * UM, color="tab:green", lw=0.8, ls="--", label="level")
    ax.plot(x * UM, z * UM, color="0.2", lw=0.6, label="profile")
    ax.plot(apex * UM, top * UM, "v", color="tab:red", ms=3, label="summits")
    ax.set_xlabel("x (µm)")
    ax.set_ylabel("z (µm)")
    ax.set_title(f"{profile.name or 'profile'}: {int(a_shown.sum())} of {a.count} asperities shown "
                 f"({a.absorbed} summits absorbed, {a.trimmed} triangles trimmed)", fontsize=9)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7)  # beside the axes, off the data
    ax.autoscale_view()
    return save(fig, path, dpi)


def plot_spectrum(spectrum: PowerSpectrum, path: str | os.PathLike, *, fit: HurstFit | None = None,
                  dpi: int = 120) -> Path:
    """Power spectral density C(q) on log-log axes, with the Hurst fit's line over its band."""
    fig, (ax,) = figure(1, width=6.0, height=3.6)
    ax.loglog(spectrum.q, spectrum.psd, color="0.3", lw=0.7, label=f"C(q), {spectrum.method}")
    if fit is not None:
        q = np.geomspace(fit.q_min, fit.q_max, 50)
        ax.loglog(q, fit.prefactor * q ** fit.slope, color="tab:red", lw=2,
                  label=f"fit: H = {fit.hurst:.3f} ± {fit.hurst_stderr:.3f}")
    ax.set_xlabel("wavenumber q (rad/m)")
    ax.set_ylabel("C(q) (m³)")
    ax.legend(fontsize=8)
    return save(fig, path, dpi)
