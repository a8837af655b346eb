"""Verdicts in plain words: the rule that decides what a comparison against a reference shows.

A claim "the variant lowers (raises) the measure" ends in one of five outcomes, each earned:

* :data:`HOLDS` ("holds"): the one-sided Wilcoxon signed-rank test in the claimed direction
  gives p < alpha *and* the mean moved by at least the measure's margin m
  (:data:`MIN_EFFECT`, 1 %, unless the measure's rule says otherwise);
* :data:`NO_EFFECT` ("no effect"): equivalence is shown by two one-sided tests (TOST) at the
  margin: the Hodges-Lehmann ratio's ``1 - 2 alpha`` interval
  (:func:`asperity2d.stats.equivalence`, the ratios neither one-sided signed-rank test at
  alpha rejects) lies inside [1 - m, 1 + m];
* :data:`FAILS` ("does not hold"): the effect is shown to go *the other way*: the one-sided
  test in the opposite direction gives p < alpha and the mean moved that way by at least m;
* :data:`UNDECIDED` ("undecided"): none of these is shown yet; :func:`seeds_needed` says how
  many seeds would decide it at the observed spread;
* :data:`UNTESTABLE` ("not testable with so few seeds"): even every seed on one side could not
  reach p < alpha (the exact one-sided p is then at least 2**-n).

A :class:`VerdictRule` carries alpha, the direction and the margin; every named measure carries
one (:data:`asperity2d.experiments.measures.MEASURES`), so
:meth:`Comparison.verdict <asperity2d.experiments.compare.Comparison.verdict>` says what the
command line, the workbench and the scene scripts print. Claim records (:func:`claim`) and their
one-line form (:func:`verdict_line`) are the format every study writes
(:mod:`asperity2d.studies.claims`); :func:`rejudge` reads a record written before the
equivalence numbers were stored by the rule above.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from statistics import NormalDist

from ..errors import SceneError

HOLDS, NO_EFFECT, UNDECIDED, FAILS, UNTESTABLE = (
    "holds", "no effect", "undecided", "does not hold", "not testable with so few seeds")
#: Every outcome of :func:`judge`, in the order a reader meets them.
OUTCOMES = (HOLDS, NO_EFFECT, FAILS, UNDECIDED, UNTESTABLE)
#: The outcomes that answer the question (the rest want more seeds).
DECIDED = (HOLDS, NO_EFFECT, FAILS)


#: The smallest relative change a verdict counts as an effect: twice the model's own force
#: resolution (the flank laws and the quasi-static ladder agree to 0.3-0.5 %), so a change the
#: model cannot resolve -- a deterministic +0.02 % that every seed repeats -- is no effect.
MIN_EFFECT = 0.01

#: :func:`seeds_needed` gives up beyond this many seeds: an observed effect that sits at the
#: margin needs ever more seeds as it gets closer, and no finite number decides it exactly there.
SEEDS_CAP = 10_000

#: Asymptotic relative efficiency of the signed-rank test against the t test under normal data
#: (3/pi, Hodges & Lehmann 1956): the signed-rank test needs about pi/3 times the seeds.
_ARE = 3.0 / math.pi


def _finite(x) -> bool:
    return isinstance(x, (int, float)) and math.isfinite(x)


def _sign(direction: str) -> int:
    if direction not in ("less", "greater"):
        raise SceneError(f"`direction` must be 'less' or 'greater', got {direction!r}")
    return -1 if direction == "less" else 1


def _p_opposite(numbers: dict) -> float:
    """The one-sided p the other way: stored, or from the two-sided p of an older record (scipy's
    two-sided signed-rank p is twice the smaller tail, so it is the opposite tail's twice when the
    claimed direction's p is over one half)."""
    p = numbers.get("p_wilcoxon_opposite")
    if _finite(p):
        return p
    claimed, both = numbers.get("p_wilcoxon"), numbers.get("p_wilcoxon_two_sided")
    if _finite(claimed) and _finite(both) and claimed > 0.5:
        return both / 2.0
    return math.nan


def tost_interval(numbers: dict, alpha: float) -> tuple[float, float, float]:
    """``(low, high, level)``: the ratio interval a "no effect" verdict at ``alpha`` is judged on.

    The numbers' own ``1 - 2 alpha`` interval (``ratio_tost_low``/``ratio_tost_high`` from
    :func:`asperity2d.stats.equivalence`) when it was computed at ``alpha`` or a smaller one
    (a wider interval: conservative). A record without one (written before these numbers were
    stored) has the 95 % interval ``ratio_ci_low``/``ratio_ci_high``: used as it is when
    ``alpha >= 0.025``, otherwise widened about ``ratio_hl`` by z(1 - alpha) / z(0.975) -- a
    derived interval, on the normal approximation. NaN when there is none."""
    low, high, tost_alpha = (numbers.get(k) for k in ("ratio_tost_low", "ratio_tost_high", "tost_alpha"))
    if _finite(low) and _finite(high) and _finite(tost_alpha) and tost_alpha <= alpha * (1 + 1e-9):
        level = numbers.get("tost_level")
        return low, high, level if _finite(level) else 1.0 - 2.0 * tost_alpha
    low, high, centre = (numbers.get(k) for k in ("ratio_ci_low", "ratio_ci_high", "ratio_hl"))
    if "tost_alpha" in numbers or not (_finite(low) and _finite(high)):
        return math.nan, math.nan, math.nan  # computed at a larger alpha only: too narrow to use
    if alpha >= 0.025:
        return low, high, 0.95
    if not _finite(centre):
        return math.nan, math.nan, math.nan
    widen = NormalDist().inv_cdf(1.0 - alpha) / NormalDist().inv_cdf(0.975)
    return centre - widen * (centre - low), centre + widen * (high - centre), 1.0 - 2.0 * alpha


def judge(numbers: dict, alpha: float, *, direction: str = "less", min_effect: float = MIN_EFFECT) -> str:
    """The verdict of a one-sided comparison against a reference, from
    :func:`asperity2d.stats.versus_reference` numbers (or :meth:`Comparison.versus
    <asperity2d.experiments.compare.Comparison.versus>` with :func:`asperity2d.stats.equivalence`).

    Parameters
    ----------
    numbers : dict
        ``n``, ``relative_difference`` (the mean's change, a fraction), ``p_wilcoxon`` (one-sided
        in ``direction``), ``p_wilcoxon_opposite`` (the other way) and the ``1 - 2 alpha`` ratio
        interval (:func:`tost_interval`).
    alpha : float
        The level of each one-sided test.
    direction : {"less", "greater"}
        The claim: the variant lowers ("less") or raises ("greater") the measure.
    min_effect : float
        The margin m (fraction): an effect is a change of at least m; "no effect" a ratio
        interval inside [1 - m, 1 + m].

    Returns
    -------
    str
        :data:`HOLDS`, :data:`NO_EFFECT`, :data:`FAILS` (shown the other way),
        :data:`UNDECIDED` or :data:`UNTESTABLE` (too few seeds for p < alpha).

    Examples
    --------
    >>> from asperity2d import stats
    >>> judge(stats.versus_reference([0.9, 0.88, 0.93, 0.91, 0.87, 0.9, 0.92, 0.89], 1.0), 0.01)
    'holds'
    >>> judge(stats.versus_reference([1.001, 0.999, 1.0, 1.002, 0.998, 1.001, 0.999, 1.0], 1.0), 0.01)
    'no effect'
    >>> judge(stats.versus_reference([0.99, 1.02, 0.97, 1.01, 0.98, 1.0, 0.985, 1.015], 1.0), 0.01)
    'undecided'
    >>> judge(stats.versus_reference([0.9, 0.88, 0.93], 1.0), 0.01)
    'not testable with so few seeds'
    """
    sign = _sign(direction)
    if 0.5 ** numbers.get("n", 0) >= alpha:
        return UNTESTABLE
    rel = numbers.get("relative_difference")
    if _finite(rel):
        p = numbers.get("p_wilcoxon")
        if sign * rel >= min_effect and _finite(p) and p < alpha:
            return HOLDS
        p_other = _p_opposite(numbers)
        if -sign * rel >= min_effect and _finite(p_other) and p_other < alpha:
            return FAILS
    low, high, _ = tost_interval(numbers, alpha)
    if _finite(low) and _finite(high) and low >= 1.0 - min_effect and high <= 1.0 + min_effect:
        return NO_EFFECT
    return UNDECIDED


def seeds_needed(numbers: dict, alpha: float, *, direction: str = "less",
                 min_effect: float = MIN_EFFECT) -> int | None:
    """About how many seeds would decide an undecided comparison, at the spread observed.

    The assumption: the per-seed relative changes (value / reference - 1) are normal with the
    observed spread s (``relative_std``; an older record's abs(``relative_difference`` /
    ``effect_size_d``), the same number) and the observed effect e, the mean's change (the
    number the rule's margin is checked on), stays what it is. Then a
    one-sided test at alpha reaches significance at n = (z s / e)**2 when abs(e) >= m (holds, or
    the other way), and the ``1 - 2 alpha`` interval e +- z s / sqrt(n) fits inside +-m at
    n = (z s / (m - abs(e)))**2 when abs(e) < m (z = z(1 - alpha)); the signed-rank test needs pi/3
    times that (its efficiency against the t test on normal data). The estimate is at least one
    seed more than ``n`` and at least the smallest testable count.

    Returns the number, or None when it is over :data:`SEEDS_CAP` (the effect sits so close to
    the margin that no practical number of seeds decides it) or the numbers have no spread.

    Examples
    --------
    >>> numbers = {"n": 8, "relative_difference": -0.008, "relative_std": 0.017}
    >>> seeds_needed(numbers, 0.01)   # 0.2 % from the 1 % margin, 1.7 % spread
    410
    >>> seeds_needed({**numbers, "relative_difference": -0.02}, 0.01)
    9
    """
    sign = _sign(direction)
    n = numbers.get("n", 0) or 0
    rel = numbers.get("relative_difference")
    spread = numbers.get("relative_std")
    if not _finite(spread):
        d = numbers.get("effect_size_d")
        spread = abs(rel / d) if _finite(rel) and _finite(d) and d else math.nan
    if not (_finite(rel) and _finite(spread)) or spread <= 0:
        return None
    z = NormalDist().inv_cdf(1.0 - alpha)
    # holds (or the other way) once the test is significant; no effect once the interval fits
    distance = abs(rel) if abs(rel) >= min_effect else min_effect - abs(rel)
    if distance <= 0:
        return None
    estimate = (z * spread / distance) ** 2 / _ARE
    if not math.isfinite(estimate) or estimate > SEEDS_CAP:
        return None
    smallest = math.floor(math.log(alpha) / math.log(0.5)) + 1  # the fewest with 2**-n < alpha
    return max(math.ceil(estimate), n + 1, smallest)


def rejudge(record: dict, alpha: float = 0.01, *, min_effect: float = MIN_EFFECT) -> str:
    """A claim record's verdict by today's rule.

    A record whose numbers are a comparison against a reference (``p_wilcoxon`` and
    ``relative_difference``) and whose verdict was "does not hold" -- the old word for
    everything that did not hold -- is judged again by :func:`judge` (its direction from
    ``alternative``, else from its test's words "(higher)"/"(lower)"; ``alpha`` from the record's
    ``tost_alpha`` when it has one), so an older table says "no effect", "undecided" or "does not
    hold" as the rule would now. Every other record keeps its verdict."""
    numbers = record.get("numbers") or {}
    verdict = record.get("verdict")
    if verdict != FAILS or not isinstance(numbers, dict) or "p_wilcoxon" not in numbers \
            or "relative_difference" not in numbers:
        return verdict
    direction = numbers.get("alternative")
    if direction not in ("less", "greater"):
        direction = "greater" if "(higher)" in str(record.get("test", "")) else "less"
    return judge(numbers, numbers.get("tost_alpha", alpha), direction=direction,
                 min_effect=numbers.get("margin", min_effect))


def claim(text: str, holds: bool | str, numbers: dict, test: str, *, setup: str | None = None) -> dict:
    """A claim record: the statement, its verdict (a bool, or a verdict from :func:`judge`), the
    numbers behind it and the test used."""
    verdict = holds if isinstance(holds, str) else (HOLDS if holds else FAILS)
    out = {"claim": text, "verdict": verdict, "numbers": numbers, "test": test}
    if setup is not None:
        out["setup"] = setup
    return out


def _ratio(x: float) -> str:
    return f"{x:.3g}"


def effect(numbers: dict) -> str:
    """``"-19 %, x0.81 [0.76, 0.85], 10/10 seeds below, Wilcoxon p = 0.001"`` from
    :func:`asperity2d.stats.versus_reference` numbers (or whatever part of it ``numbers`` has):
    the change of the mean, the Hodges-Lehmann ratio with its 95 % interval when the numbers
    carry one (``ratio_hl``, ``ratio_ci_low``, ``ratio_ci_high``), the seeds below and the test;
    a comparison run in stages (``stages``) adds how many seeds it took in how many stages."""
    parts = []
    rel = numbers.get("relative_difference")
    if _finite(rel):
        parts.append(f"{100 * rel:+.0f} %" if abs(rel) >= 0.095 else f"{100 * rel:+.1g} %")
    ratio = numbers.get("ratio_hl")
    if _finite(ratio):
        low, high = numbers.get("ratio_ci_low"), numbers.get("ratio_ci_high")  # None: NaN read from JSON
        ci = f" [{_ratio(low)}, {_ratio(high)}]" if _finite(low) and _finite(high) else ""
        parts.append(f"x{_ratio(ratio)}{ci}")
    if "below" in numbers and "n" in numbers:
        parts.append(f"{numbers['below']}/{numbers['n']} seeds below")
    p = numbers.get("p_wilcoxon")
    if _finite(p):
        parts.append(f"Wilcoxon p = {p:.2g}")
    stages = numbers.get("stages")
    if isinstance(stages, list) and stages:
        parts.append(f"{numbers.get('n', '?')} seeds in {len(stages)} stage{'s' * (len(stages) > 1)}")
    return ", ".join(parts)


def _percent(m: float) -> str:
    return f"{100 * m:g} %"


def outcome_text(verdict: str, numbers: dict, *, alpha: float | None = None,
                 min_effect: float | None = None, direction: str | None = None) -> str:
    """The verdict and its evidence in words a newcomer reads, e.g. ``"no effect (within +-1 %:
    x0.9980 [0.9940, 1.0030] 98 % interval, 24 seeds)"`` or ``"undecided (-0.8 %, x0.992 [0.973,
    1.01], 5/8 seeds below, Wilcoxon p = 0.15; about 40 seeds would decide it at this spread)"``.
    ``alpha``, ``min_effect`` and ``direction`` default to the numbers' own (``tost_alpha``,
    ``margin``, ``alternative``) and then to 0.01, :data:`MIN_EFFECT` and "less"."""
    alpha = alpha if alpha is not None else numbers.get("tost_alpha", 0.01)
    margin = min_effect if min_effect is not None else numbers.get("margin", MIN_EFFECT)
    direction = direction or numbers.get("alternative") or "less"
    if direction not in ("less", "greater"):
        direction = "less"
    detail = effect(numbers)
    if verdict == NO_EFFECT:
        low, high, level = tost_interval(numbers, alpha)
        ratio = numbers.get("ratio_hl")
        centre = f"x{ratio:.4f} " if _finite(ratio) else ""
        seeds = f", {numbers['n']} seeds" if "n" in numbers else ""
        staged = numbers.get("stages")
        if isinstance(staged, list) and len(staged) > 1:
            seeds += f" in {len(staged)} stages"
        return (f"{NO_EFFECT} (within +-{_percent(margin)}: {centre}[{low:.4f}, {high:.4f}] "
                f"{100 * level:.0f} % interval{seeds})")
    if verdict == UNDECIDED:
        n_more = numbers.get("seeds_needed", "?")
        if n_more == "?":
            n_more = seeds_needed(numbers, alpha, direction=direction, min_effect=margin)
        if n_more is None:
            more = (f"no number of seeds up to {SEEDS_CAP:,} would decide it at this spread: the "
                    f"effect sits at the {_percent(margin)} margin")
        else:
            more = f"about {n_more} seeds would decide it at this spread"
        return f"{UNDECIDED} ({detail}; {more})" if detail else f"{UNDECIDED} ({more})"
    if verdict == FAILS and "p_wilcoxon" in numbers:
        p_other = _p_opposite(numbers)
        other = f"; one-sided p = {p_other:.2g} that way" if _finite(p_other) else ""
        return f"{FAILS}: it goes the other way ({detail}{other})"
    return f"{verdict} ({detail})" if detail else verdict


def verdict_line(record: dict) -> str:
    """``"<claim>: holds (<effect>)"``, with the set-up in brackets when the record has one; a
    "no effect" line gives the interval and the margin, an "undecided" one the seeds that would
    decide it (:func:`outcome_text`)."""
    setup = f"[{record['setup']}] " if record.get("setup") else ""
    return f"{setup}{record['claim']}: {outcome_text(record['verdict'], record.get('numbers', {}))}"


@dataclass(frozen=True)
class VerdictRule:
    """How a comparison against a reference is judged (:func:`judge`): one-sided in
    ``direction`` (``"less"``: the claim is that the variant lowers the measure; ``"greater"``:
    raises it) at level ``alpha``, with the margin ``min_effect`` (fraction) that separates an
    effect from no effect. The criterion is fixed before the numbers are looked at.

    Examples
    --------
    >>> rule = VerdictRule(alpha=0.01, direction="less", min_effect=0.01)
    >>> rule.verb, rule.judge({"n": 3, "relative_difference": -0.5, "p_wilcoxon": 0.125})
    ('lowers', 'not testable with so few seeds')
    """

    alpha: float = 0.01
    direction: str = "less"
    min_effect: float = MIN_EFFECT

    def __post_init__(self):
        if not (isinstance(self.alpha, (int, float)) and 0.0 < self.alpha < 0.5):
            raise SceneError(f"`alpha` must be in (0, 0.5), got {self.alpha!r}")
        _sign(self.direction)
        if not (isinstance(self.min_effect, (int, float)) and 0.0 <= self.min_effect < 1.0):
            raise SceneError(f"`min_effect` must be in [0, 1), got {self.min_effect!r}")

    def judge(self, numbers: dict, *, alpha: float | None = None) -> str:
        """The outcome for these numbers (:func:`judge`); ``alpha`` overrides the rule's level
        (a sequential design's nominal level at its last look)."""
        return judge(numbers, self.alpha if alpha is None else alpha, direction=self.direction,
                     min_effect=self.min_effect)

    def seeds_needed(self, numbers: dict, *, alpha: float | None = None) -> int | None:
        """:func:`seeds_needed` under this rule."""
        return seeds_needed(numbers, self.alpha if alpha is None else alpha, direction=self.direction,
                            min_effect=self.min_effect)

    @property
    def verb(self) -> str:
        """"lowers" or "raises": how a claim under this rule reads."""
        return "lowers" if self.direction == "less" else "raises"

    def describe(self, test: str) -> str:
        """The test and the criterion in words, as a claim record's ``test`` field."""
        side = "lower" if self.direction == "less" else "higher"
        m = _percent(self.min_effect)
        return (f"{test}, one-sided ({side}); holds if p < {self.alpha:g} and the change is at "
                f"least {m}; no effect if the {100 * (1 - 2 * self.alpha):g} % interval of the ratio "
                f"lies within +-{m}; does not hold if shown the other way")
