"""The stick-force distributions' step bias and per-seed precision, computed from the measured
passes in ``docs/data/measures/stick_bias.json`` (made by ``tools/investigate/stick_bias.py``).

The findings page renders its table from :func:`summary` (``.. stick-precision-table::`` in
``docs/_ext/asperity_docs.py``), so none of these numbers is typed by hand::

    python docs/data/stick_precision.py                 # every seed measured at all three steps
    python docs/data/stick_precision.py 9401-9424       # a range of seeds

For each stick force of a pass (first breakaway, peak, mean; the 5-pass ensemble mean per seed):

* the step bias: the per-seed relative shift from dt to dt/2 and from dt/2 to dt/4, its mean, one
  standard error over the seeds and a two-sided Wilcoxon p (is it distinguishable from zero?);
* the per-seed precision at the policy's step (``measures.measure_step``: dt for the peak and mean,
  dt/2 for the first breakaway): the standard deviation over seeds of the
  per-seed value relative to its mean -- the spread of the per-seed ratio to a seed-independent
  reference such as the regular surface -- and one pass's spread about its seed's mean;
* the regular surface's shift from step to step (``"regular"``; NaN where it was not measured:
  key ``"<setup>-regular/0/<factor>"``), which a ratio random / regular divides by;
* how many seeds a 5 % difference needs at the package's verdict rule (one-sided Wilcoxon
  p < 0.01 and a change of at least 1 %, :class:`asperity2d.experiments.verdicts.VerdictRule`):
  the smallest n at which 80 % of comparisons of n seeds against a reference 5 % away hold, the
  n seeds drawn with replacement from the measured per-seed values (relative to their mean).
  The rule cannot hold below 7 seeds (2**-6 > 0.01).
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np

DATA = Path(__file__).resolve().parent / "measures" / "stick_bias.json"
FACTORS = ("1.0", "0.5", "0.25")
MEASURES = {"first_breakaway": "first breakaway", "peak": "peak stick force", "mean": "mean stick force"}
#: each stick force's named measure, whose step policy says where its precision is read
NAMED = {"first_breakaway": "first-breakaway", "peak": "peak-stick", "mean": "mean-stick"}
STEP_NAMES = {"1.0": "dt", "0.5": "dt/2", "0.25": "dt/4"}


def policy_factor(name: str) -> str:
    """The step (a key of :data:`FACTORS`) the stick force ``name`` runs at under the step policy."""
    from asperity2d.experiments import measures

    return repr(float(measures.MEASURES.lookup(NAMED[name], "name").dt_fraction))


#: the verdict rule's numbers and the power asked of it
ALPHA, MIN_EFFECT, EFFECT, POWER, DRAWS = 0.01, 0.01, 0.05, 0.8, 2000


def _signed_rank_p_less(x: np.ndarray) -> np.ndarray:
    """One-sided ("less") Wilcoxon signed-rank p of each row of ``x`` against 0: exact null
    distribution up to 60 values, the normal approximation beyond (no ties: continuous draws)."""
    from asperity2d.stats import _signed_rank_cdf

    n = x.shape[1]
    ranks = np.argsort(np.argsort(np.abs(x), axis=1), axis=1) + 1
    t_plus = np.sum(np.where(x > 0, ranks, 0), axis=1)
    if n <= 60:
        return _signed_rank_cdf(n)[t_plus]
    from scipy.stats import norm

    mean, sd = n * (n + 1) / 4, math.sqrt(n * (n + 1) * (2 * n + 1) / 24)
    return norm.cdf((t_plus + 0.5 - mean) / sd)


def seeds_needed(relative: np.ndarray, *, effect: float = EFFECT, power: float = POWER,
                 max_seeds: int = 3200, seed: int = 20261128) -> int | None:
    """The smallest number of seeds at which a variant ``effect`` below its reference holds by the
    verdict rule in ``power`` of the comparisons, its per-seed values drawn with replacement from
    ``relative`` (per-seed values over their mean); None if not within ``max_seeds``."""
    relative = np.asarray(relative, float)
    relative = relative[np.isfinite(relative)]
    if len(relative) < 2:
        return None
    rng = np.random.default_rng(seed)

    def holds(n: int) -> float:
        values = (1.0 - effect) * rng.choice(relative, size=(DRAWS, n))
        ok = (_signed_rank_p_less(values - 1.0) < ALPHA) & (values.mean(axis=1) <= 1.0 - MIN_EFFECT)
        return float(ok.mean())

    n_low = 7
    if holds(n_low) >= power:
        return n_low
    n_high = n_low
    while holds(n_high) < power:
        n_low, n_high = n_high, 2 * n_high
        if n_high > max_seeds:
            return None
    while n_high - n_low > 1:
        mid = (n_low + n_high) // 2
        n_low, n_high = (n_low, mid) if holds(mid) >= power else (mid, n_high)
    return n_high


def seed_range(text: str | None) -> tuple[int, int] | None:
    """``"9401-9424"`` -> (9401, 9424); None or "" -> None (every seed)."""
    if not text:
        return None
    first, _, last = text.partition("-")
    return int(first), int(last or first)


def summary(path: Path = DATA, *, setup: str = "fixed", seeds: tuple[int, int] | None = None) -> dict:
    """The bias and precision of each stick force over the seeds measured at every step (within
    ``seeds``, inclusive, if given)."""
    from scipy.stats import wilcoxon

    data = json.loads(Path(path).read_text(encoding="utf-8"))
    found = sorted({int(k.split("/")[1]) for k in data if k.startswith(setup + "/")})
    used = [s for s in found if all(f"{setup}/{s}/{f}" in data for f in FACTORS)
            and (seeds is None or seeds[0] <= s <= seeds[1])]
    if not used:
        raise ValueError(f"no {setup} seed in {path} measured at every step")
    passes = len(data[f"{setup}/{used[0]}/0.5"]["peak"])
    out = {"setup": setup, "seeds": used, "passes": passes,
           "cpu_minutes": sum(data[f"{setup}/{s}/{f}"]["cpu_s"] for s in used for f in FACTORS) / 60,
           "measures": {}}
    for name, label in MEASURES.items():
        avg = {f: np.array([np.nanmean(data[f"{setup}/{s}/{f}"][name]) for s in used]) for f in FACTORS}
        entry = {"label": label}
        for x, y in (("1.0", "0.5"), ("0.5", "0.25")):
            r = avg[y] / avg[x] - 1.0
            r = r[np.isfinite(r)]
            nonzero = r[np.abs(r) > 1e-12]
            entry[f"{x}->{y}"] = {
                "mean": float(r.mean()), "se": float(r.std(ddof=1) / math.sqrt(len(r))),
                "sd": float(r.std(ddof=1)), "n": int(len(r)), "up": int(np.sum(r > 1e-12)),
                "down": int(np.sum(r < -1e-12)),
                "p_wilcoxon": float(wilcoxon(nonzero).pvalue) if len(nonzero) >= 2 else math.nan}
        step = policy_factor(name)
        at_policy = avg[step][np.isfinite(avg[step])]
        relative = at_policy / at_policy.mean()
        rel = np.concatenate([np.asarray(data[f"{setup}/{s}/{step}"][name], float)
                              / np.nanmean(data[f"{setup}/{s}/{step}"][name]) - 1 for s in used])
        rel = rel[np.isfinite(rel)]
        entry.update(step=STEP_NAMES[step], per_seed_sd=float(relative.std(ddof=1)),
                     per_pass_sd=float(math.sqrt(np.sum(rel ** 2) / (len(rel) - len(used)))),
                     seeds_for_5_percent=seeds_needed(relative))
        regular = [np.nanmean(data[f"{setup}-regular/0/{f}"][name]) if f"{setup}-regular/0/{f}" in data else math.nan
                   for f in FACTORS]
        entry["regular"] = {"1.0->0.5": float(regular[1] / regular[0] - 1.0),
                            "0.5->0.25": float(regular[2] / regular[1] - 1.0)}
        out["measures"][name] = entry
    return out


def seeds_text(seeds: list[int]) -> str:
    """``"7601–7610, 9401–9424 (34 seeds)"``: the seeds as runs of consecutive integers."""
    runs, start = [], seeds[0]
    for before, seed in zip(seeds, seeds[1:] + [None]):
        if seed != before + 1:
            runs.append(f"{start}–{before}" if before != start else str(start))
            start = seed
    return ", ".join(runs) + f" ({len(seeds)} seed{'s' if len(seeds) != 1 else ''})"


def report(result: dict) -> str:
    lines = [f"stick forces, {result['setup']} track 10/3 random, {result['passes']} passes, seeds "
             f"{seeds_text(result['seeds'])}, {result['cpu_minutes']:.1f} CPU-minutes"]
    for name, e in result["measures"].items():
        for step in ("1.0->0.5", "0.5->0.25"):
            s = e[step]
            lines.append(f"  {name:15s} dt*{step}: {100 * s['mean']:+.2f} +- {100 * s['se']:.2f} % (one standard "
                         f"error; sd {100 * s['sd']:.1f} %; {s['up']} up, {s['down']} down; Wilcoxon p {s['p_wilcoxon']:.2g})")
        lines.append(f"  {name:15s} regular surface: dt -> dt/2 {100 * e['regular']['1.0->0.5']:+.2f} %, "
                     f"dt/2 -> dt/4 {100 * e['regular']['0.5->0.25']:+.2f} %")
        lines.append(f"  {name:15s} at {e['step']}: per-seed sd {100 * e['per_seed_sd']:.1f} %, one pass {100 * e['per_pass_sd']:.1f} %; "
                     f"a 5 % difference needs {e['seeds_for_5_percent']} seeds (one-sided Wilcoxon p < {ALPHA:g}, "
                     f"{100 * POWER:.0f} % of the time)")
    return "\n".join(lines)


if __name__ == "__main__":
    print(report(summary(seeds=seed_range(sys.argv[1] if len(sys.argv) > 1 else None))))
