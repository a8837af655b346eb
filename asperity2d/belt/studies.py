"""Helpers for the seed-001 study scripts in ``scenes/belt_*.py``.

Every quantitative statement of the thesis becomes a record
``{"claim", "thesis", "computed", "criterion", "verdict"}`` with the verdict
"holds" or "does not hold" judged by a criterion fixed before looking at the
numbers (default: within ``REL_TOL`` = 5 % for a number read off a figure).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from .._io import atomic_write_text
from .presets import preset
from .regime import classify
from .solver import simulate_chain

REL_TOL = 0.05
RENDERS = Path(__file__).resolve().parents[2] / "renders" / "belt"


def run(name: str, *, quick: bool = False, **overrides):
    """Simulate preset ``name`` (fewer output samples when ``quick``; the physics is unchanged)."""
    return simulate_chain(**preset(name, n_samples=501 if quick else 4001, **overrides))


def number_claim(text, thesis_value, computed, unit="s", rel_tol=REL_TOL):
    ok = abs(computed - thesis_value) <= rel_tol * abs(thesis_value)
    return {"claim": text, "thesis": f"{thesis_value} {unit}", "computed": f"{computed:.6g} {unit}",
            "criterion": f"|computed - thesis| <= {rel_tol:.0%} of thesis", "verdict": _v(ok)}


def trend_claim(text, labels, values, expect, criterion, unit=""):
    """``expect(values) -> bool``; values listed against labels."""
    ok = bool(expect(np.asarray(values, dtype=float)))
    return {"claim": text, "thesis": "trend", "computed": {str(l): _r(v) for l, v in zip(labels, values)},
            "unit": unit, "criterion": criterion, "verdict": _v(ok)}


def _v(ok):
    return "holds" if ok else "does not hold"


def _r(v):
    return float(f"{float(v):.6g}")


def first_stick(result, i):
    """(start, end) of mass i's first stick interval of positive length, or None."""
    for a, b in result.stick_intervals[i]:
        if b > a:
            return (a, b)
    return None


def final_rest(result, i):
    """Start of the stick interval that lasts to the end of the run (s), or None."""
    per = result.stick_intervals[i]
    if per and per[-1][1] >= result.t[-1]:
        return per[-1][0]
    return None


def total_stick(result):
    return [float(sum(b - a for a, b in per)) for per in result.stick_intervals]


def amplitude(result, *, window=0.5):
    """Half the peak-to-peak displacement of each mass over the last ``window`` of the run (m)."""
    sel = result.t >= (1 - window) * result.t[-1]
    return [float(a) for a in 0.5 * np.ptp(result.x[:, sel], axis=1)]


def oscillations(result):
    """Number of upward crossings of each mass's mean position (a count of oscillations)."""
    out = []
    for x in result.x:
        y = x - x.mean()
        out.append(int(np.count_nonzero((y[:-1] < 0) & (y[1:] >= 0))))
    return out


def case_summary(result):
    return {
        "first_stick": [first_stick(result, i) for i in range(result.n)],
        "total_stick_time_s": [_r(s) for s in total_stick(result)],
        "stick_count": [len(per) for per in result.stick_intervals],
        "amplitude_m": [_r(a) for a in amplitude(result)],
        "oscillations": oscillations(result),
        "regime": classify(result),
        "events": result.meta["n_events"],
        "energy_balance_error": result.energy_balance_error(),
    }


def cli(study, name: str, argv=None) -> int:
    """Common ``main``: parse --quick / --out, run ``study(quick) -> (summary, {label: result})``, write outputs."""
    parser = argparse.ArgumentParser(prog=f"belt_{name}", description=study.__doc__)
    parser.add_argument("--quick", action="store_true", help="fewer samples, no plots (for tests)")
    parser.add_argument("--out", type=Path, default=RENDERS, help="output directory")
    args = parser.parse_args(argv)
    summary, results = study(args.quick)
    summary["solver"] = "asperity2d.belt exact event-driven (closed-form phases, brentq switches)"
    summary["verdict_rule"] = f"numbers read off the thesis' figures hold within {REL_TOL:.0%}; trends as stated"
    if not args.quick:
        from .plots import plot_chain

        for label, result in results.items():
            path = plot_chain(result, args.out / f"{name}_{label}.png", title=f"{name}: {label}")
            summary.setdefault("plots", []).append(str(path))
    atomic_write_text(args.out / f"{name}.json", json.dumps(summary, indent=2, default=_json_default) + "\n")
    for c in summary.get("claims", []):
        print(f"[{c['verdict']:>13}] {c['claim']}: thesis {c['thesis']}, computed {c['computed']}")
    print(f"wrote {args.out / (name + '.json')}")
    return 0


def _json_default(obj):
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, (np.floating,)):
        return float(obj)
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    return str(obj)
