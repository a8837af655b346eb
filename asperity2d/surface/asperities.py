"""Profile -> asperities: each summit of a profile becomes a triangular asperity.

The rule, step by step (``find_asperities``):

1. **Summits** are the peaks of z(x) found by ``scipy.signal.find_peaks`` with
   prominence >= ``min_prominence``; their width at half prominence (the
   "FWHM" that ``scipy.signal.peak_widths`` measures, interpolated between
   samples) must be >= ``min_width``.
2. **Triangle.** The apex is the summit (x_p, z_p); the height h is the
   summit's prominence (its rise above the higher of the two valleys that
   separate it from higher ground), so the base line lies at z_p - h. Each
   flank is the straight line through the apex and the point where the
   profile crosses half the prominence on that side, so the left and right
   runs (apex to foot, horizontal) are twice the distances from the apex to
   those crossings. A profile made of triangles gives them back exactly. On
   a summit with a shoulder that line can reach past the valley bottom that
   sets the prominence on its side (``find_peaks``' ``left_bases`` /
   ``right_bases``); the foot is then moved to that bottom (the flank
   steepens), so no triangle spans a valley that drops to its base line.
3. **Absorption.** Summits are taken in order of decreasing prominence; one
   whose apex lies on the base of a triangle already taken (a shoulder or a
   double summit of one asperity) is absorbed into it, not made an asperity
   of its own.
4. **No overlap.** Where the bases of two neighbours still overlap, their
   shared boundary is put at the lowest point of the profile between their
   apexes (the middle of it, if the lowest level is flat), and each triangle
   reaching past it is shrunk about its apex until its foot sits on it. A
   shrunk triangle is similar to the original: the apex (so the summit's
   elevation) and both flank angles, which set the wedge law
   tan(theta + atan mu), are kept; the height and base shrink by one factor.
5. **Stiffness and mass** per asperity: one value for all, or from the
   material (Ooten's Table 1 / Appendix A, see :func:`table1_stiffness`
   and :func:`pyramid_mass`).
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass

import numpy as np

from .._inputs import check_int, check_nonnegative, check_positive
from ..errors import SceneError
from .profile import SurfaceProfile

#: Relative slack (of the bases) allowed where two feet meet, for rounding.
FOOT_TOLERANCE = 1e-9


@dataclass(frozen=True, eq=False)
class Asperities:
    """Triangular asperities of one surface, in SI units, ordered along x.

    Arrays, one entry per asperity (read-only float64):

    * ``centers``: x of the middle of the base (m), increasing;
    * ``heights``: apex above the triangle's own base line (m);
    * ``left_runs`` / ``right_runs``: horizontal distance from the left foot to
      the apex / from the apex to the right foot (m); base = their sum, flank
      angles atan(height / run);
    * ``base_levels``: z of each base line (m) in the profile's datum
      (default 0); the summit's elevation is ``base_levels + heights``;
    * ``stiffness`` (N/m) and ``mass`` (kg) of each asperity's spring track
      (a scalar is broadcast).

    ``absorbed`` and ``trimmed`` count the summits absorbed into a neighbour
    and the triangles shrunk to remove an overlap. Bases never overlap.

    See Also
    --------
    asperity2d.surface.find_asperities : makes one from a profile.
    asperity2d.make_scene : ``lower_surface=asperities`` builds a scene on them.

    Examples
    --------
    >>> import asperity2d.surface as surface
    >>> profile = surface.self_affine_profile(n=256, length=10e-6, rms_height=0.1e-6, hurst=0.8, seed=1)
    >>> asperities = surface.find_asperities(profile, min_prominence=20e-9, stiffness=37200.0, mass=2.88e-16)
    >>> len(asperities.centers), bool((asperities.heights > 0).all())
    (10, True)
    """

    #: The family :func:`asperity2d.render` draws it as (``.png``, ``.svg``, ``.pdf``).
    kind = "asperities"

    centers: np.ndarray
    heights: np.ndarray
    left_runs: np.ndarray
    right_runs: np.ndarray
    stiffness: np.ndarray
    mass: np.ndarray
    base_levels: np.ndarray | None = None
    absorbed: int = 0
    trimmed: int = 0

    def __post_init__(self):
        centers = _array("centers", self.centers, None, positive=False)
        n = len(centers)
        if n < 1:
            raise SceneError("`centers` must hold at least one asperity")
        values = {"centers": centers}
        for name in ("heights", "left_runs", "right_runs", "stiffness", "mass"):
            values[name] = _array(name, getattr(self, name), n, positive=True,
                                  scalar=name in ("stiffness", "mass"))
        levels = np.zeros(n) if self.base_levels is None else self.base_levels
        values["base_levels"] = _array("base_levels", levels, n, positive=False, scalar=True)
        for name, value in values.items():
            value.setflags(write=False)
            object.__setattr__(self, name, value)
        check_int("absorbed", self.absorbed, minimum=0)
        check_int("trimmed", self.trimmed, minimum=0)
        bases = self.bases
        gap = self.left_feet[1:] - self.right_feet[:-1]
        slack = FOOT_TOLERANCE * (bases[1:] + bases[:-1])
        if np.any(gap < -slack):
            i = int(np.argmax(gap < -slack))
            raise SceneError(f"asperities {i} and {i + 1} overlap by {-gap[i]:.6g} m: `centers`, "
                             "`left_runs` and `right_runs` must give non-overlapping bases in x order")

    @property
    def count(self) -> int:
        return len(self.centers)

    @property
    def bases(self) -> np.ndarray:
        """Base widths (m)."""
        return self.left_runs + self.right_runs

    @property
    def apex_x(self) -> np.ndarray:
        """x of each apex (m)."""
        return self.centers - 0.5 * self.bases + self.left_runs

    @property
    def left_feet(self) -> np.ndarray:
        return self.centers - 0.5 * self.bases

    @property
    def right_feet(self) -> np.ndarray:
        return self.centers + 0.5 * self.bases

    @property
    def summits(self) -> np.ndarray:
        """Elevation of each apex in the profile's datum (m)."""
        return self.base_levels + self.heights

    @property
    def left_angles(self) -> np.ndarray:
        """Rise of the left flank from horizontal (degrees)."""
        return np.degrees(np.arctan2(self.heights, self.left_runs))

    @property
    def right_angles(self) -> np.ndarray:
        """Rise of the right flank from horizontal (degrees)."""
        return np.degrees(np.arctan2(self.heights, self.right_runs))

    def to_dict(self) -> dict:
        """Plain lists and numbers (JSON-ready)."""
        names = ("centers", "heights", "left_runs", "right_runs", "base_levels", "stiffness", "mass")
        return {**{n: getattr(self, n).tolist() for n in names},
                "absorbed": self.absorbed, "trimmed": self.trimmed}


