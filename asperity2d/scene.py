"""Scene specification: frozen, validated dataclasses in SI units.

A :class:`Scene` is pure data; it round-trips through plain dicts (JSON,
TOML). The builder scripts and studies use, :func:`asperity2d.make_scene`,
lives in :mod:`asperity2d.builders`. Nothing here touches pymunk.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from ._validate import check_choice, check_finite, check_nonnegative, check_positive, per_item
from .errors import SceneError
from .geometry import Profile, RandomSpacing, RegularSpacing, Spacing

TRACKS = ("free", "fixed")


@dataclass(frozen=True)
class LowerSurface:
    """Asperities on vertical spring-damper tracks (seed 000 figures 5, 7, 8).

    ``mass`` (kg), ``stiffness`` (N/m) and ``damping`` (N s/m) are scalars or
    one value per asperity; they are stored as tuples. ``travel_down`` and
    ``travel_up`` (m) limit each track below / above the rest position
    (default: the asperity height).

    ``lateral_stiffness`` (N/m) turns the tracks into seed 000's MATLAB
    lattice (its figure 14, equations 9-18): the peaks then move in x and y,
    each held by its vertical spring to ground and joined to its neighbours
    and the two walls by horizontal springs: n + 1 values (wall-peak 1,
    peak 1-peak 2, ..., peak n-wall; a scalar applies to all, 0 removes a
    link), with ``lateral_damping`` (N s/m) in parallel. Track travel limits
    do not apply to the lattice.
    """

    profile: Profile = field(default_factory=Profile)
    spacing: Spacing = field(default_factory=RegularSpacing)
    mass: float | tuple[float, ...] = 2.88e-16
    stiffness: float | tuple[float, ...] = 37_200.0
    damping: float | tuple[float, ...] = 0.0
    travel_down: float | None = None
    travel_up: float | None = None
    lateral_stiffness: float | tuple[float, ...] | None = None
    lateral_damping: float | tuple[float, ...] = 0.0

    def __post_init__(self):
        n = self.spacing.count
        object.__setattr__(self, "mass", per_item("mass", self.mass, n, allow_zero=False))
        object.__setattr__(self, "stiffness", per_item("stiffness", self.stiffness, n, allow_zero=False))
        object.__setattr__(self, "damping", per_item("damping", self.damping, n, allow_zero=True))
        if self.lateral_stiffness is not None:
            object.__setattr__(self, "lateral_stiffness", per_item(
                "lateral_stiffness", self.lateral_stiffness, n + 1, allow_zero=True))
        object.__setattr__(self, "lateral_damping", per_item(
            "lateral_damping", self.lateral_damping, n + 1, allow_zero=True))
        for name in ("travel_down", "travel_up"):
            value = getattr(self, name)
            if value is None:
                object.__setattr__(self, name, self.profile.height)
            else:
                check_positive(name, value)
        self.centers()  # validates that asperities do not overlap

    @property
    def count(self) -> int:
        return self.spacing.count

    @property
    def is_lattice(self) -> bool:
        """True when the peaks move in x too (seed 000's MATLAB model)."""
        return self.lateral_stiffness is not None

    def centers(self) -> np.ndarray:
        """Base-centre x positions (m)."""
        return self.spacing.centers(self.profile.base)

    def lateral_stiffness_matrix(self) -> np.ndarray:
        """The n x n horizontal stiffness matrix K (N/m) of the lattice's springs."""
        n = self.count
        k = np.asarray(self.lateral_stiffness if self.is_lattice else np.zeros(n + 1), dtype=float)
        K = np.diag(k[:-1] + k[1:])
        K -= np.diag(k[1:-1], 1) + np.diag(k[1:-1], -1)
        return K


@dataclass(frozen=True)
class Slider:
    """The upper body carrying its own asperities, on a horizontal track.

    ``track="free"``: free to move vertically, pressed down by
    ``normal_load`` (N). ``track="fixed"``: held at a fixed height such that
    its tips reach ``interference`` (m) below the lower tips' rest height.
    """

    profile: Profile = field(default_factory=Profile)
    spacing: Spacing = field(default_factory=lambda: RegularSpacing(count=4))
    mass: float = 2.88e-15
    track: str = "free"
    normal_load: float = 0.01
    interference: float | None = None

    def __post_init__(self):
        check_positive("slider_mass", self.mass)
        check_choice("track", self.track, TRACKS)
        check_nonnegative("normal_load", self.normal_load)
        if self.interference is None:
            object.__setattr__(self, "interference", self.profile.height / 4.0)
        else:
            check_positive("interference", self.interference)
        self.centers()

    @property
    def count(self) -> int:
        return self.spacing.count

    def centers(self) -> np.ndarray:
        """Base-centre x positions relative to the slider's reference point (m)."""
        c = self.spacing.centers(self.profile.base)
        return c - c[0]


@dataclass(frozen=True)
class ConstantForce:
    """A constant horizontal force on the slider (N), as in Working Model."""

    force: float = 0.02

    def __post_init__(self):
        check_finite("drive_force", self.force)


@dataclass(frozen=True)
class SpringDrive:
    """A spring (N/m) and parallel damper (N s/m) whose far end moves at ``velocity`` (m/s).

    The pull is horizontal. The spring starts stretched to hold ``preload``
    (N, default 0: unstretched).
    """

    stiffness: float = 3_720.0
    velocity: float = 20.0
    damping: float = 0.0
    preload: float = 0.0

    def __post_init__(self):
        check_positive("drive_stiffness", self.stiffness)
        check_positive("drive_velocity", self.velocity)
        check_nonnegative("drive_damping", self.damping)
        check_finite("drive_preload", self.preload)


Drive = ConstantForce | SpringDrive


@dataclass(frozen=True)
class Contact:
    """Friction at the asperity contacts (both surfaces).

    ``mu_static`` >= ``mu_kinetic`` (default: equal). A stuck contact keeps
    ``mu_static`` until it has slid ``slip_distance`` (m, default 0.1 % of the
    asperity base) without pause, so a micro-slip of a step or two under a
    suddenly applied load (measured: ~2e-5 base) does not drop it to
    ``mu_kinetic``; ``slip_distance=0`` switches on the instantaneous slip
    speed alone. A sliding
    contact sticks again when its slip speed falls below ``stick_speed``
    (m/s, default 1e-4 of base x natural frequency).

    ``restitution`` (in [0, 1], pymunk's elasticity) is the ratio of the
    normal relative speed after an impact to that before: 0 (the default) is
    a perfectly inelastic impact, which loses the normal part of the relative
    kinetic energy; 1 loses nothing.
    """

    mu_static: float = 0.3
    mu_kinetic: float | None = None
    slip_distance: float | None = None
    stick_speed: float | None = None
    restitution: float = 0.0

    def __post_init__(self):
        check_nonnegative("mu_static", self.mu_static)
        if self.mu_kinetic is None:
            object.__setattr__(self, "mu_kinetic", self.mu_static)
        check_nonnegative("mu_kinetic", self.mu_kinetic)
        if self.mu_kinetic > self.mu_static:
            raise SceneError(
                f"`mu_static` ({self.mu_static!r}) must be >= `mu_kinetic` ({self.mu_kinetic!r})"
            )
        if self.slip_distance is not None:
            check_nonnegative("slip_distance", self.slip_distance)
        if self.stick_speed is not None:
            check_positive("stick_speed", self.stick_speed)
        if check_nonnegative("restitution", self.restitution) > 1:
            raise SceneError(f"`restitution` must be <= 1, got {self.restitution!r}")


@dataclass(frozen=True)
class Scene:
    """A complete asperity contact scene (SI units throughout)."""

    lower: LowerSurface = field(default_factory=LowerSurface)
    slider: Slider = field(default_factory=Slider)
    drive: Drive = field(default_factory=SpringDrive)
    contact: Contact = field(default_factory=Contact)
    gravity: float = 0.0
    name: str = ""

    def __post_init__(self):
        check_nonnegative("gravity", self.gravity)
        if self.slider.track == "free" and self.slider.normal_load == 0 and self.gravity == 0:
            raise SceneError("`normal_load` must be > 0 for a free slider when `gravity` is 0")

    # -- derived quantities --------------------------------------------------
    @property
    def base(self) -> float:
        return self.lower.profile.base

    def natural_frequencies(self) -> dict[str, float]:
        """Angular natural frequencies (rad/s) of the scene's spring-mass pairs."""
        k, m = np.asarray(self.lower.stiffness), np.asarray(self.lower.mass)
        freqs = {"lower": float(np.max(np.sqrt(k / m)))}
        if self.lower.is_lattice:
            # Gershgorin bound on the lattice's highest horizontal mode.
            row = np.abs(self.lower.lateral_stiffness_matrix()).sum(axis=1)
            freqs["lattice"] = float(np.max(np.sqrt(row / m)))
        if isinstance(self.drive, SpringDrive):
            freqs["drive"] = math.sqrt(self.drive.stiffness / self.slider.mass)
        return freqs

    def shortest_period(self) -> float:
        """Shortest natural period T = 2 pi / omega_max (s); dt defaults to T/50."""
        return 2.0 * math.pi / max(self.natural_frequencies().values())

    def slowest_period(self) -> float:
        """Longest spring-mass period in the scene (s), including the slider on one lower spring."""
        k, m = np.asarray(self.lower.stiffness), np.asarray(self.lower.mass)
        omegas = list(np.sqrt(k / m)) + [math.sqrt(float(np.min(k)) / self.slider.mass)]
        if isinstance(self.drive, SpringDrive):
            omegas.append(math.sqrt(self.drive.stiffness / self.slider.mass))
        return 2.0 * math.pi / min(omegas)

    def replace(self, **changes) -> "Scene":
        return dataclasses.replace(self, **changes)

    # -- serialisation -------------------------------------------------------
    def to_dict(self) -> dict:
        return _to_plain(self)

    @classmethod
    def from_dict(cls, data: dict) -> "Scene":
        return _from_plain(data)


_TYPES = {c.__name__: c for c in (Scene, LowerSurface, Slider, ConstantForce, SpringDrive,
                                  Contact, Profile, RegularSpacing, RandomSpacing)}


def _to_plain(obj):
    if dataclasses.is_dataclass(obj):
        out = {"type": type(obj).__name__}
        for f in dataclasses.fields(obj):
            out[f.name] = _to_plain(getattr(obj, f.name))
        return out
    if isinstance(obj, tuple):
        return [_to_plain(v) for v in obj]
    return obj


def _from_plain(data):
    if isinstance(data, dict) and "type" in data:
        cls = _TYPES.get(data["type"])
        if cls is None:
            raise SceneError(f"unknown scene component type `{data['type']}`")
        kwargs = {k: _from_plain(v) for k, v in data.items() if k != "type"}
        return cls(**kwargs)
    if isinstance(data, list):
        return tuple(_from_plain(v) for v in data)
    return data
