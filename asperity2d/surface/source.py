"""A rough surface for a scene: a profile (record, arrays or file) -> asperities -> surface spec.

:func:`asperity2d.make_scene` takes ``lower_surface=`` / ``upper_surface=`` as
any of

* a :class:`~asperity2d.surface.SurfaceProfile` (metres);
* arrays: ``(x, z)`` (two sequences) or an ``(n, 2)`` array, in metres;
* a file path (``str`` or ``os.PathLike``): read by
  :func:`~asperity2d.surface.read_profile` in ``surface_unit`` (or the unit the
  file states in a ``# unit: um`` comment); a relative path is relative to
  the working directory (a TOML scene's own folder for the command line);
* an :class:`~asperity2d.surface.Asperities` record (already extracted, its
  own stiffness and mass).

A profile is first levelled (``surface_detrend=True``: its least-squares line
is removed, a tilt of the sample is not roughness), then its summits become
triangles by :func:`~asperity2d.surface.find_asperities` with
``min_prominence`` (default :data:`DEFAULT_PROMINENCE` x the levelled profile's
rms height) and ``min_width``. Each asperity keeps its apex position, its
height and flank runs, and its base level (the summit's elevation is
``level + height``, so only the highest summits meet the other surface).

The upper surface is the profile turned face down about the sliding
direction: z -> -z, x kept; its summits become the slider's downward tips,
the highest summit the deepest tip.

Between lower asperities whose bases do not touch, the profile's valleys
become rigid substrate (:func:`valleys`): without it a rigid tip sinks into a
wide valley down to the engine's guard floor, far below the real valley.
The slider's own valleys are not modelled (a lower tip can rise into a wide
valley of an upper profile until other upper tips rest on the lower surface).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..errors import SceneError
from ..geometry import ExplicitSpacing, Profile
from ..shapes import Shapes
from .asperities import FOOT_TOLERANCE, Asperities, find_asperities
from .profile import SurfaceProfile
from .read import read_profile
from .stats import rms_height

#: Default smallest summit prominence, as a fraction of the levelled profile's rms height.
DEFAULT_PROMINENCE = 0.1


def as_profile(source, *, name: str, unit: str | None = None) -> SurfaceProfile:
    """``source`` (a SurfaceProfile, ``(x, z)`` arrays, an ``(n, 2)`` array or a file path) as a
    profile in metres; errors name the parameter ``name`` (e.g. ``lower_surface``)."""
    if isinstance(source, SurfaceProfile):
        return source
    if isinstance(source, (str, os.PathLike)):
        path = Path(source)
        if not path.is_file():
            raise SceneError(f"`{name}` is not a file: {str(path)!r}")
        try:
            return read_profile(path, unit=unit)
        except SceneError as exc:
            text = str(exc).replace("`unit`", "`surface_unit`").replace("`path`", f"`{name}`")
            raise SceneError(text) from None
    if isinstance(source, (bytes, dict)) or not hasattr(source, "__len__"):
        raise SceneError(f"`{name}` must be a SurfaceProfile, (x, z) arrays, an (n, 2) array, a file "
                         f"path or an Asperities record, got {type(source).__name__}")
    try:
        arr = np.asarray(source, dtype=float)
    except (TypeError, ValueError):
        raise SceneError(f"`{name}` must hold numbers: (x, z) arrays or an (n, 2) array") from None
    if arr.ndim == 2 and arr.shape[0] == 2 and arr.shape[1] != 2:
        x, z = arr
    elif arr.ndim == 2 and arr.shape[1] == 2:
        x, z = arr[:, 0], arr[:, 1]
    else:
        raise SceneError(f"`{name}` arrays must be (x, z) or one (n, 2) array (m), got shape {arr.shape}")
    try:
        return SurfaceProfile(x, z, name=name)
    except SceneError as exc:
        raise SceneError(f"`{name}`: {exc}") from None


def surface_asperities(source, *, name: str, unit: str | None = None,
                       min_prominence: float | None = None, min_width: float = 0.0,
                       detrend: bool = True) -> tuple[Asperities, SurfaceProfile | None]:
    """The asperities of ``source`` (see the module notes) and the levelled profile they came
    from (None for an Asperities record, returned as is).

    The record's stiffness and mass are placeholders (1 N/m, 1 kg) for a profile:
    :func:`asperity2d.make_scene` sets them by its own rule.
    """
    if isinstance(source, Asperities):
        return source, None
    profile = as_profile(source, name=name, unit=unit)
    if not isinstance(detrend, bool):
        raise SceneError(f"`surface_detrend` must be True or False, got {detrend!r}")
    if detrend:
        profile = profile.detrended()
    if min_prominence is None:
        min_prominence = DEFAULT_PROMINENCE * rms_height(profile)
        if not min_prominence > 0:
            raise SceneError(f"`{name}` is flat (rms height 0): it has no summits")
    try:
        found = find_asperities(profile, min_prominence=min_prominence, min_width=min_width,
                                stiffness=1.0, mass=1.0)
    except SceneError as exc:
        raise SceneError(f"`{name}`: {exc}") from None
    return found, profile


def surface_spec(asperities: Asperities, profile: SurfaceProfile | None = None):
    """The surface spec parts of ``asperities``: ``(nominal profile, tip positions, shapes, substrate)``.

    Tips are the apexes, shifted so the first is at x = 0. The nominal
    :class:`Profile` (a full triangle of the median base and median height)
    gives the scene its length scale; each asperity's own shape is in the
    :class:`Shapes` (heights, runs, and the base levels). The same record
    serves either surface: the slider's shapes point down. ``substrate``
    (:func:`valleys` of ``profile``, in the tips' frame; None without a
    profile) is the rigid valley floor between the lower asperities.
    """
    a = asperities
    apex = a.apex_x
    tips = apex - apex[0]
    nominal = Profile(kind="full", base=float(np.median(a.bases)), height=float(np.median(a.heights)))
    pitch = None if a.count > 1 else float(a.bases[0])
    shapes = Shapes(heights=a.heights, left_runs=a.left_runs, right_runs=a.right_runs,
                    levels=a.base_levels)
    substrate = None if profile is None else valleys(a, profile, shift=float(apex[0]))
    return nominal, ExplicitSpacing(positions=tips, mean_pitch=pitch), shapes, substrate


#: Most points kept of one valley of the substrate (the highest of each bin).
VALLEY_POINTS = 16


def valleys(asperities: Asperities, profile: SurfaceProfile, *, shift: float = 0.0) -> tuple:
    """The profile between the feet of neighbouring asperities that do not touch: the rigid
    valley floor (substrate) a rigid tip meets when it sinks between two summits.

    Each valley is a polyline from the right foot of one asperity (at its base level)
    through the profile's points in between, thinned to at most :data:`VALLEY_POINTS` by
    keeping the highest point of each bin (an upper envelope: a tip from above never
    passes below the profile), to the left foot of the next; x minus ``shift`` (m). Its
    points are lowered to the chord joining the two feet where the profile is above it,
    so the rigid floor never stands above the compliant asperities' bases (a bump below
    the prominence threshold next to a foot is flattened).
    """
    a = asperities
    x, z = profile.x, profile.z
    right, left = a.right_feet[:-1], a.left_feet[1:]
    gaps = np.flatnonzero(left - right > FOOT_TOLERANCE * (a.bases[:-1] + a.bases[1:]))
    out = []
    for i in gaps.tolist():
        j0, j1 = int(np.searchsorted(x, right[i], "right")), int(np.searchsorted(x, left[i], "left"))
        xs, zs = x[j0:j1], z[j0:j1]
        if len(xs) > VALLEY_POINTS:
            bins = np.array_split(np.arange(len(xs)), VALLEY_POINTS)
            keep = [b[np.argmax(zs[b])] for b in bins]
            xs, zs = xs[keep], zs[keep]
        # never above the chord joining the two feet: a sub-threshold bump next to a foot must
        # not stand up as a rigid wall in front of (or above) the compliant asperities
        z0, z1 = a.base_levels[i], a.base_levels[i + 1]
        chord = z0 + (z1 - z0) * (xs - right[i]) / (left[i] - right[i])
        line = [(right[i], z0)] + list(zip(xs.tolist(), np.minimum(zs, chord).tolist())) + [(left[i], z1)]
        out.append(tuple((float(u) - shift, float(v)) for u, v in line))
    return tuple(out)


def label(source) -> str:
    """A short name for a profile surface (scene names)."""
    if isinstance(source, (str, os.PathLike)):
        return Path(source).name
    return getattr(source, "name", "") or type(source).__name__


def check_heights(shapes: Shapes, *, name: str, floor: float) -> None:
    """Refuse, naming the parameter ``name``, a profile asperity lower than ``floor`` (m),
    the smallest height the engine resolves (:data:`asperity2d.units.MIN_LENGTH_RATIO` of the
    scene's length scale)."""
    from ..units import MIN_LENGTH_RATIO

    h = np.asarray(shapes.heights)
    if h.min() < floor:
        i = int(np.argmin(h))
        raise SceneError(f"`{name}`: asperity {i} is {h[i]:.3g} m high, under {MIN_LENGTH_RATIO:g} of "
                         f"the scene's length scale (the median lower base, {floor / MIN_LENGTH_RATIO:.3g} m), "
                         f"the smallest height the engine resolves; raise `min_prominence` to at least "
                         f"{floor:.3g} m")


def lower_material(record: Asperities, *, own: bool, stiffness, modulus, mass, density,
                   default_stiffness, default_mass):
    """Track stiffness (N/m) and mass (kg) of a profile's lower asperities.

    ``modulus`` (Pa) -> K = 2 E b and ``density`` (kg/m^3) -> m = rho b^2 h / 3
    per asperity (:func:`table1_stiffness`, :func:`pyramid_mass`); else a given
    ``stiffness`` / ``mass`` for all; else an Asperities record's own values
    (``own``); else the defaults. Per-asperity values come back as tuples.
    """
    from .asperities import pyramid_mass, table1_stiffness

    if modulus is not None:
        k = table1_stiffness(record.bases, modulus)
    else:
        k = stiffness if stiffness is not None else (record.stiffness if own else default_stiffness)
    if density is not None:
        m = pyramid_mass(record.bases, record.heights, density)
    else:
        m = mass if mass is not None else (record.mass if own else default_mass)
    return _plain(m), _plain(k)


def _plain(value):
    return tuple(np.asarray(value, dtype=float).tolist()) if np.ndim(value) else value


def resolve_paths(params: dict, folder) -> dict:
    """``params`` (make_scene's arguments read from a file in ``folder``) with relative profile
    paths in ``lower_surface`` / ``upper_surface`` made relative to ``folder``, so a TOML
    scene names its profile file as it sits beside it."""
    out = dict(params)
    for key in ("lower_surface", "upper_surface"):
        value = out.get(key)
        if isinstance(value, str) and not Path(value).is_absolute():
            out[key] = str(Path(folder) / value)
    return out