def _array(name, value, n, *, positive, scalar=False) -> np.ndarray:
    if scalar and np.ndim(value) == 0:
        value = np.full(n, value, dtype=float) if _is_number(value) else value
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise SceneError(f"`{name}` must be a sequence of numbers, got {value!r}") from None
    if arr.ndim != 1 or (n is not None and len(arr) != n):
        raise SceneError(f"`{name}` must be one value per asperity ({n}), got shape {arr.shape}")
    bad = ~np.isfinite(arr) | ((arr <= 0) if positive else False)
    if np.any(bad):
        i = int(np.argmax(bad))
        need = "finite and > 0" if positive else "finite"
        raise SceneError(f"`{name}[{i}]` must be {need}, got {arr[i]!r}")
    return arr


def _is_number(value) -> bool:
    return isinstance(value, (int, float, np.number)) and not isinstance(value, bool)


def table1_stiffness(bases, modulus: float) -> np.ndarray:
    """Track stiffness K = 2 E b (N/m) of asperities with base ``bases`` (m), modulus E (Pa).

    Ooten's Table 1 / Appendix A treats an asperity as a column of section
    A = 4 b^2 and modulus E, K = E A / l; its 37,200 N/m for b = 1 um and
    E = 1.86e10 Pa needs l = 2 b (Ooten does not state l), hence
    K = E 4 b^2 / (2 b) = 2 E b. (Ooten's E = 1.86e10 Pa for "30e6 psi"
    steel is itself off: 30e6 psi is 2.07e11 Pa.)

    Parameters
    ----------
    bases : float or array_like
        Asperity bases b (m).
    modulus : float
        Young's modulus E (Pa).

    Returns
    -------
    numpy.ndarray
        K (N/m).

    See Also
    --------
    asperity2d.surface.pyramid_mass

    Examples
    --------
    >>> from asperity2d.surface import table1_stiffness
    >>> float(table1_stiffness(1e-6, 1.86e10))  # Ooten's 37,200 N/m
    37200.0
    """
    modulus = check_positive("modulus", modulus)
    return 2.0 * modulus * np.asarray(bases, dtype=float)


