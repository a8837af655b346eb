"""Comparisons over seeds: statistics against hand-computed numbers, scipy, persistence."""

import math

import numpy as np
import pytest
from scipy import stats

import asperity2d as a
from asperity2d.compare import Comparison, compare


def last_lower_centre(scene):
    """A cheap, seed-dependent measure (m): no simulation needed."""
    return float(scene.lower.tips()[-1])


VARIANTS = {"regular": {"spacing": "regular"}, "random": {"spacing": "random"},
            "random-wide": {"spacing": "random", "pitch": 1.5e-6}}


def test_compare_builds_each_variant_on_each_seed():
    c = compare(last_lower_centre, VARIANTS, range(4), base={"lower_count": 5}, progress=False)
    assert c.seeds == (0, 1, 2, 3)
    assert list(c.values) == list(VARIANTS)
    for name, kwargs in VARIANTS.items():
        expected = [last_lower_centre(a.make_scene(lower_count=5, seed=s, **kwargs)) for s in range(4)]
        assert list(c.values[name]) == expected
    assert len(set(c.values["regular"])) == 1  # regular spacing ignores the seed
    assert len(set(c.values["random"])) == 4
    assert c.measure == "last_lower_centre"
    assert c.base == {"lower_count": 5}


def test_results_do_not_depend_on_workers():
    serial = compare(last_lower_centre, VARIANTS, [3, 1, 4, 1, 5], progress=False)
    parallel = compare(last_lower_centre, VARIANTS, [3, 1, 4, 1, 5], progress=False, workers=2)
    assert serial == parallel


def test_bad_arguments_fail_before_any_run():
    calls = []

    def measure(scene):
        calls.append(scene)
        return 0.0

    with pytest.raises(a.SceneError, match="`pitchh`"):
        compare(measure, {"ok": {}, "typo": {"pitchh": 1e-6}}, [0, 1], progress=False)
    with pytest.raises(a.SceneError, match="`seed`"):
        compare(measure, {"x": {"seed": 3}}, [0], progress=False)
    with pytest.raises(a.SceneError, match="`seeds`"):
        compare(measure, {"x": {}}, [], progress=False)
    with pytest.raises(a.SceneError, match="`workers`"):
        compare(measure, {"x": {}}, [0], progress=False, workers=0)
    with pytest.raises(a.SceneError, match="`variants`"):
        compare(measure, {}, [0], progress=False)
    with pytest.raises(a.SceneError, match="`measure`"):
        compare(measure, {"x": {}}, [0], progress=False, workers=2)  # a local function
    assert calls == []


def failing_measure(scene):
    if scene.lower.spacing.seed % 2:
        raise RuntimeError("diverged")
    return 1.0


def test_a_failing_run_names_its_variant_and_seed():
    with pytest.raises(RuntimeError, match="diverged") as info:
        compare(failing_measure, {"random": {"spacing": "random"}}, [0, 1, 2], progress=False)
    seed = [s for s in (0, 1, 2) if a.make_scene(spacing="random", seed=s).lower.spacing.seed % 2][0]
    assert f"variant 'random' with seed {seed}" in "".join(info.value.__notes__)


def test_statistics_against_hand_computed_values():
    c = Comparison(values={"a": (1.0, 2.0, 3.0, 4.0, 5.0), "b": (2.0, 4.0, 6.0, 8.0, math.nan)},
                   seeds=(0, 1, 2, 3, 4))
    assert c.mean("a") == 3.0
    assert c.std("a") == pytest.approx(math.sqrt(2.5))
    t975_4 = 2.7764451051977987  # Student t, 97.5 % quantile, 4 degrees of freedom (tables)
    half = t975_4 * math.sqrt(2.5) / math.sqrt(5)
    lo, hi = c.ci("a")
    assert (lo, hi) == (pytest.approx(3.0 - half, rel=1e-12), pytest.approx(3.0 + half, rel=1e-12))
    # NaN is ignored: b has four values 2, 4, 6, 8
    assert c.mean("b") == 5.0 and c.std("b") == pytest.approx(math.sqrt(20 / 3))
    s = c.summary()
    assert s["b"]["n"] == 4 and s["b"]["median"] == 5.0 and s["a"]["ci_high"] == pytest.approx(hi)
    single = Comparison(values={"one": (1.0,)}, seeds=(0,))
    assert all(math.isnan(v) for v in single.ci("one"))


def test_mann_whitney_matches_scipy_and_the_exact_count():
    c = Comparison(values={"low": (1.0, 2.0, 3.0), "high": (4.0, 5.0, 6.0)}, seeds=(0, 1, 2))
    # fully separated samples of 3 and 3: exact two-sided p = 2 / C(6, 3) = 0.1
    assert c.mann_whitney("low", "high") == pytest.approx(0.1)
    assert c.mann_whitney("low", "high", alternative="less") == pytest.approx(0.05)
    rng = np.random.default_rng(0)
    x, y = rng.normal(0, 1, 12), rng.normal(0.8, 1, 12)
    c2 = Comparison(values={"x": tuple(x), "y": tuple(y)}, seeds=tuple(range(12)))
    assert c2.mann_whitney("x", "y") == stats.mannwhitneyu(x, y).pvalue


def test_one_sample_tests():
    c = Comparison(values={"a": (1.1, 1.2, 1.3, 1.4, 1.5)}, seeds=(0, 1, 2, 3, 4))
    # all five above the reference: exact signed-rank two-sided p = 2 / 2**5
    assert c.one_sample("a", 1.0) == pytest.approx(2 / 32)
    assert c.one_sample("a", 1.0, test="t") == pytest.approx(
        stats.ttest_1samp([1.1, 1.2, 1.3, 1.4, 1.5], 1.0).pvalue)
    assert c.one_sample("a", 1.3, test="t") == pytest.approx(1.0)
    with pytest.raises(a.SceneError, match="`test`"):
        c.one_sample("a", 1.0, test="z")
    with pytest.raises(a.SceneError, match="`name`"):
        c.mean("missing")


def test_save_load_round_trip(tmp_path):
    c = compare(last_lower_centre, VARIANTS, [0, 2], progress=False)
    path = c.save(tmp_path / "study" / "cmp.json")
    assert Comparison.load(path) == c
    with_nan = Comparison(values={"a": (1.0, math.nan)}, seeds=(0, 1), measure="critical_force")
    back = Comparison.load(with_nan.save(tmp_path / "nan.json"))
    assert back.measure == "critical_force" and back.values["a"][0] == 1.0
    assert math.isnan(back.values["a"][1])
    assert [p.name for p in tmp_path.iterdir() if p.suffix == ".tmp"] == []


def test_bad_files_and_shapes(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text("{\"format\": \"something else\"}")
    with pytest.raises(a.SceneError, match="`path`"):
        Comparison.load(bad)
    with pytest.raises(a.SceneError, match="`path`"):
        Comparison.load(tmp_path / "missing.json")
    with pytest.raises(a.SceneError, match="`values`"):
        Comparison(values={"a": (1.0, 2.0)}, seeds=(0,))
