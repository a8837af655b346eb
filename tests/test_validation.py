"""The closed-form checks of asperity2d.validation: the model against the references of DESIGN.md
section 6 and the minimal model's closed forms.

Each check carries its own tolerance and says why it is that size (asperity2d/validation.py); the
documentation's validation page tabulates the same records, so what the page shows is what
this test accepts. About 12 s of CPU for all of them.
"""

import math

import pytest

from asperity2d import validation


@pytest.mark.parametrize("check_id", list(validation.CHECKS))
def test_closed_form_check_holds(check_id):
    check = validation.CHECKS[check_id]()
    assert math.isfinite(check.expected) and math.isfinite(check.measured), check
    assert check.passed, check.line()
    assert check.tolerance < 0.05 and check.why and check.source and check.closed_form


def test_a_check_fails_when_the_model_is_off():
    """The verdict can fail: a value 3 % off a 2 % check, or NaN, is a failure."""
    good = validation.CHECKS["wedge-45-0.3"]()
    off = validation.Check(**{**good.__dict__, "measured": good.expected * 1.03})
    assert not off.passed and "FAIL" in off.line()
    assert not validation.Check(**{**good.__dict__, "measured": math.nan}).passed


def test_pinned_closed_form_of_the_default_minimal_model():
    """Regression pin (labelled as such): the default minimal model's mu_crit."""
    from asperity2d.belt import MinimalModel

    assert MinimalModel().mu_crit == pytest.approx(0.42566217763170, rel=1e-12)


def test_command_line_prints_the_table_and_refuses_an_unknown_check(capsys):
    assert validation.main(["incline", "belt-force-drop"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("ok   a block moves from rest") and out[-1] == "2 of 2 checks within tolerance"
    with pytest.raises(SystemExit) as info:
        validation.main(["no-such-check"])
    assert info.value.code == 2
    assert "unknown check 'no-such-check'" in capsys.readouterr().err
