"""Regime maps: where a belt chain sticks, slips or slides steadily
================================================================

From the thesis *Vibration Analysis of Multi Degree of Freedom Self-excited
Systems* (no author named in the copy used here), called the multi-DOF belt
thesis below.

Which motion a belt chain settles into, over a grid of two of its parameters: belt speed x
damping for one mass on a belt with a falling (Stribeck) friction curve, and belt speed x
stiffness for the thesis' three-mass chain (Table 2). Each grid point is one exact run, classified
by :func:`asperity2d.belt.classify`; the Stribeck map carries the linear stability boundary
c + N mu'(v) = 0, below which steady sliding is unstable.

Run::

    python scenes/belt_regime_map.py [--quick] [--plots] [-o DIR] [--json]

Writes ``summary.json`` (both maps: every point's regime, the counts) and, unless ``--quick``
without ``--plots``, ``regime_stribeck.png`` and ``regime_table2.png``.
"""

# %%
# The lesson is made of the package's public calls: :func:`asperity2d.belt.regime_map` runs and
# classifies a grid, ``asperity2d.belt.presets`` holds the thesis' chains,
# :class:`asperity2d.friction.Stribeck` is the falling friction curve, matplotlib draws the map.

import numpy as np
from matplotlib.colors import ListedColormap
from matplotlib.figure import Figure

from asperity2d import scripting
from asperity2d.belt import presets, regime_map
from asperity2d.friction import Stribeck


# %%
# 1. A mass on a Stribeck belt
# ----------------------------
#
# Friction falls from 0.4 at rest to 0.25 above about 0.05 m/s. Where the curve falls faster than
# the damper can make up for (c + N mu'(v_belt) < 0), steady sliding is unstable and the mass
# sticks and slips; at higher belt speed or damping it slides steadily.

def stribeck_map(size: int, t_end: float):
    """The regime map of one mass on a Stribeck belt over belt speed (m/s) x damping (N s/m)."""
    law = Stribeck(mu_s=0.4, mu_k=0.25, v_s=0.05)
    chain = dict(masses=[1.0], springs=[10.0, 0.0], dampers=[0.0, 0.0], friction=law, v_belt=0.1,
                 x0=[0.0], v0=[0.0], t_end=t_end, n_samples=801)
    return law, regime_map(chain, "v_belt", np.linspace(0.02, 0.3, size), "c", np.linspace(0.0, 3.0, size))


# %%
# 2. The thesis' three-mass chain
# -------------------------------
#
# Table 2's chain (mu0 = 0.2, one coefficient: no static excess) over belt speed x spring
# stiffness, each run 20 s from eq 3.12.

def table2_map(size: int):
    """The regime map of the Table 2 chain over belt speed (m/s) x stiffness (N/m)."""
    chain = presets.preset("table2-3dof", n_samples=801, t_end=20.0)
    return regime_map(chain, "v_belt", np.linspace(0.1, 0.8, size), "k", np.linspace(10.0, 40.0, size))


# %%
# 3. The picture
# --------------
#
# One colour per regime over the grid, and the Stribeck stability boundary where the map has one
# (``rm.boundary``).

UNITS = {"v_belt": "belt speed (m/s)", "k": "stiffness k (N/m)", "c": "damping c (N s/m)"}
COLOURS = ("tab:green", "tab:red", "tab:blue", "tab:gray")


def draw(rm, path, title: str):
    """Draw regime map ``rm`` to ``path``; the file's name."""
    names = list(rm.to_dict()["counts"])  # every regime the classifier knows, in its order
    codes = np.array([[names.index(label) for label in row] for row in rm.labels], dtype=float)
    fig = Figure(figsize=(6.5, 4.6), layout="constrained")
    ax = fig.add_subplot()
    mesh = ax.pcolormesh(rm.x_values, rm.y_values, codes.T, shading="nearest",
                         cmap=ListedColormap(COLOURS[:len(names)]), vmin=-0.5, vmax=len(names) - 0.5)
    bar = fig.colorbar(mesh, ax=ax, ticks=range(len(names)))
    bar.ax.set_yticklabels(names)
    if rm.boundary is not None:
        ax.plot(rm.boundary[0], rm.boundary[1], "k-", lw=2, label="c + N mu'(v) = 0")
        ax.legend(loc="upper right")
        ax.set_ylim(min(rm.y_values), max(rm.y_values))
    ax.set_xlim(left=max(ax.get_xlim()[0], 0.0))  # a grid of speeds from 0.02 m/s: no negative axis
    ax.set_xlabel(UNITS.get(rm.x_name, rm.x_name))
    ax.set_ylabel(UNITS.get(rm.y_name, rm.y_name))
    ax.set_title(title, fontsize=10)
    fig.savefig(path, dpi=120)
    return path.name


# %%
# The command line
# ----------------
#
# ``main`` reads the options (``--quick``: 3 x 3 grids), makes both maps, draws them and prints
# how many grid points each regime took.

def main(argv=None) -> int:
    p = scripting.parser(scripting.title(__doc__))
    p.add_argument("--plots", action="store_true", help="write the plots with --quick too")
    args = p.parse_args(argv)
    out = scripting.out_dir(args, __file__)
    size = 3 if args.quick else 10
    law, smap = stribeck_map(size, 20.0 if args.quick else 40.0)
    tmap = table2_map(size)
    summary = {"stribeck_1dof": {**smap.to_dict(), "law": law.to_dict(),
                                 "boundary": "steady sliding linearly unstable where c < -N mu'(v_belt)"},
               "table2_3dof": tmap.to_dict()}
    if not args.quick or args.plots:
        summary["plots"] = summary["outputs"] = [
            draw(smap, out / "regime_stribeck.png", f"one mass on a Stribeck belt, {size} x {size} runs"),
            draw(tmap, out / "regime_table2.png", f"the Table 2 chain, {size} x {size} runs")]
    lines = []
    for name, m in (("a mass on a Stribeck belt (belt speed x damping)", smap),
                    ("the Table 2 chain (belt speed x stiffness)", tmap)):
        counts = m.to_dict()["counts"]
        total = sum(counts.values()) or 1
        lines.append(f"{name}: " + ", ".join(f"{k} {v} ({100 * v / total:.0f} %)" for k, v in counts.items() if v))
    return scripting.finish(args, summary, out, lines)


if __name__ == "__main__":
    scripting.run(main)
