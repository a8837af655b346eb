"""SI <-> internal unit scaling.

pymunk's tolerances (``collision_slop`` in length units, ``collision_bias``
and ``error_bias`` per unit time) assume numbers of order one. Raw SI at the
micrometre scale silently disables its overlap correction, so the adapter
works in scaled units: length = asperity base, mass = lower asperity mass,
time = 1 / omega with omega the stiffest spring-mass pair. A micrometre scene
and the same scene scaled up then produce the same internal numbers.

:func:`check_scales` refuses, before pymunk sees it, any scene whose
parameters differ from these scales by more than the engine can resolve
(an overflowing mass once aborted the whole process inside Chipmunk).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ._inputs import show
from .errors import SceneError

#: Ratios of a parameter to its internal scale the engine resolves.
RATIO_RANGE = (1e-9, 1e9)
#: Smallest interference and asperity height, in asperity bases: below the
#: collision slop (1e-3 base) a contact is never pushed apart.
MIN_LENGTH_RATIO = 2e-3


@dataclass(frozen=True)
class Units:
    """Internal unit scale: ``length`` (m), ``mass`` (kg), ``time`` (s)."""

    length: float
    mass: float
    time: float

    @classmethod
    def for_scene(cls, scene) -> "Units":
        """The scales of ``scene`` (:class:`SceneError` if they are not finite and positive)."""
        with np.errstate(all="ignore"):
            freqs = scene.natural_frequencies()
            omega = max(freqs.values())
            mass = float(np.mean(scene.lower.mass))
        if not (math.isfinite(omega) and omega > 0 and math.isfinite(mass) and mass > 0
                and math.isfinite(1.0 / omega) and 1.0 / omega > 0):
            culprit = {"lower": "`stiffness` / `mass`", "lattice": "`lateral_stiffness` / `mass`",
                       "drive": "`drive_stiffness` / `slider_mass`"}[max(freqs, key=freqs.get)]
            raise SceneError(f"{culprit} give a natural frequency the engine cannot represent "
                             f"(omega = {omega!r} rad/s)")
        return cls(length=scene.base, mass=mass, time=1.0 / omega)

    @property
    def velocity(self) -> float:
        return self.length / self.time

    @property
    def acceleration(self) -> float:
        return self.length / self.time**2

    @property
    def force(self) -> float:
        return self.mass * self.length / self.time**2

    @property
    def stiffness(self) -> float:
        return self.mass / self.time**2

    @property
    def damping(self) -> float:
        return self.mass / self.time

    @property
    def energy(self) -> float:
        return self.force * self.length

    def to_dict(self) -> dict:
        return {"length_m": self.length, "mass_kg": self.mass, "time_s": self.time,
                "force_N": self.force, "velocity_m_per_s": self.velocity}


def check_scales(scene, units: Units) -> None:
    """Refuse parameters the engine cannot represent next to the scene's scales.

    Every mass, stiffness, damping, force, speed and length is compared with
    its internal unit (:class:`Units`); a ratio outside :data:`RATIO_RANGE`
    (or a length under :data:`MIN_LENGTH_RATIO` bases) raises
    :class:`SceneError` naming the parameter as ``make_scene`` spells it and
    the parameter that set the scale. Per-asperity values (masses,
    stiffnesses, and the heights and bases of :class:`~asperity2d.shapes.Shapes`)
    are checked in one pass each; the message names the asperity.
    """
    from .scene import SpringDrive

    freqs = scene.natural_frequencies()
    setter = {"lower": "`stiffness` and `mass`", "lattice": "`lateral_stiffness` and `mass`",
              "drive": "`drive_stiffness` and `slider_mass`"}[max(freqs, key=freqs.get)]
    scales = {"mass": (units.mass, "kg", "the mean lower asperity `mass`"),
              "stiffness": (units.stiffness, "N/m", f"the stiffest spring-mass pair ({setter})"),
              "damping": (units.damping, "N s/m", f"the stiffest spring-mass pair ({setter})"),
              "force": (units.force, "N", f"the stiffness scale ({setter}) times the asperity `base`"),
              "velocity": (units.velocity, "m/s", f"`base` times the highest natural frequency ({setter})"),
              "length": (units.length, "m", "the asperity `base`"),
              "acceleration": (units.acceleration, "m/s^2", "`base` times the frequency scale squared")}
    lower, slider, drive = scene.lower, scene.slider, scene.drive
    # (name, kind, values): values may be an array (one per asperity), checked in one pass
    checks = [("mass", "mass", lower.mass), ("slider_mass", "mass", slider.mass),
              ("stiffness", "stiffness", lower.stiffness),
              ("damping", "damping", [v for v in lower.damping if v > 0])]
    if lower.is_lattice:
        checks.append(("lateral_stiffness", "stiffness", [v for v in lower.lateral_stiffness if v > 0]))
    checks.append(("lateral_damping", "damping", [v for v in lower.lateral_damping if v > 0]))
    tips = lower.tips()
    checks += [("pitch", "length", lower.spacing.mean_pitch), ("pitch", "length", slider.spacing.mean_pitch),
               ("travel_down", "length", lower.travel_down), ("travel_up", "length", lower.travel_up),
               ("height", "length", lower.heights()), ("height", "length", slider.heights()),
               ("base", "length", slider.shape_set().bases),
               ("surface length", "length", float(tips[-1] - tips[0]) or lower.profile.base)]
    if lower.shapes is not None:
        checks.append(("base", "length", lower.shapes.bases))
    for surface in (lower, slider):
        if surface.shapes is not None:
            span = float(np.ptp(surface.shapes.levels))
            if span > 0:  # how far apart the base levels lie (a measured profile's summits)
                checks.append(("base level spread", "length", span))
    if slider.track == "free":
        checks.append(("normal_load", "force", slider.normal_load))
    else:
        checks.append(("interference", "length", slider.interference))
    if isinstance(drive, SpringDrive):
        checks += [("drive_stiffness", "stiffness", drive.stiffness), ("drive_velocity", "velocity", drive.velocity)]
        if drive.damping > 0:
            checks.append(("drive_damping", "damping", drive.damping))
        if drive.preload != 0:
            checks.append(("drive_preload", "force", abs(drive.preload)))
    elif drive.force != 0:
        checks.append(("drive_force", "force", abs(drive.force)))
    if scene.gravity > 0:
        checks.append(("gravity", "acceleration", scene.gravity))
    low, high = RATIO_RANGE
    if scene.gravity > 0 and scene.gravity / units.acceleration < low:
        # Gravity far below the scene's accelerations changes nothing the engine can resolve (the
        # lower asperities sag by g/omega^2, 1e-13 of a base for steel at 9.81 m/s^2): it is kept
        # (harmless) unless it is the free slider's only load, which would then never press it on.
        checks = [c for c in checks if c[0] != "gravity"]
        if slider.track == "free" and slider.normal_load == 0:
            raise SceneError(
                f"`gravity` = {show(scene.gravity)} m/s^2 is the free slider's only load, and at this scale "
                f"it is {scene.gravity / units.acceleration:.3g} times the scene's accelerations "
                f"({units.acceleration:.3g} m/s^2): too weak to press the slider onto the surface; give a "
                "`normal_load`")
    for name, kind, values in checks:
        scale, unit, what = scales[kind]
        values = np.atleast_1d(np.asarray(values, dtype=float))
        if not len(values):
            continue
        with np.errstate(all="ignore"):
            ratios = values / scale
        floor = MIN_LENGTH_RATIO if name in ("height", "interference") else low
        bad = ~((ratios >= floor) & (ratios <= high))  # also NaN and inf
        if np.any(bad):
            i = int(np.argmax(bad))
            value, ratio = float(values[i]), float(ratios[i])
            which = f" (asperity {i})" if len(values) > 1 else ""
            raise SceneError(
                f"`{name}`{which} = {show(value)} {unit} is {ratio:.3g} times its scale in this scene "
                f"({scale:.3g} {unit}, set by {what}); the engine resolves {floor:g} to {high:g} times: "
                f"bring `{name}` closer to the scene's other parameters")
