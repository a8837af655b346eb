"""The closed-form checks of asperity2d.closed_forms: the model against the references of DESIGN.md
section 6 and the minimal model's closed forms.

Each check carries its own tolerance and says why it is that size (asperity2d/validation.py); the
documentation's validation page tabulates the same records, so what the page shows is what
this test accepts. About 45 s of CPU for all of them (the contact laws' flat-block checks 30 s of it).
"""

import json
import math

import pytest

from asperity2d import closed_forms


@pytest.mark.parametrize("check_id", list(closed_forms.CHECKS))
def test_closed_form_check_holds(check_id):
    check = closed_forms.CHECKS[check_id]()
    assert math.isfinite(check.expected) and math.isfinite(check.measured), check
    assert check.passed, check.line()
    assert check.tolerance < 0.05 and check.why and check.source and check.closed_form


def test_a_check_fails_when_the_model_is_off():
    """The verdict can fail: a value 3 % off a 2 % check, or NaN, is a failure."""
    good = closed_forms.CHECKS["wedge-45-0.3"]()
    off = closed_forms.Check(**{**good.__dict__, "measured": good.expected * 1.03})
    assert not off.passed and "FAIL" in off.line()
    assert not closed_forms.Check(**{**good.__dict__, "measured": math.nan}).passed


def test_pinned_closed_form_of_the_default_minimal_model():
    """Regression pin (labelled as such): the default minimal model's mu_crit."""
    from asperity2d.belt import MinimalModel

    assert MinimalModel().mu_crit == pytest.approx(0.42566217763170, rel=1e-12)


def test_command_line_prints_the_table_and_refuses_an_unknown_check(capsys):
    from asperity2d.cli import main

    assert main(["validate", "incline", "belt-force-drop"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("ok   a block moves from rest") and out[-1] == "2 of 2 checks within tolerance"
    assert main(["validate", "--json", "incline"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record["failed"] == 0 and record["checks"][0]["id"] == "incline" and record["checks"][0]["passed"]
    assert main(["validate", "no-such-check"]) == 2
    err = capsys.readouterr().err
    assert "unknown check 'no-such-check'" in err and len(err.strip().splitlines()) == 1
