"""Scene builders: named physical parameters in, a validated :class:`Scene` out.

:func:`make_scene` is a pure function of its arguments: random spacings and
random heights are reproducible from ``seed`` (each surface gets independent
streams derived from it with ``numpy.random.SeedSequence``: the spacings from
``generate_state(2)`` as always, the heights from its two spawned children).
A surface can also be a measured or generated profile (``lower_surface`` /
``upper_surface``, see :mod:`asperity2d.surface.source`). :data:`DEFAULTS` lists every
parameter it accepts; its values come from :data:`asperity2d.scene.SEED_000`,
the same table the dataclasses use, so ``make_scene()`` builds ``Scene()``.
Every argument is checked (type, finiteness, range) before any arithmetic,
whether or not the chosen drive or spacing uses it; an unknown one raises
:class:`SceneError` with the closest known name, and two that contradict each
other (``mu`` with ``mu_static``) are refused.
"""

from __future__ import annotations

import difflib

import numpy as np

from ._validate import (check_choice, check_finite, check_int, check_nonnegative, check_positive,
                        check_text, is_real, per_item, show)
from .errors import SceneError
from .geometry import KINDS, Profile, RandomSpacing, RegularSpacing, half_of
from .scene import (SEED_000, ConstantForce, Contact, LowerSurface, Scene, Slider, SpringDrive,
                    kinetic_default)
from .surface.asperities import Asperities
from .surface.heights import DISTRIBUTIONS, random_shapes
from .surface.read import UNITS
from .surface.source import check_heights, label, lower_material, surface_asperities, surface_spec
from .units import MIN_LENGTH_RATIO, Units, check_scales

#: Every override make_scene accepts, with its default (None: derived, see make_scene).
DEFAULTS = {
    **SEED_000,
    "height": None,  # m; instead of flank_angle
    "half_shape": "apex-cut",  # half triangles: "apex-cut" (seed 000 fig. 9) or "full-base"
    "lower_pitch": None, "upper_pitch": None,  # m, default `pitch`
    "min_gap": 0.0,  # m, random spacing
    "lower_spacing": None, "upper_spacing": None,  # "regular" | "random"; default from `spacing`
    "lower_profile": None, "upper_profile": None,  # "full" | "half" | "flat"; default from `profile`
    "damping": None,  # N s/m; instead of damping_ratio
    "travel_down": None, "travel_up": None,  # m, default the asperity height
    "lateral_stiffness": None,  # N/m: seed 000's MATLAB lattice (peaks move in x too)
    "lateral_damping": 0.0,
    "interference": None,  # m, fixed track; default a quarter of the asperity height
    "mu": None,  # sets both coefficients
    "mu_kinetic": None,  # default: two thirds of mu_static
    "slip_distance": None, "stick_speed": None,
    "restitution": 0.0,  # contact elasticity in [0, 1]: 0 inelastic impacts, 1 no impact loss
    "drive_damping": 0.0,
    "drive_preload": 0.0,  # N, initial spring force
    "gravity": 0.0,  # m/s^2; negligible at the micrometre scale
    "name": "",
    # random heights (m): the std of each asperity's height about `height` (or the flank_angle's)
    "height_std": None, "lower_height_std": None, "upper_height_std": None,
    "height_distribution": "gaussian",  # or "uniform"
    # rough surfaces from profiles (asperity2d.surface.source)
    "lower_surface": None, "upper_surface": None,  # SurfaceProfile, (x, z), (n, 2), path, Asperities
    "surface_unit": None,  # "m" | "mm" | "um" | "nm" of a profile file's columns
    "min_prominence": None,  # m, default 0.1 x the profile's rms height
    "min_width": 0.0,  # m, width at half prominence
    "surface_detrend": True,  # remove the profile's least-squares line first
    "modulus": None,  # Pa: stiffness K = 2 E b per profile asperity (seed 000 Table 1)
    "density": None,  # kg/m^3: mass rho b^2 h / 3 per profile asperity (Appendix A)
}

SPACINGS = ("regular", "random", "random-upper", "random-lower")
HALF_SHAPES = ("apex-cut", "full-base")
#: Pairs that say the same thing two ways: give one or the other.
_EXCLUSIVE = (("mu", "mu_static"), ("mu", "mu_kinetic"), ("damping", "damping_ratio"),
              ("height", "flank_angle"), ("modulus", "stiffness"), ("density", "mass"))
