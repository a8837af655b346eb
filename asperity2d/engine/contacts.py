"""Contacts of an asperity scene: one batch read per step, the stick/slip switch, contact forces.

Part of the adapter (:mod:`asperity2d.engine`). :class:`Arbiters` holds one
``pymunk.batch`` read of every contact after a step; the stick/slip switch and
the force read-out both use it, so the space is read once.

Static > kinetic friction: pymunk has one coefficient per contact (the
product of the two shapes' coefficients; the slider's shapes have 1). After
every step each lower asperity's coefficient is set from the stick/slip state
of its contact with the slider, kept in NumPy arrays. A stuck contact keeps
``mu_static`` until it has slid ``slip_distance`` without pause (speed above
``stick_speed`` every step), so a micro-slip of a step or two under a sudden
load does not make it kinetic; a sliding contact sticks again when its slip
speed drops below ``stick_speed``. The new coefficient acts from the next
step, as a ``pre_solve`` callback would; pymunk is touched only for the
shapes whose coefficient changes.
"""

from __future__ import annotations

import math

import numpy as np
from pymunk import batch

from ..scene import SpringDrive

ARBITER_FIELDS = (batch.ArbiterFields.BODY_A_ID | batch.ArbiterFields.BODY_B_ID
                  | batch.ArbiterFields.CONTACT_COUNT | batch.ArbiterFields.TOTAL_IMPULSE
                  | batch.ArbiterFields.NORMAL | batch.ArbiterFields.DISTANCE_1
                  | batch.ArbiterFields.DISTANCE_2)


class Arbiters:
    """The slider's touching contacts after one step (internal units), from one batch read.

    ``pairs()`` gives each contact's lower asperity index (-1: the floor) and
    normal, cheap enough for every step; :meth:`forces` and :meth:`touched`
    derive the rest when a sample is recorded.
    """

    __slots__ = ("_ints", "_floats", "_slider_id", "_index")

    def __init__(self, buf: batch.Buffer, layout):
        ints = np.frombuffer(buf.int_buf(), dtype=np.uintp).reshape(-1, 3)
        floats = np.frombuffer(buf.float_buf(), dtype=np.float64).reshape(-1, 6)
        if len(ints) and not ints[:, 2].all():  # cached arbiters with no contact points
            keep = ints[:, 2] > 0
            ints, floats = ints[keep], floats[keep]
        self._ints, self._floats = ints, floats
        self._slider_id, self._index = layout.slider_id, layout.lower_index

    def __len__(self) -> int:
        return len(self._ints)

    def pairs(self) -> list[tuple[int, float, float]]:
        """``(lower index, nx, ny)`` of every contact (index -1: the floor)."""
        # Every arbiter is the slider against a lower asperity or the floor (shape
        # filters), so a + b - slider is the other body's id.
        sid, index = self._slider_id, self._index
        return [(index.get(a + b - sid, -1), nx, ny)
                for (a, b, _), (nx, ny) in zip(self._ints.tolist(), self._floats[:, 2:4].tolist())]

    def forces(self, dt: float) -> tuple[float, float, float, int, float]:
        """``(fx, fy, f_tangential, count, max_overlap)`` on the slider (internal units).

        ``fx``, ``fy``: the summed contact force (impulse / dt); ``f_tangential``:
        the summed tangential (Coulomb) parts projected on each contact's +x
        tangent with the sign flipped (resisting +x motion is positive);
        ``count``: touching contacts; ``max_overlap``: the deepest overlap (0 if none).
        """
        if not len(self._ints):
            return 0.0, 0.0, 0.0, 0, 0.0
        ints, floats = self._ints, self._floats
        # impulses are on body A: flip those where the slider is body B
        j = np.where((ints[:, 0] == self._slider_id)[:, None], floats[:, 0:2], -floats[:, 0:2])
        nx, ny = floats[:, 2], floats[:, 3]
        jn = j[:, 0] * nx + j[:, 1] * ny
        ty = np.where(ny >= 0, -nx, nx)  # the tangent (|ny|, ty) points to +x
        ft = (j[:, 0] - jn * nx) * np.abs(ny) + (j[:, 1] - jn * ny) * ty
        # distances are negative when overlapping; a single-point contact has no second one
        depth = np.maximum(-floats[:, 4], np.where(ints[:, 2] > 1, -floats[:, 5], 0.0))
        inv_dt = 1.0 / dt
        # fsum: the arbiters come in hash-set order, which varies between
        # processes; an exactly rounded sum keeps the result bit-identical.
        return (math.fsum(j[:, 0]) * inv_dt, math.fsum(j[:, 1]) * inv_dt, -math.fsum(ft) * inv_dt,
                len(self._ints), max(0.0, float(depth.max())))

    def touched(self, n: int) -> np.ndarray:
        """Boolean mask of the ``n`` lower asperities touching the slider."""
        mask = np.zeros(n, dtype=bool)
        mask[[i for i, _, _ in self.pairs() if i >= 0]] = True
        return mask


