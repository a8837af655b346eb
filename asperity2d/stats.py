"""Statistics of measured values: the one place the package computes intervals and tests.

Everything goes through :mod:`scipy.stats` (imported when first used: it
costs about a second). Non-finite values (a run that produced no number) are
left out and counted separately, so ``n`` is always the number of finite
values actually used.

* :func:`describe` -- n, mean, sample std, median and the t confidence
  interval of the mean (``scipy.stats.ttest_1samp(...).confidence_interval``);
* :func:`mann_whitney` -- two independent samples (``mannwhitneyu``);
* :func:`wilcoxon` -- one sample against a reference value, or two paired
  samples (``wilcoxon`` on the differences);
* :func:`versus_reference` -- :func:`describe` plus the effect against a
  deterministic reference, its one-sample Wilcoxon tests (in the claimed direction and
  the opposite one) and :func:`equivalence`'s numbers;
* :func:`equivalence` -- what a verdict needs beyond the test: the Hodges-Lehmann
  ratio's (1 - 2 alpha) interval (the two one-sided tests of an equivalence claim) and
  the spread of the per-seed relative change (the seeds a question needs);
* :func:`hodges_lehmann` -- the location estimate that goes with the Wilcoxon
  signed-rank test (median of the Walsh averages) and its distribution-free
  confidence interval (the one that inverts the test); :func:`relative_effect`
  applies it to relative differences (values / reference - 1, or paired
  ratios - 1), the effect size the verdicts report.
"""

from __future__ import annotations

import math

import numpy as np

from ._inputs import check_choice
from .errors import SceneError

ALTERNATIVES = ("two-sided", "less", "greater")


def finite(values) -> np.ndarray:
    """The finite values of ``values`` as a float array."""
    a = np.asarray(values, dtype=float).ravel()
    return a[np.isfinite(a)]


#: Values closer than this (relative) are the same number reached by a different rounding path
#: (e.g. the fixed track's first breakaway, spacing-independent by construction, differs by
#: <= 4e-15 between spacings): such differences count as zero, so rounding noise can neither
#: make a test significant nor count as a seed below or above.
SAME_RTOL = 1e-12


def _same(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    return np.abs(x - y) <= SAME_RTOL * np.maximum(np.abs(x), np.abs(y))


def difference(a, b) -> np.ndarray:
    """``a - b`` elementwise, with differences at rounding level (:data:`SAME_RTOL`) set to 0:
    the paired differences to test against zero."""
    x, y = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(b, dtype=float))
    return np.where(_same(x, y), 0.0, x - y)


def describe(values, *, level: float = 0.95) -> dict:
    """``n`` (finite values), ``missing`` (non-finite ones), ``mean``, ``std`` (ddof=1),
    ``median``, ``ci_low``/``ci_high`` (t interval of the mean at ``level``; NaN below 2 values)."""
    from scipy import stats

    if not 0.0 < level < 1.0:
        raise SceneError(f"`level` must be in (0, 1), got {level!r}")
    a = finite(values)
    out = {"n": int(len(a)), "missing": int(np.size(values) - len(a)),
           "mean": float(a.mean()) if len(a) else math.nan,
           "std": float(a.std(ddof=1)) if len(a) > 1 else math.nan,
           "median": float(np.median(a)) if len(a) else math.nan,
           "ci_low": math.nan, "ci_high": math.nan}
    if len(a) > 1:
        if np.ptp(a) <= SAME_RTOL * np.max(np.abs(a)):  # no spread beyond rounding: the value itself
            out["ci_low"] = out["ci_high"] = out["mean"]
        else:
            ci = stats.ttest_1samp(a, 0.0).confidence_interval(level)
            out["ci_low"], out["ci_high"] = float(ci.low), float(ci.high)
    return out


def mann_whitney(a, b, *, alternative: str = "two-sided") -> float:
    """p-value of the Mann–Whitney U test of independent samples ``a`` and ``b`` (NaN if one is empty)."""
    from scipy import stats

    check_choice("alternative", alternative, ALTERNATIVES)
    x, y = finite(a), finite(b)
    if not len(x) or not len(y):
        return math.nan
    return float(stats.mannwhitneyu(x, y, alternative=alternative).pvalue)