#: Per-surface parameters a profile surface sets itself.
_FROM_PROFILE = ("count", "spacing", "pitch", "profile", "height_std")
_POSITIVE = ("base", "pitch", "mass", "stiffness", "slider_mass", "drive_stiffness", "drive_velocity")
_NONNEGATIVE = ("damping_ratio", "normal_load", "mu_static", "min_gap", "drive_damping", "gravity")
_OPTIONAL_POSITIVE = ("height", "lower_pitch", "upper_pitch", "travel_down", "travel_up",
                      "interference", "stick_speed", "min_prominence", "modulus", "density")
_OPTIONAL_NONNEGATIVE = ("mu", "mu_kinetic", "slip_distance", "height_std", "lower_height_std",
                         "upper_height_std")
_PER_ITEM = {"mass": False, "stiffness": False, "damping": True}  # name -> zero allowed


def _check_arguments(p: dict, given: set, spacing: str) -> None:
    """Type- and range-check every parameter, used by the chosen set-up or not."""
    for a, b in _EXCLUSIVE:
        if a in given and b in given:
            raise SceneError(f"`{a}` and `{b}` both given: they set the same thing, give one")
    for name in ("lower_count", "upper_count"):
        check_int(name, p[name], minimum=1)
    for name in _POSITIVE + _NONNEGATIVE + _OPTIONAL_POSITIVE + _OPTIONAL_NONNEGATIVE:
        value = p[name]
        if value is None and name in _OPTIONAL_POSITIVE + _OPTIONAL_NONNEGATIVE:
            continue
        if name in _PER_ITEM and not is_real(value):
            continue  # a sequence, checked per item below
        (check_positive if name in _POSITIVE + _OPTIONAL_POSITIVE else check_nonnegative)(name, value)
    for name, zero in _PER_ITEM.items():
        if p[name] is None:
            continue
        if p["lower_surface"] is not None and not is_real(p[name]):
            raise SceneError(f"`{name}` must be one number with `lower_surface` (the profile sets the "
                             f"asperity count){'; `modulus` / `density` give per-asperity values' if name != 'damping' else ''}")
        per_item(name, p[name], p["lower_count"], allow_zero=zero)
    if not 0.0 < check_finite("flank_angle", p["flank_angle"]) < 90.0:
        raise SceneError(f"`flank_angle` must be in (0, 90) degrees, got {show(p['flank_angle'])}")
    check_finite("drive_force", p["drive_force"])
    check_finite("drive_preload", p["drive_preload"])
    check_choice("track", p["track"], ("free", "fixed"))
    check_choice("half_shape", p["half_shape"], HALF_SHAPES)
    check_text("name", p["name"])
    for name in ("lower_profile", "upper_profile"):
        if p[name] is not None:
            check_choice(name, p[name], KINDS)
    for name in ("lower_spacing", "upper_spacing"):
        if p[name] is not None:
            check_choice(name, p[name], ("regular", "random"))
    check_choice("height_distribution", p["height_distribution"], DISTRIBUTIONS)
    check_nonnegative("min_width", p["min_width"])
    if p["surface_unit"] is not None:
        check_choice("surface_unit", p["surface_unit"], UNITS)
    for surface in ("lower", "upper"):
        if p[f"{surface}_surface"] is None:
            continue
        for what in _FROM_PROFILE:
            if f"{surface}_{what}" in given:
                raise SceneError(f"`{surface}_{what}` and `{surface}_surface` both given: the profile "
                                 f"sets the {surface} surface's {what.replace('_', ' ')}")
    if not isinstance(p["surface_detrend"], bool):
        raise SceneError(f"`surface_detrend` must be True or False, got {show(p['surface_detrend'])}")
    if p["lower_surface"] is not None and p["upper_surface"] is not None:
        if "height_std" in given:
            raise SceneError("`height_std` has no surface to apply to: both surfaces are profiles")
        if spacing != "regular":
            raise SceneError(f"`spacing` = {spacing!r} has no surface to apply to: both surfaces are profiles")
    if p["lower_surface"] is None and ("modulus" in given or "density" in given):
        raise SceneError("`modulus` / `density` set the stiffness / mass of a profile's asperities: "
                         "give `lower_surface` too (or `stiffness` / `mass`)")


