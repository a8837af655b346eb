"""The whole scene: :class:`~asperity2d.Scene` (its parts put together, validated as a whole),
its derived quantities (natural frequencies, periods, the guard floor), its plain-dict and TOML
forms and its one-line description.

A :class:`~asperity2d.Scene` is pure data; it round-trips through plain dicts (JSON,
TOML). :data:`OOTEN_DEFAULTS` holds Ooten's fixed track (the Working Model
set-up of E. Ooten's thesis, see :data:`OOTEN_PARAMETERS`), the defaults of
both these dataclasses and :func:`asperity2d.make_scene` (in
:mod:`asperity2d.builders`), so ``Scene()`` and ``make_scene()`` build the
same scene. Nothing here touches pymunk.

The parts and the parameter records live in one module each and are re-exported here, so
``asperity2d.scene.X`` keeps working for every name of ``__all__``:
``asperity2d.scene_parts`` (:class:`~asperity2d.LowerSurface`, :class:`~asperity2d.Slider`,
the drives, :class:`~asperity2d.Contact`) and ``asperity2d.scene_parameters``
(:class:`Parameter`, :data:`OOTEN_PARAMETERS`, :data:`OOTEN_DEFAULTS`).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from ._format import si
from ._inputs import check_nonnegative, check_text, show
from .errors import SceneError
from .contact_laws import DEFAULT_CONTACT_LAW
from .geometry import ExplicitSpacing, Profile, RandomSpacing, RegularSpacing
from .scene_parameters import OOTEN_DEFAULTS, OOTEN_PARAMETERS, Parameter, kinetic_default  # noqa: F401
from .scene_parts import (TRACKS, ConstantForce, Contact, Drive, LowerSurface, Slider,  # noqa: F401
                          SpringDrive, gershgorin_rows)
from .shapes import Shapes

#: The public names (the API reference's ``asperity2d.scene`` page): those defined here and those
#: of the parts and parameter records it re-exports.
__all__ = ["DEFAULT_CONTACT_LAW", "TRACKS", "FLOOR_OVERLAP", "Parameter", "OOTEN_PARAMETERS", "OOTEN_DEFAULTS",
           "kinetic_default", "LowerSurface", "gershgorin_rows", "Slider", "ConstantForce", "SpringDrive",
           "Contact", "Scene", "TOML_FORMAT", "spec_from_toml", "describe"]

#: How far (fraction of the slider's tip depth) a slider lying on the guard floor still reaches
#: above the lower asperities' bases (:attr:`Scene.floor`): well above the collision slop (1e-3
#: base) and below every free slider's tips in ordinary contact (on Ooten's random spacing
#: the deepest tip in a valley, 0.25 um plus the springs' give, stays above -0.4 um).
FLOOR_OVERLAP = 0.1


@dataclass(frozen=True)
class Scene:
    """A complete asperity contact scene (SI units throughout).

    Frozen: change a part with :func:`dataclasses.replace`. :func:`~asperity2d.make_scene` builds one
    from named parameters; this class is for changing one part of a built scene.

    Parameters
    ----------
    lower : LowerSurface
        The lower asperities on their tracks.
    slider : Slider
        The upper body and its asperities.
    drive : SpringDrive or ConstantForce
        What pulls the slider.
    contact : Contact
        Friction at the asperity contacts.
    gravity : float, default 0.0
        Downward acceleration (m/s^2), >= 0.
    name : str, default ""
        A label (``make_scene`` names it by its parameters).

    See Also
    --------
    asperity2d.make_scene, asperity2d.simulate

    Examples
    --------
    >>> import dataclasses
    >>> import asperity2d as a
    >>> scene = a.make_scene(lower_count=4, upper_count=2)
    >>> scene.name
    'regular-full-spring-fixed-seed0'
    >>> pushed = dataclasses.replace(scene, drive=a.ConstantForce(0.01))
    >>> pushed.drive
    ConstantForce(force=0.01)
    """

    lower: LowerSurface = field(default_factory=LowerSurface)
    slider: Slider = field(default_factory=Slider)
    drive: Drive = field(default_factory=SpringDrive)
    contact: Contact = field(default_factory=Contact)
    gravity: float = 0.0
    name: str = ""

    def __post_init__(self):
        object.__setattr__(self, "gravity", check_nonnegative("gravity", self.gravity))
        check_text("name", self.name)
        for attr, kind in (("lower", LowerSurface), ("slider", Slider), ("contact", Contact)):
            if not isinstance(getattr(self, attr), kind):
                raise SceneError(f"`{attr}` must be a {kind.__name__}, got {show(getattr(self, attr))}")
        if not isinstance(self.drive, (ConstantForce, SpringDrive)):
            raise SceneError(f"`drive` must be a SpringDrive or ConstantForce, got {show(self.drive)}")
        if self.slider.track == "free" and self.slider.normal_load == 0 and self.gravity == 0:
            raise SceneError("`normal_load` must be > 0 for a free slider when `gravity` is 0")
        if self.slider.track == "fixed":
            # Measured from the highest lower tip; it must not reach that asperity's base.
            if self.lower.shapes is None:
                height, what = self.lower.profile.height, "the lower asperity height"
            else:
                i = int(np.argmax(self.lower.shapes.summits))
                height, what = self.lower.shapes.heights[i], f"the height of the highest lower asperity ({i})"
            if self.slider.interference >= height:
                raise SceneError(
                    f"`interference` ({self.slider.interference:g} m) must be smaller than {what} "
                    f"({height:g} m): the tips would reach the base")
            if self.lower.substrate:
                level = self.lower.top - self.slider.interference
                highest = max(z for line in self.lower.substrate for _, z in line)
                if highest >= level:
                    raise SceneError(
                        f"`interference` ({self.slider.interference:g} m) puts the fixed track's tips at "
                        f"{level:g} m, at or below the profile's rigid valley floor ({highest:g} m): the "
                        "slider would jam; use a smaller `interference`")

    # -- display -------------------------------------------------------------
    def __repr__(self) -> str:
        """One readable line (``Scene('name', 16 lower full triangles 1 µm base, ...)``); the full
        parameters are in ``to_dict()``."""
        return f"Scene({self.name!r}, {describe(self)})" if self.name else f"Scene({describe(self)})"

    def _repr_svg_(self) -> str:
        """The scene at rest as an SVG drawing (Jupyter shows it)."""
        from ._display import represent

        return represent(self, "svg")

    # -- derived quantities --------------------------------------------------
    @property
    def base(self) -> float:
        return self.lower.profile.base

    @property
    def floor(self) -> float:
        """Height of the engine's guard floor (m): the lower surface's (``travel_down`` below its
        lowest base level), raised where needed so that a slider lying on it still reaches
        :data:`~asperity2d.scene.FLOOR_OVERLAP` of its tip depth above every lower asperity's base level.

        At ``travel_down`` = the asperity height a slider resting on the floor had its top
        exactly at the base level: it slid beneath the asperities untouched (one lower asperity
        and a free slider: the tip slid down the front flank and passed underneath at a
        quarter of the wedge law). Raised, such a slider meets the asperity flank to flank and
        must climb it. A profile's rigid valleys (``substrate``) are the surface between its
        asperities and keep the lower surface's floor.
        """
        floor = self.lower.floor
        if self.lower.substrate:
            return floor
        top_of_bases = max(self.lower.shape_set().levels)
        return max(floor, top_of_bases - (1.0 - FLOOR_OVERLAP) * self.slider.depth)

    def natural_frequencies(self) -> dict[str, float]:
        """Angular natural frequencies (rad/s) of the scene's spring-mass pairs (inf where a
        ratio overflows: ``Units`` refuses those scenes)."""
        k, m = np.asarray(self.lower.stiffness), np.asarray(self.lower.mass)
        with np.errstate(over="ignore", divide="ignore"):
            freqs = {"lower": float(np.max(np.sqrt(k / m)))}
        if self.lower.is_lattice:
            # Gershgorin bound on the lattice's highest horizontal mode, in O(n) memory
            row = gershgorin_rows(self.lower.lateral_stiffness if self.lower.is_lattice else ())
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
        """The scene ``to_dict()`` wrote; a record that is not a scene's raises SceneError."""
        if not isinstance(data, dict) or data.get("type") != cls.__name__:
            raise SceneError(f"`scene` must be a scene record (a table with type = {cls.__name__!r}), "
                             f"got {type(data).__name__}" + (f" of type {data.get('type')!r}"
                                                             if isinstance(data, dict) else ""))
        try:
            return _from_plain(data)
        except TypeError as exc:  # a missing or unknown field of a component
            raise SceneError(f"`scene` record does not fit: {exc}") from None

    def to_toml(self, path, *, run: dict | None = None):
        """Write the whole scene as a TOML scene file (``asperity2d run FILE`` runs it, bit for
        bit as :func:`~asperity2d.simulate` runs this scene); ``run`` is its ``[run]`` table
        (``duration`` in s). Every number is written exactly (shortest round-trip text); a
        field left at None is left out (it reads back as its default). Returns the path."""
        from ._io import atomic_write_text, toml_text

        tables = {"format": TOML_FORMAT, **({"run": dict(run)} if run else {}), "spec": _drop_none(self.to_dict())}
        return atomic_write_text(path, toml_text(tables, header="asperity2d scene, written by Scene.to_toml"))

    @classmethod
    def from_toml(cls, path) -> "Scene":
        """The scene of a TOML file written by :meth:`to_toml` (``SceneError`` if it is not one;
        a file of ``make_scene`` arguments is read by ``asperity2d.scene_io.read_scene``)."""
        from ._io import read_toml

        data = read_toml("path", path)
        return spec_from_toml(data, path)


