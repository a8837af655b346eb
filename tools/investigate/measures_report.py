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
    d = json.loads((DATA / "stick_bias.json").read_text())
    F = ("1.0", "0.5", "0.25")
    seeds = sorted({k.split("/")[1] for k in d if k.startswith(setup + "/")})
    seeds = [s for s in seeds if all(f"{setup}/{s}/{f}" in d for f in F)]
    cpu = sum(d[f"{setup}/{s}/{f}"]["cpu_s"] for s in seeds for f in F)
    print(f"stick forces, {setup} track 10/3 random, 5 passes, seeds {seeds[0]}-{seeds[-1]} "
          f"({len(seeds)} seeds, {cpu / 60:.1f} CPU-minutes)")
    for name in ("first_breakaway", "peak", "mean"):
        avg = {f: np.array([np.nanmean(d[f"{setup}/{s}/{f}"][name]) for s in seeds]) for f in F}
        for x, y in (("1.0", "0.5"), ("0.5", "0.25"), ("1.0", "0.25")):
            r = avg[y] / avg[x] - 1
            print(f"  {name:15s} dt*{x} -> dt*{y}: {100 * r.mean():+.2f} +- {100 * r.std(ddof=1) / math.sqrt(len(r)):.2f} % "
                  f"(one standard error; sd over seeds {100 * r.std(ddof=1):.1f} %)")
        # per-pass spread about the seed's ensemble mean, at the policy's step (dt/2)
        rel = np.concatenate([np.asarray(d[f"{setup}/{s}/0.5"][name], float) / np.nanmean(d[f"{setup}/{s}/0.5"][name]) - 1
                              for s in seeds])
        rel = rel[np.isfinite(rel)]
        s_pass = float(np.sqrt(np.sum(rel ** 2) / (len(rel) - len(seeds))))  # pooled within-seed sd
        need = 2 * (2 * s_pass / 0.05) ** 2  # paired difference of two variants, 2 standard errors = 5 %
        print(f"  {name:15s} one pass: sd {100 * s_pass:.1f} % of its seed's mean; a P-pass mean {100 * s_pass:.1f}/sqrt(P) %; "
              f"a 5 % difference between two variants (two standard errors) needs passes x seeds >= {need:.0f}")


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
