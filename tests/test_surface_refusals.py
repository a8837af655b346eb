"""The rough-surface functions refuse bad input with one SceneError naming it (issue 27 items 4, 10).

They leaked TypeError / ZeroDivisionError / AttributeError from deep inside NumPy and SciPy,
accepted ``rolloff=None`` and ``name=1j``, and returned ``inf`` silently for heights of 1e200 m.
"""

import math

import numpy as np
import pytest

import asperity2d.surface as S
from asperity2d.errors import SceneError

GOOD = dict(n=256, length=1e-4, rms_height=1e-7, hurst=0.8)


@pytest.mark.parametrize("change, name", [
    ({"rolloff": None}, "`rolloff`"), ({"rolloff": 1j}, "`rolloff`"), ({"name": 1j}, "`name`"),
    ({"name": None}, "`name`"), ({"length": 1e-300}, "`length`"), ({"length": 1e300}, "`length`"),
    ({"rms_height": 1e200}, "`rms_height`"), ({"n": 2**40}, "`n`"),
])
def test_generators_name_the_bad_parameter(change, name):
    with pytest.raises(SceneError) as info:
        S.self_affine_profile(**{**GOOD, **change})
    assert name in str(info.value)


def test_gaussian_profile_names_its_bad_name():
    with pytest.raises(SceneError, match="`name`"):
        S.gaussian_profile(n=256, length=1e-4, rms_height=1e-7, correlation_length=1e-6, name=1j)


@pytest.mark.parametrize("function", [S.rms_height, S.rms_slope, S.power_spectrum, S.fit_hurst,
                                      lambda p: S.find_asperities(p, min_prominence=1e-9)])
@pytest.mark.parametrize("value", [None, 1j, "profile.csv", 3.0, [1.0, 2.0], np.zeros(5)])
def test_statistics_refuse_what_is_not_a_profile(function, value):
    with pytest.raises(SceneError, match="`profile` must be a SurfaceProfile"):
        function(value)


def test_heights_beyond_the_magnitude_window_are_refused_not_returned_as_inf():
    x = np.linspace(0.0, 1.0, 100)
    with pytest.raises(SceneError, match=r"`z` must be within \+-1e\+100 m"):
        S.SurfaceProfile(x, 1e200 * np.sin(40 * x))
    # inside the window the statistics are finite (or refused, never inf)
    p = S.SurfaceProfile(x, 1e90 * np.sin(40 * x))
    assert math.isfinite(S.rms_height(p)) and math.isfinite(S.rms_slope(p))
    assert S.rms_height(p) == pytest.approx(1e90 / math.sqrt(2), rel=0.05)


def test_a_profile_name_must_be_text():
    with pytest.raises(SceneError, match="`name` must be a string"):
        S.SurfaceProfile([0.0, 1.0, 2.0], [0.0, 1.0, 0.0], name=1j)


def test_a_legitimate_profile_still_works():
    p = S.self_affine_profile(**{**GOOD, "n": 4096}, rolloff=True, name="ok")
    assert p.name == "ok" and p.metadata["rolloff"] is True
    assert S.rms_height(p) == pytest.approx(1e-7, rel=1e-12)
    # one seed of 4096 points: the fit scatters by ~0.035 (tests/test_surface_profile.py); 0.2 is 5 sigma
    assert S.fit_hurst(p).hurst == pytest.approx(0.8, abs=0.2)