#: The format tag of a whole-scene TOML file (:meth:`Scene.to_toml`).
TOML_FORMAT = "asperity2d.scene/1"


def spec_from_toml(data: dict, path) -> Scene:
    """The :class:`Scene` of a parsed whole-scene TOML document (``format``, ``spec``, ``run``)."""
    if data.get("format") != TOML_FORMAT or not isinstance(data.get("spec"), dict):
        raise SceneError(f"`path` {str(path)!r} is not a scene file written by Scene.to_toml (format "
                         f"{TOML_FORMAT!r} and a [spec] table)")
    extra = sorted(set(data) - {"format", "spec", "run"})
    if extra:
        raise SceneError(f"`{extra[0]}` in {str(path)!r} is not part of a scene file (format, [run], [spec])")
    try:
        scene = _from_plain(data["spec"])
    except TypeError as exc:  # a field the component does not have
        raise SceneError(f"`spec` in {str(path)!r} is invalid: {exc}") from None
    if not isinstance(scene, Scene):
        raise SceneError(f"`spec` in {str(path)!r} must describe a Scene, got {type(scene).__name__}")
    return scene


def _drop_none(data):
    """``data`` without the None fields (TOML has no null; each such field defaults to None)."""
    if isinstance(data, dict):
        return {k: _drop_none(v) for k, v in data.items() if v is not None}
    if isinstance(data, list):
        if any(v is None for v in data):
            raise SceneError("a scene with None inside a list cannot be written as TOML")
        return [_drop_none(v) for v in data]
    return data