def pyramid_mass(bases, heights, density: float) -> np.ndarray:
    """Mass rho b^2 h / 3 (kg) of a square pyramid of base side b and height h (m).

    Ooten's Appendix A: "six pyramids in a cube", V = b^3 / 6, the pyramid of
    height b / 2 (a 45-degree asperity); b^2 h / 3 is the same pyramid for any
    height. (Ooten's printed V = 3.6e-17 m^3 for b = 1 um does not follow
    from its formula, which gives 1.67e-19 m^3; we use the formula.)

    Parameters
    ----------
    bases, heights : float or array_like
        Base side b and height h (m).
    density : float
        rho (kg/m^3).

    Returns
    -------
    numpy.ndarray
        Masses (kg).

    See Also
    --------
    asperity2d.surface.table1_stiffness

    Examples
    --------
    >>> from asperity2d.surface import pyramid_mass
    >>> f'{float(pyramid_mass(1e-6, 0.5e-6, 7800.0)):.3g} kg'  # a 45-degree steel asperity
    '1.3e-15 kg'
    """
    density = check_positive("density", density)
    bases = np.asarray(bases, dtype=float)
    return density * bases * bases * np.asarray(heights, dtype=float) / 3.0


def find_asperities(profile: SurfaceProfile, *, min_prominence: float, min_width: float = 0.0,
                    stiffness: float | None = None, modulus: float | None = None,
                    mass: float | None = None, density: float | None = None) -> Asperities:
    """Triangular asperities from the summits of ``profile`` (rule in the module notes).

    Parameters
    ----------
    profile : SurfaceProfile
        The surface, heights in m (read, generated or measured).
    min_prominence : float
        Smallest summit prominence kept (m); set it above the noise of a
        measured trace.
    min_width : float
        Smallest width at half prominence kept (m); a triangle's is half its base.
    stiffness, modulus : float
        Give one: a track stiffness for all asperities (N/m), or a Young's
        modulus (Pa) for :func:`table1_stiffness`.
    mass, density : float
        Give one: a mass for all asperities (kg), or a density (kg/m^3) for
        :func:`pyramid_mass`.

    Returns
    -------
    Asperities

    Raises
    ------
    SceneError
        No summit above ``min_prominence``, or a bad parameter.

    See Also
    --------
    asperity2d.make_scene : does this for ``lower_surface=profile``.
    asperity2d.surface.table1_stiffness : the rules behind ``modulus`` and ``density``.
    asperity2d.surface.pyramid_mass

    Examples
    --------
    >>> import asperity2d.surface as surface
    >>> profile = surface.self_affine_profile(n=256, length=10e-6, rms_height=0.1e-6, hurst=0.8, seed=1)
    >>> asperities = surface.find_asperities(profile, min_prominence=20e-9, modulus=1.86e10, density=7800.0)
    >>> len(asperities.centers)
    10
    >>> print(f'{asperities.stiffness.min():.3g} to {asperities.stiffness.max():.3g} N/m')
    6.07e+03 to 5.99e+04 N/m
    """
    from scipy.signal import find_peaks

    from .stats import check_profile

    check_profile(profile)
    min_prominence = check_positive("min_prominence", min_prominence)
    min_width = check_nonnegative("min_width", min_width)
    _one_of("stiffness", stiffness, "modulus", modulus)
    _one_of("mass", mass, "density", density)
    x, z = profile.x, profile.z
    peaks, props = find_peaks(z, prominence=min_prominence, width=0.0, rel_height=0.5)
    index = np.arange(len(x), dtype=float)
    half_left = np.interp(props["left_ips"], index, x)
    half_right = np.interp(props["right_ips"], index, x)
    keep = half_right - half_left >= min_width
    if not np.any(keep):
        raise SceneError(f"`min_prominence` / `min_width`: no summit of {profile.name or 'the profile'} "
                         f"has prominence >= {min_prominence:.6g} m and width >= {min_width:.6g} m "
                         f"(rms height {float(np.std(z)):.6g} m)")
    peaks = peaks[keep]
    apex = x[peaks]
    height = props["prominences"][keep]
    left = np.minimum(2.0 * (apex - half_left[keep]), apex - x[props["left_bases"][keep]])
    right = np.minimum(2.0 * (half_right[keep] - apex), x[props["right_bases"][keep]] - apex)
    taken, absorbed = _absorb(apex, left, right, height)
    peaks, apex, height, left, right = (a[taken] for a in (peaks, apex, height, left, right))
    scale = _shared_boundaries(x, z, peaks, apex, left, right)
    trimmed = int(np.count_nonzero(scale < 1.0))
    height, left, right = height * scale, left * scale, right * scale
    bases = left + right
    return Asperities(
        centers=apex - left + 0.5 * bases, heights=height, left_runs=left, right_runs=right,
        base_levels=z[peaks] - height,
        stiffness=table1_stiffness(bases, modulus) if stiffness is None else check_positive("stiffness", stiffness),
        mass=pyramid_mass(bases, height, density) if mass is None else check_positive("mass", mass),
        absorbed=absorbed, trimmed=trimmed)


