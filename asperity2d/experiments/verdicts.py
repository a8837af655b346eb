"""Verdicts in plain words: the rule that decides whether a comparison's claim holds.

A verdict is one of :data:`HOLDS`, :data:`FAILS` ("does not hold") or
:data:`UNTESTABLE` ("not testable with so few seeds"), decided by :func:`judge`
from the numbers of a one-sided Wilcoxon comparison
(:func:`asperity2d.stats.versus_reference`, :meth:`Comparison.versus
<asperity2d.experiments.compare.Comparison.versus>`): it holds if p < alpha
*and* the mean moved by at least :data:`MIN_EFFECT` -- a change under 1 % is
no effect. A :class:`VerdictRule` carries alpha, the direction and the
smallest effect; every named measure carries one
(:data:`asperity2d.experiments.measures.MEASURES`), so
:meth:`Comparison.verdict <asperity2d.experiments.compare.Comparison.verdict>`
says what the command line and the scene scripts print. Claim records
(:func:`claim`) and their one-line form (:func:`verdict_line`) are the format
every study writes (:mod:`asperity2d.studies.claims`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

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


@dataclass(frozen=True)
class VerdictRule:
    """How a comparison against a reference is judged: one-sided in ``direction`` (``"less"``:
    the claim is that the variant lowers the measure; ``"greater"``: raises it), holds if the
    p-value is under ``alpha`` and the relative change of the mean is at least ``min_effect``.
    The criterion is fixed before the numbers are looked at."""

    alpha: float = 0.01
    direction: str = "less"
    min_effect: float = MIN_EFFECT

    def judge(self, numbers: dict) -> str:
        """:data:`HOLDS`, :data:`FAILS` or :data:`UNTESTABLE` for these numbers (:func:`judge`)."""
        return judge(numbers, self.alpha, direction=self.direction, min_effect=self.min_effect)

    @property
    def verb(self) -> str:
        """"lowers" or "raises": how a claim under this rule reads."""
        return "lowers" if self.direction == "less" else "raises"

    def describe(self, test: str) -> str:
        """The test and the criterion in words, as a claim record's ``test`` field."""
        side = "lower" if self.direction == "less" else "higher"
        return (f"{test}, one-sided ({side}); holds if p < {self.alpha:g} and the change is at "
                f"least {100 * self.min_effect:g} %")
