"""Per-step energy accounting of an asperity :class:`~asperity2d.engine.Engine`.

:class:`EnergyMeter` hooks into ``Engine.step_hooks`` and, after every step,
reads all bodies and all contacts with ``pymunk.batch`` and the spring
impulses, then integrates (vectorised over bodies, contacts and springs):

* ``drive_work`` -- work of the moving far end of the drive spring,
  sum F_d·V·dt (J); the only energy source (the normal load and gravity are
  potentials, below);
* ``friction_work`` -- energy dissipated by the contacts' tangential
  (Coulomb) impulses, -sum J_t·v_rel (J, >= 0);
* ``normal_work`` -- energy lost by the contacts' normal impulses,
  -sum J_n·v_rel (J): pymunk contacts are perfectly inelastic (restitution 0),
  so every impact on a flank loses the normal part of the relative kinetic
  energy; this is the "inelastic contact loss";
* ``damper_work`` -- energy dissipated by the dampers of the ``DampedSpring``
  tracks and lattice links and by the drive damper (J, >= 0). pymunk applies
  a spring's force and its damping as one accumulated impulse; the damping
  part is that impulse minus k·(rest - length)·dt;
* ``stored_energy`` -- kinetic energy of every body plus the energy of every
  spring (tracks, lattice, drive) plus the potential of the normal load
  L·y and of gravity (J).

Impulses act on the step's mean velocity (v_n + v_n+1)/2, which makes each
body's kinetic-energy change exact; what the balance then leaves,
``residual = drive_work - friction_work - normal_work - damper_work -
(stored_energy - stored_energy_0)``, is the integrator's (symplectic Euler)
bounded oscillating error plus the energy moved by pymunk's position
correction and the track projection; it does not grow with the distance slid.
"""

from __future__ import annotations

import math

import numpy as np
import pymunk
from pymunk import batch

from ..scene import SpringDrive

_BODY_FIELDS = batch.BodyFields.POSITION | batch.BodyFields.VELOCITY
_ARB_FIELDS = (batch.ArbiterFields.BODY_A_ID | batch.ArbiterFields.BODY_B_ID
               | batch.ArbiterFields.CONTACT_COUNT | batch.ArbiterFields.TOTAL_IMPULSE
               | batch.ArbiterFields.NORMAL)
TOTALS = ("drive_work", "friction_work", "normal_work", "damper_work", "friction_impulse", "time")


