"""The multi-DOF belt thesis' studies: masses on a moving belt (the ``scenes/belt_*.py`` scripts).

Every quantitative statement of the thesis becomes a claim record
(:mod:`asperity2d.studies.claims`) whose numbers hold the thesis' value and the
computed one, judged by a criterion fixed before looking at the numbers
(default: within ``REL_TOL`` = 5 % for a number read off a figure).
:func:`belt_chain_run` is the sweep run function of ``scenes/belt_study.toml``.
"""

from __future__ import annotations

import argparse
import math
import os
from pathlib import Path

import numpy as np

from .._format import si
from .._io import write_json
from ..belt import presets, regime, simulate_chain
from ..belt.presets import preset
from ..belt.regime import classify
from .claims import claim

REL_TOL = 0.05


def renders() -> Path:
    """The default output directory of the belt-chain scripts: ``belt`` under
    ``$ASPERITY2D_RENDERS`` (the scene scripts' output root) or ``renders/belt`` in the
    working directory -- never inside the installed package."""
    return Path(os.environ.get("ASPERITY2D_RENDERS", Path.cwd() / "renders")) / "belt"


def run(name: str, *, quick: bool = False, **overrides):
    """Simulate preset ``name`` (fewer output samples when ``quick``; the physics is unchanged)."""
    return simulate_chain(**preset(name, n_samples=501 if quick else 4001, **overrides))


def number_claim(text, thesis_value, computed, unit="s", rel_tol=REL_TOL):
    """A number read off the thesis against the computed one (``numbers``: both as text in
    engineering units, and the relative difference at full precision)."""
    ok = abs(computed - thesis_value) <= rel_tol * abs(thesis_value)
    rel = (computed - thesis_value) / thesis_value if thesis_value and math.isfinite(computed) else math.nan
    return claim(text, ok, numbers={"thesis": si(thesis_value, unit, 3, trim=True),
                                    "computed": si(computed, unit, 3), "relative_difference": rel},
                 test=f"|computed - thesis| <= {rel_tol:.0%} of thesis")


def trend_claim(text, labels, values, expect, criterion, unit=""):
    """A stated trend: ``expect(values) -> bool``; values listed against labels."""
    ok = bool(expect(np.asarray(values, dtype=float)))
    return claim(text, ok, numbers={"thesis": "trend", "unit": unit,
                                    "computed": {str(lab): _r(v) for lab, v in zip(labels, values)}},
                 test=criterion)


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
    parser.add_argument("--plots", action="store_true", help="write the plots with --quick too")
    parser.add_argument("-o", "--out", type=Path, default=None,
                        help="output directory (default renders/belt in the working directory)")
    args = parser.parse_args(argv)
    args.out = args.out or renders()
    summary, results = study(args.quick)
    summary["solver"] = "asperity2d.belt exact event-driven (closed-form phases, brentq switches)"
    summary["verdict_rule"] = f"numbers read off the thesis' figures hold within {REL_TOL:.0%}; trends as stated"
    if not args.quick or args.plots:
        from ..renderers.belt import plot_chain

        for label, result in results.items():
            path = plot_chain(result, args.out / f"{name}_{label}.png", title=f"{name}: {label}")
            summary.setdefault("plots", []).append(str(path))
    write_json(args.out / f"{name}.json", summary)
    for c in summary.get("claims", []):
        n = c["numbers"]
        computed = n["computed"]
        if isinstance(computed, dict):  # a trend: one value per case, in the claim's unit
            computed = ", ".join(f"{label}: {si(v, n['unit'], 3) if n.get('unit') else f'{v:.3g}'}"
                                 for label, v in computed.items())
        said = "" if n["thesis"] == "trend" else f"the thesis says {n['thesis']}, "
        print(f"[{c['verdict']:>13}] {c['claim']}: {said}computed {computed}")
    print(f"wrote {args.out / (name + '.json')}")
    return 0


def belt_chain_run(*, seed: int = 0, preset_name: str = "table2-3dof", ic_spread: float = 0.0,
                   **overrides) -> dict:
    """Sweep run for a belt chain of the multi-DOF belt thesis: regime and stick-slip measures.

    ``preset_name`` is a :mod:`asperity2d.belt.presets` name; ``overrides``
    replace its ``simulate_chain`` arguments (``v_belt``, ``mu_s``, ...). With
    ``ic_spread`` > 0 the initial displacements get seeded uniform noise of
    that half-width (m): a Monte-Carlo over initial conditions.
    """
    kwargs = presets.preset(preset_name, **overrides)
    if ic_spread > 0:
        rng = np.random.default_rng(seed)
        x0 = np.asarray(kwargs["x0"], dtype=float)
        kwargs["x0"] = list(x0 + rng.uniform(-ic_spread, ic_spread, len(x0)))
    result = simulate_chain(**kwargs)
    label = regime.classify(result)
    return {"stick_slip": float(label == "stick-slip"), "quasi_harmonic": float(label == "quasi-harmonic"),
            "total_stick_s": float(sum(total_stick(result))), "amplitude_m": float(max(amplitude(result))),
            "energy_balance_error": float(result.energy_balance_error())}
