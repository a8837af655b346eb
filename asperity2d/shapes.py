"""Per-asperity shapes: each asperity of a surface with its own height, flank runs and base level.

A rough surface (random heights from :func:`asperity2d.make_scene`, or the
summits of a measured profile, :mod:`asperity2d.surface`) is described by one
:class:`Shapes` record per surface, overriding the surface's uniform
:class:`~asperity2d.geometry.Profile`. Without one, a surface is ``count``
copies of its profile, and :meth:`Shapes.uniform` gives exactly those shapes
(same floats), so code that reads per-asperity geometry has one path.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._inputs import MAX_COUNT, show
from .errors import SceneError
from .geometry import Profile, float_array, outline


@dataclass(frozen=True)
class Shapes:
    """Each asperity's own shape on one surface (SI), overriding the surface's uniform profile.

    One value per asperity, stored as tuples of floats:

    * ``heights``: tip above the asperity's own base line (m), > 0;
    * ``left_runs`` / ``right_runs``: horizontal distance from the tip to the
      left / right foot (m), >= 0 with a positive sum (a zero run is a
      vertical face, as in a half triangle); flank angles atan(height / run);
    * ``levels``: height of each base line above the surface's rest datum (m),
      measured the way the tips point (up for the lower surface, down for
      the slider); default 0, all bases on one line. A measured profile's
      summits keep their elevations this way (``levels + heights``).

    The surface's :class:`Profile` still gives the kind (triangle or flat)
    and the scene's length scale (its ``base``).
    """

    heights: tuple[float, ...]
    left_runs: tuple[float, ...]
    right_runs: tuple[float, ...]
    levels: tuple[float, ...] | None = None

    def __post_init__(self):
        heights = float_array("heights", self.heights, None, minimum="positive")
        n = len(heights)
        if not 1 <= n <= MAX_COUNT:
            raise SceneError(f"`heights` must hold 1 to {MAX_COUNT} asperities, got {n}")
        left = float_array("left_runs", self.left_runs, n, minimum="nonnegative")
        right = float_array("right_runs", self.right_runs, n, minimum="nonnegative")
        bad = ~(left + right > 0)
        if np.any(bad):
            i = int(np.argmax(bad))
            raise SceneError(f"`left_runs[{i}]` + `right_runs[{i}]` (the base) must be > 0, got 0")
        levels = np.zeros(n) if self.levels is None else float_array("levels", self.levels, n, minimum=None)
        for name, value in (("heights", heights), ("left_runs", left), ("right_runs", right),
                            ("levels", levels)):
            object.__setattr__(self, name, tuple(value.tolist()))

    @classmethod
    def uniform(cls, profile: Profile, count: int, *, upper: bool) -> "Shapes":
        """``count`` copies of ``profile`` (the shapes a surface has without an override)."""
        left, right = profile.runs(upper=upper)
        return cls(heights=(profile.height,) * count, left_runs=(left,) * count,
                   right_runs=(right,) * count)

    @property
    def count(self) -> int:
        return len(self.heights)

    def runs(self) -> tuple[np.ndarray, np.ndarray]:
        """``(left, right)`` runs from each tip to its feet (m)."""
        return np.array(self.left_runs), np.array(self.right_runs)

    @property
    def bases(self) -> np.ndarray:
        """Base widths (m)."""
        return np.array(self.left_runs) + np.array(self.right_runs)

    @property
    def summits(self) -> np.ndarray:
        """Each tip's distance from the rest datum, ``levels + heights`` (m)."""
        return np.array(self.levels) + np.array(self.heights)

    def vertices(self, kind: str, *, upper: bool) -> list[list[tuple[float, float]]]:
        """Each asperity's polygon (m) relative to its tip's x and the rest datum (see :func:`outline`)."""
        return [outline(kind, a, b, h, z, upper=upper)
                for a, b, h, z in zip(self.left_runs, self.right_runs, self.heights, self.levels)]


def check_substrate(value) -> tuple:
    """Rigid valley floor between asperities: polylines of (x, z) points (m), each with at
    least two points and x strictly increasing, as a tuple of tuples of (x, z) tuples."""
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__len__"):
        raise SceneError(f"`substrate` must be a sequence of polylines, got {show(value)}")
    out = []
    for i, line in enumerate(value):
        try:
            pts = np.array(line, dtype=float)
        except (TypeError, ValueError):
            raise SceneError(f"`substrate[{i}]` must be a sequence of (x, z) points") from None
        if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 2:
            raise SceneError(f"`substrate[{i}]` must hold at least two (x, z) points, got shape {pts.shape}")
        if not np.all(np.isfinite(pts)) or not np.all(np.diff(pts[:, 0]) > 0):
            raise SceneError(f"`substrate[{i}]` must be finite with x strictly increasing")
        out.append(tuple(map(tuple, pts.tolist())))
    return tuple(out)


class SurfaceGeometry:
    """Per-asperity geometry of a surface spec (mixed into
    :class:`~asperity2d.scene.LowerSurface` and :class:`~asperity2d.scene.Slider`, which
    have ``profile``, ``spacing`` and ``shapes``): its ``shapes`` override, or ``count``
    copies of its ``profile`` (:meth:`Shapes.uniform`, the very same floats)."""

    _upper = False

    def _check_shapes(self) -> None:
        if self.shapes is None:
            return
        if not isinstance(self.shapes, Shapes):
            raise SceneError(f"`shapes` must be a Shapes record or None, got {show(self.shapes)}")
        if self.shapes.count != self.spacing.count:
            raise SceneError(f"`shapes` holds {self.shapes.count} asperities but the spacing places "
                             f"{self.spacing.count}")

    @property
    def count(self) -> int:
        return self.spacing.count

    def shape_set(self) -> Shapes:
        """Every asperity's shape (m): the override, or copies of the profile."""
        return self.shapes or Shapes.uniform(self.profile, self.count, upper=self._upper)

    def runs(self):
        """Runs from each tip to its left / right foot (m): the profile's two numbers
        when uniform, else one array each."""
        return self.profile.runs(upper=self._upper) if self.shapes is None else self.shapes.runs()

    def heights(self) -> np.ndarray:
        """Each asperity's height above its own base line (m)."""
        return np.array(self.shape_set().heights)

    def summits(self) -> np.ndarray:
        """Each tip's rest distance from the surface's datum, base level + height (m),
        up for the lower surface, down for the slider."""
        return self.shape_set().summits

    def outlines(self) -> list[list[tuple[float, float]]]:
        """Each asperity's polygon (m) relative to its tip's x and the rest datum."""
        if self.shapes is None:
            return [self.profile.vertices(upper=self._upper)] * self.count
        return self.shapes.vertices(self.profile.kind, upper=self._upper)
