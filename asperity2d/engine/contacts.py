"""Contact-level parts of the asperity engine: stick/slip switching and read-out.

Mixed into :class:`asperity2d.engine.asperity.Engine` (same adapter; split
out to keep each module to one role). Static > kinetic friction: pymunk has
one coefficient per contact (the product of the two shapes' coefficients).
After every step the contacts are read in one batch call and each lower
asperity's coefficient is set from the stick/slip state of its contact with
the slider. A stuck contact keeps ``mu_static`` until it has slid
``slip_distance`` without pause (speed above ``stick_speed`` every step), so a
micro-slip of a step or two under a sudden load does not make it kinetic; a
sliding contact sticks again when its slip speed drops below ``stick_speed``.
"""

from __future__ import annotations

import math

import numpy as np
from pymunk import batch

from ..scene import SpringDrive

_LOWER, _SLIDER, _FLOOR = 1, 2, 4  # shape categories (bit masks) and collision types
_BODY_FIELDS = batch.BodyFields.POSITION | batch.BodyFields.VELOCITY
_FRICTION_FIELDS = (batch.ArbiterFields.BODY_A_ID | batch.ArbiterFields.BODY_B_ID
                    | batch.ArbiterFields.CONTACT_COUNT | batch.ArbiterFields.NORMAL)
_ARB_FIELDS = (batch.ArbiterFields.BODY_A_ID | batch.ArbiterFields.BODY_B_ID
               | batch.ArbiterFields.CONTACT_COUNT | batch.ArbiterFields.TOTAL_IMPULSE
               | batch.ArbiterFields.NORMAL | batch.ArbiterFields.DISTANCE_1
               | batch.ArbiterFields.DISTANCE_2)


