"""Scene builders: named physical parameters in, a validated :class:`~asperity2d.Scene` out.

:func:`~asperity2d.make_scene` is a pure function of its arguments: random spacings and
random heights are reproducible from ``seed`` (each surface gets independent
streams derived from it with ``numpy.random.SeedSequence``: the spacings from
``generate_state(2)`` as always, the heights from its two spawned children).
A surface can also be a measured or generated profile (``lower_surface`` /
``upper_surface``, see ``asperity2d.surface.source``). :data:`PARAMETERS`
lists every parameter it accepts with its default, unit and meaning (the
documentation's parameter table is generated from it) and :data:`DEFAULTS`
is its dict; Ooten's fixed track comes from
:data:`asperity2d.scene.OOTEN_PARAMETERS`, the same records the dataclasses
use, so ``make_scene()`` builds ``Scene()``.
Every argument is checked (type, finiteness, range) before any arithmetic,
whether or not the chosen drive or spacing uses it; an unknown one raises
:class:`~asperity2d.SceneError` with the closest known name, and two that contradict each
other (``mu`` with ``mu_static``) are refused.
"""

from __future__ import annotations

import difflib

import numpy as np

from ._inputs import (check_choice, check_finite, check_int, check_nonnegative, check_positive,
                        check_text, is_real, per_item, show)
from .contact_laws import DEFAULT_CONTACT_LAW, LAWS, contact_law
from .errors import SceneError
from .geometry import KINDS, Profile, RandomSpacing, RegularSpacing, half_of
from .scene import (OOTEN_PARAMETERS, ConstantForce, Contact, LowerSurface, Parameter, Scene, Slider,
                    SpringDrive, kinetic_default)
from .surface.asperities import Asperities
from .surface.heights import DISTRIBUTIONS, random_shapes
from .surface.read import UNITS
from .surface.source import check_heights, label, lower_material, surface_asperities, surface_spec
from .units import MIN_LENGTH_RATIO, Units, check_scales

#: make_scene's named keywords before the overrides, with their defaults (the signature's).
KEYWORDS = (
    Parameter("spacing", "regular", "-", 'spacing of both surfaces: "regular", "random", '
              '"random-upper" (Ooten\'s random upper / regular lower case) or "random-lower"'),
    Parameter("seed", 0, "1", "random seed of the random spacings and heights (each surface gets "
              "its own streams derived from it)"),
    Parameter("profile", "full", "-", 'asperity shape of both surfaces: "full" triangles, "half" '
              "triangles (Ooten's figure 9) or \"flat\" blocks"),
    Parameter("drive", "spring", "-", '"spring": a spring whose far end moves at `drive_velocity` '
              '(stick-slip); "force": a constant `drive_force`'),
)

_P = Parameter


def _law_meaning(q) -> str:
    """A contact law parameter's meaning with its default (the record itself says None: only the
    chosen law's parameters may be given)."""
    if "default" in q.meaning or q.default is None:
        return q.meaning
    return f"{q.meaning} (default {q.default:g}{'' if q.unit == '1' else ' ' + q.unit})"

