"""Plots of belt-chain results (matplotlib imported lazily, no pyplot, files written atomically).

``plot_chain``: per mass, displacement and velocity against time with the
stick intervals shaded, plus the phase portrait (v against x). The file
format follows the extension (.png, .svg, .pdf).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .plots import blank, figure, save
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


#: colours of the contact regimes (asperity2d.belt.regime.CONTACT_REGIMES), failed runs light grey
_CONTACT_COLORS = ("#4c72b0", "#8fbc8f", "#dd8452", "#c44e52", "#8172b3", "#937860", "#222222")


def plot_contact_map(contact_map, path, *, title: str = ""):
    """Regimes of the minimal model over (mu, belt speed) (a :class:`~asperity2d.studies.contact.ContactMap`),
    with the closed-form flutter onset mu_crit(eta) and the speed V*(mu) below which a growing flutter
    meets stick before separation."""
    from matplotlib.colors import ListedColormap
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from ..belt.regime import CONTACT_REGIMES

    cm = contact_map
    lab = np.asarray(cm.values["label"], dtype=float)
    shown = np.where(lab >= 0, lab, np.nan)
    fig, (ax,) = figure(1, width=9.6, height=4.8, sharex=False)
    ax.set_facecolor("#dddddd")
    ax.pcolormesh(_edges(cm.mu, log=False), _edges(cm.v_belt, log=True), shown.T,
                  cmap=ListedColormap(_CONTACT_COLORS), vmin=-0.5, vmax=len(CONTACT_REGIMES) - 0.5, shading="flat")
    ax.set_yscale("log")
    mu_c = cm.model.mu_crit_damped()
    ax.axvline(mu_c, color="k", lw=1.5, ls="--")
    mus = np.linspace(max(mu_c, cm.mu.min()) * (1 + 1e-6), cm.mu.max(), 200)
    vstar = np.array([cm.model.first_limit_speed(m) for m in mus])
    ax.plot(mus, vstar, "k-", lw=1.5)
    counts = cm.counts()
    handles = [Patch(facecolor=c, label=f"{name} ({counts[name]})") for c, name in zip(_CONTACT_COLORS, CONTACT_REGIMES)
               if counts[name]]
    handles += [Line2D([], [], color="k", ls="--", label=f"flutter onset mu_crit = {mu_c:.4f} (closed form)"),
                Line2D([], [], color="k", label="V*: below, flutter meets stick first")]
    ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), framealpha=0.9)
    ax.set_xlim(_edges(cm.mu, log=False)[[0, -1]])
    ax.set_ylim(_edges(cm.v_belt, log=True)[[0, -1]])
    ax.set_xlabel("friction coefficient mu (= mu_s = mu_k)")
    ax.set_ylabel("belt speed (m/s)")
    ax.set_title(title or f"minimal model: regime after {cm.t_end * 1e3:g} ms from kicked steady sliding", fontsize=9)
    return save_figure(fig, path)


def _edges(centres, *, log: bool):
    """Cell edges around grid ``centres``: midpoints (geometric on a log axis), the ends mirrored."""
    c = np.log(np.asarray(centres, dtype=float)) if log else np.asarray(centres, dtype=float)
    if c.size == 1:
        mid = np.array([c[0] - 0.5, c[0] + 0.5])
    else:
        inner = 0.5 * (c[1:] + c[:-1])
        mid = np.concatenate([[c[0] - (inner[0] - c[0])], inner, [c[-1] + (c[-1] - inner[-1])]])
    return np.exp(mid) if log else mid


def plot_contact_run(result, path, *, t_window=None, title: str = ""):
    """Tangential velocity, gap and normal force of a contact-chain run (mass 1) over ``t_window`` (s, a
    (start, end) pair; default the last 3 % of the run), separated intervals shaded blue and stick intervals
    orange, beside the normal phase portrait (gap against its rate)."""
    t = result.t
    a, b = t_window if t_window is not None else (t[-1] - 0.03 * (t[-1] - t[0]), t[-1])
    w = (t >= a) & (t <= b)
    fig = blank(11, 5.6)
    grid = fig.add_gridspec(3, 2, width_ratios=[2.2, 1])
    axes = [fig.add_subplot(grid[i, 0]) for i in range(3)]
    V = float(result.chain.v_belt)
    series = ((result.v[0] - V, "v1 - V (m/s)"), (result.y[0] * 1e6, "gap y1 (µm)"), (result.normal_force[0], "N1 (N)"))
    for ax, (y, label) in zip(axes, series):
        ax.plot(t[w] * 1e3, y[w], lw=0.9)
        ax.set_ylabel(label, fontsize=8)
        for lo, hi in result.separation_intervals[0]:
            if hi >= a and lo <= b:
                ax.axvspan(max(lo, a) * 1e3, min(hi, b) * 1e3, color="tab:blue", alpha=0.15, lw=0)
        for lo, hi in result.stick_intervals[0]:
            if hi >= a and lo <= b:
                ax.axvspan(max(lo, a) * 1e3, min(hi, b) * 1e3, color="tab:orange", alpha=0.3, lw=0)
    axes[1].axhline(0, color="k", lw=0.5)
    axes[-1].set_xlabel("t (ms)")
    axes[0].set_title("blue: separated, orange: stuck", fontsize=8)
    ax = fig.add_subplot(grid[:, 1])
    sep = result.state[0] == 2
    ax.plot(result.y[0, w] * 1e6, result.vy[0, w], color="0.6", lw=0.5)
    ax.plot(np.where(sep, result.y[0], np.nan)[w] * 1e6, result.vy[0, w], color="tab:blue", lw=1.2, label="separated")
    ax.axvline(0, color="k", lw=0.5)
    ax.set_xlabel("gap y1 (µm)")
    ax.set_ylabel("vy1 (m/s)")
    ax.legend(fontsize=7)
    if title:
        fig.suptitle(title, fontsize=9)
    return save_figure(fig, path)


def plot_opening(rows, path, *, curves=None, title: str = ""):
    """The multi-DOF belt thesis' chain with normal compliance: growth rate of steady sliding against the contact stiffness;
    markers are simulated runs (one marker shape per belt speed), filled where the contact opened. ``curves``
    maps mu to (k_c values, growth rates) drawn as lines (the linearisation on a fine grid)."""
    fig, (ax,) = figure(1, width=7, height=4, sharex=False)
    colors = {}
    for mu in sorted({r["mu"] for r in rows}):
        if curves and mu in curves:
            line, = ax.plot(*curves[mu], lw=1, label=f"mu = {mu:g}: steady sliding's growth rate")
        else:
            line, = ax.plot([], [], lw=1, label=f"mu = {mu:g}")
        colors[mu] = line.get_color()
    marks = dict(zip(sorted({r["v_belt"] for r in rows}), "osD^v"))
    for r in rows:
        ax.plot(r["contact_stiffness"], r["growth_rate"], marks[r["v_belt"]], color=colors[r["mu"]], ms=6,
                mfc=colors[r["mu"]] if r["openings"] else "none")
    for v, m in marks.items():
        ax.plot([], [], m, color="0.3", mfc="none", label=f"run at V = {v:g} m/s (filled: contact opened)")
    ax.set_xscale("log")
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xlabel("contact stiffness k_c (N/m)")
    ax.set_ylabel("growth rate of steady sliding (1/s)")
    ax.set_title(title or "thesis 3-DOF chain + normal compliance: filled = contact opened", fontsize=9)
    ax.legend(fontsize=7)
    return save_figure(fig, path)
