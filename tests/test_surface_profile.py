"""Surface profiles: generators against their closed forms, statistics, and the readers."""

import math
from pathlib import Path

import numpy as np
import pytest

from asperity2d import SceneError
from asperity2d.surface import (SurfaceProfile, fit_hurst, gaussian_profile, power_spectrum,
                                read_profile, rms_height, rms_slope, self_affine_profile)

DATA = Path(__file__).resolve().parent.parent / "scenes" / "data"


@pytest.mark.parametrize("hurst", [0.3, 0.5, 0.8])
def test_self_affine_fitted_hurst_matches_the_request(hurst):
    """Mean fitted H over 4 seeds within 0.1 of the request (issue 14 item 6).

    The fit is over the generator's whole band except the 8 longest and the
    shortest 3/4 of wavelengths (the default band, ~500 periodogram values);
    measured per-seed scatter 0.035 (6 seeds, this n), so the 4-seed mean
    scatters by ~0.02 and 0.1 is a 5-sigma bound. Measured: within 0.01.
    """
    fits = [fit_hurst(self_affine_profile(n=4096, length=4.096e-3, rms_height=1e-6, hurst=hurst,
                                          seed=seed)).hurst for seed in range(4)]
    assert np.mean(fits) == pytest.approx(hurst, abs=0.1)


def test_hurst_fit_within_a_band_limited_generator():
    """H fitted over a stated band inside the generator's cut-offs; outside it C = 0."""
    q_min, q_max = 2 * math.pi / 256e-6, 2 * math.pi / 8e-6
    profile = self_affine_profile(n=4096, length=4.096e-3, rms_height=1e-6, hurst=0.6, seed=3,
                                  q_min=q_min, q_max=q_max)
    fits = [fit_hurst(self_affine_profile(n=4096, length=4.096e-3, rms_height=1e-6, hurst=0.6,
                                          seed=s, q_min=q_min, q_max=q_max),
                      q_min=2 * q_min, q_max=q_max).hurst for s in range(4)]
    assert np.mean(fits) == pytest.approx(0.6, abs=0.1)
    # The generated profile has no Fourier component outside the band (rounding aside).
    amplitude = np.abs(np.fft.rfft(profile.z))
    q = 2 * math.pi * np.arange(len(amplitude)) / profile.length
    outside = (q < 0.99 * q_min) | (q > 1.01 * q_max)
    assert amplitude[outside].max() < 1e-12 * amplitude.max()


@pytest.mark.parametrize("make", [
    lambda s: self_affine_profile(n=1000, length=1e-4, rms_height=2.5e-7, hurst=0.7, seed=s),
    lambda s: self_affine_profile(n=1001, length=1e-4, rms_height=2.5e-7, hurst=0.3, seed=s,
                                  q_min=2 * math.pi / 2e-5, rolloff=True),
    lambda s: gaussian_profile(n=1000, length=1e-4, rms_height=2.5e-7, correlation_length=2e-6,
                               seed=s),
])
def test_generated_rms_height_equals_the_request_and_seeds_reproduce(make):
    profile = make(5)
    assert rms_height(profile) == pytest.approx(2.5e-7, rel=1e-12)
    assert abs(profile.z.mean()) < 1e-12 * 2.5e-7 * profile.count
    np.testing.assert_array_equal(make(5).z, profile.z)
    assert not np.array_equal(make(6).z, profile.z)
    assert profile.is_uniform and profile.count in (1000, 1001)


def test_gaussian_profile_autocorrelation_is_one_over_e_at_the_correlation_length():
    """R(l) / R(0) = exp(-1) for R(d) = exp(-d^2 / l^2); 4 seeds of 2^16 points, l = 20 samples.

    The ACF estimate at lag l scatters by ~sqrt(l / N) ~ 0.02 per seed (measured
    0.025), 0.012 for the 4-seed mean; tolerance 0.04.
    """
    from scipy import signal

    ratios = []
    for seed in range(4):
        g = gaussian_profile(n=2**16, length=2**16 * 1e-8, rms_height=1e-7,
                             correlation_length=20e-8, seed=seed)
        acf = signal.correlate(g.z, g.z, mode="full", method="fft")[g.count - 1:]
        ratios.append(acf[20] / acf[0])
    assert np.mean(ratios) == pytest.approx(math.exp(-1), abs=0.04)


