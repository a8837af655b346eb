"""Asperity profiles and surface spacings (pure, seeded, SI units).

Conventions (seed 000, figures 5-9): the lower surface lies on y = 0 with its
asperities pointing up; the slider's asperities hang below its underside and
point down; the slider moves towards +x. A spacing gives the x of every
asperity's *tip* (apex); an asperity's shape is its height and the horizontal
runs of its two flanks from the tip: ``left`` (towards -x) and ``right``.

* ``full`` triangle: isosceles, left = right = base / 2.
* ``half`` triangle (seed 000 figure 9): a right triangle with one vertical
  face through the tip. The lower one rises towards the oncoming slider
  (sloped flank on the -x side, vertical face at +x); the upper one is its
  mirror image (sloped flank leading on the +x side, vertical face at its
  back). Once an upper tip passes a lower tip, the lower peak springs back up
  behind the upper vertical face and cannot push the slider on.
  :func:`half_of` cuts a full triangle through its apex as the seed draws it:
  same height, same flank, half the base.
* ``flat``: a rectangle (a flat block or surface, for Coulomb checks); its
  "tip" is the middle of its top face.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._validate import check_choice, check_finite, check_int, check_nonnegative, check_positive, show
from .errors import SceneError

KINDS = ("full", "half", "flat")


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
        angle instead (angle and height are separate parameters: seed 000's
        1.5 µm tip on a 1 µm base is inconsistent with 45° flanks).
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
        left, right = self.runs(upper=upper)
        h = -self.height if upper else self.height
        if self.kind == "flat":
            return [(-left, 0.0), (right, 0.0), (right, h), (-left, h)]
        return [(-left, 0.0), (right, 0.0), (0.0, h)]


def half_of(full: Profile) -> Profile:
    """Seed 000 figure 9: the full triangle ``full`` cut through its apex (same height and
    flank, half the base, one vertical face)."""
    if full.kind != "full":
        raise SceneError(f"`profile` must be a full triangle to be cut in half, got {full.kind!r}")
    return Profile(kind="half", base=full.base / 2.0, height=full.height)


def _check_overlap(name: str, tips: np.ndarray, left: float, right: float) -> None:
    """Bases of neighbouring asperities may touch but not overlap."""
    if len(tips) > 1:
        gaps = np.diff(tips) - (left + right)
        if gaps.min() < -1e-9 * (left + right):
            raise SceneError(f"`{name}` is too small: asperity bases ({left + right:g} m wide) would "
                             f"overlap (closest tips {float(np.diff(tips).min()):g} m apart)")


@dataclass(frozen=True)
class RegularSpacing:
    """``count`` asperity tips at ``offset + i * pitch`` (m)."""

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

    def tips(self, left: float, right: float, *, name: str = "mean_pitch") -> np.ndarray:
        """Tip x positions (m) for asperities whose bases reach ``left`` / ``right`` of the tip."""
        shortest = left + right + self.min_gap
        if self.count > 1 and self.mean_pitch < shortest:
            raise SceneError(
                f"`{name}` ({self.mean_pitch:g} m) must be >= base + min_gap "
                f"({shortest:g} m): asperities on one surface would overlap")
        rng = np.random.default_rng(self.seed)
        spread = 2.0 * (self.mean_pitch - shortest)
        gaps = shortest + spread * rng.random(self.count - 1)
        return self.offset + np.concatenate(([0.0], np.cumsum(gaps)))

    @property
    def pitch(self) -> float:
        return self.mean_pitch


Spacing = RegularSpacing | RandomSpacing
