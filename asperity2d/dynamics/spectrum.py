"""Power spectra: dominant frequency, distinct peaks, harmonics and their distortion.

:func:`spectrum` resamples a series to a uniform grid (:func:`.signals.resample`)
and estimates its one-sided power spectral density with
``scipy.signal.welch`` (averaged Hann segments, the default) or
``scipy.signal.periodogram`` (one Hann window over the whole run: finest
resolution, no averaging). The PSD is in (unit of y)²/Hz.

* the **dominant frequency** is the largest PSD bin above 0 Hz, refined by a
  parabola through the logarithm of the three bins around it (a Hann peak is
  close to a Gaussian there, so the refinement is good to a small fraction of
  a bin);
* **band power** of a peak sums the PSD over ±2 bins around it (the Hann
  main lobe is 4 bins wide) times the bin width: the mean square of that
  spectral line, (unit)²;
* **harmonics** are the band powers of the largest bins within ±max(1 bin,
  0.5 % of k·f0) of k·f0, k = 1..n (narrow, so a nearby incommensurate line
  is not taken for a harmonic); ``thd`` = sqrt(Σ_{k≥2} P_k / P_1) is the
  total harmonic distortion (0 for a sine; about 0.8 for an ideal sawtooth,
  whose P_k fall as 1/k²).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SceneError
from .signals import check_series, resample

METHODS = ("welch", "periodogram")
_LOBE = 2  # bins each side of a Hann peak counted in its band power


@dataclass(frozen=True)
class Peak:
    """A spectral line: ``frequency`` (Hz) and ``power`` (band power, (unit)²).

    See Also
    --------
    asperity2d.dynamics.spectrum : ``Spectrum.peaks`` lists them.

    Examples
    --------
    >>> from asperity2d import belt, dynamics
    >>> chain = dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...             v_belt=0.1, x0=[0.0], v0=[0.1], t_end=20.0)
    >>> result = belt.simulate_chain(**chain)  # one mass, stick-slip on the belt
    >>> t, v = dynamics.signal(result, 'v')
    >>> peak = dynamics.spectrum(t, v).peaks[0]
    >>> round(peak.frequency, 2)  # Hz: the stick-slip frequency, 1 / 0.669 s
    1.49
    """

    frequency: float
    power: float


@dataclass(frozen=True)
class Spectrum:
    """One-sided PSD of a series and what stands out in it (see the module docstring).

    Attributes: ``frequency`` (Hz), ``power`` (PSD, (unit)²/Hz), ``resolution``
    (bin width, Hz), ``dominant`` (Hz), ``peaks`` (distinct lines, strongest
    first), ``harmonics`` (k = 1.. of ``dominant``; NaN power beyond Nyquist),
    ``thd``, ``method``, ``sample_rate`` (Hz).

    See Also
    --------
    asperity2d.dynamics.spectrum : computes one.

    Examples
    --------
    >>> from asperity2d import belt, dynamics
    >>> chain = dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...             v_belt=0.1, x0=[0.0], v0=[0.1], t_end=20.0)
    >>> result = belt.simulate_chain(**chain)  # one mass, stick-slip on the belt
    >>> t, v = dynamics.signal(result, 'v')
    >>> s = dynamics.spectrum(t, v)
    >>> print(f'dominant {s.dominant:.3f} Hz, bins {s.resolution:.2f} Hz wide, THD {s.thd:.2f}')
    dominant 1.495 Hz, bins 0.20 Hz wide, THD 0.16
    """

    frequency: np.ndarray
    power: np.ndarray
    resolution: float
    dominant: float
    peaks: tuple
    harmonics: tuple
    thd: float
    method: str
    sample_rate: float

    def to_dict(self) -> dict:
        """JSON-able summary (without the PSD arrays)."""
        return {
            "method": self.method, "resolution_hz": self.resolution, "sample_rate_hz": self.sample_rate,
            "dominant_hz": self.dominant, "thd": self.thd,
            "peaks": [{"frequency_hz": p.frequency, "power": p.power} for p in self.peaks],
            "harmonics": [{"k": k + 1, "frequency_hz": p.frequency, "power": p.power}
                          for k, p in enumerate(self.harmonics)],
        }


def spectrum(t, y, *, method: str = "welch", segment: float | None = None, dt: float | None = None,
             detrend: str = "linear", n_harmonics: int = 8, n_peaks: int = 6) -> Spectrum:
    """Power spectrum of ``y(t)`` (SI): see the module docstring.

    Parameters
    ----------
    t : array_like
        Sample times (s), increasing; resampled to a uniform step.
    y : array_like
        The signal at ``t`` (any SI unit; the power is in its unit squared per Hz).
    method : str
        ``"welch"`` (averaged segments) or ``"periodogram"`` (one segment: the whole run).
    segment : float, optional
        Welch's segment length (s; default: a quarter of the run, giving 7 half-overlapping
        averages, but at least 16 samples); the bin width is 1/segment.
    dt : float, optional
        The resampling step (s; default: the median sample spacing).
    detrend : str
        ``"linear"``, ``"constant"`` or ``"none"``, applied per segment; the linear default keeps a
        drifting position (an asperity slider's x) from flooding the low bins.
    n_harmonics : int
        Harmonics of the dominant frequency measured (for the distortion ``thd``).
    n_peaks : int
        Largest peaks listed.

    Returns
    -------
    Spectrum

    See Also
    --------
    asperity2d.dynamics.Spectrum, asperity2d.dynamics.Peak
    asperity2d.surface.power_spectrum : of a surface profile.

    Examples
    --------
    >>> from asperity2d import belt, dynamics
    >>> chain = dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...             v_belt=0.1, x0=[0.0], v0=[0.1], t_end=20.0)
    >>> result = belt.simulate_chain(**chain)  # one mass, stick-slip on the belt
    >>> t, v = dynamics.signal(result, 'v')
    >>> s = dynamics.spectrum(t, v)
    >>> round(s.dominant, 2), round(1 / dynamics.chain_cycle(result).period, 2)  # Hz; within a bin (0.2 Hz)
    (1.49, 1.49)
    """
    from scipy import signal as sps

    t, y = check_series(t, y)
    if method not in METHODS:
        raise SceneError(f"`method` must be one of {', '.join(METHODS)}, got {method!r}")
    if detrend not in ("linear", "constant", "none"):
        raise SceneError(f"`detrend` must be 'linear', 'constant' or 'none', got {detrend!r}")
    for name, val in (("n_harmonics", n_harmonics), ("n_peaks", n_peaks)):
        if isinstance(val, bool) or not isinstance(val, (int, np.integer)) or val < 1:
            raise SceneError(f"`{name}` must be an integer >= 1, got {val!r}")
    tu, yu = resample(t, y, dt=dt)
    if tu.size < 16:
        raise SceneError(f"`y` spans only {tu.size} samples at the resampling step; need at least 16")
    fs = 1.0 / (tu[1] - tu[0])
    trend = False if detrend == "none" else detrend
    if method == "welch":
        # default: quarters of the run, but never under 16 samples (a short run: one segment)
        nperseg = min(tu.size, max(16, tu.size // 4)) if segment is None else int(round(segment * fs))
        if not 16 <= nperseg <= tu.size:
            raise SceneError(f"`segment` must span 16 samples to the whole run ({tu[-1] - tu[0]:.6g} s), "
                             f"got {segment!r}")
        f, p = sps.welch(yu, fs=fs, window="hann", nperseg=nperseg, detrend=trend)
    else:
        f, p = sps.periodogram(yu, fs=fs, window="hann", detrend=trend)
    df = float(f[1] - f[0])
    dominant = _refine(f, p, 1 + int(np.argmax(p[1:])))
    harmonics = tuple(_harmonic(f, p, k * dominant, df) for k in range(1, n_harmonics + 1))
    fundamental = harmonics[0].power
    upper = sum(h.power for h in harmonics[1:] if np.isfinite(h.power))
    thd = float(np.sqrt(upper / fundamental)) if fundamental > 0 else float("nan")
    return Spectrum(frequency=f, power=p, resolution=df, dominant=dominant, peaks=_peaks(f, p, df, n_peaks),
                    harmonics=harmonics, thd=thd, method=method, sample_rate=fs)


def _refine(f, p, k) -> float:
    """Vertex of the parabola through log p at bins k-1, k, k+1 (the bin itself at an edge)."""
    if k <= 0 or k >= p.size - 1 or np.any(p[k - 1:k + 2] <= 0):
        return float(f[k])
    a, b, c = np.log(p[k - 1:k + 2])
    denom = a - 2 * b + c
    shift = 0.5 * (a - c) / denom if denom < 0 else 0.0
    return float(f[k] + np.clip(shift, -0.5, 0.5) * (f[1] - f[0]))


def _band(f, p, k, df) -> float:
    lo, hi = max(k - _LOBE, 1), min(k + _LOBE + 1, p.size)
    return float(p[lo:hi].sum() * df)


def _harmonic(f, p, target, df) -> Peak:
    if target > f[-1]:
        return Peak(float(target), float("nan"))
    half = max(df, 0.005 * target)  # the refined f0 puts k·f0 within a bin; wider windows catch other lines
    window = np.flatnonzero((f >= target - half) & (f <= target + half) & (f > 0))
    if window.size == 0:
        return Peak(float(target), 0.0)
    k = int(window[np.argmax(p[window])])
    return Peak(_refine(f, p, k), _band(f, p, k, df))


def _peaks(f, p, df, count) -> tuple:
    """The ``count`` strongest local maxima (band power), at least a main lobe apart."""
    from scipy.signal import find_peaks

    idx, _ = find_peaks(p, distance=2 * _LOBE + 1)
    idx = idx[idx > 0]
    if idx.size == 0:
        return ()
    bands = np.array([_band(f, p, k, df) for k in idx])
    order = np.argsort(bands)[::-1][:count]
    return tuple(Peak(_refine(f, p, int(idx[i])), float(bands[i])) for i in order)
