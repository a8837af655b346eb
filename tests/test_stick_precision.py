"""docs/data/stick_precision.py: the seeds a 5 % difference needs under the verdict rule, and the
step bias the findings page renders from docs/data/measures/stick_bias.json."""

import importlib.util
import json
import math
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
_spec = importlib.util.spec_from_file_location("stick_precision", ROOT / "docs" / "data" / "stick_precision.py")
sp = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(sp)


def test_signed_rank_p_is_scipys_exact_one_sided_p():
    from scipy.stats import wilcoxon

    x = np.random.default_rng(3).normal(-0.3, 1.0, size=(5, 12))
    expected = [wilcoxon(row, alternative="less", method="exact").pvalue for row in x]
    assert np.allclose(sp._signed_rank_p_less(x), expected, rtol=1e-12)


@pytest.mark.parametrize("sd", [0.10, 0.15])
def test_seeds_needed_is_the_normal_theory_number_on_normal_values(sd):
    """On normal per-seed values the Wilcoxon test's sample size is the t-test's divided by its
    asymptotic relative efficiency 3/pi: n = ((z_0.99 + z_0.8) sd / 0.05)^2 / (3 / pi), 42 at
    sd 10 % and 95 at 15 % (at 5 %, 10.5, the exact small-sample distribution adds a quarter:
    measured 13, so the check stays where the asymptotics hold). The bootstrap's power has a
    sampling error of about 1 % (2000 draws), a few percent in n: 15 %."""
    values = 1.0 + sd * np.random.default_rng(7).standard_normal(20000)
    theory = ((2.3263 + 0.8416) * sd / 0.05) ** 2 / (3 / math.pi)
    assert sp.seeds_needed(values) == pytest.approx(theory, rel=0.15)


def test_the_rule_needs_seven_seeds_at_least():
    """2**-6 > 0.01: with 6 seeds even all below cannot reach p < 0.01; a spread-free measure
    needs exactly 7."""
    assert sp.seeds_needed(np.full(10, 1.0) + 1e-6 * np.arange(10)) == 7


def test_summary_reads_the_shift_of_each_seed(tmp_path):
    """Two seeds whose 5-pass means rise by exactly 10 % and 20 % from dt to dt/2 and stay: the
    mean shift 15 %, one standard error 5 %; none from dt/2 to dt/4."""
    data = {}
    for seed, rise in ((1, 1.1), (2, 1.2)):
        for factor, scale in (("1.0", 1.0), ("0.5", rise), ("0.25", rise)):
            forces = [scale * f for f in (1.0, 2.0, 3.0)]
            data[f"fixed/{seed}/{factor}"] = {"first_breakaway": forces, "peak": forces, "mean": forces,
                                              "cpu_s": 1.0}
    path = tmp_path / "bias.json"
    path.write_text(json.dumps(data))
    result = sp.summary(path)
    assert result["seeds"] == [1, 2] and result["passes"] == 3
    shift = result["measures"]["peak"]["1.0->0.5"]
    assert shift["mean"] == pytest.approx(0.15) and shift["se"] == pytest.approx(0.05)
    assert result["measures"]["peak"]["0.5->0.25"]["mean"] == pytest.approx(0.0, abs=1e-15)
    # one pass's spread about its seed's mean: (-1/2, 0, +1/2) on 2 seeds, 4 degrees of freedom
    assert result["measures"]["mean"]["per_pass_sd"] == pytest.approx(math.sqrt(4 * 0.25 / 4))


def test_seeds_are_written_as_runs():
    assert sp.seeds_text([7601, 7602, 7603, 9401, 9403, 9404]) == "7601–7603, 9401, 9403–9404 (6 seeds)"
    assert sp.seed_range("9401-9424") == (9401, 9424) and sp.seed_range("") is None
