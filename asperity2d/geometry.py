"""Asperity profiles and surface spacings (pure, seeded, SI units).

Conventions (Ooten's thesis, figures 5-9): the lower surface lies on y = 0 with its
asperities pointing up; the slider's asperities hang below its underside and
point down; the slider moves towards +x. A spacing gives the x of every
asperity's *tip* (apex); an asperity's shape is its height and the horizontal
runs of its two flanks from the tip: ``left`` (towards -x) and ``right``.

* ``full`` triangle: isosceles, left = right = base / 2.
* ``half`` triangle (Ooten's figure 9): a right triangle with one vertical
  face through the tip. The lower one rises towards the oncoming slider
  (sloped flank on the -x side, vertical face at +x); the upper one is its
  mirror image (sloped flank leading on the +x side, vertical face at its
  back). Once an upper tip passes a lower tip, the lower peak springs back up
  behind the upper vertical face and cannot push the slider on.
  :func:`half_of` cuts a full triangle through its apex as Ooten's figure 9 draws it:
  same height, same flank, half the base.
* ``flat``: a rectangle (a flat block or surface, for Coulomb checks) whose
  contact-face edges are rounded off (:data:`FLAT_EDGE`); its "tip" is the
  middle of its top face.

A :class:`Profile` gives every asperity of a surface one shape. :class:`Shapes`
overrides it per asperity (a rough surface: random heights, or the summits of
a measured profile): each asperity's own height, flank runs and base level.
:class:`ExplicitSpacing` places tips at given positions (a profile's summits).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._inputs import (MAX_COUNT, check_choice, check_finite, check_int, check_nonnegative,
                        check_positive, show)
from .errors import SceneError

KINDS = ("full", "half", "flat")
#: A flat block's contact-face edges, from the face outwards: (run as a fraction of the width,
#: slope) of each segment -- 1:10 over 10 % of the width, then 45 deg over 5 % (1 % and 5 % of
#: the width deep; scaled down on a slab thinner than twice that).
FLAT_EDGE = ((0.10, 0.1), (0.05, 1.0))


@dataclass(frozen=True)
class Profile:
    """Shape of one asperity.

    Parameters
    ----------
    kind : {"full", "half", "flat"}
    base : float
        Width of the asperity's base (m): a half triangle's own base, the
        run of its one sloped flank.
    height : float
        Height from base to tip (m). See :meth:`from_angle` to give the flank
        angle instead (angle and height are separate parameters: Ooten's
        1.5 µm tip on a 1 µm base is inconsistent with 45° flanks).

    Raises
    ------
    SceneError
        An unknown ``kind``, or a ``base`` or ``height`` that is not > 0.

    See Also
    --------
    asperity2d.make_scene : ``profile=``, ``base=``, ``flank_angle=`` build it for you.

    Examples
    --------
    >>> from asperity2d import Profile
    >>> Profile.from_angle("full", base=1e-6, flank_angle=45)
    Profile(kind='full', base=1e-06, height=4.999999999999999e-07)
    """

    kind: str = "full"
    base: float = 1e-6
    height: float = 0.5e-6

    def __post_init__(self):
        check_choice("kind", self.kind, KINDS)
        object.__setattr__(self, "base", check_positive("base", self.base))
        object.__setattr__(self, "height", check_positive("height", self.height))

    @classmethod
    def from_angle(cls, kind: str = "full", *, base: float = 1e-6, flank_angle: float = 45.0) -> "Profile":
        """Profile whose sloped flank rises at ``flank_angle`` degrees from horizontal."""
        check_choice("kind", kind, KINDS)
        base = check_positive("base", base)
        angle = check_finite("flank_angle", flank_angle)
        if not 0.0 < angle < 90.0:
            raise SceneError(f"`flank_angle` must be in (0, 90) degrees, got {show(flank_angle)}")
        run = base / 2.0 if kind == "full" else base
        return cls(kind=kind, base=base, height=run * math.tan(math.radians(angle)))

    @property
    def flank_angle(self) -> float:
        """Angle of the sloped flank from horizontal (degrees); 0 for ``flat``."""
        if self.kind == "flat":
            return 0.0
        run = self.base / 2.0 if self.kind == "full" else self.base
        return math.degrees(math.atan2(self.height, run))

    def runs(self, *, upper: bool) -> tuple[float, float]:
        """Horizontal extent of the base from the tip: ``(left, right)`` (m)."""
        if self.kind == "half":
            return (0.0, self.base) if upper else (self.base, 0.0)
        return (self.base / 2.0, self.base / 2.0)

    def vertices(self, *, upper: bool) -> list[tuple[float, float]]:
        """Polygon vertices (m) relative to the tip's x at base level (y = 0).

        ``upper=True`` gives the slider's downward-pointing version.
        """
        return outline(self.kind, *self.runs(upper=upper), self.height, 0.0, upper=upper)


def outline(kind: str, left: float, right: float, height: float, level: float, *,
            upper: bool) -> list[tuple[float, float]]:
    """Vertices (m) of one asperity relative to its tip's x and the surface's rest datum.

    The base line lies at ``level`` and the tip ``height`` beyond it, both
    measured in the direction the tips point: up for the lower surface,
    down (negative y) for the slider (``upper=True``).
    """
    # 0.0 - level, not -level: a zero level stays +0.0, so a uniform surface's
    # vertices are the very floats they were before per-asperity shapes existed.
    base = 0.0 - level if upper else level
    tip = base - height if upper else level + height
    if kind == "flat":
        # The corners of the contact face are rounded off (FLAT_EDGE): with square corners a
        # block meets a neighbour standing a fraction of a nanometre proud face-on -- pymunk
        # takes the shallower penetration, the horizontal one, as the contact normal -- and
        # jams (contiguous blocks: 140 mN = 47 mu_s N on a 0.27 nm step). Every real edge is
        # rounded; here a 1:10 slope then a 45 deg bevel, so a small step is climbed gently and
        # a larger one still can be; a step taller than the edge is a real step.
        width = left + right
        (run1, drop1), (run2, drop2) = ((f * width, s * f * width) for f, s in FLAT_EDGE)
        if drop1 + drop2 > 0.5 * height:  # a thin slab: scale the edge down to half its height
            scale = 0.5 * height / (drop1 + drop2)
            run1, drop1, run2, drop2 = run1 * scale, drop1 * scale, run2 * scale, drop2 * scale
        sign = 1.0 if upper else -1.0  # from the contact face into the block
        edge = [(run1 + run2, 0.0), (run2, drop1), (0.0, drop1 + drop2)]  # (inset, depth) pairs
        right_side = [(right - i, tip + sign * d) for i, d in reversed(edge)]
        left_side = [(-left + i, tip + sign * d) for i, d in edge]
        return [(-left, base), (right, base), *right_side, *left_side]
    return [(-left, base), (right, base), (0.0, tip)]


def half_of(full: Profile) -> Profile:
    """Ooten's figure 9: the full triangle ``full`` cut through its apex (same height and
    flank, half the base, one vertical face)."""
    if full.kind != "full":
        raise SceneError(f"`profile` must be a full triangle to be cut in half, got {full.kind!r}")
    return Profile(kind="half", base=full.base / 2.0, height=full.height)


def _check_overlap(name: str, tips: np.ndarray, left, right) -> None:
    """Bases of neighbouring asperities may touch but not overlap.

    ``left`` / ``right`` are the runs from each tip to its feet (m): one value
    for all asperities, or one per asperity.
    """
    if len(tips) < 2:
        return
    if np.ndim(left) == 0 and np.ndim(right) == 0:
        gaps = np.diff(tips) - (left + right)
        if gaps.min() < -1e-9 * (left + right):
            raise SceneError(f"`{name}` is too small: asperity bases ({left + right:g} m wide) would "
                             f"overlap (closest tips {float(np.diff(tips).min()):g} m apart)")
        return
    left, right = _per_tip(left, len(tips)), _per_tip(right, len(tips))
    need = right[:-1] + left[1:]
    gaps = np.diff(tips) - need
    slack = 1e-9 * float(np.max(left + right))
    if gaps.min() < -slack:
        i = int(np.argmin(gaps))
        raise SceneError(f"`{name}` is too small: the bases of asperities {i} and {i + 1} would overlap "
                         f"(tips {float(tips[i + 1] - tips[i]):g} m apart, their flanks need "
                         f"{float(need[i]):g} m)")


def float_array(name: str, value, count: int | None, *, minimum: str | None = None) -> np.ndarray:
    """``value`` as a 1-D array of finite floats, ``count`` long if given; ``minimum`` is
    None, ``"positive"`` or ``"nonnegative"``. A bad entry is named ``name[i]``. Numeric
    arrays are checked in one pass (a profile can hold thousands of asperities)."""
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__len__"):
        raise SceneError(f"`{name}` must be a sequence of numbers, got {show(value)}")
    raw = np.asarray(value)
    if raw.ndim != 1:
        raise SceneError(f"`{name}` must be one-dimensional, got shape {raw.shape}")
    if raw.dtype.kind in "fiu":
        arr = raw.astype(float)
    else:  # strings, booleans, objects: the scalar checks name the entry
        check = {"positive": check_positive, "nonnegative": check_nonnegative}.get(minimum, check_finite)
        arr = np.array([check(f"{name}[{i}]", v) for i, v in enumerate(raw.tolist())], dtype=float)
    if count is not None and len(arr) != count:
        raise SceneError(f"`{name}` must have {count} entries (one per asperity), got {len(arr)}")
    bad = ~np.isfinite(arr)
    if minimum == "positive":
        bad |= ~(arr > 0)
    elif minimum == "nonnegative":
        bad |= ~(arr >= 0)
    if np.any(bad):
        i = int(np.argmax(bad))
        need = {"positive": "finite and > 0", "nonnegative": "finite and >= 0"}.get(minimum, "finite")
        raise SceneError(f"`{name}[{i}]` must be {need}, got {float(arr[i])!r}")  # not np.float64(...)
    return arr


def _per_tip(runs, count: int) -> np.ndarray:
    out = np.asarray(runs, dtype=float)
    return np.full(count, float(out)) if out.ndim == 0 else out


@dataclass(frozen=True)
class RegularSpacing:
    """``count`` asperity tips at ``offset + i * pitch`` (m).

    Parameters
    ----------
    count : int, default 16
        Number of asperities.
    pitch : float, default 1.25e-6
        Distance between neighbouring tips (m).
    offset : float, default 0.0
        Position of the first tip (m).

    See Also
    --------
    asperity2d.RandomSpacing
    asperity2d.make_scene : ``spacing="regular"`` with ``lower_count``, ``pitch``, ...

    Examples
    --------
    >>> import numpy as np
    >>> from asperity2d import RegularSpacing
    >>> spacing = RegularSpacing(count=4)
    >>> np.round(spacing.tips(0.5e-6, 0.5e-6) * 1e6, 3)  # tip positions, um
    array([0.  , 1.25, 2.5 , 3.75])
    """

    count: int = 16
    pitch: float = 1.25e-6
    offset: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "count", check_int("count", self.count, minimum=1))
        object.__setattr__(self, "pitch", check_positive("pitch", self.pitch))
        object.__setattr__(self, "offset", check_finite("offset", self.offset))

    def tips(self, left: float, right: float, *, name: str = "pitch") -> np.ndarray:
        """Tip x positions (m) for asperities whose bases reach ``left`` / ``right`` of the tip."""
        out = self.offset + self.pitch * np.arange(self.count, dtype=float)
        _check_overlap(name, out, left, right)
        return out

    @property
    def mean_pitch(self) -> float:
        return self.pitch


@dataclass(frozen=True)
class RandomSpacing:
    """``count`` asperity tips with random gaps, reproducible from ``seed``.

    Consecutive bases are ``min_gap + U * 2 * (mean_pitch - width - min_gap)``
    apart (``width`` the base width, ``U`` uniform on [0, 1)): the pitch
    averages ``mean_pitch`` and bases never overlap.

    Parameters
    ----------
    count : int, default 16
        Number of asperities.
    mean_pitch : float, default 1.25e-6
        Mean distance between neighbouring tips (m).
    min_gap : float, default 0.0
        Smallest gap between neighbouring bases (m).
    seed : int, default 0
        Seed of the gaps (the same seed, the same surface).
    offset : float, default 0.0
        Position of the first tip (m).

    See Also
    --------
    asperity2d.RegularSpacing
    asperity2d.make_scene : ``spacing="random"`` and ``seed=`` build it for you.

    Examples
    --------
    >>> import numpy as np
    >>> from asperity2d import RandomSpacing
    >>> np.round(RandomSpacing(count=4, seed=1).tips(0.5e-6, 0.5e-6) * 1e6, 3)  # um
    array([0.   , 1.256, 2.731, 3.803])
    """

    count: int = 16
    mean_pitch: float = 1.25e-6
    min_gap: float = 0.0
    seed: int = 0
    offset: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "count", check_int("count", self.count, minimum=1))
        object.__setattr__(self, "mean_pitch", check_positive("mean_pitch", self.mean_pitch))
        object.__setattr__(self, "min_gap", check_nonnegative("min_gap", self.min_gap))
        object.__setattr__(self, "seed", check_int("seed", self.seed, minimum=0, maximum=2**63 - 1))
        object.__setattr__(self, "offset", check_finite("offset", self.offset))

    def tips(self, left, right, *, name: str = "mean_pitch") -> np.ndarray:
        """Tip x positions (m) for asperities whose bases reach ``left`` / ``right`` of the tip.

        With one run per asperity (arrays), gap i is drawn between its own
        shortest value ``right[i] + left[i + 1] + min_gap`` and twice the mean
        pitch minus it, so every gap still averages ``mean_pitch``; equal runs
        give exactly the tips of the scalar case (same draws, same floats).
        """
        if np.ndim(left) == 0 and np.ndim(right) == 0:
            shortest = left + right + self.min_gap
            widest = shortest
        else:
            left, right = _per_tip(left, self.count), _per_tip(right, self.count)
            shortest = right[:-1] + left[1:] + self.min_gap
            widest = float(shortest.max()) if self.count > 1 else 0.0
        if self.count > 1 and self.mean_pitch < widest:
            raise SceneError(
                f"`{name}` ({self.mean_pitch:g} m) must be >= base + min_gap "
                f"({widest:g} m): asperities on one surface would overlap")
        rng = np.random.default_rng(self.seed)
        spread = 2.0 * (self.mean_pitch - shortest)
        gaps = shortest + spread * rng.random(self.count - 1)
        return self.offset + np.concatenate(([0.0], np.cumsum(gaps)))

    @property
    def pitch(self) -> float:
        return self.mean_pitch


@dataclass(frozen=True)
class ExplicitSpacing:
    """Tips at the given x ``positions`` (m, strictly increasing), e.g. a profile's summits.

    ``mean_pitch`` (m) defaults to the mean distance between neighbouring
    tips; a single tip needs it given (it sets run lengths and views).
    """

    positions: tuple[float, ...]
    mean_pitch: float | None = None

    def __post_init__(self):
        pos = float_array("positions", self.positions, None)
        if len(pos) < 1:
            raise SceneError("`positions` must hold at least one tip")
        if len(pos) > MAX_COUNT:
            raise SceneError(f"`positions` must hold <= {MAX_COUNT} tips, got {len(pos)}")
        steps = np.diff(pos)
        if np.any(steps <= 0):
            i = int(np.argmax(steps <= 0))
            raise SceneError(f"`positions` must increase: {float(pos[i + 1])!r} follows {float(pos[i])!r} "
                             f"at index {i + 1}")
        object.__setattr__(self, "positions", tuple(pos.tolist()))
        if self.mean_pitch is None:
            if len(pos) == 1:
                raise SceneError("`mean_pitch` is required with a single tip position")
            object.__setattr__(self, "mean_pitch", float((pos[-1] - pos[0]) / (len(pos) - 1)))
        object.__setattr__(self, "mean_pitch", check_positive("mean_pitch", self.mean_pitch))

    @property
    def count(self) -> int:
        return len(self.positions)

    @property
    def pitch(self) -> float:
        return self.mean_pitch

    def tips(self, left, right, *, name: str = "positions") -> np.ndarray:
        """The tip positions (m), checked for overlapping bases."""
        out = np.array(self.positions, dtype=float)
        _check_overlap(name, out, left, right)
        return out


Spacing = RegularSpacing | RandomSpacing | ExplicitSpacing
