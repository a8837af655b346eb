"""Regime maps: where a belt chain sticks, slips or slides steadily
================================================================

From the thesis *Vibration Analysis of Multi Degree of Freedom Self-excited
Systems* (no author named in the copy used here), called the multi-DOF belt
thesis below.

Regime maps: belt speed x damping for a mass on a Stribeck belt, belt speed x stiffness for Table 2.

Run: ``python scenes/belt_regime_map.py [--quick] [--out DIR]``; writes two maps and ``regime_map.json``.
The Stribeck map carries the linear stability boundary c + N·mu'(v) = 0.
"""

import argparse
from pathlib import Path

import numpy as np

from asperity2d._io import write_json
from asperity2d.belt.presets import preset
from asperity2d.belt.regime import regime_map
from asperity2d.studies.mdof_belt import renders
from asperity2d.friction import Stribeck
from asperity2d import scripting


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="belt_regime_map", description=__doc__)
    parser.add_argument("--quick", action="store_true", help="coarse 3x3 grids, no plots")
    parser.add_argument("--plots", action="store_true", help="write the plots with --quick too")
    parser.add_argument("-o", "--out", type=Path, default=None,
                        help="output directory (default renders/belt in the working directory)")
    args = parser.parse_args(argv)
    args.out = args.out or renders()
    size = 3 if args.quick else 10
    law = Stribeck(mu_s=0.4, mu_k=0.25, v_s=0.05)
    stribeck = dict(masses=[1.0], springs=[10.0, 0.0], dampers=[0.0, 0.0], friction=law, v_belt=0.1,
                    x0=[0.0], v0=[0.0], t_end=20.0 if args.quick else 40.0, n_samples=801)
    smap = regime_map(stribeck, "v_belt", np.linspace(0.02, 0.3, size), "c", np.linspace(0.0, 3.0, size))
    table2 = preset("table2-3dof", n_samples=801, t_end=20.0)
    tmap = regime_map(table2, "v_belt", np.linspace(0.1, 0.8, size), "k", np.linspace(10.0, 40.0, size))
    summary = {"stribeck_1dof": {**smap.to_dict(), "law": law.to_dict(),
                                 "boundary": "steady sliding linearly unstable where c < -N mu'(v_belt)"},
               "table2_3dof": tmap.to_dict()}
    if not args.quick or args.plots:
        from asperity2d.renderers.belt import plot_regime_map

        summary["plots"] = [str(plot_regime_map(smap, args.out / "regime_stribeck.png")),
                            str(plot_regime_map(tmap, args.out / "regime_table2.png"))]
    write_json(args.out / "regime_map.json", summary)
    for name, m in (("a mass on a Stribeck belt (belt speed x damping)", smap),
                    ("the Table 2 chain (belt speed x stiffness)", tmap)):
        counts = m.to_dict()["counts"]
        total = sum(counts.values()) or 1
        print(f"{name}: " + ", ".join(f"{k} {v} ({100 * v / total:.0f} %)" for k, v in counts.items() if v))
    return 0


if __name__ == "__main__":
    scripting.run(main)
