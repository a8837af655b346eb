"""1-D surface profiles: the :class:`SurfaceProfile` record and seeded generators.

A profile is a height trace z(x) along one line of a surface, in metres. Two
kinds of random rough surface are generated, both reproducible from ``seed``
through ``numpy.random.default_rng``:

* **self-affine** (:func:`self_affine_profile`): the one-sided power spectral
  density is C(q) proportional to q^-(1+2H) between a long- and a
  short-wavelength cut-off, with H the Hurst exponent (0 < H <= 1); the
  height difference over a distance d then grows as d^H. Made by Fourier
  filtering of white noise (as SurfaceTopography's ``fourier_synthesis``).
* **Gaussian-correlated** (:func:`gaussian_profile`): autocorrelation
  R(d) = h_rms^2 exp(-d^2 / l^2) with correlation length l, made by
  convolving white noise with a Gaussian kernel (``scipy.ndimage``).

Both are periodic over their length (the generated trace can be tiled) and are
scaled so that their rms height equals ``rms_height`` exactly: the sample rms
of one realisation would otherwise scatter around the request.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

from .._inputs import HUGE, check_finite, check_flag, check_int, check_positive, check_real, check_text
from ..errors import SceneError

#: Relative tolerance on the sample spacing for a profile to count as uniformly sampled.
UNIFORM_TOLERANCE = 1e-3
#: The smallest sample step (m): a femtometre, far below any instrument's (and an atom's 1e-10 m);
#: steps far smaller (subnormal numbers: 1e-320) leave the levelling fit without a solution.
MIN_STEP = 1e-15
#: Most points of a generated profile (a 2**24-point trace is 128 MB of heights).
MAX_POINTS = 2**24


@dataclass(frozen=True, eq=False)
class SurfaceProfile:
    """A height trace: ``z`` (m) at positions ``x`` (m), x strictly increasing.

    ``x`` and ``z`` are stored as read-only float64 arrays; ``metadata`` (a
    read-only mapping) records where the profile came from (generator and its
    parameters, or the file, its unit and header comments). Not to be confused
    with :class:`asperity2d.geometry.Profile`, the shape of one asperity.

    Parameters
    ----------
    x, z : array_like
        Positions and heights (m), the same length; x strictly increasing.
    name : str, default ""
        A label.
    metadata : mapping, optional
        Where the profile came from.

    Raises
    ------
    SceneError
        Arrays of different lengths, non-finite values, or x not increasing.

    See Also
    --------
    asperity2d.surface.self_affine_profile : make one.
    asperity2d.surface.gaussian_profile
    asperity2d.surface.read_profile
    asperity2d.make_scene : ``lower_surface=profile`` turns its summits into asperities.

    Examples
    --------
    >>> import numpy as np
    >>> from asperity2d.surface import SurfaceProfile
    >>> x = np.linspace(0, 4e-6, 5)
    >>> profile = SurfaceProfile(x, 1e-7 * np.array([0, 2, 0, 3, 0]), name='two bumps')
    >>> profile.name, len(profile.x)
    ('two bumps', 5)
    """

    x: np.ndarray
    z: np.ndarray
    name: str = ""
    metadata: Mapping = field(default_factory=dict)

    def __post_init__(self):
        check_text("name", self.name)
        if not isinstance(self.metadata, Mapping):
            raise SceneError(f"`metadata` must be a mapping, got {type(self.metadata).__name__}")
        x, z = _vector("x", self.x), _vector("z", self.z)
        if len(x) != len(z):
            raise SceneError(f"`x` and `z` must have the same length, got {len(x)} and {len(z)}")
        if len(x) < 3:
            raise SceneError(f"a profile needs at least 3 points, got {len(x)}")
        steps = np.diff(x)
        if not np.all(steps > 0):
            i = int(np.argmax(steps <= 0))
            raise SceneError(f"`x` must be strictly increasing: x[{i + 1}] = {x[i + 1]!r} "
                             f"follows x[{i}] = {x[i]!r}")
        if np.min(steps) < MIN_STEP:
            i = int(np.argmin(steps))
            raise SceneError(f"`x` steps must be at least {MIN_STEP:g} m (positions are in m), got "
                             f"{float(steps[i])!r} between x[{i}] and x[{i + 1}]")
        object.__setattr__(self, "x", x)
        object.__setattr__(self, "z", z)
        object.__setattr__(self, "metadata", MappingProxyType(dict(self.metadata)))

    def __reduce__(self):
        # the read-only metadata mapping does not pickle; process pools (compare, sweeps) need to
        return (SurfaceProfile, (np.array(self.x), np.array(self.z), self.name, dict(self.metadata)))

    @property
    def count(self) -> int:
        """Number of points."""
        return len(self.x)

    @property
    def spacing(self) -> float:
        """Median sample spacing (m)."""
        return float(np.median(np.diff(self.x)))

    @property
    def length(self) -> float:
        """Sampled length, ``count`` x ``spacing`` (m): the period of a generated profile."""
        return self.count * self.spacing

    @property
    def is_uniform(self) -> bool:
        """True when every sample spacing is within 0.1 % of the median."""
        steps = np.diff(self.x)
        return bool(np.all(np.abs(steps - self.spacing) <= UNIFORM_TOLERANCE * self.spacing))

    def detrended(self) -> "SurfaceProfile":
        """The profile minus its least-squares straight line (form / tilt removal)."""
        try:
            slope, intercept = np.polyfit(self.x, self.z, 1)
        except (np.linalg.LinAlgError, ValueError) as exc:  # the rule on x steps should prevent it
            raise SceneError(f"profile {self.name!r} cannot be levelled (a least-squares line through "
                             f"its points has no solution: {exc}); use surface_detrend=False") from None
        return SurfaceProfile(self.x, self.z - (slope * self.x + intercept),
                              name=self.name, metadata={**self.metadata, "detrended": True})


def _vector(name: str, values) -> np.ndarray:
    try:
        arr = np.array(values, dtype=float)
    except (TypeError, ValueError):
        raise SceneError(f"`{name}` must be a sequence of numbers") from None
    if arr.ndim != 1:
        raise SceneError(f"`{name}` must be one-dimensional, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        i = int(np.argmax(~np.isfinite(arr)))
        raise SceneError(f"`{name}` must be finite, got {arr[i]!r} at index {i}")
    # the package's magnitude window: squares (rms, spectra) and products must not overflow
    big = np.abs(arr) > HUGE
    if np.any(big):
        i = int(np.argmax(big))
        raise SceneError(f"`{name}` must be within +-{HUGE:g} m, got {arr[i]!r} at index {i}")
    arr.setflags(write=False)
    return arr


def _grid(n, length) -> tuple[int, float, np.ndarray]:
    n = check_int("n", n, minimum=8, maximum=MAX_POINTS)
    length = check_real("length", length, positive=True)
    return n, length, np.arange(n) * (length / n)


def _scaled(z: np.ndarray, rms_height: float) -> np.ndarray:
    z = z - z.mean()
    spread = math.sqrt(float(np.mean(z * z)))
    if not (math.isfinite(spread) and spread > 0):  # a spectrum that under- or overflowed
        raise SceneError(f"the profile's spectrum over `length` does not fit in double precision "
                         f"(rms {spread!r} before scaling); use a `length` nearer to 1 m")
    return z * (rms_height / spread)


def self_affine_profile(*, n: int, length: float, rms_height: float, hurst: float,
                        q_min: float | None = None, q_max: float | None = None,
                        rolloff: bool = False, seed: int = 0, name: str = "") -> SurfaceProfile:
    """A periodic self-affine profile of ``n`` points over ``length`` (m).

    Parameters
    ----------
    n : int
        Number of points (the profile is periodic: point ``n`` would be point 0 again).
    length : float
        Length of the profile (m); the spacing is ``length / n``.
    rms_height : float
        Root-mean-square height (m); the result has exactly this rms.
    hurst : float
        Hurst exponent H in (0, 1]: C(q) ~ q^-(1+2H) in the self-affine band.
    q_min, q_max : float, optional
        Band of wavenumbers q = 2 pi / wavelength (rad/m) with power. Defaults:
        the longest wavelength that fits, 2 pi / length, and the Nyquist
        wavenumber pi / spacing. Outside the band C = 0, except that
        ``rolloff=True`` keeps C = C(q_min) below q_min (a roll-off plateau,
        as measured on many real surfaces).
    rolloff : bool
        Keep the power of ``q_min`` below it (see ``q_min``) instead of none.
    seed : int
        Seed of ``numpy.random.default_rng``.
    name : str
        A name the profile carries (shown in plots and records).

    Returns
    -------
    SurfaceProfile

    See Also
    --------
    asperity2d.surface.fit_hurst : measures H back.
    asperity2d.surface.gaussian_profile : another random profile.

    Examples
    --------
    >>> import asperity2d.surface as surface
    >>> profile = surface.self_affine_profile(n=4096, length=100e-6, rms_height=0.1e-6, hurst=0.8, seed=1)
    >>> f'{surface.rms_height(profile):.3g} m'
    '1e-07 m'
    >>> round(surface.fit_hurst(profile).hurst, 2)  # one realisation, a finite band: 0.75 for 0.8
    0.75
    """
    n, length, x = _grid(n, length)
    rms_height = check_real("rms_height", rms_height, positive=True)
    rolloff = check_flag("rolloff", rolloff)
    name = check_text("name", name)
    hurst = check_finite("hurst", hurst)
    if not 0.0 < hurst <= 1.0:
        raise SceneError(f"`hurst` must be in (0, 1], got {hurst!r}")
    q_lo, q_hi = 2.0 * math.pi / length, math.pi * n / length
    q_min = q_lo if q_min is None else check_positive("q_min", q_min)
    q_max = q_hi if q_max is None else check_positive("q_max", q_max)
    if q_max > q_hi * (1 + 1e-12):
        raise SceneError(f"`q_max` must be <= the Nyquist wavenumber pi n / length = {q_hi:.6g} "
                         f"rad/m, got {q_max!r}")
    q = 2.0 * math.pi * np.arange(n // 2 + 1) / length
    band = (q >= q_min * (1 - 1e-12)) & (q <= q_max * (1 + 1e-12))
    if np.count_nonzero(band) < 2:
        raise SceneError(f"`q_min` .. `q_max` ({q_min:.6g} .. {q_max:.6g} rad/m) must hold at least two "
                         f"wavenumbers 2 pi k / length (spacing {q_lo:.6g} rad/m)")
    psd = np.zeros_like(q)
    psd[band] = q[band] ** -(1.0 + 2.0 * hurst)
    if rolloff:
        psd[(q > 0) & (q < q_min)] = q_min ** -(1.0 + 2.0 * hurst)
    rng = np.random.default_rng(check_int("seed", seed, minimum=0))
    # Complex Gaussian coefficients with variance proportional to C(q): random
    # phases and Rayleigh amplitudes, i.e. a Gaussian random field.
    coeffs = (rng.standard_normal(len(q)) + 1j * rng.standard_normal(len(q))) * np.sqrt(psd)
    z = _scaled(np.fft.irfft(coeffs, n), rms_height)
    meta = {"kind": "self-affine", "hurst": hurst, "rms_height": rms_height, "q_min": q_min,
            "q_max": q_max, "rolloff": bool(rolloff), "seed": seed, "periodic": True}
    return SurfaceProfile(x, z, name=name or f"self-affine H={hurst:g}", metadata=meta)


def gaussian_profile(*, n: int, length: float, rms_height: float, correlation_length: float,
                     seed: int = 0, name: str = "") -> SurfaceProfile:
    """A periodic profile with Gaussian autocorrelation R(d) = h_rms^2 exp(-d^2 / l^2).

    ``correlation_length`` l (m) is the lag at which the autocorrelation has
    fallen to 1/e; it must span at least two samples and at most a quarter of
    ``length`` (the kernel must not wrap onto itself). White noise convolved
    with a Gaussian kernel of standard deviation l / 2 has exactly this
    autocorrelation; the result is scaled to ``rms_height`` (m).

    Parameters
    ----------
    n : int
        Number of points.
    length : float
        Length (m).
    rms_height : float
        Root-mean-square height (m).
    correlation_length : float
        Lag (m) at which the autocorrelation falls to 1/e.
    seed : int, default 0
        The same seed, the same profile.
    name : str, default ""
        A label.

    Returns
    -------
    SurfaceProfile

    Raises
    ------
    SceneError
        A bad parameter, named.

    See Also
    --------
    asperity2d.surface.self_affine_profile

    Examples
    --------
    >>> import asperity2d.surface as surface
    >>> profile = surface.gaussian_profile(n=256, length=10e-6, rms_height=0.1e-6, correlation_length=0.5e-6)
    >>> f'{surface.rms_height(profile):.3g} m'
    '1e-07 m'
    """
    from scipy.ndimage import gaussian_filter1d

    n, length, x = _grid(n, length)
    rms_height = check_real("rms_height", rms_height, positive=True)
    name = check_text("name", name)
    ell = check_positive("correlation_length", correlation_length)
    dx = length / n
    if not 2.0 * dx <= ell <= length / 4.0:
        raise SceneError(f"`correlation_length` must be between 2 samples ({2 * dx:.6g} m) and "
                         f"length / 4 ({length / 4:.6g} m), got {ell!r}")
    rng = np.random.default_rng(check_int("seed", seed, minimum=0))
    z = gaussian_filter1d(rng.standard_normal(n), sigma=0.5 * ell / dx, mode="wrap", truncate=4.0)
    meta = {"kind": "gaussian", "rms_height": rms_height, "correlation_length": ell,
            "seed": seed, "periodic": True}
    return SurfaceProfile(x, _scaled(z, rms_height), name=name or f"gaussian l={ell:g} m",
                          metadata=meta)