def make_scene(*, spacing: str = "regular", seed: int = 0, profile: str = "full",
               drive: str = "spring", **overrides) -> Scene:
    """Build a scene from named physical parameters (SI units).

    The defaults are seed 000's Working Model set-up (:data:`SEED_000`): 16
    lower and 4 upper 45° full triangles, Table 1 steel, the slider on a
    fixed-height horizontal track; ``track="free"`` puts it on the surface
    under ``normal_load`` instead.

    Parameters
    ----------
    spacing : {"regular", "random", "random-upper", "random-lower"}
        Spacing of both surfaces; ``"random-upper"`` is seed 000's random
        upper / regular lower case. ``lower_spacing`` / ``upper_spacing``
        override each surface.
    seed : int
        Seed of the random spacings and heights (each surface gets
        independent streams derived from it).
    profile : {"full", "half", "flat"}
        Asperity shape of both surfaces (``lower_profile`` / ``upper_profile``
        override each). ``"half"`` is seed 000 figure 9's half triangle: the
        full triangle of ``base`` and ``flank_angle`` cut through its apex
        (same height and flank, half the base); ``half_shape="full-base"``
        keeps the whole base instead (twice the height at the same angle).
    drive : {"spring", "force"}
        Spring whose far end moves at ``drive_velocity`` (stick-slip), or a
        constant ``drive_force``.
    **overrides
        Any key of :data:`DEFAULTS`; an unknown key raises :class:`SceneError`.

    Rough surfaces
    --------------
    ``height_std`` (m; ``lower_height_std`` / ``upper_height_std`` override
    each surface) gives every asperity its own height, drawn about the
    profile's height (``height`` or the ``flank_angle``'s) from
    ``height_distribution`` ("gaussian" or "uniform"), on the same base (so
    each has its own flank angles). Heights at or below 2e-3 of the base (the
    smallest the engine resolves) are redrawn; a std that would redraw over
    1 % of them is refused (:func:`asperity2d.surface.heights.max_std`).

    ``lower_surface`` / ``upper_surface`` build a surface from a profile (a
    ``SurfaceProfile``, ``(x, z)`` arrays in m, an ``(n, 2)`` array, a file
    path read in ``surface_unit`` or the unit the file states, or an
    ``Asperities`` record): its summits become triangles
    (:mod:`asperity2d.surface.source`: ``surface_detrend``, ``min_prominence``,
    ``min_width``); the upper one is turned face down. Each lower asperity
    gets ``stiffness`` and ``mass``, or by rule from ``modulus`` (K = 2 E b)
    and ``density`` (rho b^2 h / 3). With a profile surface, a fixed track's
    ``interference`` defaults to a quarter of the median lower height, below
    the highest lower tip.
    """
    unknown = sorted(set(overrides) - set(DEFAULTS), key=str)
    if unknown:
        hints = {u: difflib.get_close_matches(str(u), DEFAULTS, n=1) for u in unknown}
        msg = "; ".join(f"`{u}`" + (f" (did you mean `{h[0]}`?)" if h else "") for u, h in hints.items())
        raise SceneError(f"unknown scene parameter {msg}")
    check_choice("spacing", spacing, SPACINGS)
    check_choice("drive", drive, ("spring", "force"))
    check_choice("profile", profile, KINDS)
    seed = check_int("seed", seed, minimum=0, maximum=2**63 - 1)
    p = {**DEFAULTS, **overrides}
    given = set(overrides)
    _check_arguments(p, given, spacing)

    def make_profile(kind: str) -> Profile:
        if kind == "half" and p["half_shape"] == "apex-cut":
            return half_of(make_profile("full"))
        if p["height"] is not None:
            return Profile(kind=kind, base=p["base"], height=p["height"])
        return Profile.from_angle(kind, base=p["base"], flank_angle=p["flank_angle"])

    lower_kind = p["lower_spacing"] or ("random" if spacing in ("random", "random-lower") else "regular")
    upper_kind = p["upper_spacing"] or ("random" if spacing in ("random", "random-upper") else "regular")
    streams = np.random.SeedSequence(seed)
    lower_seed, upper_seed = (int(s) for s in streams.generate_state(2))  # the spacings, as always
    lower_heights, upper_heights = streams.spawn(2)  # the heights: independent of the spacings

    def make_spacing(kind, count, surface, shape, sub_seed):
        name = f"{surface}_pitch" if p[f"{surface}_pitch"] is not None else "pitch"
        pitch = p[name]
        if kind == "regular":
            spec = RegularSpacing(count=count, pitch=pitch)
        else:
            spec = RandomSpacing(count=count, mean_pitch=pitch, min_gap=p["min_gap"], seed=sub_seed)
        spec.tips(*shape.runs(upper=surface == "upper"), name=name)  # overlap, named as the user wrote it
        return spec

    records = {s: None if p[f"{s}_surface"] is None else surface_asperities(
        p[f"{s}_surface"], name=f"{s}_surface", unit=p["surface_unit"], min_prominence=p["min_prominence"],
        min_width=p["min_width"], detrend=p["surface_detrend"]) for s in ("lower", "upper")}
    parts, substrate = {}, {"lower": None, "upper": None}  # the slider's valleys are not modelled
    for surface, kind, sub_seed in (("lower", lower_kind, lower_seed), ("upper", upper_kind, upper_seed)):
        if records[surface] is not None:
            shape, spec, shapes, substrate[surface] = surface_spec(*records[surface])
            parts[surface] = (shape, spec, shapes)
        else:
            shape = make_profile(p[f"{surface}_profile"] or profile)
            parts[surface] = (shape, make_spacing(kind, p[f"{surface}_count"], surface, shape, sub_seed), None)
    floor = MIN_LENGTH_RATIO * parts["lower"][0].base  # the smallest height the engine resolves
    for surface, stream in (("lower", lower_heights), ("upper", upper_heights)):
        shape, spec, shapes = parts[surface]
        name = f"{surface}_height_std" if p[f"{surface}_height_std"] is not None else "height_std"
        if records[surface] is not None:
            check_heights(shapes, name=f"{surface}_surface", floor=floor)
        elif p[name] is not None:
            shapes = random_shapes(shape, spec.count, std=p[name], name=name, floor=floor,
                                   distribution=p["height_distribution"], seed=stream,
                                   upper=surface == "upper")
        parts[surface] = (shape, spec, shapes)
    if records["lower"] is None:
        mass, stiffness = p["mass"], p["stiffness"]
    else:
        mass, stiffness = lower_material(
            records["lower"][0], own=isinstance(p["lower_surface"], Asperities),
            stiffness=p["stiffness"] if "stiffness" in given else None, modulus=p["modulus"],
            mass=p["mass"] if "mass" in given else None, density=p["density"],
            default_stiffness=p["stiffness"], default_mass=p["mass"])
    interference = p["interference"]
    if interference is None and any(r is not None for r in records.values()):
        interference = parts["lower"][0].height / 4.0  # a quarter of the median lower height
    lower_shape, lower_spacing, lower_shapes = parts["lower"]
    upper_shape, upper_spacing, upper_shapes = parts["upper"]
    lower = LowerSurface(
        profile=lower_shape, spacing=lower_spacing, shapes=lower_shapes, substrate=substrate["lower"],
        mass=mass, stiffness=stiffness, damping=p["damping"],
        damping_ratio=p["damping_ratio"], travel_down=p["travel_down"], travel_up=p["travel_up"],
        lateral_stiffness=p["lateral_stiffness"], lateral_damping=p["lateral_damping"])
    slider = Slider(
        profile=upper_shape, spacing=upper_spacing, shapes=upper_shapes,
        mass=p["slider_mass"], track=p["track"], normal_load=p["normal_load"],
        interference=interference)
    if drive == "spring":
        drv = SpringDrive(stiffness=p["drive_stiffness"], velocity=p["drive_velocity"],
                          damping=p["drive_damping"], preload=p["drive_preload"])
    else:
        drv = ConstantForce(force=p["drive_force"])
    if p["mu"] is not None:
        mu_s = mu_k = check_nonnegative("mu", p["mu"])
    else:
        mu_s = p["mu_static"]
        mu_k = kinetic_default(mu_s) if p["mu_kinetic"] is None else p["mu_kinetic"]
    contact = Contact(mu_static=mu_s, mu_kinetic=mu_k, slip_distance=p["slip_distance"],
                      stick_speed=p["stick_speed"], restitution=p["restitution"])
    name = p["name"] or f"{spacing}-{profile}-{drive}-{p['track']}-seed{seed}"
    if not p["name"] and any(r is not None for r in records.values()):
        name = "-".join(f"{k}={label(p[f'{k}_surface'])}" for k, r in records.items() if r is not None) + \
            f"-{drive}-{p['track']}-seed{seed}"
    scene = Scene(lower=lower, slider=slider, drive=drv, contact=contact, gravity=p["gravity"], name=name)
    check_scales(scene, Units.for_scene(scene))  # refused here, not only when it is run
    return scene