def wilcoxon(a, b=None, *, reference: float | None = None, alternative: str = "two-sided") -> float:
    """p-value of the Wilcoxon signed-rank test: ``a`` against a ``reference`` value, or ``a``
    paired with ``b`` (pairs with a non-finite member are dropped). Differences within
    :data:`SAME_RTOL` of the values count as zero; 1.0 when every difference is zero; NaN with
    no pairs."""
    from scipy import stats

    check_choice("alternative", alternative, ALTERNATIVES)
    if (b is None) == (reference is None):
        raise SceneError("give `b` (paired samples) or `reference` (one sample), not both")
    x = np.asarray(a, dtype=float).ravel()
    y = np.full_like(x, float(reference)) if b is None else np.asarray(b, dtype=float).ravel()
    if len(x) != len(y):
        raise SceneError(f"`a` and `b` must pair up, got {len(x)} and {len(y)} values")
    keep = np.isfinite(x) & np.isfinite(y)
    d = np.where(_same(x[keep], y[keep]), 0.0, (x - y)[keep])
    if not len(d):
        return math.nan
    if not np.any(d):
        return 1.0
    return float(stats.wilcoxon(d, alternative=alternative).pvalue)


def versus_reference(values, reference: float, *, alternative: str = "less", level: float = 0.95,
                     alpha: float = 0.01) -> dict:
    """:func:`describe` of ``values`` plus their effect against a deterministic ``reference``:
    ``reference``, ``difference`` (mean - reference), ``relative_difference`` (fraction),
    ``below`` / ``above`` (how many values are under / over it), ``effect_size_d``
    ((mean - reference) / std), ``p_wilcoxon`` (one-sided in ``alternative``),
    ``p_wilcoxon_opposite`` (one-sided the other way; NaN for a two-sided ``alternative``),
    ``p_wilcoxon_two_sided``, ``alternative``, and :func:`equivalence` of the values against
    the reference at ``alpha`` (``tost_level``, ``ratio_tost_low``/``ratio_tost_high``,
    ``relative_hl``, ``relative_std``)."""
    check_choice("alternative", alternative, ALTERNATIVES)
    out = describe(values, level=level)
    a = finite(values)
    same = _same(a, np.full_like(a, float(reference)))
    diff = out["mean"] - reference
    opposite = {"less": "greater", "greater": "less"}.get(alternative)
    out.update(reference=float(reference), difference=diff,
               relative_difference=diff / reference if reference else math.nan,
               below=int(np.sum((a < reference) & ~same)), above=int(np.sum((a > reference) & ~same)),
               effect_size_d=diff / out["std"] if out["std"] and out["std"] > 0 else math.nan,
               p_wilcoxon=wilcoxon(a, reference=reference, alternative=alternative),
               p_wilcoxon_opposite=(wilcoxon(a, reference=reference, alternative=opposite)
                                    if opposite else math.nan),
               p_wilcoxon_two_sided=wilcoxon(a, reference=reference), alternative=alternative)
    if reference:
        out.update(equivalence(values, reference, alpha=alpha))
    return out


def equivalence(values, reference, *, alpha: float = 0.01) -> dict:
    """The numbers an equivalence ("no effect") verdict and a seed estimate need.

    From the per-seed relative changes ``values / reference - 1`` (``reference`` a number, or
    a sequence paired with ``values``, as :func:`relative_effect`):

    * ``tost_alpha`` (= ``alpha``) and ``tost_level``, the coverage the interval reached (its
      nominal level is ``1 - 2 alpha``; NaN when too few values can reach it);
    * ``ratio_tost_low`` / ``ratio_tost_high``: the Hodges-Lehmann ratio's distribution-free
      ``1 - 2 alpha`` interval, exactly the ratios that neither one-sided signed-rank test at
      ``alpha`` rejects -- so "the interval lies inside [1 - m, 1 + m]" *is* the two one-sided
      tests (TOST) of equivalence within a margin m, each at ``alpha``;
    * ``relative_hl``: the Hodges-Lehmann estimate of the relative change (fraction);
    * ``relative_std``: the sample standard deviation of the per-seed relative changes
      (ddof = 1; NaN below 2 values), the spread a seed estimate scales with.

    Examples
    --------
    >>> from asperity2d import stats
    >>> e = stats.equivalence([0.998, 1.001, 0.999, 1.002, 1.0, 0.997, 1.003, 0.999], 1.0, alpha=0.01)
    >>> round(e["ratio_tost_low"], 4), round(e["ratio_tost_high"], 4), round(e["tost_level"], 3)
    (0.9975, 1.0025, 0.984)
    """
    if not 0.0 < alpha < 0.5:
        raise SceneError(f"`alpha` must be in (0, 0.5), got {alpha!r}")
    effect = relative_effect(values, reference, level=1.0 - 2.0 * alpha)
    rel = _relative_changes(values, reference)
    return {"tost_alpha": float(alpha), "tost_level": effect["level"],
            "ratio_tost_low": 1.0 + effect["ci_low"], "ratio_tost_high": 1.0 + effect["ci_high"],
            "relative_hl": effect["estimate"],
            "relative_std": float(np.std(rel, ddof=1)) if len(rel) > 1 else math.nan}