def test_parseval_holds_exactly_for_the_boxcar_periodogram():
    profile = self_affine_profile(n=2048, length=1e-3, rms_height=1e-6, hurst=0.5, seed=2)
    flat = profile.detrended()
    variance = float(np.mean((flat.z - flat.z.mean()) ** 2))
    assert power_spectrum(profile, window="boxcar").variance() == pytest.approx(variance, rel=1e-10)
    welch = power_spectrum(profile, method="welch", segments=4)
    assert welch.q[0] == pytest.approx(4 * 2 * math.pi / profile.length, rel=1e-9)


def test_rms_slope_of_a_sawtooth_is_its_slope():
    x = np.arange(0, 40) * 0.25e-6
    z = 0.3 * np.abs((x % 2e-6) - 1e-6)  # slope +-0.3, kinks on samples
    assert rms_slope(SurfaceProfile(x, z)) == pytest.approx(0.3, rel=1e-12)


@pytest.mark.parametrize("call, name", [
    (lambda: self_affine_profile(n=64, length=1e-5, rms_height=1e-7, hurst=1.2), "`hurst`"),
    (lambda: self_affine_profile(n=64, length=1e-5, rms_height=-1.0, hurst=0.5), "`rms_height`"),
    (lambda: self_affine_profile(n=64, length=1e-5, rms_height=1e-7, hurst=0.5, q_max=1e9), "`q_max`"),
    (lambda: self_affine_profile(n=64, length=1e-5, rms_height=1e-7, hurst=0.5, q_min=3e6,
                                 q_max=3.1e6), "`q_min`"),
    (lambda: self_affine_profile(n=4, length=1e-5, rms_height=1e-7, hurst=0.5), "`n`"),
    (lambda: gaussian_profile(n=64, length=1e-5, rms_height=1e-7, correlation_length=1e-7),
     "`correlation_length`"),
    (lambda: SurfaceProfile([0.0, 2.0, 1.0], [0.0, 0.0, 0.0]), "`x`"),
    (lambda: SurfaceProfile([0.0, 1.0, 2.0], [0.0, float("nan"), 0.0]), "`z`"),
    (lambda: SurfaceProfile([0.0, 1.0, 2.0], [0.0, 1.0]), "`x` and `z`"),
    (lambda: power_spectrum(SurfaceProfile([0.0, 1.0, 3.0, 4.0], [0, 1, 0, 1])), "`profile`"),
    (lambda: fit_hurst(self_affine_profile(n=64, length=1e-5, rms_height=1e-7, hurst=0.5),
                       q_min=1e9, q_max=2e9), "`q_min`"),
])
def test_bad_profile_input_is_one_scene_error_naming_the_parameter(call, name):
    with pytest.raises(SceneError, match=name):
        call()


def test_profile_arrays_are_read_only_copies():
    x, z = np.arange(5.0), np.zeros(5)
    profile = SurfaceProfile(x, z, metadata={"a": 1})
    x[0] = -1.0
    assert profile.x[0] == 0.0
    with pytest.raises(ValueError):
        profile.z[0] = 1.0
    with pytest.raises(TypeError):
        profile.metadata["a"] = 2


# -- reading ---------------------------------------------------------------------------

def test_text_reader_handles_comments_header_separators_and_units(tmp_path):
    path = tmp_path / "trace.csv"
    path.write_text("# instrument: stylus\n# unit: um\n\nx (um);z (um)\n"
                    "0.0;0.5\n0.5, -0.25\n1.0\t0.125\n  1.5   0.0  \n% trailing comment\n")
    profile = read_profile(path, unit="um")
    np.testing.assert_allclose(profile.x, [0.0, 0.5e-6, 1.0e-6, 1.5e-6], rtol=1e-15)
    np.testing.assert_allclose(profile.z, [0.5e-6, -0.25e-6, 0.125e-6, 0.0], rtol=1e-15)
    assert profile.name == "trace.csv" and profile.metadata["unit"] == "um"
    assert "# instrument: stylus" in profile.metadata["comments"]
    nm = tmp_path / "trace.txt"
    nm.write_text("0 1\n1 2\n2 3\n")
    assert read_profile(nm, unit="nm").z[2] == pytest.approx(3e-9, rel=1e-15)