class StickSlipSwitch:
    """Per-contact static / kinetic friction (needs the engine's bodies and units)."""

    def _install_friction(self):
        contact, u = self.scene.contact, self.units
        self.mu_static, self.mu_kinetic = mu_s, mu_k = contact.mu_static, contact.mu_kinetic
        for shape in self.space.shapes:
            # Contact friction is the product of the two shapes' coefficients.
            shape.friction = 1.0 if shape.collision_type == _SLIDER else mu_k
        self.two_coefficients = mu_s != mu_k
        n = len(self.lower_bodies)
        self.lower_shapes = [next(iter(b.shapes)) for b in self.lower_bodies]
        #: lower asperity index -> [stuck, distance slid since stuck] of its contact
        self.contact_states: dict[int, list] = {}
        self._mu_now = [mu_k] * n
        self.slip_distance = (1e-3 * u.length if contact.slip_distance is None
                              else contact.slip_distance) / u.length
        if contact.stick_speed is not None:
            self.stick_speed = contact.stick_speed / u.velocity
        else:
            self.stick_speed = 1e-4
            if isinstance(self.scene.drive, SpringDrive):
                self.stick_speed = min(self.stick_speed, 0.1 * self.scene.drive.velocity / u.velocity)

    def _update_friction(self) -> None:
        """Set each lower asperity's coefficient from its contact's stick/slip state.

        Reads the contacts with one ``pymunk.batch`` call after a step and
        loops over the few touching pairs in plain Python (cheaper than NumPy
        for a handful of items, and than a per-contact ``pre_solve``
        callback); a shape is touched only when its state changes. The new
        coefficient acts from the next step, as a ``pre_solve`` would.
        """
        buf = self._fric_buf
        buf.clear()
        batch.get_space_arbiters(self.space, _FRICTION_FIELDS, buf)
        ints = np.frombuffer(buf.int_buf(), dtype=np.uintp).tolist()
        normals = np.frombuffer(buf.float_buf(), dtype=np.float64).tolist()
        sid, index, bodies = self._slider_id, self._lower_index, self.lower_bodies
        svx, svy = self.slider.velocity
        slips: dict[int, float] = {}
        for k in range(len(ints) // 3):
            a, b, count = ints[3 * k: 3 * k + 3]
            i = index.get(b if a == sid else a)
            if i is None or count == 0:
                continue
            lvx, lvy = bodies[i].velocity
            nx, ny = normals[2 * k], normals[2 * k + 1]
            slip = abs((svx - lvx) * ny - (svy - lvy) * nx)
            if slip > slips.get(i, -1.0):
                slips[i] = slip
        states, v_stick = self.contact_states, self.stick_speed
        for i in [i for i in states if i not in slips]:
            del states[i]
            self._set_mu(i, self.mu_kinetic)
        for i, slip in slips.items():
            st = states.get(i)
            if st is None:
                st = states[i] = [slip < v_stick, 0.0]
            elif st[0]:
                if slip > v_stick:
                    st[1] += slip * self.dt
                    if st[1] > self.slip_distance:
                        st[0] = False
                else:
                    st[1] = 0.0
            elif slip < v_stick:
                st[0], st[1] = True, 0.0
            self._set_mu(i, self.mu_static if st[0] else self.mu_kinetic)

    def _set_mu(self, i: int, mu: float) -> None:
        if self._mu_now[i] != mu:
            self.lower_shapes[i].friction = mu
            self._mu_now[i] = mu


class Readout:
    """Batch reads of the bodies and of the slider's contacts (internal units)."""

    def bodies(self) -> np.ndarray:
        """All dynamic bodies' ``[x, y, vx, vy]`` rows (internal units)."""
        buf = self._body_buf
        buf.clear()
        batch.get_space_bodies(self.space, _BODY_FIELDS, buf)
        return np.frombuffer(buf.float_buf(), dtype=np.float64).reshape(-1, 4)

    def contacts(self) -> tuple[float, float, float, int, float, list[int]]:
        """Contact forces on the slider from the last step's impulses (internal units).

        Returns ``(fx, fy, f_tangential, count, max_overlap, touched)``: the
        summed contact force, the summed tangential (Coulomb) parts projected
        on each contact's +x tangent with the sign flipped (resisting +x
        motion is positive), the number of touching contacts, the deepest
        overlap (length units) and the indices of the lower asperities
        touching the slider.
        """
        buf = self._arb_buf
        buf.clear()
        batch.get_space_arbiters(self.space, _ARB_FIELDS, buf)
        # A handful of arbiters: plain Python beats NumPy's per-call overhead.
        ints = np.frombuffer(buf.int_buf(), dtype=np.uintp).tolist()
        floats = np.frombuffer(buf.float_buf(), dtype=np.float64).tolist()
        fx, fy, ft, touched = [], [], [], []
        touching, overlap, sid, index = 0, 0.0, self._slider_id, self._lower_index
        for k in range(len(ints) // 3):
            count = ints[3 * k + 2]
            if count == 0:
                continue
            jx, jy, nx, ny, d1, d2 = floats[6 * k: 6 * k + 6]
            other = ints[3 * k + 1]
            if ints[3 * k] != sid:
                jx, jy, other = -jx, -jy, ints[3 * k]
            if other in index:
                touched.append(index[other])
            jn = jx * nx + jy * ny
            tx, ty = (abs(ny), -nx) if ny >= 0 else (abs(ny), nx)  # tangent with tx >= 0
            fx.append(jx)
            fy.append(jy)
            ft.append((jx - jn * nx) * tx + (jy - jn * ny) * ty)
            touching += 1
            overlap = max(overlap, -d1, -d2 if count > 1 else 0.0)
        inv_dt = 1.0 / self.dt
        # fsum: the arbiters come in hash-set order, which varies between
        # processes; an exactly rounded sum keeps the result bit-identical.
        return (math.fsum(fx) * inv_dt, math.fsum(fy) * inv_dt, -math.fsum(ft) * inv_dt,
                touching, overlap, touched)
