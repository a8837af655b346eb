"""The run's record and its divergence guard, kept in the engine's internal units (part of the
adapter, :mod:`asperity2d.engine`).

:class:`Recorder` samples an :class:`~.core.Engine`'s state into preallocated arrays (the
slider's columns and the lower asperities' displacements and contacts), checks at every sample
that the run has not diverged (kinetic energy against what the scene held and was given;
overlap), fills the SI view that stop conditions and observers see, and hands the record out in
SI (:meth:`Recorder.arrays`). :mod:`asperity2d.run` sees only SI values.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import SimulationError
from .validity import Validity

#: Divergence: deepest overlap (asperity bases); kinetic energy above this
#: multiple of the energy the scene held at t = 0 plus all the drive has put in.
MAX_OVERLAP = 0.5
ENERGY_FACTOR = 10.0
#: The slider's recorded columns, in the order of :attr:`Recorder._cols`.
COLUMNS = ("t", "x", "v", "y", "vy", "drive_x", "drive_force", "normal_force", "friction_force",
           "tangential_force", "contact_count")


class Recorder:
    """Samples of ``engine``'s state (internal units) and the divergence guard's books.

    :attr:`max_overlap` and :attr:`max_drift` are the largest overlap and track drift seen at
    the samples (base lengths); :attr:`size` the number of samples.
    """

    def __init__(self, engine):
        self.engine = engine
        self.reset()

    def reset(self) -> None:
        """An empty record and fresh books (a fork starts here)."""
        n = self.engine.scene.lower.count
        self._cols = np.empty((len(COLUMNS), 64))
        self._lower = np.empty((3, n, 64))
        self.size = 0
        self._last_sampled_step = -1
        self.max_overlap = 0.0
        self.max_drift = 0.0
        self._energy = None  # the divergence guard's books, opened at the first sample
        self.validity = Validity(self.engine)  # the physical-validity checks, beside the guard

    def _check_energy(self, rows: np.ndarray, drive_force: float) -> None:
        """Raise SimulationError if the bodies hold far more kinetic energy than the scene
        had at the first sample plus every joule the drive, the load and gravity could have
        put in since (internal units; also catches NaN and inf)."""
        e = self.engine
        layout, d = e.layout, e.drive
        v = rows[:, 2:]
        kinetic = 0.5 * float(np.dot(layout.masses, np.einsum("ij,ij->i", v, v)))
        b = self._energy
        if b is None:
            sx, sy = rows.item(layout.slider_row, 0), rows.item(layout.slider_row, 1)
            k = np.asarray(e.scene.lower.stiffness) / e.units.stiffness
            potential = 0.5 * float(np.dot(k, rows[layout.lower_rows, 1] ** 2))
            if d.spring:
                potential += 0.5 * d.k * (d.position(e.step_count, e.dt_internal) - sx) ** 2
            floor = 1e-3 * 0.5 * float(k.min()) * layout.lower_height ** 2
            self._energy = {"held": kinetic + potential + floor, "input": 0.0, "x": sx, "y": sy,
                            "f": abs(drive_force), "step": e.step_count, "heights": rows[:, 1].copy(),
                            "g": -layout.space.gravity.y}
            return
        r = layout.slider_row
        sx, sy, svx, svy = rows.item(r, 0), rows.item(r, 1), rows.item(r, 2), rows.item(r, 3)
        steps = e.step_count - b["step"]
        g = b["g"]
        if d.spring:  # the far end's power |F| |v| over the samples' interval, F at its larger end
            b["input"] += max(b["f"], abs(drive_force)) * abs(d.v) * steps * e.dt_internal
        else:
            b["input"] += abs(d.force) * abs(sx - b["x"])
        b["input"] += e.load_internal * abs(sy - b["y"])
        if g:  # gravity's work on every body
            b["input"] += g * float(np.dot(layout.masses, np.abs(rows[:, 1] - b["heights"])))
            b["heights"] = rows[:, 1].copy()
        b["x"], b["y"], b["f"], b["step"] = sx, sy, abs(drive_force), e.step_count
        # pymunk moves a body with its old velocity, then updates the velocity: kinetic energy is
        # ahead of the displacement that paid for it by one step, so allow one step of that work
        # (gravity's share only with gravity: without, a NaN or inf velocity already makes the
        # kinetic energy fail the test below)
        ahead = e.dt_internal * ((0.0 if d.spring else abs(d.force * svx)) + e.load_internal * abs(svy)
                                 + (g * float(np.dot(layout.masses, np.abs(rows[:, 3]))) if g else 0.0))
        limit = ENERGY_FACTOR * (b["held"] + b["input"] + ahead)
        if not kinetic <= limit:  # also true for NaN
            u = e.units
            raise SimulationError(
                f"run diverged at t = {e.time:.6g} s: kinetic energy {kinetic * u.energy:.3g} J is over "
                f"{ENERGY_FACTOR:g} x the {limit / ENERGY_FACTOR * u.energy:.3g} J the scene held and "
                f"was given; use a smaller dt (now {e.dt:.3g} s, default T/50) or more iterations",
                time=e.time)

    def _guard(self, rows: np.ndarray, drive_force: float, overlap: float) -> None:
        """Raise SimulationError if the run has diverged: kinetic energy (:meth:`_check_energy`)
        or asperities overlapping by ``overlap`` (base lengths) over ``MAX_OVERLAP``."""
        self._check_energy(rows, drive_force)
        if overlap > MAX_OVERLAP:
            e = self.engine
            raise SimulationError(
                f"run diverged at t = {e.time:.6g} s: asperities overlap by {overlap:.2f} of a base; "
                f"use a smaller dt (now {e.dt:.3g} s) or more iterations", time=e.time)
        if overlap > self.max_overlap:
            self.max_overlap = overlap
        self.validity.check(rows)

    def check(self) -> None:
        """The divergence guard alone on the engine's current state (a run that keeps no record)."""
        e = self.engine
        rows, r = e.bodies_internal(), e.layout.slider_row
        self._guard(rows, e.drive_force_internal(rows.item(r, 0), rows.item(r, 2)),
                    e.arbiters_internal().max_overlap())

    def sample(self) -> None:
        """Record the engine's current state and check it has not diverged."""
        e = self.engine
        if e.step_count == self._last_sampled_step:
            return
        rows = e.bodies_internal()
        layout = e.layout
        sx, sy, svx, svy = rows[layout.slider_row].tolist()
        drive_force = e.drive_force_internal(sx, svx)
        arbiters = e.arbiters_internal()
        fx, fy, ft, count, overlap = arbiters.forces(e.dt_internal)
        self._guard(rows, drive_force, overlap)
        lower = rows[layout.lower_rows]
        dx = lower[:, 0] - layout.lower_x0
        drift = float(np.abs(dx).max()) if len(dx) and layout.tracked else 0.0
        if layout.fixed_slider:
            drift = max(drift, abs(sy - layout.slider_y_track))
        self.max_drift = max(self.max_drift, drift)
        i = self.size
        if i == self._cols.shape[1]:
            self._cols = np.concatenate([self._cols, np.empty_like(self._cols)], axis=1)
            self._lower = np.concatenate([self._lower, np.empty_like(self._lower)], axis=2)
        drive_x = e.drive.position(e.step_count, e.dt_internal) if e.drive.spring else math.nan
        self._cols[:, i] = (e.step_count, sx, svx, sy, svy, drive_x, drive_force, fy, -fx, ft, count)
        self._lower[0, :, i] = dx
        self._lower[1, :, i] = lower[:, 1]
        self._lower[2, :, i] = arbiters.touched(len(dx))
        self.size = i + 1
        self._last_sampled_step = e.step_count

    def probe(self, probe) -> None:
        """Fill ``probe`` (:class:`asperity2d.run.Probe`) with the current state, SI."""
        e = self.engine
        u = e.units
        sx, sy, svx, _ = e.bodies_internal()[e.layout.slider_row].tolist()
        probe.t = e.step_count * e.dt
        probe.x, probe.v, probe.y = sx * u.length, svx * u.velocity, sy * u.length
        probe.drive_force = e.drive_force_internal(sx, svx) * u.force
        probe.rear_apex_x = (sx + e.layout.upper_apex[0]) * u.length

    def last_apex_x(self) -> float:
        """x of the lower surface's last apex (m)."""
        e = self.engine
        return float(e.layout.lower_apex_x[-1]) * e.units.length

    def arrays(self, start: int = 0) -> dict[str, np.ndarray]:
        """The samples from ``start`` on, SI: the :data:`COLUMNS` (s, m, m/s, N, count) and
        ``lower_dx``, ``lower_dy`` (m), ``lower_contact`` (bool), each lower asperity a row."""
        e, m = self.engine, self.size
        u = e.units
        c = self._cols[:, start:m]
        scale = {"t": e.dt, "x": u.length, "v": u.velocity, "y": u.length, "vy": u.velocity,
                 "drive_x": u.length, "drive_force": u.force, "normal_force": u.force,
                 "friction_force": u.force, "tangential_force": u.force, "contact_count": 1.0}
        arrays = {name: c[j] * scale[name] for j, name in enumerate(COLUMNS)}
        arrays.update(lower_dx=self._lower[0, :, start:m] * u.length,
                      lower_dy=self._lower[1, :, start:m] * u.length,
                      lower_contact=self._lower[2, :, start:m] > 0)
        return arrays
