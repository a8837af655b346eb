"""The statistics module against hand-computed values and exact distributions."""

import math

import numpy as np
import pytest
from scipy import stats as sp

import asperity2d as a
from asperity2d import stats


def test_describe_matches_the_t_interval_by_hand():
    d = stats.describe([1.0, 2.0, 3.0, 4.0, 5.0, math.nan])
    assert (d["n"], d["missing"], d["mean"], d["median"]) == (5, 1, 3.0, 3.0)
    assert d["std"] == pytest.approx(math.sqrt(2.5))
    t975_4 = 2.7764451051977987  # Student t, 97.5 % quantile, 4 degrees of freedom (tables)
    half = t975_4 * math.sqrt(2.5) / math.sqrt(5)
    assert (d["ci_low"], d["ci_high"]) == (pytest.approx(3 - half, rel=1e-12), pytest.approx(3 + half, rel=1e-12))
    single = stats.describe([7.0])
    assert single["mean"] == 7.0 and math.isnan(single["std"]) and math.isnan(single["ci_low"])
    assert stats.describe([2.0, 2.0, 2.0])["ci_low"] == 2.0  # no spread: no interval
    with pytest.raises(a.SceneError, match="`level`"):
        stats.describe([1.0, 2.0], level=1.5)


def test_mann_whitney_exact_counts_and_scipy():
    # fully separated samples of 3 and 3: exact two-sided p = 2 / C(6, 3) = 0.1
    assert stats.mann_whitney([1, 2, 3], [4, 5, 6]) == pytest.approx(0.1)
    assert stats.mann_whitney([1, 2, 3], [4, 5, 6], alternative="less") == pytest.approx(0.05)
    x, y = np.random.default_rng(0).normal(0, 1, (2, 12))
    assert stats.mann_whitney(x, y + 0.8) == sp.mannwhitneyu(x, y + 0.8).pvalue
    assert math.isnan(stats.mann_whitney([], [1.0]))
    with pytest.raises(a.SceneError, match="`alternative`"):
        stats.mann_whitney([1], [2], alternative="sideways")


def test_wilcoxon_one_sample_and_paired():
    # all five above the reference: exact signed-rank two-sided p = 2 / 2**5
    assert stats.wilcoxon([1.1, 1.2, 1.3, 1.4, 1.5], reference=1.0) == pytest.approx(2 / 32)
    assert stats.wilcoxon([1.1, 1.2, 1.3, 1.4, 1.5], reference=1.0, alternative="greater") == pytest.approx(1 / 32)
    assert stats.wilcoxon([1, 2, 3], [1, 2, 3]) == 1.0  # every difference zero
    assert stats.wilcoxon([1.0, math.nan], [0.0, 1.0]) == 1.0  # the NaN pair dropped; one positive difference
    with pytest.raises(a.SceneError, match="`b`"):
        stats.wilcoxon([1.0], [1.0], reference=0.0)


def test_rounding_level_differences_are_no_effect():
    """A measure equal to its reference up to rounding (the fixed track's first breakaway
    differs by <= 4e-15 between spacings) must not test significant nor count as below."""
    ref = 6.332050719200081e-3
    values = [ref * (1 - k * 2.2e-16) for k in range(1, 11)] + [ref * (1 + 1.1e-16)] * 3
    assert stats.wilcoxon(values, reference=ref, alternative="less") == 1.0
    v = stats.versus_reference(values, ref)
    assert v["below"] == v["above"] == 0 and v["p_wilcoxon"] == 1.0
    assert np.all(stats.difference(values, ref) == 0.0)  # paired differences: zero as well
    # a real (1e-6) difference is still one
    assert stats.wilcoxon([ref * (1 - 1e-6)] * 10, reference=ref, alternative="less") < 0.01


def test_versus_reference_effect_numbers():
    v = stats.versus_reference([0.8, 0.9, 1.0, 0.7, math.nan], 1.0)
    assert v["n"] == 4 and v["missing"] == 1 and v["below"] == 3 and v["above"] == 0
    assert v["relative_difference"] == pytest.approx(-0.15)
    assert v["effect_size_d"] == pytest.approx(-0.15 / np.std([0.8, 0.9, 1.0, 0.7], ddof=1))
    assert v["p_wilcoxon"] == pytest.approx(1 / 8)  # three non-zero differences, all below: 1 / 2**3


def test_a_change_below_the_models_resolution_is_no_effect():
    # 10 seeds every one 0.02 % above the reference: p = 2^-10, but the model resolves forces to
    # ~0.5 %, so "holds" would be a verdict of rounding-level physics; 2 % above holds
    from asperity2d.studies.claims import FAILS, HOLDS, judge

    tiny = a.stats.versus_reference([1.0002 + 1e-6 * i for i in range(10)], 1.0, alternative="greater")
    clear = a.stats.versus_reference([1.02 + 1e-6 * i for i in range(10)], 1.0, alternative="greater")
    assert tiny["p_wilcoxon"] < 0.01 and clear["p_wilcoxon"] < 0.01
    assert judge(tiny, 0.01, direction="greater") == FAILS
    assert judge(clear, 0.01, direction="greater") == HOLDS