#: Every override make_scene accepts: Ooten's fixed track (:data:`asperity2d.scene.OOTEN_PARAMETERS`)
#: and the parameters it leaves at a derived value or off. A default of None is derived from
#: the others, as each meaning says.
PARAMETERS = OOTEN_PARAMETERS + (
    _P("height", None, "m", "asperity height, instead of `flank_angle` (default: from the angle)"),
    _P("half_shape", "apex-cut", "-", 'half triangles: "apex-cut" (Ooten\'s figure 9: the full '
       'triangle cut through its apex, half the base) or "full-base" (the whole base, twice as tall)'),
    _P("lower_pitch", None, "m", "pitch of the lower surface (default `pitch`)"),
    _P("upper_pitch", None, "m", "pitch of the slider's tips (default `pitch`)"),
    _P("min_gap", 0.0, "m", "smallest gap between neighbouring asperities under random spacing"),
    _P("lower_spacing", None, "-", '"regular" or "random" for the lower surface (default from `spacing`)'),
    _P("upper_spacing", None, "-", '"regular" or "random" for the slider (default from `spacing`)'),
    _P("lower_profile", None, "-", '"full", "half" or "flat" for the lower surface (default `profile`)'),
    _P("upper_profile", None, "-", '"full", "half" or "flat" for the slider (default `profile`)'),
    _P("damping", None, "N s/m", "damping of each lower track, instead of `damping_ratio`; one "
       "value or one per asperity"),
    _P("travel_down", None, "m", "how far a lower asperity can move below its rest height before "
       "it hits a stop (default its height)"),
    _P("travel_up", None, "m", "how far it can move above its rest height (default its height)"),
    _P("lateral_stiffness", None, "N/m", "horizontal springs between neighbouring lower peaks and "
       "the walls: Ooten's MATLAB lattice (n + 1 values or one); default none (vertical tracks only)"),
    _P("lateral_damping", 0.0, "N s/m", "dampers in parallel with `lateral_stiffness`"),
    _P("interference", None, "m", "fixed track: how far the deepest tip reaches below the highest "
       "lower tip (default a quarter of the asperity height)"),
    _P("slider_start", None, "m", "where the slider's rear tip starts along the track, the first lower "
       "tip at 0 (default the set-up's: left of the surface on the fixed track, over the first valley "
       "when free)"),
    _P("mu", None, "1", "sets `mu_static` and `mu_kinetic` to one value"),
    _P("mu_kinetic", None, "1", "kinetic friction coefficient (default two thirds of `mu_static`)"),
    _P("slip_distance", None, "m", "how far a stuck contact must slide without pause before it "
       "drops from `mu_static` to `mu_kinetic` (default 0.1 % of the base)"),
    _P("stick_speed", None, "m/s", "slip speed below which a sliding contact sticks again "
       "(default 1e-4 of base × natural frequency)"),
    _P("restitution", 0.0, "1", "contact elasticity in [0, 1]: 0 inelastic impacts, 1 no impact loss"),
    _P("contact_law", DEFAULT_CONTACT_LAW, "-", 'the per-contact friction law: "static-kinetic" (the '
       'hold rule), "velocity-weakening", "viscous", "rate-state" or a registered one; its '
       "parameters follow"),
    _P("law_params", None, "-", "the contact law's parameters as a mapping (SI), for a law whose "
       "parameters have no keyword here (one registered from outside)"),
    # the built-in contact laws' own parameters (asperity2d.contact_laws): given only with their law
    # (None here: a keyword of another law than the chosen one is refused, so none is set unless given)
    *(_P(q.name, None, q.unit, _law_meaning(q)) for e in LAWS.values() if e.model == "asperity"
      for q in e.law.parameters),
    _P("drive_damping", 0.0, "N s/m", "damper in parallel with the drive spring"),
    _P("drive_preload", 0.0, "N", "the drive spring's force at the start"),
    _P("gravity", 0.0, "m/s²", "gravitational acceleration (negligible at the micrometre scale)"),
    _P("name", "", "-", "a label for the scene (default built from spacing, profile, drive, track "
       "and seed)"),
    _P("height_std", None, "m", "random heights: standard deviation of each asperity's height "
       "about the nominal one, on both surfaces (default none: equal heights)"),
    _P("lower_height_std", None, "m", "the same for the lower surface only"),
    _P("upper_height_std", None, "m", "the same for the slider only"),
    _P("height_distribution", "gaussian", "-", 'distribution of random heights: "gaussian" or "uniform"'),
    _P("lower_surface", None, "-", "a rough lower surface from a profile: a SurfaceProfile, (x, z) "
       "arrays in m, an (n, 2) array, a file path or an Asperities record"),
    _P("upper_surface", None, "-", "the same for the slider (turned face down)"),
    _P("surface_unit", None, "-", 'unit of a profile file\'s columns: "m", "mm", "um" or "nm" '
       "(default: what the file states)"),
    _P("min_prominence", None, "m", "smallest summit prominence a profile asperity needs "
       "(default 0.1 × the profile's rms height)"),
    _P("min_width", 0.0, "m", "smallest summit width at half prominence"),
    _P("surface_detrend", True, "-", "remove the profile's least-squares line first"),
    _P("modulus", None, "Pa", "profile asperities: stiffness from Young's modulus, K = 2 E b "
       "(Ooten's Table 1 rule)"),
    _P("density", None, "kg/m³", "profile asperities: mass ρ b² h / 3 from the density"),
)
del _P
#: Every override make_scene accepts, with its default (None: derived, see :data:`PARAMETERS`).
DEFAULTS = {p.name: p.default for p in PARAMETERS}

