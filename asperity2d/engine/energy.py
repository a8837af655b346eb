"""Per-step energy accounting of an asperity :class:`~asperity2d.engine.Engine`: books that close.

:class:`EnergyMeter` hooks into the engine (``projection_hooks`` just before
the track projection, ``step_hooks`` after the step), reads all bodies, the
contacts (``pymunk.batch``) and the spring impulses, and integrates every
energy flow (J). Sources and stores:

* ``drive_work`` -- the drive's work: a spring drive's far end, force x its
  displacement; a constant force, force x the slider's displacement;
* ``stored_energy`` -- kinetic energy of every body, energy of every spring
  (tracks, lattice, drive) and the potential of the normal load L·y and of
  gravity.

Energy removed (J, positive = taken out of the books), one channel each:

* ``friction_work`` -- tangential (Coulomb) contact impulses, -sum J_t·v_rel;
* ``normal_work`` -- normal contact impulses, -sum J_n·v_rel: the impact loss
  (contact restitution 0 loses the normal part of the relative kinetic energy
  at every impact; restitution 1 keeps it). Both count what pymunk applied,
  not what it reports: see :func:`_remembered` (a reported impulse measured
  up to 700 x a step's load impulse with restitution 1 was never applied);
* ``damper_work`` -- the track / lattice dampers and the drive damper;
* ``stop_work`` -- the travel stops: a lower asperity that reaches the end of
  its groove (``travel_down`` / ``travel_up``) is stopped by a perfectly
  inelastic constraint impulse;
* ``constraint_work`` -- the track (groove) reactions elsewhere, whose work is
  the solver's drift off the track and the joints' error correction;
* ``position_correction`` -- pymunk pushes overlapping shapes apart by moving
  them without giving them velocity; the springs, load and drive gain or lose
  energy over that move with no force doing work (negative: energy created);
* ``projection`` -- the track projection (``Engine._project``) puts lower
  asperities back on their grooves (x, vx) and a fixed-track slider at its
  height (y, vy): the kinetic and spring energy it changes;
* ``integrator`` -- symplectic Euler conserves not E but E + C with
  C = -(dt/2)·sum F·v over the conservative forces (springs, load, gravity,
  drive), exactly for linear springs: E then oscillates by -dC, a bounded term
  (|C| <= dt/2·|F||v|) that does not grow with the distance slid.

Impulses act on the step's mean velocity (v_n + v_n+1)/2, which makes each
body's kinetic-energy change exact. Every impulse that is not a spring, load,
drive or contact impulse is a groove joint's, so each body's momentum change
minus the metered impulses is its constraint impulse (``stop_work`` at a
travel end, ``constraint_work`` elsewhere); ``unmatched_impulse_fraction``
checks that against pymunk's own record, the share of it the groove joints do
not report (measured <= 1e-12). ``residual = drive_work - removed -
(stored_energy - stored_energy_0)`` is what the accounting leaves out (the
hanging track springs' geometric nonlinearity, a change of drive speed or
force between steps): below 1e-6 of the drive work.
"""

from __future__ import annotations

import math

import numpy as np
import pymunk
from pymunk import batch

from ..scene import SpringDrive

_ARB_FIELDS = (batch.ArbiterFields.BODY_A_ID | batch.ArbiterFields.BODY_B_ID
               | batch.ArbiterFields.CONTACT_COUNT | batch.ArbiterFields.TOTAL_IMPULSE
               | batch.ArbiterFields.NORMAL)
#: Energy removed from the books, one channel each (see the module doc).
REMOVED = ("friction_work", "normal_work", "damper_work", "stop_work", "constraint_work",
           "position_correction", "projection", "integrator")
#: Of those, the physical losses (the rest are the numerical method's).
PHYSICAL = ("friction_work", "normal_work", "damper_work", "stop_work")
TOTALS = ("drive_work", *REMOVED, "friction_impulse", "time", "remainder_impulse", "unmatched_impulse")


class _Remembered(list):
    """One step's remembered contact impulses ``(id_a, id_b, jx, jy, nx, ny)``.

    ``Space.copy`` pickles collision handlers with their data; a copy is
    inert, so a copied engine never collects them (detach before copying).
    """

    active = True

    def __reduce__(self):
        return _inert, ()


