"""SI <-> internal unit scaling.

pymunk's tolerances (``collision_slop`` in length units, ``collision_bias``
and ``error_bias`` per unit time) assume numbers of order one. Raw SI at the
micrometre scale silently disables its overlap correction, so the adapter
works in scaled units: length = asperity base, mass = lower asperity mass,
time = 1 / omega with omega the stiffest spring-mass pair. A micrometre scene
and the same scene scaled up then produce the same internal numbers.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Units:
    """Internal unit scale: ``length`` (m), ``mass`` (kg), ``time`` (s)."""

    length: float
    mass: float
    time: float

    @classmethod
    def for_scene(cls, scene) -> "Units":
        omega = max(scene.natural_frequencies().values())
        return cls(length=scene.base, mass=float(np.mean(scene.lower.mass)), time=1.0 / omega)

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

    def as_dict(self) -> dict:
        return {"length_m": self.length, "mass_kg": self.mass, "time_s": self.time,
                "force_N": self.force, "velocity_m_per_s": self.velocity}