#: The built-in contact laws' parameter keywords -> their law.
_LAW_KEYWORDS = {q.name: k for k, e in LAWS.items() if e.model == "asperity" for q in e.law.parameters}
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


def _law_params(law: str, keys: set, overrides: dict) -> dict:
    """The contact law's parameters from make_scene's keywords and ``law_params``; a built-in
    law's keyword given with another law is refused, naming both."""
    params = overrides.get("law_params")
    if params is None:
        params = {}
    elif not hasattr(params, "items"):
        raise SceneError(f"`law_params` must be a mapping of parameter names to values, got {show(params)}")
    params = dict(params)
    for name, value in overrides.items():
        if name in keys:
            if name in params:
                raise SceneError(f"`{name}` given both as a keyword and in `law_params`: give one")
            params[name] = value
        elif name in _LAW_KEYWORDS:
            owner = _LAW_KEYWORDS[name]
            raise SceneError(f"`{name}` is a parameter of the contact law {owner!r}, and `contact_law` is "
                             f"{law!r}: set contact_law={owner!r} or drop it")
    return params


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

    The defaults are Ooten's fixed track, the Working Model set-up of E.
    Ooten's thesis (:data:`asperity2d.scene.OOTEN_DEFAULTS`): 16 lower and 4
    upper 45° full triangles, steel asperities (Ooten's Table 1), the slider
    on a fixed-height horizontal track; ``track="free"`` puts it on the
    surface under ``normal_load`` instead (the free slider under a load).
    Every keyword, with its unit, default and meaning, is in the parameter
    table of the documentation (:doc:`/parameters`, generated from
    :data:`asperity2d.builders.PARAMETERS`).

    Parameters
    ----------
    spacing : {"regular", "random", "random-upper", "random-lower"}
        Spacing of both surfaces; ``"random-upper"`` is Ooten's random
        upper / regular lower case. ``lower_spacing`` / ``upper_spacing``
        override each surface.
    seed : int
        Seed of the random spacings and heights (each surface gets
        independent streams derived from it).
    profile : {"full", "half", "flat"}
        Asperity shape of both surfaces (``lower_profile`` / ``upper_profile``
        override each). ``"half"`` is Ooten's figure 9 half triangle: the
        full triangle of ``base`` and ``flank_angle`` cut through its apex
        (same height and flank, half the base); ``half_shape="full-base"``
        keeps the whole base instead (twice the height at the same angle).
    drive : {"spring", "force"}
        Spring whose far end moves at ``drive_velocity`` (stick-slip), or a
        constant ``drive_force``.
    **overrides
        Any key of :data:`asperity2d.builders.DEFAULTS` (see
        :data:`asperity2d.builders.PARAMETERS` for units and meanings); an
        unknown key raises :class:`~asperity2d.SceneError`.

    Returns
    -------
    Scene
        The validated scene (SI units).

    Raises
    ------
    SceneError
        An unknown, mistyped, out-of-range or contradictory parameter, named.

    See Also
    --------
    asperity2d.simulate : runs the scene.
    asperity2d.Scene : what it returns; change a part with :func:`dataclasses.replace`.
    asperity2d.surface.self_affine_profile : a rough surface for ``lower_surface=``.

    Notes
    -----
    Rough surfaces: ``height_std`` (m; ``lower_height_std`` / ``upper_height_std`` override
    each surface) gives every asperity its own height, drawn about the
    profile's height (``height`` or the ``flank_angle``'s) from
    ``height_distribution`` ("gaussian" or "uniform"), on the same base (so
    each has its own flank angles). Heights at or below 2e-3 of the base (the
    smallest the engine resolves) are redrawn; a std that would redraw over
    1 % of them is refused (``asperity2d.surface.heights.max_std``).

    ``lower_surface`` / ``upper_surface`` build a surface from a profile (a
    ``SurfaceProfile``, ``(x, z)`` arrays in m, an ``(n, 2)`` array, a file
    path read in ``surface_unit`` or the unit the file states, or an
    ``Asperities`` record): its summits become triangles
    (``asperity2d.surface.source``: ``surface_detrend``, ``min_prominence``,
    ``min_width``); the upper one is turned face down. Each lower asperity
    gets ``stiffness`` and ``mass``, or by rule from ``modulus`` (K = 2 E b)
    and ``density`` (rho b^2 h / 3). With a profile surface, a fixed track's
    ``interference`` defaults to a quarter of the median lower height, below
    the highest lower tip.

    Examples
    --------
    Ooten's set-up, made small for a quick run:

    >>> import asperity2d as a
    >>> scene = a.make_scene(lower_count=4, upper_count=2)
    >>> scene.name, scene.lower.count, scene.slider.count
    ('regular-full-spring-fixed-seed0', 4, 2)

    Random spacing (one surface per seed) and the free slider under a 5 mN load:

    >>> a.make_scene(spacing="random", seed=3, lower_count=4, upper_count=2, track="free",
    ...              normal_load=5e-3).name
    'random-full-spring-free-seed3'

    A rough lower surface: its summits become the asperities:

    >>> from asperity2d.surface import self_affine_profile
    >>> profile = self_affine_profile(n=512, length=20e-6, rms_height=0.2e-6, hurst=0.8, seed=1)
    >>> a.make_scene(lower_surface=profile, upper_count=2).lower.count
    16

    A misspelt parameter is one line, with the likely one:

    >>> a.make_scene(lower_cont=4)
    Traceback (most recent call last):
    ...
    asperity2d.errors.SceneError: unknown scene parameter `lower_cont` (did you mean `lower_count`?)
    """
    # the chosen contact law's parameters (a law registered from outside included) are keywords
    law_name = overrides.get("contact_law", DEFAULT_CONTACT_LAW)
    try:
        law_keys = {q.name for q in contact_law(law_name).parameters}
    except (SceneError, TypeError):
        known = ", ".join(k for k, e in LAWS.items() if e.model == "asperity")
        raise SceneError(f"`contact_law` must be one of {known}, got {show(law_name)}") from None
    unknown = sorted(set(overrides) - set(DEFAULTS) - law_keys, key=str)
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
        interference=interference, start=p["slider_start"])
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
                      stick_speed=p["stick_speed"], restitution=p["restitution"], law=law_name,
                      law_params=_law_params(law_name, law_keys, overrides))
    name = p["name"] or f"{spacing}-{profile}-{drive}-{p['track']}-seed{seed}"
    if not p["name"] and any(r is not None for r in records.values()):
        name = "-".join(f"{k}={label(p[f'{k}_surface'])}" for k, r in records.items() if r is not None) + \
            f"-{drive}-{p['track']}-seed{seed}"
    scene = Scene(lower=lower, slider=slider, drive=drv, contact=contact, gravity=p["gravity"], name=name)
    check_scales(scene, Units.for_scene(scene))  # refused here, not only when it is run
    return scene
