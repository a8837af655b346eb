"""Scene builders: named physical parameters in, a validated :class:`Scene` out.

:func:`make_scene` is a pure function of its arguments: random spacings are
reproducible from ``seed`` (the two surfaces get independent streams derived
from it with ``numpy.random.SeedSequence``). :data:`DEFAULTS` lists every
parameter it accepts; an unknown one raises :class:`SceneError` with the
closest known name.
"""

from __future__ import annotations

import difflib
import math

import numpy as np

from ._validate import check_choice, check_int, check_nonnegative, check_positive, per_item
from .errors import SceneError
from .geometry import KINDS, Profile, RandomSpacing, RegularSpacing
from .scene import ConstantForce, Contact, LowerSurface, Scene, Slider, SpringDrive

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
    "restitution": 0.0,  # contact elasticity in [0, 1]: 0 inelastic impacts, 1 no impact loss
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
                      stick_speed=p["stick_speed"], restitution=p["restitution"])
    name = p["name"] or f"{spacing}-{profile}-{drive}-seed{seed}"
    return Scene(lower=lower, slider=slider, drive=drv, contact=contact, gravity=p["gravity"], name=name)
