"""The numbers the findings page quotes for the step policy, from the measured data in
docs/data/measures/ (made by tools/investigate/stick_bias.py and travel_dt.py; copied there from
renders/measures/). python tools/investigate/measures_report.py"""
import json, math
from pathlib import Path

import numpy as np
from scipy.stats import wilcoxon

import asperity2d as a

DATA = Path(__file__).resolve().parents[2] / "docs" / "data" / "measures"


def stick_bias(setup="fixed"):
    """The stick forces' bias and precision: docs/data/stick_precision.py's report, on the 24
    seeds 9401-9424, the 10 before them (7601-7610) and all pooled."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("stick_precision", DATA.parent / "stick_precision.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    for seeds in ((9401, 9424), (7601, 7610), None):
        print(module.report(module.summary(DATA / "stick_bias.json", setup=setup, seeds=seeds)))


def travel():
    d = json.loads((DATA / "travel_dt.json").read_text())
    seeds = [s for s in d if s != "0"]
    print(f"figure-10 travel, fixed track 10/3, mu 0.3/0.2, 0.9 x the half triangles' run-up critical force, "
          f"seeds {seeds[0]}-{seeds[-1]} ({len(seeds)})")
    for f in ("1.0", "0.5", "0.25", "0.125"):
        half = np.array([d[s][f"half/{f}"]["travel_m"] for s in seeds])
        full = np.array([d[s][f"full/{f}"]["travel_m"] for s in seeds])
        e = a.stats.relative_effect(half, full)
        print(f"  dt*{f}: half / full x{e['ratio']:.2f} [{1 + e['ci_low']:.2f}, {1 + e['ci_high']:.2f}], geometric mean "
              f"{np.exp(np.log(half / full).mean()):.3f}, {(half >= full).sum()}/{len(seeds)} above, "
              f"Wilcoxon p {wilcoxon(half, full, alternative='less').pvalue:.1g}; regular "
              f"{d['0'][f'half/{f}']['travel_m'] / d['0'][f'full/{f}']['travel_m']:.3f}")
    for p in ("half", "full"):
        for x, y in (("1.0", "0.5"), ("0.5", "0.25"), ("0.25", "0.125")):
            m = np.array([abs(d[s][f"{p}/{x}"]["travel_m"] / d[s][f"{p}/{y}"]["travel_m"] - 1) for s in seeds])
            print(f"  {p} travel dt*{x} -> dt*{y}: {np.sum(m <= 0.01)}/{len(m)} seeds within 1 %, largest {100 * m.max():.0f} %")


if __name__ == "__main__":
    stick_bias()
    travel()