class EnergyMeter:
    """Accumulates the energy flows of ``engine`` from now on (SI out, see module doc).

    Construct after settling; it appends itself to ``engine.step_hooks``.
    ``friction_impulse`` (N s) is the time integral of the horizontal contact
    force resisting +x motion, so ``friction_impulse / time`` is the exact
    mean friction force over the metered steps.
    """

    def __init__(self, engine):
        self.engine = e = engine
        u = e.units
        self._energy, self._force = u.energy, u.force
        space = e.layout.space
        buf = batch.Buffer()
        batch.get_space_bodies(space, batch.BodyFields.BODY_ID, buf)
        ids = np.frombuffer(buf.int_buf(), dtype=np.uintp).copy()
        bodies = {b.id: b for b in space.bodies}
        self._ids = ids
        # the batch rows may include the static body: it carries no kinetic energy
        self._mass = np.array([bodies[int(i)].mass if int(i) in bodies else 0.0 for i in ids])
        self._row = {int(i): k for k, i in enumerate(ids)}
        static = len(ids)  # a virtual row holding the static body (at rest, at the origin)
        springs = [c for c in space.constraints if isinstance(c, pymunk.DampedSpring)]
        self._springs = springs
        ra = [self._row.get(c.a.id, static) for c in springs]
        rb = [self._row.get(c.b.id, static) for c in springs]
        self._ra, self._rb = np.array(ra, dtype=np.intp), np.array(rb, dtype=np.intp)
        self._anchor_a = np.array([tuple(c.anchor_a) for c in springs]).reshape(-1, 2)
        self._anchor_b = np.array([tuple(c.anchor_b) for c in springs]).reshape(-1, 2)
        self._rest = np.array([c.rest_length for c in springs])
        self._k = np.array([c.stiffness for c in springs])
        self._slider = self._row[e.layout.slider.id]
        self._spring_drive = isinstance(e.scene.drive, SpringDrive)
        self._g = -space.gravity.y
        self._buf, self._arb = batch.Buffer(), batch.Buffer()
        self.totals = dict.fromkeys(TOTALS, 0.0)  # internal units while running
        pos, vel = self._read()
        self._pos0, self._vel0 = pos, vel
        self._y_ref = pos[self._slider, 1]
        self.stored_energy_0 = self.stored_energy()
        e.step_hooks.append(self)

    def detach(self) -> None:
        """Stop metering (remove the hook)."""
        if self in self.engine.step_hooks:
            self.engine.step_hooks.remove(self)

    # -- reading -------------------------------------------------------------
    def _read(self):
        buf = self._buf
        buf.clear()
        batch.get_space_bodies(self.engine.layout.space, _BODY_FIELDS, buf)
        rows = np.frombuffer(buf.float_buf(), dtype=np.float64).reshape(-1, 4)
        # one extra zero row: the static body
        pos = np.zeros((len(rows) + 1, 2))
        vel = np.zeros((len(rows) + 1, 2))
        pos[:-1], vel[:-1] = rows[:, :2], rows[:, 2:]
        return pos, vel

    def _spring_geometry(self, pos):
        d = (pos[self._rb] + self._anchor_b) - (pos[self._ra] + self._anchor_a)
        length = np.hypot(d[:, 0], d[:, 1])
        return d / np.maximum(length, 1e-300)[:, None], length

    def _internal_stored(self, pos, vel) -> float:
        kinetic = 0.5 * float(np.dot(self._mass, (vel[:-1] ** 2).sum(axis=1)))
        _, length = self._spring_geometry(pos)
        springs = 0.5 * float(np.dot(self._k, (length - self._rest) ** 2))
        e = self.engine
        load = e.load_internal * (pos[self._slider, 1] - self._y_ref)
        grav = self._g * float(np.dot(self._mass, pos[:-1, 1])) if self._g else 0.0
        drive = 0.0
        if self._spring_drive:
            drive = 0.5 * e.drive.k * (self._drive_x() - pos[self._slider, 0]) ** 2
        return kinetic + springs + load + grav + drive

    def _drive_x(self) -> float:
        e = self.engine
        return e.drive.position(e.step_count, e.dt_internal)

    def stored_energy(self) -> float:
        """Kinetic + spring + load/gravity potential energy now (J)."""
        pos, vel = self._read()
        return self._internal_stored(pos, vel) * self._energy

    # -- the hook --------------------------------------------------------------
    def __call__(self) -> None:
        e, tot = self.engine, self.totals
        dt = e.dt_internal
        d = e.drive
        pos, vel = self._read()
        vmean = 0.5 * (vel + self._vel0)
        s = self._slider
        # drive: the force applied during this step was set from the previous state
        if self._spring_drive:
            rel_v = d.v - self._vel0[s, 0]
            # the spring is evaluated at the step's end position (Engine.step)
            f_d = d.k * (self._drive_x() - pos[s, 0]) + d.c * rel_v
            tot["drive_work"] += f_d * d.v * dt
            if d.c:
                tot["damper_work"] += d.c * rel_v * (d.v - vmean[s, 0]) * dt
        else:
            tot["drive_work"] += d.force * vmean[s, 0] * dt
        # contacts
        buf = self._arb
        buf.clear()
        batch.get_space_arbiters(e.layout.space, _ARB_FIELDS, buf)
        ints = np.frombuffer(buf.int_buf(), dtype=np.uintp).reshape(-1, 3)
        if len(ints):
            floats = np.frombuffer(buf.float_buf(), dtype=np.float64).reshape(-1, 4)
            live = ints[:, 2] > 0
            row = self._row
            ra = np.array([row.get(int(i), len(self._ids)) for i in ints[live, 0]], dtype=np.intp)
            rb = np.array([row.get(int(i), len(self._ids)) for i in ints[live, 1]], dtype=np.intp)
            j, n = floats[live, :2], floats[live, 2:]  # impulse on body A, contact normal
            v_rel = vmean[ra] - vmean[rb]
            jn = (j * n).sum(axis=1)
            w_total = (j * v_rel).sum(axis=1)
            w_normal = jn * (n * v_rel).sum(axis=1)
            tot["normal_work"] -= float(w_normal.sum())
            tot["friction_work"] -= float((w_total - w_normal).sum())
            jx_slider = float(j[ra == s, 0].sum() - j[rb == s, 0].sum())
            tot["friction_impulse"] -= jx_slider
        # spring dampers: accumulated impulse minus the spring's own part
        if self._springs:
            impulse = np.array([c.impulse for c in self._springs])
            nvec, length = self._spring_geometry(pos)
            j_damp = impulse - (self._rest - length) * self._k * dt
            vrn = ((vmean[self._rb] - vmean[self._ra]) * nvec).sum(axis=1)
            tot["damper_work"] -= float(np.dot(j_damp, vrn))
        tot["time"] += dt
        self._pos0, self._vel0 = pos, vel

    # -- results ---------------------------------------------------------------
    def report(self) -> dict:
        """The accumulated flows and the balance (SI: J, N s, s), JSON-ready."""
        u, t = self.engine.units, self.totals
        out = {f"{k}_J": float(t[k]) * self._energy for k in ("drive_work", "friction_work", "normal_work",
                                                       "damper_work")}
        out["friction_impulse_Ns"] = t["friction_impulse"] * self._force * u.time
        out["time_s"] = t["time"] * u.time
        stored = float(self.stored_energy())
        out["stored_energy_J"] = stored
        out["stored_energy_change_J"] = stored - self.stored_energy_0
        dissipated = out["friction_work_J"] + out["normal_work_J"] + out["damper_work_J"]
        out["dissipated_J"] = dissipated
        out["residual_J"] = out["drive_work_J"] - dissipated - out["stored_energy_change_J"]
        scale = max(abs(out["drive_work_J"]), dissipated, 1e-300)
        out["residual_fraction"] = float(abs(out["residual_J"]) / scale)
        out["mean_friction_force_N"] = (out["friction_impulse_Ns"] / out["time_s"]
                                        if out["time_s"] > 0 else math.nan)
        return out