def _inert() -> _Remembered:
    out = _Remembered()
    out.active = False
    return out


def _remembered(arbiter, space, phantoms: _Remembered) -> None:
    """pre_solve: a contact touching again within pymunk's collision persistence (3 steps)
    of separating starts from the impulse it remembered from before; pymunk does not apply
    that impulse (no warm start on a first contact) but reports it in the total."""
    if phantoms.active and arbiter.is_first_contact:
        j = arbiter.total_impulse  # before the solve: the remembered impulse
        if j.x or j.y:
            a, b = arbiter.bodies
            phantoms.append((a.id, b.id, j.x, j.y, *arbiter.normal))


class EnergyMeter:
    """Accumulates the energy flows of ``engine`` from now on (SI out, see module doc).

    Construct after settling; it adds itself to the engine's hooks
    (:meth:`detach` removes it; an engine without a meter pays nothing).
    ``friction_impulse`` (N s) is the time integral of the horizontal contact
    force resisting +x motion, so ``friction_impulse / time`` is the exact
    mean friction force over the metered steps.
    """

    def __init__(self, engine):
        self.engine = e = engine
        layout, scene, u = e.layout, e.scene, e.units
        self._energy, self._force, self._time = u.energy, u.force, u.time
        space = layout.space
        rows = e.bodies_internal()
        nb = len(rows)
        buf = batch.Buffer()
        batch.get_space_bodies(space, batch.BodyFields.BODY_ID, buf)
        ids = np.frombuffer(buf.int_buf(), dtype=np.uintp)
        # rows 0..nb-1 are the batch rows (a static body's row has mass 0 and is not used);
        # row nb is a virtual static body (at rest at the origin) that every static id maps to
        self._mass = np.append(layout.masses[:nb], 0.0)
        self._row = {int(i): k for k, i in enumerate(ids[:nb]) if self._mass[k] > 0}
        self._nb = nb
        springs = [c for c in space.constraints if isinstance(c, pymunk.DampedSpring)]
        self._springs = springs
        self._ra = np.array([self._row.get(c.a.id, nb) for c in springs], dtype=np.intp)
        self._rb = np.array([self._row.get(c.b.id, nb) for c in springs], dtype=np.intp)
        self._anchor_a = np.array([tuple(c.anchor_a) for c in springs]).reshape(-1, 2)
        self._anchor_b = np.array([tuple(c.anchor_b) for c in springs]).reshape(-1, 2)
        self._rest = np.array([c.rest_length for c in springs])
        self._k = np.array([c.stiffness for c in springs])
        self._s = layout.slider_row
        self._spring_drive = isinstance(scene.drive, SpringDrive)
        self._g = -space.gravity.y
        # travel ends of the lower grooves (internal units; none in the lattice)
        self._lower = np.arange(nb)[layout.lower_rows] if layout.tracked else np.zeros(0, np.intp)
        self._down = -scene.lower.travel_down / u.length
        self._up = scene.lower.travel_up / u.length
        grooves = [c for c in space.constraints if isinstance(c, pymunk.GrooveJoint)]
        self._grooves = grooves
        self._groove_rows = np.array([self._row.get(c.b.id, nb) for c in grooves], dtype=np.intp)
        self._arb = batch.Buffer()
        self._phantoms = _Remembered()
        space.on_collision(None, None, pre_solve=_remembered, data=self._phantoms)
        self._pre = np.zeros((nb + 1, 4))
        self.totals = dict.fromkeys(TOTALS, 0.0)  # internal units while running
        self._P, self._V = self._state(rows)
        self._X = self._anchor()
        self._y_ref = self._P[self._s, 1]
        self._E, self._C = self._energies(self._P, self._V, self._X)
        self.stored_energy_0 = self._E * self._energy
        e.projection_hooks.append(self._before_projection)
        e.step_hooks.append(self)

    def detach(self) -> None:
        """Stop metering (remove the hooks and the space's ``pre_solve`` callback)."""
        e = self.engine
        if self in e.step_hooks:
            e.step_hooks.remove(self)
            e.projection_hooks.remove(self._before_projection)
            e.layout.space.on_collision(None, None, pre_solve=pymunk.empty_callback)
            self._phantoms.clear()

    # -- the model -------------------------------------------------------------
    def _state(self, rows):
        """Positions and velocities with the static row appended (copies)."""
        out = np.zeros((self._nb + 1, 4))
        out[:-1] = rows
        return out[:, :2], out[:, 2:]

    def _anchor(self) -> float:
        e = self.engine
        return e.drive.position(e.step_count, e.dt_internal)

    def _elastic(self, P, V, X):
        """Kinetic energy T, potential energy U and the integrator's shadow term
        C = -(dt/2) sum F·v of states stacked on the first axis (``P``, ``V``: (k, rows, 2)),
        with the springs' unit vectors a -> b and forces on b (internal units)."""
        e, s, d, m = self.engine, self._s, self.engine.drive, self._mass
        gap = (P[:, self._rb] + self._anchor_b) - (P[:, self._ra] + self._anchor_a)
        length = np.sqrt((gap * gap).sum(-1))
        nvec = gap / np.maximum(length, 1e-300)[..., None]
        f = self._k * (self._rest - length)
        u = 0.5 * (self._k * (length - self._rest) ** 2).sum(-1) + e.load_internal * (P[:, s, 1] - self._y_ref)
        fv = (f * ((V[:, self._rb] - V[:, self._ra]) * nvec).sum(-1)).sum(-1) - e.load_internal * V[:, s, 1]
        if self._g:
            u = u + self._g * (P[..., 1] @ m)
            fv = fv - self._g * (V[..., 1] @ m)
        if self._spring_drive:
            stretch = X - P[:, s, 0]
            u = u + 0.5 * d.k * stretch ** 2
            fv = fv + d.k * stretch * (V[:, s, 0] - d.v)
        else:
            fv = fv + d.force * V[:, s, 0]
        return 0.5 * ((V * V).sum(-1) @ m), u, -0.5 * e.dt_internal * fv, nvec, f

    def _energies(self, P, V, X):
        """Stored energy E = kinetic + potential and the shadow term C of one state (internal units)."""
        t, u, c, _, _ = self._elastic(P[None], V[None], X)
        return float(t[0] + u[0]), float(c[0])

    def stored_energy(self) -> float:
        """Kinetic + spring + load/gravity potential energy now (J)."""
        P, V = self._state(self.engine.bodies_internal())
        return self._energies(P, V, self._anchor())[0] * self._energy

    # -- the hooks -------------------------------------------------------------
    def _before_projection(self, rows) -> None:
        self._pre[:-1] = rows

    def __call__(self) -> None:
        e, tot, s, d = self.engine, self.totals, self._s, self.engine.drive
        h = e.dt_internal
        P0, V0, X0 = self._P, self._V, self._X
        Pp, Vp = self._pre[:, :2].copy(), self._pre[:, 2:].copy()  # after pymunk, before projection
        P1, V1 = self._state(e.bodies_internal())
        X1 = self._anchor()
        vm = 0.5 * (V0 + Vp)
        Pf = P0 + h * V0  # where the bodies' velocities alone moved them
        # free, corrected (pymunk's), projected states: one vectorised evaluation
        T, U, C, nvec, f = self._elastic(np.stack([Pf, Pp, P1]), np.stack([Vp, Vp, V1]), X1)
        J = self._mass[:, None] * (Vp - V0)  # every impulse of the step, per body
        # drive (applied from the start-of-step state, Engine.step) and load, gravity
        if self._spring_drive:
            f_spring = d.k * (X1 - Pf[s, 0])
            f_damp = d.c * (d.v - V0[s, 0])
            tot["drive_work"] += (f_spring + f_damp) * (X1 - X0)
            tot["damper_work"] += f_damp * ((X1 - X0) - h * vm[s, 0])
            J[s, 0] -= (f_spring + f_damp) * h
        else:
            tot["drive_work"] += d.force * (Pp[s, 0] - P0[s, 0])
            tot["position_correction"] += d.force * (Pp[s, 0] - Pf[s, 0])
            J[s, 0] -= d.force * h
        J[s, 1] += e.load_internal * h
        if self._g:
            J[:, 1] += self._g * self._mass * h
        # springs: pymunk's accumulated impulse = spring part (at Pp) + damping part
        if self._springs:
            j_total = np.array([c.impulse for c in self._springs])
            dv = vm[self._rb] - vm[self._ra]
            v_p, v_f = (dv * nvec[1]).sum(-1), (dv * nvec[0]).sum(-1)
            tot["damper_work"] -= float(np.dot(j_total - f[1] * h, v_p))
            jv = nvec[1] * j_total[:, None]
            np.subtract.at(J, self._rb, jv)
            np.add.at(J, self._ra, jv)
            # the springs acted at the corrected positions, not the free ones: position correction
            tot["position_correction"] -= h * float(np.dot(f[1], v_p) - np.dot(f[0], v_f))
        self._contacts(vm, J)
        # what is left is each body's groove impulse: at a travel end, or a track reaction;
        # cross-check its size against what the grooves report
        w = (J * vm).sum(axis=1)[:-1]
        mag = np.hypot(J[:-1, 0], J[:-1, 1])
        groove = np.zeros(self._nb + 1)
        np.add.at(groove, self._groove_rows, [c.impulse for c in self._grooves])
        tot["remainder_impulse"] += float(mag.sum())
        tot["unmatched_impulse"] += float(np.abs(mag - groove[:-1]).sum())
        y = Pp[self._lower, 1]
        w_stop = float(w[self._lower[(y <= self._down) | (y >= self._up)]].sum())
        tot["stop_work"] -= w_stop
        tot["constraint_work"] -= float(w.sum()) - w_stop
        # position correction (Pf -> Pp), integrator shadow term, projection (Pp -> P1)
        tot["position_correction"] -= float((U[1] - U[0]) + (C[1] - C[0]))
        tot["integrator"] += float(C[1]) - self._C
        self._E, self._C = float(T[2] + U[2]), float(C[2])
        tot["projection"] += float(T[1] + U[1]) - self._E
        tot["time"] += h
        self._P, self._V, self._X = P1, V1, X1

    def _contacts(self, vm, J) -> None:
        """Meter the contact impulses pymunk applied (friction, normal) and take them out of ``J``."""
        buf, row, nb = self._arb, self._row, self._nb
        buf.clear()
        batch.get_space_arbiters(self.engine.layout.space, _ARB_FIELDS, buf)
        ints = np.frombuffer(buf.int_buf(), dtype=np.uintp).reshape(-1, 3)
        floats = np.frombuffer(buf.float_buf(), dtype=np.float64).reshape(-1, 4)
        live = ints[:, 2] > 0  # cached arbiters (not touching) report nothing
        ids_a, ids_b, j, n = ints[live, 0], ints[live, 1], floats[live, :2], floats[live, 2:]
        if self._phantoms:  # reported but never applied: take them off as negative contacts
            ph = self._phantoms
            ids_a = np.concatenate([ids_a, np.array([p[0] for p in ph], dtype=np.uintp)])
            ids_b = np.concatenate([ids_b, np.array([p[1] for p in ph], dtype=np.uintp)])
            vec = np.array([p[2:] for p in ph], dtype=float)
            j, n = np.concatenate([j, -vec[:, :2]]), np.concatenate([n, vec[:, 2:]])
            self._phantoms.clear()
        if not len(j):
            return
        ra = np.array([row.get(int(i), nb) for i in ids_a], dtype=np.intp)  # impulse j is on A
        rb = np.array([row.get(int(i), nb) for i in ids_b], dtype=np.intp)
        v_rel = vm[ra] - vm[rb]
        w_normal = (j * n).sum(axis=1) * (n * v_rel).sum(axis=1)
        tot, s = self.totals, self._s
        tot["normal_work"] -= float(w_normal.sum())
        tot["friction_work"] -= float(((j * v_rel).sum(axis=1) - w_normal).sum())
        tot["friction_impulse"] -= float(j[ra == s, 0].sum() - j[rb == s, 0].sum())
        np.subtract.at(J, ra, j)
        np.add.at(J, rb, j)

    # -- results ---------------------------------------------------------------
    def report(self) -> dict:
        """The accumulated flows and the balance (SI: J, N s, s), JSON-ready.

        ``<channel>_J`` for the drive work and every channel of
        :data:`REMOVED`; ``dissipated_J`` (the physical losses,
        :data:`PHYSICAL`), ``numerical_J`` (the rest), ``stored_energy_J``,
        ``stored_energy_change_J``, ``residual_J`` and ``residual_fraction``
        (of the larger of the drive work and the energy removed), and
        ``numerical_fraction``: the numerical channels' absolute values summed, over the same
        scale. The residual closes by construction (every flow the method makes is a channel);
        ``numerical_fraction`` is what says how good the run is: it shrinks with dt.
        """
        t = self.totals
        out = {f"{k}_J": float(t[k]) * self._energy for k in ("drive_work", *REMOVED)}
        out["friction_impulse_Ns"] = t["friction_impulse"] * self._force * self._time
        out["time_s"] = t["time"] * self._time
        stored = float(self.stored_energy())
        out["stored_energy_J"] = stored
        out["stored_energy_change_J"] = float(stored - self.stored_energy_0)
        out["dissipated_J"] = sum(out[f"{k}_J"] for k in PHYSICAL)
        out["numerical_J"] = sum(out[f"{k}_J"] for k in REMOVED if k not in PHYSICAL)
        removed = out["dissipated_J"] + out["numerical_J"]
        out["residual_J"] = float(out["drive_work_J"] - removed - out["stored_energy_change_J"])
        scale = max(abs(out["drive_work_J"]), abs(removed), 1e-300)
        out["residual_fraction"] = float(abs(out["residual_J"]) / scale)
        # what the numerical method took, channel by channel (they may cancel in numerical_J)
        out["numerical_fraction"] = float(sum(abs(out[f"{k}_J"]) for k in REMOVED if k not in PHYSICAL) / scale)
        out["mean_friction_force_N"] = (out["friction_impulse_Ns"] / out["time_s"]
                                        if out["time_s"] > 0 else math.nan)
        out["unmatched_impulse_fraction"] = (t["unmatched_impulse"] / t["remainder_impulse"]
                                             if t["remainder_impulse"] > 0 else 0.0)
        return out


