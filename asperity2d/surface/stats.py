"""Statistics of a 1-D profile: rms height, rms slope, power spectrum, Hurst exponent.

Conventions (as in the rough-surface literature, e.g. Jacobs, Junge & Pastewka
2017, "Quantitative characterization of surface topography using spectral
analysis"):

* rms height h_rms = sqrt(<(z - <z>)^2>) (m), the standard Rq;
* rms slope = sqrt(<(dz/dx)^2>) with forward differences between neighbouring
  samples (dimensionless); it depends on the sampling, since finer sampling
  sees shorter, steeper wavelengths;
* power spectral density C(q) (m^3), one-sided, over the wavenumber
  q = 2 pi / wavelength (rad/m), normalised so that the integral of C over
  q > 0 is the height variance h_rms^2 (Parseval). It is estimated with
  ``scipy.signal.periodogram`` or ``scipy.signal.welch`` (linear detrend) and
  converted from cycles/m to rad/m. The default Hann window keeps the leakage
  of a measured, non-periodic trace from flattening steep spectra; Parseval
  then holds on average over realisations, not for each one (the window
  weights the middle of the trace). ``window="boxcar"`` is exact and
  leakage-free for periodic profiles such as the generated ones;
* Hurst exponent H: C(q) ~ q^-(1+2H) for a self-affine profile, fitted by
  least squares on log C against log q over a stated band
  (``scipy.stats.linregress``). Periodogram values scatter like chi^2 with
  two degrees of freedom; their logarithm's bias is the same at every q, so it
  moves the fitted prefactor but not the slope.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._inputs import check_choice, check_int, check_positive, show
from ..errors import SceneError
from .profile import SurfaceProfile

METHODS = ("periodogram", "welch")
WINDOWS = ("hann", "boxcar")


def check_profile(profile, *, spectrum: bool = False) -> SurfaceProfile:
    """``profile`` if it is a :class:`SurfaceProfile` (or, with ``spectrum``, a
    :class:`PowerSpectrum`); else SceneError naming it."""
    kinds = (SurfaceProfile, PowerSpectrum) if spectrum else (SurfaceProfile,)
    if not isinstance(profile, kinds):
        raise SceneError(f"`profile` must be a {' or '.join(k.__name__ for k in kinds)} (see "
                         f"asperity2d.surface), got {show(profile)}")
    return profile


def _finite(what: str, value: float) -> float:
    """``value``, or SceneError if the statistic overflowed (heights near the magnitude window)."""
    if not math.isfinite(value):
        raise SceneError(f"the profile's {what} overflows double precision ({value!r}); express its "
                         "heights and positions in metres nearer to 1")
    return value


def rms_height(profile: SurfaceProfile) -> float:
    """Root-mean-square height about the mean line, Rq (m).

    Parameters
    ----------
    profile : SurfaceProfile

    Returns
    -------
    float
        Rq (m).

    See Also
    --------
    asperity2d.surface.rms_slope, asperity2d.surface.power_spectrum

    Examples
    --------
    >>> import asperity2d.surface as surface
    >>> profile = surface.self_affine_profile(n=256, length=10e-6, rms_height=0.1e-6, hurst=0.8, seed=1)
    >>> f'{surface.rms_height(profile):.3g} m'
    '1e-07 m'
    """
    z = check_profile(profile).z
    z = z - z.mean()
    with np.errstate(over="ignore", invalid="ignore"):
        return _finite("rms height", math.sqrt(float(np.mean(z * z))))


def rms_slope(profile: SurfaceProfile) -> float:
    """Root-mean-square slope from forward differences (dimensionless).

    Parameters
    ----------
    profile : SurfaceProfile

    Returns
    -------
    float
        The rms slope (dimensionless).

    See Also
    --------
    asperity2d.surface.rms_height

    Examples
    --------
    >>> import asperity2d.surface as surface
    >>> profile = surface.self_affine_profile(n=256, length=10e-6, rms_height=0.1e-6, hurst=0.8, seed=1)
    >>> round(surface.rms_slope(profile), 3)
    0.269
    """
    profile = check_profile(profile)
    with np.errstate(over="ignore", invalid="ignore"):
        slope = np.diff(profile.z) / np.diff(profile.x)
        return _finite("rms slope", math.sqrt(float(np.mean(slope * slope))))


@dataclass(frozen=True, eq=False)
class PowerSpectrum:
    """One-sided PSD ``psd`` (m^3) at wavenumbers ``q`` (rad/m, q > 0), from ``method``.

    Attributes
    ----------
    q : numpy.ndarray
        Wavenumbers (rad/m).
    psd : numpy.ndarray
        One-sided power spectral density (m^3).
    method : str
        ``"periodogram"`` or ``"welch"``.

    See Also
    --------
    asperity2d.surface.power_spectrum : computes one.
    asperity2d.surface.fit_hurst : fits it.

    Examples
    --------
    >>> import asperity2d.surface as surface
    >>> profile = surface.self_affine_profile(n=256, length=10e-6, rms_height=0.1e-6, hurst=0.8, seed=1)
    >>> spectrum = surface.power_spectrum(profile)
    >>> spectrum.q.shape, spectrum.method
    ((128,), 'periodogram')
    """

    #: The family :func:`asperity2d.render` draws it as (``.png``, ``.svg``, ``.pdf``).
    kind = "spectrum"

    q: np.ndarray
    psd: np.ndarray
    method: str

    def variance(self) -> float:
        """Sum of PSD x bin width over the (uniform) q bins (m^2): the variance it accounts for.

        For a periodogram with ``window="boxcar"`` this is exactly the
        variance of the linearly detrended profile (discrete Parseval).
        """
        return float(self.psd.sum() * (self.q[1] - self.q[0])) if len(self.q) > 1 else 0.0


def power_spectrum(profile: SurfaceProfile, *, method: str = "periodogram",
                   window: str = "hann", segments: int = 8) -> PowerSpectrum:
    """Power spectral density of a uniformly sampled profile (see module notes).

    ``method="periodogram"`` uses the whole trace (finest q resolution);
    ``"welch"`` averages ``segments`` half-overlapping windowed segments
    (less scatter, coarser resolution, longest wavelength length / segments).
    ``window``: ``"hann"`` or ``"boxcar"`` (see the module notes).

    Parameters
    ----------
    profile : SurfaceProfile
        Uniformly sampled.
    method : {"periodogram", "welch"}, default "periodogram"
        Whole trace, or averaged segments.
    window : {"hann", "boxcar"}, default "hann"
        The window.
    segments : int, default 8
        Segments of a Welch estimate.

    Returns
    -------
    PowerSpectrum

    Raises
    ------
    SceneError
        A non-uniform profile or a bad parameter.

    See Also
    --------
    asperity2d.surface.fit_hurst

    Examples
    --------
    >>> import asperity2d.surface as surface
    >>> profile = surface.self_affine_profile(n=256, length=10e-6, rms_height=0.1e-6, hurst=0.8, seed=1)
    >>> spectrum = surface.power_spectrum(profile, method='welch', segments=4)
    >>> spectrum.method, len(spectrum.q) < len(profile.x) // 2
    ('welch', True)
    """
    from scipy import signal

    profile = check_profile(profile)
    check_choice("method", method, METHODS)
    check_choice("window", window, WINDOWS)
    if not profile.is_uniform:
        raise SceneError("`profile` must be uniformly sampled for a power spectrum "
                         "(resample it, e.g. with numpy.interp, first)")
    fs = 1.0 / profile.spacing  # samples per metre
    if method == "periodogram":
        f, p = signal.periodogram(profile.z, fs=fs, window=window, detrend="linear",
                                  scaling="density")
    else:
        segments = check_int("segments", segments, minimum=1)
        nperseg = profile.count // segments
        if nperseg < 16:
            raise SceneError(f"`segments` leaves {nperseg} points per segment; need >= 16")
        f, p = signal.welch(profile.z, fs=fs, window=window, nperseg=nperseg, detrend="linear",
                            scaling="density")
    keep = f > 0
    q, psd = 2.0 * math.pi * f[keep], p[keep] / (2.0 * math.pi)  # per cycle/m -> per rad/m
    if not (np.all(np.isfinite(psd)) and np.all(np.isfinite(q))):
        _finite("power spectrum", math.inf)
    q.setflags(write=False)
    psd.setflags(write=False)
    return PowerSpectrum(q=q, psd=psd, method=method)


@dataclass(frozen=True)
class HurstFit:
    """Fit C(q) = prefactor * q^slope over ``q_min`` .. ``q_max`` (rad/m).

    ``hurst`` = -(1 + slope) / 2; ``hurst_stderr`` is the regression's
    standard error of the slope divided by 2 (it ignores the correlation of
    neighbouring windowed periodogram bins, so treat it as a lower bound);
    ``points`` is the number of spectrum values in the band.

    See Also
    --------
    asperity2d.surface.fit_hurst : makes one.

    Examples
    --------
    >>> import asperity2d.surface as surface
    >>> profile = surface.self_affine_profile(n=256, length=10e-6, rms_height=0.1e-6, hurst=0.8, seed=1)
    >>> fit = surface.fit_hurst(profile)
    >>> fit.points > 10, round(-(1 + fit.slope) / 2 - fit.hurst, 12)
    (True, 0.0)
    """

    hurst: float
    hurst_stderr: float
    slope: float
    prefactor: float
    q_min: float
    q_max: float
    points: int


def fit_hurst(profile: SurfaceProfile | PowerSpectrum, *, q_min: float | None = None,
              q_max: float | None = None) -> HurstFit:
    """Hurst exponent from a log-log fit of the power spectrum over ``q_min`` .. ``q_max``.

    ``profile`` may be a :class:`SurfaceProfile` (its periodogram is used) or a
    :class:`PowerSpectrum`. Default band: wavelengths from an eighth of the
    length down to eight samples, i.e. q from 16 pi / length to pi / (4 dx) for a
    profile (from 8 x the lowest to a quarter of the highest q of a spectrum):
    it leaves out the few longest wavelengths, poorly sampled and smeared by
    the window, and the shortest, where noise and aliasing flatten real traces.

    Parameters
    ----------
    profile : SurfaceProfile or PowerSpectrum
        The surface, or its spectrum.
    q_min, q_max : float, optional
        The band fitted (rad/m); defaults above.

    Returns
    -------
    HurstFit

    Raises
    ------
    SceneError
        A band with too few points.

    See Also
    --------
    asperity2d.surface.self_affine_profile, asperity2d.surface.power_spectrum

    Examples
    --------
    >>> import asperity2d.surface as surface
    >>> profile = surface.self_affine_profile(n=4096, length=100e-6, rms_height=0.1e-6, hurst=0.8, seed=1)
    >>> fit = surface.fit_hurst(profile)
    >>> f'H = {fit.hurst:.2f} +- {fit.hurst_stderr:.2f}'
    'H = 0.75 +- 0.03'
    """
    from scipy import stats

    check_profile(profile, spectrum=True)
    spectrum = profile if isinstance(profile, PowerSpectrum) else power_spectrum(profile)
    q, psd = spectrum.q, spectrum.psd
    q_min = 8.0 * float(q[0]) if q_min is None else check_positive("q_min", q_min)
    q_max = 0.25 * float(q[-1]) if q_max is None else check_positive("q_max", q_max)
    band = (q >= q_min) & (q <= q_max) & (psd > 0)
    points = int(np.count_nonzero(band))
    if points < 3:
        raise SceneError(f"`q_min` .. `q_max` ({q_min:.6g} .. {q_max:.6g} rad/m) holds {points} "
                         f"spectrum values (spectrum spans {q[0]:.6g} .. {q[-1]:.6g} rad/m); need >= 3")
    log_q, log_c = np.log(q[band]), np.log(psd[band])
    if np.ptp(log_q) == 0 or not np.all(np.isfinite(log_c)):
        raise SceneError(f"`q_min` .. `q_max` ({q_min:.6g} .. {q_max:.6g} rad/m): the spectrum values in "
                         "the band cannot be fitted (one wavenumber, or values that under- or overflow)")
    fit = stats.linregress(log_q, log_c)
    return HurstFit(hurst=float(-(1.0 + fit.slope) / 2.0), hurst_stderr=float(fit.stderr / 2.0),
                    slope=float(fit.slope), prefactor=math.exp(fit.intercept), q_min=q_min,
                    q_max=q_max, points=points)