@pytest.mark.parametrize("body, kwargs, message", [
    ("0,0\n1,1\nabc,2\n3,3\n", {}, r"trace.csv line 3: .*'abc,2'"),
    ("0,0\n1,1\n2,2,2\n3,3\n", {}, r"trace.csv line 3"),
    ("0,0\n\n1\n2,2\n3,3\n", {}, r"trace.csv line 3"),
    ("0,0\n1,nan\n2,2\n", {}, r"trace.csv line 2"),
    ("# c\n0,0\n2,1\n1,2\n3,3\n", {}, r"trace.csv line 4: x must increase"),
    ("# unit: mm\n0,0\n1,1\n2,2\n", {}, r"`unit` is 'um' but trace.csv line 1 says 'mm'"),
    ("x,z\n0,0\n1,1\n", {}, r"holds 2 data lines"),
    ("0,0\n1,1\n2,2\n", {"unit": "inch"}, r"`unit` must be one of"),
    ("0,0\n1,1\n2,2\n", {"unit": None}, r"`unit` is required"),
])
def test_text_reader_errors_name_the_file_and_line(tmp_path, body, kwargs, message):
    path = tmp_path / "trace.csv"
    path.write_text(body)
    with pytest.raises(SceneError, match=message):
        read_profile(path, **{"unit": "um", **kwargs})


def test_missing_file_and_unknown_format_are_scene_errors(tmp_path):
    with pytest.raises(SceneError, match="`path` is not a file"):
        read_profile(tmp_path / "nope.csv", unit="um")
    other = tmp_path / "scan.x3p"
    other.write_bytes(b"not a real file")
    try:
        import SurfaceTopography  # noqa: F401
    except ImportError:
        with pytest.raises(SceneError, match=r"asperity2d\[profiles\]"):
            read_profile(other)
    else:
        with pytest.raises(SceneError, match="`path` scan.x3p|`unit`"):
            read_profile(other)


def test_instrument_reader_through_surfacetopography(tmp_path):
    """Optional extra: a netCDF line scan and one line of a 2-D map come back in metres."""
    st = pytest.importorskip("SurfaceTopography")
    z = np.sin(np.linspace(0, 6, 64))
    st.UniformLineScan(z, physical_sizes=8.0, unit="um").to_netcdf(str(tmp_path / "line.nc"))
    profile = read_profile(tmp_path / "line.nc")
    np.testing.assert_allclose(profile.z, z * 1e-6, rtol=1e-12)
    assert profile.spacing == pytest.approx(8e-6 / 64, rel=1e-12)
    heights = np.arange(48.0).reshape(8, 6)
    st.Topography(heights, physical_sizes=(4.0, 3.0), unit="nm").to_netcdf(str(tmp_path / "map.nc"))
    with pytest.raises(SceneError, match="`line` is required"):
        read_profile(tmp_path / "map.nc")
    np.testing.assert_allclose(read_profile(tmp_path / "map.nc", line=2).z, heights[:, 2] * 1e-9)


def test_shipped_profile_is_what_its_recipe_makes():
    """scenes/data/measured_style_profile.csv: the recipe regenerates it (to the written digits)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("make_measured_profile",
                                                  DATA / "make_measured_profile.py")
    recipe = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(recipe)
    shipped = read_profile(DATA / "measured_style_profile.csv", unit="um")
    x, z = recipe.make()
    assert shipped.count == 4096 and shipped.is_uniform
    np.testing.assert_allclose(shipped.x, x, rtol=0, atol=0.6e-12)  # written to 1 pm
    np.testing.assert_allclose(shipped.z, z, rtol=0, atol=0.6e-10)  # quantised to 0.1 nm
    assert "SYNTHETIC" in shipped.metadata["comments"][0]
    # Its statistics are the recipe's: rms 0.15 um (plus 2 nm noise in quadrature,
    # minus what the detrend removes: within 1 %), H = 0.8 within 0.1.
    flat = shipped.detrended()
    assert rms_height(flat) == pytest.approx(0.15e-6, rel=0.01)
    fit = fit_hurst(flat, q_min=2 * math.pi / 6.25e-6, q_max=2 * math.pi / 0.2e-6)
    assert fit.hurst == pytest.approx(0.8, abs=0.1)