class ContactWork:
    """Work done on the slider by its contacts, booked by what each contact does (J).

    A step hook (``Engine.step_hooks``), from its construction on (``simulate(...,
    contact_work=True)``, :meth:`asperity2d.run.Run.meter_contact_work`): after every
    step, every contact's impulse on the slider times the slider's mean
    velocity over the step (the work that changes its kinetic energy
    exactly). ``pushing_J``: positive work of contacts pushing the slider on
    towards +x while it moves that way -- a lower spring's restoring force
    through a full triangle's back flank once a tip is past an apex (Ooten's thesis
    figure 9); ``rebound_J``: positive work of contacts throwing it back
    (towards -x, while it moves back: bounces off flanks); ``resisting_J``:
    the work taken by contacts opposing its motion (tips climbing flanks,
    friction), as a positive number. ``floor_J``: the floor guard's net work
    (zero unless tips fall through the lower surface).
    """

    def __init__(self, engine):
        self.engine = engine
        self._v = engine.slider_state()[2]
        self.pushing_J = self.rebound_J = self.resisting_J = self.floor_J = 0.0
        engine.step_hooks.append(self)

    def __call__(self) -> None:
        e = self.engine
        v = e.slider_state()[2]
        v_mean, self._v = 0.5 * (v + self._v), v
        impulse = e.dt * e.units.force  # internal force -> N, times the step (s)
        for index, fx, _ in e.arbiters_internal().slider_forces(e.dt_internal):
            work = fx * impulse * v_mean
            if index < 0:
                self.floor_J += work
            elif work <= 0:
                self.resisting_J -= work
            elif fx > 0:
                self.pushing_J += work
            else:
                self.rebound_J += work

    def report(self) -> dict:
        """The books (J), JSON-ready."""
        return {"pushing_J": self.pushing_J, "rebound_J": self.rebound_J, "resisting_J": self.resisting_J,
                "floor_J": self.floor_J}