def _signed_rank_cdf(n: int) -> np.ndarray:
    """P(T+ <= t), t = 0..n(n+1)/2, of the Wilcoxon signed-rank statistic with n untied
    non-zero differences under the null (every sign equally likely): counts of the subsets
    of {1..n} with each sum, by dynamic programming (exact; n <= 60 here)."""
    counts = np.zeros(n * (n + 1) // 2 + 1)
    counts[0] = 1.0
    for rank in range(1, n + 1):
        counts[rank:] = counts[rank:] + counts[:-rank].copy()
    return np.cumsum(counts) / 2.0 ** n


def hodges_lehmann(values, *, level: float = 0.95) -> dict:
    """Hodges-Lehmann estimate of the centre of ``values`` and its confidence interval.

    The estimate is the median of the n(n+1)/2 Walsh averages (x_i + x_j) / 2, i <= j; the
    interval [W_(k), W_(N+1-k)] of the sorted averages, with k the largest rank such that
    P(T+ <= k - 1) <= (1 - level) / 2 for the signed-rank statistic T+: exactly the values
    theta that a two-sided Wilcoxon test of ``values - theta`` does not reject (exact null
    distribution up to 60 values, normal approximation beyond). Non-finite values are left
    out. Returns ``n``, ``estimate``, ``ci_low``, ``ci_high`` and the ``level`` reached (the
    interval's exact coverage, >= ``level``; NaN when even the widest interval cannot reach it).
    """
    from scipy import stats

    if not 0.0 < level < 1.0:
        raise SceneError(f"`level` must be in (0, 1), got {level!r}")
    a = finite(values)
    n = len(a)
    out = {"n": int(n), "estimate": math.nan, "ci_low": math.nan, "ci_high": math.nan, "level": math.nan}
    if not n:
        return out
    i, j = np.triu_indices(n)
    walsh = np.sort(0.5 * (a[i] + a[j]))
    out["estimate"] = float(np.median(walsh))
    total = len(walsh)
    tail = 0.5 * (1.0 - level)
    if n <= 60:
        cdf = _signed_rank_cdf(n)
        ok = np.flatnonzero(cdf <= tail)  # t = k - 1 with P(T+ <= k - 1) <= tail
        if not len(ok):
            return out
        k = int(ok[-1]) + 1
        out["level"] = float(1.0 - 2.0 * cdf[k - 1])
    else:
        mean, sd = n * (n + 1) / 4.0, math.sqrt(n * (n + 1) * (2 * n + 1) / 24.0)
        k = max(1, int(math.floor(mean - stats.norm.ppf(1.0 - tail) * sd)))
        out["level"] = float(1.0 - 2.0 * stats.norm.cdf((k - 0.5 - mean) / sd))
    out["ci_low"], out["ci_high"] = float(walsh[k - 1]), float(walsh[total - k])
    return out


def _relative_changes(values, reference) -> np.ndarray:
    """``values / reference - 1`` over the finite pairs (rounding-level differences count as 0)."""
    x = np.asarray(values, dtype=float).ravel()
    if reference is None:
        raise SceneError("`reference` must be a number or a sequence paired with `values`")
    if np.ndim(reference) == 0:
        y = np.full_like(x, float(reference))
    else:
        y = np.asarray(reference, dtype=float).ravel()
        if len(y) != len(x):
            raise SceneError(f"`values` and `reference` must pair up, got {len(x)} and {len(y)} values")
    keep = np.isfinite(x) & np.isfinite(y) & (y != 0)
    return np.where(_same(x[keep], y[keep]), 0.0, x[keep] / y[keep] - 1.0)


def relative_effect(values, reference=None, *, level: float = 0.95) -> dict:
    """Relative effect with its Hodges-Lehmann interval: of ``values`` against a deterministic
    ``reference`` (a number: ``values / reference - 1``) or paired with ``reference`` (a
    sequence, the same seeds: ``values_i / reference_i - 1``). Returns
    :func:`hodges_lehmann` of those relative differences (``estimate``, ``ci_low``,
    ``ci_high``, fractions: -0.3 is 30 % lower) and ``ratio`` = 1 + ``estimate``."""
    out = hodges_lehmann(_relative_changes(values, reference), level=level)
    out["ratio"] = 1.0 + out["estimate"]
    return out
