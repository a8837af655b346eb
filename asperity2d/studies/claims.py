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

# The verdicts (the rule, the words, the one-line form) live with the experiments that judge them;
# re-exported here, where every study's claims are written.
from ..experiments.verdicts import (DECIDED, FAILS, HOLDS, MIN_EFFECT, NO_EFFECT, OUTCOMES,  # noqa: F401
                                    UNDECIDED, UNTESTABLE, VerdictRule, claim, effect, judge,
                                    outcome_text, rejudge, seeds_needed, verdict_line)


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
