"""Comparisons over seeds: statistics against hand-computed numbers, scipy, persistence."""

import math
from statistics import NormalDist

import pytest

import asperity2d as a
from asperity2d.experiments.compare import Comparison, compare
from asperity2d.experiments.verdicts import verdict_line


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


# peak-stick is the slow one (about 70 s on a quiet 2-core machine, in workers): the default run keeps
# "critical", which exercises the same worker path; -m slow runs both
@pytest.mark.parametrize("measure", [pytest.param("peak-stick", marks=pytest.mark.slow), "critical"])
def test_real_measures_are_bit_identical_in_workers_and_here(measure):
    # a simulation's every bit is fixed by its scene (fixed dt, single-threaded pymunk, exactly
    # rounded contact sums): where it runs cannot change it
    base = {"lower_count": 4, "upper_count": 2, "drive": "force" if measure == "critical" else "spring"}
    variants = {"regular": {}, "random": {"spacing": "random"}}
    here = compare(measure, variants, [0, 1, 2], base=base, progress=False, workers=1)
    pool = compare(measure, variants, [0, 1, 2], base=base, progress=False, workers=2)
    auto = compare(measure, variants, [0, 1, 2], base=base, progress=False)
    for name in variants:
        assert [v.hex() for v in here.values[name]] == [v.hex() for v in pool.values[name]] \
            == [v.hex() for v in auto.values[name]]


def test_an_unpicklable_measure_runs_here_when_workers_are_auto():
    seen = []

    def measure(scene):  # a local function cannot travel to a worker
        seen.append(scene)
        return 1.0

    c = compare(measure, {"random": {"spacing": "random"}}, range(3), base={"lower_count": 3}, progress=False)
    assert c.values["random"] == (1.0, 1.0, 1.0) and len(seen) == 3


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


def test_a_seed_independent_variant_is_measured_once():
    calls = []

    def measure(scene):
        calls.append(scene.lower.spacing)
        return float(len(calls))

    c = compare(measure, {"regular": {"spacing": "regular"}, "random": {"spacing": "random"}}, range(5),
                base={"lower_count": 4}, progress=False)
    assert len(calls) == 1 + 5  # regular spacing does not depend on the seed
    assert c.values["regular"] == (1.0,) * 5 and len(set(c.values["random"])) == 5


def test_summary_and_versus_use_the_statistics_module():
    c = Comparison(values={"ref": (2.0,) * 5, "a": (1.0, 1.2, 1.4, 1.6, 1.8), "b": (1.1, 1.3, 1.5, 1.7, 2.1)},
                   seeds=tuple(range(5)))
    assert c.summary()["a"] == a.stats.describe([1.0, 1.2, 1.4, 1.6, 1.8])
    one = c.versus("a", "ref")  # a deterministic reference: one-sample test against the value
    assert one["reference"] == 2.0 and one["below"] == 5 and one["relative_difference"] == pytest.approx(-0.3)
    assert one["p_wilcoxon"] == pytest.approx(1 / 32)  # all five below: exact one-sided signed-rank p
    paired = c.versus("a", "b")  # seeds pair up: differences a - b are all -0.1 or -0.3
    assert paired["test"].startswith("paired") and paired["p_wilcoxon"] == pytest.approx(1 / 32)
    assert paired["relative_difference"] == pytest.approx((1.4 - 1.54) / 1.54)
    with pytest.raises(a.SceneError, match="`name`"):
        c.versus("missing", "ref")


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


def test_the_command_line_lists_every_registered_measure_with_its_unit(capsys):
    import json

    from asperity2d.cli import main
    from asperity2d.experiments.measures import MEASURES

    assert main(["measures", "--json"]) == 0
    listed = {m["name"]: m for m in json.loads(capsys.readouterr().out)["measures"]}
    assert list(listed) == list(MEASURES)
    assert listed["travel"]["unit"] == "m" and listed["critical"]["unit"] == "N"
    assert listed["peak-stick"]["kind"] == "distribution" and listed["peak-stick"]["drive"] == "spring"
    assert main(["measures"]) == 0
    assert "travel  " in capsys.readouterr().out