_KINDS = {"full": "full triangles", "half": "half triangles", "flat": "flat blocks"}


def _si(value: float, unit: str) -> str:
    return si(value, unit, trim=True)


def _span(values, unit: str) -> str:
    lo, hi = float(np.min(values)), float(np.max(values))
    return _si(lo, unit) if math.isclose(lo, hi, rel_tol=1e-9) else f"{_si(lo, unit)}–{_si(hi, unit)}"


def describe(scene: Scene) -> str:
    """A one-line, plain-words summary of ``scene``: surfaces, slider, drive (SI prefixes)."""
    lower, slider, drive = scene.lower, scene.slider, scene.drive
    kind = _KINDS.get(lower.profile.kind, lower.profile.kind)
    text = f"{lower.count} lower {kind} {_si(lower.profile.base, 'm')} base"
    if lower.shapes is not None:
        text = (f"{lower.count} lower {kind}, bases {_span(lower.shape_set().bases, 'm')}, "
                f"heights {_span(lower.heights(), 'm')}")
    spacing = lower.spacing
    if isinstance(spacing, RegularSpacing):
        text += f", pitch {_si(spacing.pitch, 'm')} regular"
    elif isinstance(spacing, RandomSpacing):
        text += f", mean pitch {_si(spacing.mean_pitch, 'm')} random"
    else:
        text += f", mean pitch {_si(spacing.mean_pitch, 'm')}"
    if lower.substrate:
        text += " on a rigid substrate"
    if lower.is_lattice:
        text += ", joined by lateral springs"
    text += f"; slider {slider.count} tip{'s' if slider.count != 1 else ''}"
    if slider.track == "fixed":
        text += f" on a fixed track ({_si(slider.interference, 'm')} interference)"
    else:
        text += f", free under {_si(slider.normal_load, 'N')}"
    if isinstance(drive, SpringDrive):
        text += f"; spring drive {_si(drive.stiffness, 'N/m')} at {_si(drive.velocity, 'm/s')}"
    else:
        text += f"; constant force {_si(drive.force, 'N')}"
    return text


_TYPES = {c.__name__: c for c in (Scene, LowerSurface, Slider, ConstantForce, SpringDrive,
                                  Contact, Profile, RegularSpacing, RandomSpacing, ExplicitSpacing,
                                  Shapes)}


def _to_plain(obj):
    if dataclasses.is_dataclass(obj):
        out = {"type": type(obj).__name__}
        for f in dataclasses.fields(obj):
            if isinstance(obj, Contact) and f.name == "law" and obj.law == DEFAULT_CONTACT_LAW:
                continue  # the default law is left out: saved scenes read as they did before it was named
            if isinstance(obj, Contact) and f.name == "law_params":
                if obj.law_params:  # a TOML table of the law's parameters (none: left out, as above)
                    out[f.name] = dict(obj.law_params)
                continue
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