def read_arbiters(space, buf: batch.Buffer, layout) -> Arbiters:
    """One batch read of the space's contacts into :class:`Arbiters`."""
    buf.clear()
    batch.get_space_arbiters(space, ARBITER_FIELDS, buf)
    return Arbiters(buf, layout)


class StickSlip:
    """Per-contact static / kinetic friction (internal units).

    The state of each lower asperity's contact with the slider is kept in
    NumPy arrays (``stuck``, ``slid``, ``mu_now``, one entry per lower
    asperity); each step updates only the few asperities in contact, in
    plain Python on the shared batch reads (measured cheaper than whole-array
    NumPy operations for the handful of contacts a slider makes: see
    ``benchmarks/bench_core.py``).
    """

    def __init__(self, scene, units, layout, dt: float):
        contact = scene.contact
        self.mu_static, self.mu_kinetic = contact.mu_static, contact.mu_kinetic
        self.active = self.mu_static != self.mu_kinetic
        self.dt = dt
        n = len(layout.lower_bodies)
        self.shapes = layout.lower_shapes
        self.stuck = np.zeros(n, dtype=bool)
        self.slid = np.zeros(n)  # distance slid since the contact last stuck
        self.mu_now = np.full(n, self.mu_kinetic)
        self._present: list[int] = []  # lower asperities in contact after the last update
        self.slip_distance = (1e-3 * units.length if contact.slip_distance is None
                              else contact.slip_distance) / units.length
        if contact.stick_speed is not None:
            self.stick_speed = contact.stick_speed / units.velocity
        else:
            self.stick_speed = 1e-4
            if isinstance(scene.drive, SpringDrive):
                self.stick_speed = min(self.stick_speed, 0.1 * scene.drive.velocity / units.velocity)

    def copy_to(self, layout) -> "StickSlip":
        """This switch's state, re-pointed at the shapes of ``layout`` (a copied space)."""
        out = object.__new__(StickSlip)
        out.__dict__.update(self.__dict__)
        out.shapes = layout.lower_shapes
        out.stuck, out.slid, out.mu_now = self.stuck.copy(), self.slid.copy(), self.mu_now.copy()
        out._present = list(self._present)
        return out

    def update(self, arbiters: "Arbiters", rows: np.ndarray, layout) -> None:
        """Set each lower asperity's coefficient from its contact's stick/slip state.

        ``rows`` are the bodies' ``[x, y, vx, vy]`` after the step (internal units).
        """
        if not len(arbiters) and not self._present:
            return
        slips: dict[int, float] = {}
        lower_v = rows[layout.lower_rows]
        svx, svy = rows[layout.slider_row, 2:4].tolist()
        for i, nx, ny in arbiters.pairs():
            if i < 0:
                continue
            lvx, lvy = lower_v[i, 2:4].tolist()
            slip = abs((svx - lvx) * ny - (svy - lvy) * nx)
            if slip > slips.get(i, -1.0):
                slips[i] = slip
        stuck, slid, v_stick = self.stuck, self.slid, self.stick_speed
        for i in self._present:
            if i not in slips:  # contact lost
                stuck[i], slid[i] = False, 0.0
                self._set_mu(i, self.mu_kinetic)
        for i, slip in slips.items():
            if i not in self._present:  # a new contact
                stuck[i], slid[i] = slip < v_stick, 0.0
            elif stuck[i]:
                if slip > v_stick:
                    slid[i] += slip * self.dt
                    if slid[i] > self.slip_distance:
                        stuck[i] = False
                else:
                    slid[i] = 0.0
            elif slip < v_stick:
                stuck[i], slid[i] = True, 0.0
            self._set_mu(i, self.mu_static if stuck[i] else self.mu_kinetic)
        self._present = list(slips)

    def _set_mu(self, i: int, mu: float) -> None:
        if self.mu_now[i] != mu:
            self.shapes[i].friction = mu
            self.mu_now[i] = mu