def test_an_unknown_measure_is_refused_in_one_line(capsys):
    from asperity2d.cli import main

    assert main(["compare", "--measure", "nope", "--seeds", "1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "`--measure` must be one of critical," in err[0]


def test_a_comparison_says_its_unit_and_its_verdict_in_words():
    # regular measured once (a value), random 10 seeds all 20 % below: one-sided Wilcoxon
    # p = 2**-10 < 0.01 and the change is far above 1 %: holds
    c = Comparison(values={"regular": (1.0,) * 10, "random": tuple(0.8 + 0.001 * k for k in range(10))},
                   seeds=tuple(range(10)), measure="travel_distance")
    assert c.unit == "m" and c.label == "travel under a constant force"
    record = c.verdict("random", "regular")
    assert record["verdict"] == "holds" and record["claim"] == "random lowers the travel under a constant force"
    assert record["numbers"]["p_wilcoxon"] == pytest.approx(2.0 ** -10)
    # a change under 1 %, however small p is, is no effect -- when the ratio's 98 % interval
    # (1 - 2 alpha) shows it: every seed at x0.995 puts the interval at [0.995, 0.995]
    small = Comparison(values={"regular": (1.0,) * 10, "random": (0.995,) * 10}, seeds=tuple(range(10)),
                       measure="critical")
    record = small.verdict("random", "regular")
    assert record["verdict"] == "no effect"
    assert verdict_line(record).endswith(": no effect (within +-1 %: x0.9950 [0.9950, 0.9950] 98 % interval, 10 seeds)")
    # the same mean change with a 2 % spread is not shown to be under 1 %: undecided, with the
    # seeds that would decide it (normal approximation: (z s / (m - |e|))**2 * pi / 3)
    spread = tuple(0.995 + 0.02 * x for x in (-1.5, -1, -0.6, -0.3, -0.1, 0.1, 0.3, 0.6, 1, 1.5))
    wide = Comparison(values={"regular": (1.0,) * 10, "random": spread}, seeds=tuple(range(10)), measure="critical")
    record = wide.verdict("random", "regular")
    e, s = record["numbers"]["relative_difference"], record["numbers"]["relative_std"]
    expected = math.ceil((NormalDist().inv_cdf(0.99) * s / (0.01 - abs(e))) ** 2 * math.pi / 3)
    assert record["verdict"] == "undecided" and record["numbers"]["seeds_needed"] == expected
    assert f"about {expected} seeds would decide it at this spread" in verdict_line(record)
    # "does not hold" only where the change is shown the other way: every seed 20 % above
    above = Comparison(values={"regular": (1.0,) * 10, "random": tuple(1.2 + 0.001 * k for k in range(10))},
                       seeds=tuple(range(10)), measure="critical")
    record = above.verdict("random", "regular")
    assert record["verdict"] == "does not hold" and "it goes the other way" in verdict_line(record)
    # 5 seeds cannot reach p < 0.01 one-sided (2**-5 = 0.03)
    few = Comparison(values={"regular": (1.0,) * 5, "random": (0.5,) * 5}, seeds=tuple(range(5)), measure="critical")
    assert few.verdict("random", "regular")["verdict"] == "not testable with so few seeds"
    summary, lines = c.report("regular", subject="{name} spacing")
    assert lines[1].startswith("  regular: mean 1.000 m")
    assert lines[-1].startswith("random spacing lowers the travel under a constant force: holds (")
    assert summary["claims"][0]["verdict"] == "holds"


def test_the_command_line_adds_seeds_in_stages(capsys):
    """``--seeds auto --max-seeds N``: one stage of 2 seeds here (plan(2)), the design and the
    seeds it took in the JSON; ``--max-seeds`` without ``auto`` and a word for ``--seeds`` are
    one line each."""
    import json

    from asperity2d.cli import main

    assert main(["compare", "--seeds", "auto", "--max-seeds", "2", "--set", "lower_count=4", "--set",
                 "upper_count=2", "--workers", "1", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["seeds"] == 2 and summary["design"]["stages"] == [2]
    assert summary["design"]["looks"][0]["seeds"] == [0, 1]
    assert summary["claims"][0]["verdict"] == "not testable with so few seeds"  # 2 seeds: p >= 1/4
    assert main(["compare", "--seeds", "3", "--max-seeds", "5"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "`--max-seeds` is the budget of `--seeds auto`" in err[0]
    assert main(["compare", "--seeds", "many"]) == 2
    assert "(or auto)" in capsys.readouterr().err
