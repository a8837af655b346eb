"""Plots of belt-chain results (matplotlib imported lazily, no pyplot, files written atomically).

``plot_chain``: per mass, displacement and velocity against time with the
stick intervals shaded, plus the phase portrait (v against x). The file
format follows the extension (.png, .svg, .pdf).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .plots import figure, save
from ..belt.regime import REGIMES


def save_figure(fig, path) -> Path:
    """Save ``fig`` to ``path`` atomically (the extension picks the format)."""
    return save(fig, path, dpi=110, bbox_inches="tight")


def plot_chain(result, path=None, *, title: str = ""):
    """Displacement (m), velocity (m/s) and phase portrait per mass; returns the figure or the saved path."""
    n = result.n
    fig, axes = figure(n, 3, width=13.0, height=2.6, sharex=False, width_ratios=[2, 2, 1.2])
    V = result.chain.belt_velocity(result.t) if result.chain is not None else None
    for i in range(n):
        ax_x, ax_v, ax_p = axes[i]
        ax_x.plot(result.t, result.x[i], lw=1)
        ax_v.plot(result.t, result.v[i], lw=1)
        if V is not None:
            ax_v.plot(result.t, V, "k--", lw=0.7, label="belt")
        for a, b in result.stick_intervals[i]:
            for ax in (ax_x, ax_v):
                ax.axvspan(a, max(b, a + 1e-9), color="tab:orange", alpha=0.25, lw=0)
        ax_p.plot(result.x[i], result.v[i], lw=0.8)
        ax_x.set_ylabel(f"x{i + 1} (m)")
        ax_v.set_ylabel(f"v{i + 1} (m/s)")
        ax_p.set_xlabel(f"x{i + 1} (m)")
        ax_p.set_ylabel(f"v{i + 1} (m/s)")
    axes[-1, 0].set_xlabel("t (s)")
    axes[-1, 1].set_xlabel("t (s)")
    axes[0, 0].set_title("displacement (stick shaded)")
    axes[0, 1].set_title("velocity")
    axes[0, 2].set_title("phase portrait")
    if title:
        fig.suptitle(title)
    return save_figure(fig, path) if path is not None else fig


def plot_regime_map(regime_map, path=None):
    """Colour map of the regime classes over the grid; Stribeck stability boundary if present."""
    from matplotlib.colors import ListedColormap

    rm = regime_map
    codes = np.vectorize(REGIMES.index)(np.asarray(rm.labels))
    fig, (ax,) = figure(1, width=6.5, height=4.8, sharex=False)
    cmap = ListedColormap(["tab:green", "tab:red", "tab:blue", "tab:gray"][: len(REGIMES)])
    mesh = ax.pcolormesh(rm.x_values, rm.y_values, codes.T, cmap=cmap, vmin=-0.5, vmax=len(REGIMES) - 0.5,
                         shading="nearest")
    cbar = fig.colorbar(mesh, ticks=range(len(REGIMES)))
    cbar.ax.set_yticklabels(REGIMES)
    if rm.boundary is not None:
        ax.plot(rm.boundary[0], rm.boundary[1], "k-", lw=2, label="c + N·μ'(v) = 0")
        ax.legend(loc="upper right")
        ax.set_ylim(min(rm.y_values), max(rm.y_values))
    units = {"v_belt": "v_belt (m/s)", "k": "k (N/m)", "c": "c (N·s/m)", "m": "m (kg)", "mu": "mu"}
    ax.set_xlabel(units.get(rm.x_name, rm.x_name))
    ax.set_ylabel(units.get(rm.y_name, rm.y_name))
    ax.set_title("belt chain regimes")
    return save_figure(fig, path) if path is not None else fig