def _one_of(name_a, a, name_b, b):
    if (a is None) == (b is None):
        raise SceneError(f"give exactly one of `{name_a}` and `{name_b}`, got "
                         f"{name_a}={a!r}, {name_b}={b!r}")


def _absorb(apex, left, right, height) -> tuple[np.ndarray, int]:
    """Indices (in x order) of the summits kept by step 3, and how many were absorbed."""
    ax, lf, rf = apex.tolist(), (apex - left).tolist(), (apex + right).tolist()
    taken_x, taken = [], []
    absorbed = 0
    for j in np.lexsort((apex, -height)).tolist():  # most prominent first, ties left to right
        pos = bisect.bisect_left(taken_x, ax[j])
        before = taken[pos - 1] if pos > 0 else None
        after = taken[pos] if pos < len(taken) else None
        # Only the nearest taken neighbours can cover this apex (a taken base
        # holds no other taken apex), or be covered by this base.
        if ((before is not None and (ax[j] < rf[before] or lf[j] < ax[before]))
                or (after is not None and (ax[j] > lf[after] or rf[j] > ax[after]))):
            absorbed += 1
            continue
        taken_x.insert(pos, ax[j])
        taken.insert(pos, j)
    return np.asarray(taken, dtype=int), absorbed


def _shared_boundaries(x, z, peaks, apex, left, right) -> np.ndarray:
    """Step 4: the factor (<= 1) by which each triangle is shrunk about its apex."""
    scale = np.ones(len(peaks))
    slack = FOOT_TOLERANCE * (left + right)
    overlap = (apex[:-1] + right[:-1]) - (apex[1:] - left[1:]) > slack[:-1] + slack[1:]
    for i in np.flatnonzero(overlap).tolist():
        a, b = int(peaks[i]), int(peaks[i + 1])
        valley = z[a:b + 1]
        lowest = np.flatnonzero(valley == valley.min())
        boundary = 0.5 * (x[a + lowest[0]] + x[a + lowest[-1]])
        scale[i] = min(scale[i], (boundary - apex[i]) / right[i])
        scale[i + 1] = min(scale[i + 1], (apex[i + 1] - boundary) / left[i + 1])
    return np.minimum(scale, 1.0)
