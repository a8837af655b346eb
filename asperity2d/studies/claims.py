"""Claim records: a source document's statement, the numbers measured, the test, the verdict.

Every study script writes its claims in this one format (in its
``summary.json``)::

    {"claim": "random spacing lowers the critical force", "verdict": "holds",
     "numbers": {...}, "test": "one-sample Wilcoxon ..., holds if p < 0.01",
     "setup": "fixed"}

The criterion is fixed before the numbers are looked at; a claim that fails is
reported, never tuned until it holds. :func:`verdict_line` says it in one line
a newcomer can read.
"""

from __future__ import annotations

import math

from .._format import split_unit, value

HOLDS, FAILS, UNTESTABLE = "holds", "does not hold", "not testable with so few seeds"


#: The smallest relative change a verdict counts as an effect: twice the model's own force
#: resolution (the flank laws and the quasi-static ladder agree to 0.3-0.5 %), so a change the
#: model cannot resolve -- a deterministic +0.02 % that every seed repeats -- is no effect.
MIN_EFFECT = 0.01


def judge(numbers: dict, alpha: float, *, direction: str = "less", min_effect: float = MIN_EFFECT) -> str:
    """The verdict of a one-sided Wilcoxon comparison (:func:`asperity2d.stats.versus_reference`
    numbers): holds if the mean moved in ``direction`` by at least ``min_effect`` (relative)
    and p < ``alpha``; untestable when even every seed on the claimed side could not reach it
    (the exact one-sided p is then 2**-n)."""
    if 0.5 ** numbers.get("n", 0) >= alpha:
        return UNTESTABLE
    moved = numbers["mean"] < numbers["reference"] if direction == "less" else numbers["mean"] > numbers["reference"]
    rel = numbers.get("relative_difference")
    if rel is not None and math.isfinite(rel) and abs(rel) < min_effect:
        return FAILS
    return HOLDS if moved and numbers["p_wilcoxon"] < alpha else FAILS


def claim(text: str, holds: bool | str, numbers: dict, test: str, *, setup: str | None = None) -> dict:
    """A claim record: the statement, its verdict (a bool, or a verdict from :func:`judge`), the
    numbers behind it and the test used."""
    verdict = holds if isinstance(holds, str) else (HOLDS if holds else FAILS)
    out = {"claim": text, "verdict": verdict, "numbers": numbers, "test": test}
    if setup is not None:
        out["setup"] = setup
    return out


def effect(numbers: dict) -> str:
    """``"-19 %, x0.81 [0.76, 0.85], 10/10 seeds below, Wilcoxon p = 0.001"`` from
    :func:`asperity2d.stats.versus_reference` numbers (or whatever part of it ``numbers`` has):
    the change of the mean, the Hodges-Lehmann ratio with its 95 % interval when the numbers
    carry one (``ratio_hl``, ``ratio_ci_low``, ``ratio_ci_high``), the seeds below and the test."""
    parts = []
    rel = numbers.get("relative_difference")
    if rel is not None and math.isfinite(rel):
        parts.append(f"{100 * rel:+.0f} %" if abs(rel) >= 0.095 else f"{100 * rel:+.1g} %")
    ratio = numbers.get("ratio_hl")
    if ratio is not None and math.isfinite(ratio):
        low, high = numbers.get("ratio_ci_low"), numbers.get("ratio_ci_high")  # None: NaN read from JSON
        ci = (f" [{low:.3g}, {high:.3g}]" if low is not None and high is not None
              and math.isfinite(low) and math.isfinite(high) else "")
        parts.append(f"x{ratio:.3g}{ci}")
    if "below" in numbers and "n" in numbers:
        parts.append(f"{numbers['below']}/{numbers['n']} seeds below")
    p = numbers.get("p_wilcoxon")
    if p is not None and math.isfinite(p):
        parts.append(f"Wilcoxon p = {p:.2g}")
    if rel is not None and math.isfinite(rel) and abs(rel) < MIN_EFFECT:
        parts.append(f"a change under {100 * MIN_EFFECT:g} % is no effect")
    return ", ".join(parts)


def verdict_line(record: dict) -> str:
    """``"<claim>: holds (<effect>)"``, with the set-up in brackets when the record has one."""
    setup = f"[{record['setup']}] " if record.get("setup") else ""
    detail = effect(record.get("numbers", {}))
    return f"{setup}{record['claim']}: {record['verdict']}" + (f" ({detail})" if detail else "")


def _value_text(x, unit: str | None, key: str) -> str:
    if isinstance(x, float) and math.isfinite(x) and not unit and (key.startswith("p_") or key.endswith("_p")):
        return f"{x:.2g}"  # a p-value: two significant digits
    return value(x, unit, 3)


def numbers_text(numbers, *, limit: int = 8, _key: str = "") -> str:
    """Claim numbers in plain words and engineering units, for a table cell or a printed line.

    Keys say their unit by suffix (:data:`asperity2d._format.UNIT_SUFFIXES`: ``critical_force_N`` -> "critical
    force 4.32 mN"); p-values get two significant digits, other numbers three; nested records
    are bracketed, lists show their first ``limit`` items. Numbers from
    :func:`asperity2d.stats.versus_reference` read as :func:`effect` does.
    """
    if isinstance(numbers, dict):
        if "p_wilcoxon" in numbers and "relative_difference" in numbers:
            return effect(numbers)
        if "thesis" in numbers and "computed" in numbers:  # a source's number or trend, and ours
            rest = {k: v for k, v in numbers.items() if k not in ("thesis", "computed", "relative_difference", "unit")}
            computed = numbers["computed"]
            if isinstance(computed, dict):
                computed = ", ".join(f"{k}: {value(v, numbers.get('unit') or None, 3)}" for k, v in computed.items())
            text = ("" if numbers["thesis"] == "trend" else f"source {numbers['thesis']}; ") + f"computed {computed}"
            rel = numbers.get("relative_difference")
            if isinstance(rel, float) and math.isfinite(rel):
                text += f" ({100 * rel:+.2g} %)"
            return text + (f"; {numbers_text(rest, limit=limit)}" if rest else "")
        parts = []
        for key, item in list(numbers.items())[:limit]:
            name, unit = split_unit(key)
            if isinstance(item, dict):
                parts.append(f"{name}: ({numbers_text(item, limit=limit, _key=str(key))})")
            elif isinstance(item, (list, tuple)):
                shown = [_value_text(v, unit, str(key)) if not isinstance(v, (dict, list, tuple))
                         else numbers_text(v, limit=limit) for v in item[:limit]]
                more = f", … ({len(item)} in all)" if len(item) > limit else ""
                parts.append(f"{name} [{', '.join(shown)}{more}]")
            else:
                parts.append(f"{name} {_value_text(item, unit, str(key))}")
        more = f"; … ({len(numbers) - limit} more)" if len(numbers) > limit else ""
        return "; ".join(parts) + more
    if isinstance(numbers, (list, tuple)):
        return ", ".join(numbers_text(v, limit=limit) for v in numbers[:limit])
    return _value_text(numbers, None, _key)
