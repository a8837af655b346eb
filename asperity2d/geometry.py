"""Asperity profiles and surface spacings (pure, seeded, SI units).

Conventions (seed 000, figures 5-9): the lower surface lies on y = 0 with its
asperities pointing up; the slider's asperities hang below its underside and
point down; the slider moves towards +x.

* ``full`` triangle: isosceles, apex above the middle of the base.
* ``half`` triangle: one vertical face. By default the sloped faces of the
  upper and lower half triangles meet (seed 000 figure 9): the lower half
  triangle's slope faces the oncoming slider (-x) and its vertical face is on
  the +x side; the upper one's slope faces +x and its vertical face is at its
  back. Once a slider tip passes a lower apex the lower peak springs back up
  behind the slider's vertical face and cannot push it on.
* ``flat``: a rectangle (a flat block / flat surface, for Coulomb checks).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._validate import check_choice, check_finite, check_int, check_positive
from .errors import SceneError

KINDS = ("full", "half", "flat")


@dataclass(frozen=True)
class Profile:
    """Shape of one asperity.

    Parameters
    ----------
    kind : {"full", "half", "flat"}
    base : float
        Width of the asperity's base (m).
    height : float
        Height from base to apex (m). See :meth:`from_angle` to give the flank
        angle instead (angle and height are separate parameters: seed 000's
        1.5 µm tip on a 1 µm base is inconsistent with 45° flanks).
    """

    kind: str = "full"
    base: float = 1e-6
    height: float = 0.5e-6

    def __post_init__(self):
        check_choice("kind", self.kind, KINDS)
        check_positive("base", self.base)
        check_positive("height", self.height)

    @classmethod
    def from_angle(cls, kind: str = "full", *, base: float = 1e-6, flank_angle: float = 45.0) -> "Profile":
        """Profile whose sloped flank rises at ``flank_angle`` degrees from horizontal."""
        check_choice("kind", kind, KINDS)
        check_finite("flank_angle", flank_angle)
        if not 0.0 < flank_angle < 90.0:
            raise SceneError(f"`flank_angle` must be in (0, 90) degrees, got {flank_angle!r}")
        run = base / 2.0 if kind == "full" else base
        return cls(kind=kind, base=base, height=run * math.tan(math.radians(flank_angle)))

    @property
    def flank_angle(self) -> float:
        """Angle of the sloped flank from horizontal (degrees); 0 for ``flat``."""
        if self.kind == "flat":
            return 0.0
        run = self.base / 2.0 if self.kind == "full" else self.base
        return math.degrees(math.atan2(self.height, run))

    def vertices(self, *, upper: bool) -> list[tuple[float, float]]:
        """Polygon vertices (m) relative to the middle of the base.

        ``upper=True`` gives the slider's downward-pointing version.
        """
        b, h = self.base / 2.0, self.height
        if self.kind == "full":
            verts = [(-b, 0.0), (b, 0.0), (0.0, h)]
        elif self.kind == "half":
            # Lower: slope faces -x, vertical face at +x. Upper (mirrored
            # through the x axis and the y axis): slope faces +x, vertical back.
            verts = [(-b, 0.0), (b, 0.0), (b, h)]
        else:
            verts = [(-b, 0.0), (b, 0.0), (b, h), (-b, h)]
        if upper:
            verts = [(-vx, -vy) for vx, vy in verts]
        return verts

    def apex_offset(self, *, upper: bool) -> float:
        """x of the apex (the tip used for "passed" tests) from the base middle (m)."""
        if self.kind == "half":
            return -self.base / 2.0 if upper else self.base / 2.0
        return 0.0


@dataclass(frozen=True)
class RegularSpacing:
    """``count`` asperities with base centres ``offset + i * pitch`` (m)."""

    count: int = 10
    pitch: float = 1.2e-6
    offset: float = 0.0

    def __post_init__(self):
        check_int("count", self.count, minimum=1)
        check_positive("pitch", self.pitch)
        check_finite("offset", self.offset)

    def centers(self, base: float) -> np.ndarray:
        """Base-centre x positions (m)."""
        if self.count > 1 and self.pitch < base:
            raise SceneError(
                f"`pitch` ({self.pitch:g} m) must be >= the asperity base ({base:g} m): "
                "asperities on one surface would overlap"
            )
        return self.offset + self.pitch * np.arange(self.count, dtype=float)

    @property
    def mean_pitch(self) -> float:
        return self.pitch


@dataclass(frozen=True)
class RandomSpacing:
    """``count`` asperities with random gaps, reproducible from ``seed``.

    Consecutive base centres are ``base + min_gap + U * 2 * (mean_pitch - base
    - min_gap)`` apart with ``U`` uniform on [0, 1): the pitch averages
    ``mean_pitch`` and never drops below ``base + min_gap`` (no overlap).
    """

    count: int = 10
    mean_pitch: float = 1.2e-6
    min_gap: float = 0.0
    seed: int = 0
    offset: float = 0.0

    def __post_init__(self):
        check_int("count", self.count, minimum=1)
        check_positive("mean_pitch", self.mean_pitch)
        check_finite("min_gap", self.min_gap)
        if self.min_gap < 0:
            raise SceneError(f"`min_gap` must be >= 0, got {self.min_gap!r}")
        check_int("seed", self.seed, minimum=0)
        check_finite("offset", self.offset)

    def centers(self, base: float) -> np.ndarray:
        """Base-centre x positions (m)."""
        shortest = base + self.min_gap
        if self.count > 1 and self.mean_pitch < shortest:
            raise SceneError(
                f"`mean_pitch` ({self.mean_pitch:g} m) must be >= base + min_gap "
                f"({shortest:g} m): asperities on one surface would overlap"
            )
        rng = np.random.default_rng(self.seed)
        spread = 2.0 * (self.mean_pitch - shortest)
        gaps = shortest + spread * rng.random(self.count - 1)
        return self.offset + np.concatenate(([0.0], np.cumsum(gaps)))

    @property
    def pitch(self) -> float:
        return self.mean_pitch


Spacing = RegularSpacing | RandomSpacing
