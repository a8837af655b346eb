"""Scene specification: frozen, validated dataclasses in SI units.

A :class:`Scene` is pure data. :func:`make_scene` is the builder used by
scripts and studies; it is a pure function of its arguments (random spacing
is reproducible from ``seed``). Nothing here touches pymunk.
"""

from __future__ import annotations

import dataclasses
import difflib
import math
from dataclasses import dataclass, field

import numpy as np

from ._validate import (check_choice, check_finite, check_int, check_nonnegative, check_positive,
                        per_item)
from .errors import SceneError
from .geometry import KINDS, Profile, RandomSpacing, RegularSpacing, Spacing

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
    """

    mu_static: float = 0.3
    mu_kinetic: float | None = None
    slip_distance: float | None = None
    stick_speed: float | None = None

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


# -- the builder ---------------------------------------------------------------

#: Every override make_scene accepts, with its default (None: derived).
DEFAULTS = {
    "base": 1e-6,  # m, seed 000 Table 1
    "flank_angle": 45.0,  # degrees
    "height": None,  # m; overrides flank_angle when given
    "lower_count": 16,
    "upper_count": 4,
    "pitch": 1.25e-6,  # m, mean pitch of both surfaces
    "lower_pitch": None,
    "upper_pitch": None,
    "min_gap": 0.0,  # m, random spacing
    "lower_spacing": None,  # "regular" | "random"; default from `spacing`
    "upper_spacing": None,
    "lower_profile": None,  # "full" | "half" | "flat"; default from `profile`
    "upper_profile": None,
    "mass": 2.88e-16,  # kg per lower asperity, seed 000 Table 1
    "stiffness": 37_200.0,  # N/m, seed 000 Table 1
    "damping": None,  # N s/m; default from damping_ratio
    "damping_ratio": 0.1,  # c / (2 sqrt(k m))
    "travel_down": None,
    "travel_up": None,
    "lateral_stiffness": None,  # N/m: seed 000's MATLAB lattice (peaks move in x too)
    "lateral_damping": 0.0,
    "slider_mass": 2.88e-15,  # kg
    "track": "free",
    "normal_load": 0.01,  # N
    "interference": None,  # m, fixed track only
    "mu": None,  # sets both coefficients
    "mu_static": 0.3,
    "mu_kinetic": None,  # default: two thirds of mu_static
    "slip_distance": None,
    "stick_speed": None,
    "drive_force": 0.02,  # N, drive="force"
    "drive_stiffness": 3_720.0,  # N/m, drive="spring"
    "drive_velocity": 20.0,  # m/s = 1.8e-3 * omega * base: quasi-static regime
    "drive_damping": 0.0,
    "drive_preload": 0.0,  # N, initial spring force
    "gravity": 0.0,  # m/s^2; negligible at the micrometre scale
    "name": "",
}

SPACINGS = ("regular", "random", "random-upper", "random-lower")


def make_scene(*, spacing: str = "regular", seed: int = 0, profile: str = "full",
               drive: str = "spring", **overrides) -> Scene:
    """Build a scene from named physical parameters (SI units).

    Parameters
    ----------
    spacing : {"regular", "random", "random-upper", "random-lower"}
        Spacing of both surfaces; ``"random-upper"`` is seed 000's random
        upper / regular lower case. ``lower_spacing`` / ``upper_spacing``
        override each surface.
    seed : int
        Seed of the random spacings (the two surfaces get independent
        streams derived from it).
    profile : {"full", "half", "flat"}
        Asperity shape of both surfaces.
    drive : {"spring", "force"}
        Spring whose far end moves at ``drive_velocity`` (stick-slip), or a
        constant ``drive_force``.
    **overrides
        Any key of :data:`DEFAULTS`; an unknown key raises :class:`SceneError`.
    """
    unknown = sorted(set(overrides) - set(DEFAULTS))
    if unknown:
        hints = {u: difflib.get_close_matches(u, DEFAULTS, n=1) for u in unknown}
        msg = "; ".join(f"`{u}`" + (f" (did you mean `{h[0]}`?)" if h else "") for u, h in hints.items())
        raise SceneError(f"unknown scene parameter {msg}")
    p = {**DEFAULTS, **overrides}
    check_choice("spacing", spacing, SPACINGS)
    check_choice("drive", drive, ("spring", "force"))
    check_choice("profile", profile, KINDS)
    for name in ("lower_count", "upper_count"):
        check_int(name, p[name], minimum=1)
    for name in ("lower_profile", "upper_profile"):
        if p[name] is not None:
            check_choice(name, p[name], KINDS)
    for name in ("pitch", "lower_pitch", "upper_pitch"):
        if p[name] is not None:
            check_positive(name, p[name])
    if not isinstance(seed, int) or isinstance(seed, bool) or seed < 0:
        raise SceneError(f"`seed` must be a non-negative integer, got {seed!r}")

    def make_profile(kind):
        if p["height"] is not None:
            return Profile(kind=kind, base=p["base"], height=p["height"])
        return Profile.from_angle(kind, base=p["base"], flank_angle=p["flank_angle"])

    lower_kind = p["lower_profile"] or profile
    upper_kind = p["upper_profile"] or profile
    lower_rand = p["lower_spacing"] or ("random" if spacing in ("random", "random-lower") else "regular")
    upper_rand = p["upper_spacing"] or ("random" if spacing in ("random", "random-upper") else "regular")
    check_choice("lower_spacing", lower_rand, ("regular", "random"))
    check_choice("upper_spacing", upper_rand, ("regular", "random"))
    lower_seed, upper_seed = (int(s) for s in np.random.SeedSequence(seed).generate_state(2))

    def make_spacing(kind, count, pitch, sub_seed):
        pitch = p["pitch"] if pitch is None else pitch
        if kind == "regular":
            return RegularSpacing(count=count, pitch=pitch)
        return RandomSpacing(count=count, mean_pitch=pitch, min_gap=p["min_gap"], seed=sub_seed)

    mass, stiffness = p["mass"], p["stiffness"]
    damping = p["damping"]
    if damping is None:
        check_nonnegative("damping_ratio", p["damping_ratio"])
        damping = tuple(
            2.0 * p["damping_ratio"] * math.sqrt(k * m)
            for k, m in zip(per_item("stiffness", stiffness, p["lower_count"], allow_zero=False),
                            per_item("mass", mass, p["lower_count"], allow_zero=False))
        )
    lower = LowerSurface(
        profile=make_profile(lower_kind),
        spacing=make_spacing(lower_rand, p["lower_count"], p["lower_pitch"], lower_seed),
        mass=mass, stiffness=stiffness, damping=damping,
        travel_down=p["travel_down"], travel_up=p["travel_up"],
        lateral_stiffness=p["lateral_stiffness"], lateral_damping=p["lateral_damping"],
    )
    slider = Slider(
        profile=make_profile(upper_kind),
        spacing=make_spacing(upper_rand, p["upper_count"], p["upper_pitch"], upper_seed),
        mass=p["slider_mass"], track=p["track"], normal_load=p["normal_load"],
        interference=p["interference"],
    )
    if drive == "spring":
        drv = SpringDrive(stiffness=p["drive_stiffness"], velocity=p["drive_velocity"],
                          damping=p["drive_damping"], preload=p["drive_preload"])
    else:
        drv = ConstantForce(force=p["drive_force"])
    mu_s, mu_k = p["mu_static"], p["mu_kinetic"]
    if mu_k is None:
        mu_k = check_nonnegative("mu_static", mu_s) * 2.0 / 3.0
    if p["mu"] is not None:
        mu_s = mu_k = p["mu"]
    contact = Contact(mu_static=mu_s, mu_kinetic=mu_k, slip_distance=p["slip_distance"],
                      stick_speed=p["stick_speed"])
    name = p["name"] or f"{spacing}-{profile}-{drive}-seed{seed}"
    return Scene(lower=lower, slider=slider, drive=drv, contact=contact, gravity=p["gravity"], name=name)
