"""Contacts of an asperity scene: one batch read per step, the contact law, contact forces.

Part of the adapter (:mod:`asperity2d.engine`). :class:`Arbiters` holds one
``pymunk.batch`` read of every contact after a step; the stick/slip switch and
the force read-out both use it, so the space is read once.

Friction per contact: pymunk has one coefficient per contact (the product of
the two shapes' coefficients; the slider's shapes have 1). After every step
each lower asperity's coefficient is set by the scene's contact law
(:mod:`asperity2d.contact_laws`) from what its contact with the slider did in
the step (signed slip speed, normal impulse) and the law's state for that
contact, kept per lower asperity. The default law is the static/kinetic switch
with the hold rule: a stuck contact keeps ``mu_static`` until it has slid
``slip_distance`` without pause (speed above ``stick_speed`` every step), so a
micro-slip of a step or two under a sudden load does not make it kinetic; a
sliding contact sticks again when its slip speed drops below ``stick_speed``.
The new coefficient acts from the next step, as a ``pre_solve`` callback
would; pymunk is touched only for the shapes whose coefficient changes.
"""

from __future__ import annotations

import math

import numpy as np
from pymunk import batch

from ..contact_laws import contact_law
from ..scene import SpringDrive
from .native import friction_setter

ARBITER_FIELDS = (batch.ArbiterFields.BODY_A_ID | batch.ArbiterFields.BODY_B_ID
                  | batch.ArbiterFields.CONTACT_COUNT | batch.ArbiterFields.TOTAL_IMPULSE
                  | batch.ArbiterFields.NORMAL | batch.ArbiterFields.DISTANCE_1
                  | batch.ArbiterFields.DISTANCE_2)


class Arbiters:
    """The slider's contacts after one step (internal units), from one batch read.

    Held as two flat Python lists (a slider makes a handful of contacts: plain
    Python beats NumPy's per-call overhead for them, measured in
    ``benchmarks/bench_core.py``). :meth:`pairs` serves the stick/slip switch
    every step; :meth:`forces` and :meth:`touched` serve the recorder.
    """

    __slots__ = ("_ints", "_floats", "_slider_id", "_index")

    def __init__(self, contacts: tuple[list[int], list[float]], layout):
        # a, b, count and jx jy nx ny d1 d2 per contact (:meth:`.native.Native.read_arbiters`)
        self._ints, self._floats = contacts
        self._slider_id, self._index = layout.slider_id, layout.lower_index

    def __len__(self) -> int:
        return len(self._ints) // 3

    def pairs(self) -> list[tuple[int, float, float]]:
        """``(lower index, nx, ny)`` of every touching contact (index -1: the floor)."""
        return pairs((self._ints, self._floats), self._slider_id, self._index)

    def forces(self, dt: float) -> tuple[float, float, float, int, float]:
        """``(fx, fy, f_tangential, count, max_overlap)`` on the slider (internal units).

        ``fx``, ``fy``: the summed contact force (impulse / dt); ``f_tangential``:
        the summed tangential (Coulomb) parts projected on each contact's +x
        tangent with the sign flipped (resisting +x motion is positive);
        ``count``: touching contacts; ``max_overlap``: the deepest overlap (0 if none).
        """
        ints, floats, sid = self._ints, self._floats, self._slider_id
        fx, fy, ft = [], [], []
        for k in range(len(ints) // 3):
            if ints[3 * k + 2] == 0:
                continue
            jx, jy, nx, ny = floats[6 * k: 6 * k + 4]
            if ints[3 * k] != sid:  # impulses are on body A
                jx, jy = -jx, -jy
            jn = jx * nx + jy * ny
            ty = -nx if ny >= 0 else nx  # the tangent (|ny|, ty) points to +x
            fx.append(jx)
            fy.append(jy)
            ft.append((jx - jn * nx) * abs(ny) + (jy - jn * ny) * ty)
        inv_dt = 1.0 / dt
        # fsum: the arbiters come in hash-set order, which varies between
        # processes; an exactly rounded sum keeps the result bit-identical.
        return (math.fsum(fx) * inv_dt, math.fsum(fy) * inv_dt, -math.fsum(ft) * inv_dt, len(fx),
                self.max_overlap())

    def max_overlap(self) -> float:
        """The deepest overlap of the touching contacts (internal length units; 0 if none)."""
        ints, floats = self._ints, self._floats
        overlap = 0.0
        for k in range(2, len(ints), 3):
            count = ints[k]
            if count:  # distances are negative when overlapping; one-point contacts have no second
                i = 2 * k  # contact j = (k - 2) / 3 has d1 at float 6 j + 4 = 2 k
                overlap = max(overlap, -floats[i], -floats[i + 1] if count > 1 else 0.0)
        return overlap

    def slider_forces(self, dt: float) -> list[tuple[int, float, float]]:
        """``(lower index, fx, fy)``: each touching contact's force on the slider (impulse /
        ``dt``, internal units; index -1: the floor), for per-contact work books."""
        ints, floats, sid, index = self._ints, self._floats, self._slider_id, self._index
        out = []
        for k in range(len(ints) // 3):
            if ints[3 * k + 2] == 0:
                continue
            sign = 1.0 if ints[3 * k] == sid else -1.0  # impulses are on body A
            out.append((index.get(ints[3 * k] + ints[3 * k + 1] - sid, -1),
                        sign * floats[6 * k] / dt, sign * floats[6 * k + 1] / dt))
        return out

    def touched(self, n: int) -> np.ndarray:
        """Boolean mask of the ``n`` lower asperities touching the slider."""
        mask = np.zeros(n, dtype=bool)
        mask[[i for i, _, _ in self.pairs() if i >= 0]] = True
        return mask


def pairs(contacts: tuple[list[int], list[float]], slider_id: int, index: dict) -> list[tuple[int, float, float]]:
    """``(lower index, nx, ny)`` of every touching contact in one read of the contacts
    (:meth:`.native.Native.read_arbiters`); index -1: the floor."""
    # Every arbiter is the slider against a lower asperity or the floor (shape
    # filters), so a + b - slider is the other body's id.
    ints, floats = contacts
    return [(index.get(ints[k] + ints[k + 1] - slider_id, -1), floats[2 * k + 2], floats[2 * k + 3])
            for k in range(0, len(ints), 3) if ints[k + 2]]


class StickSlip:
    """Per-contact friction by the scene's contact law (internal units).

    The state of each lower asperity's contact with the slider (the law's state tuple,
    :attr:`~asperity2d.contact_laws.ContactLaw.state_names`, and the current coefficient) is kept
    per lower asperity; :attr:`state` and :attr:`mu` give it as NumPy arrays (:attr:`stuck` and
    :attr:`slid` for the static/kinetic switch). Each step updates only the asperities in
    contact, in plain Python on the shared batch reads: for the handful of contacts a slider
    makes that is cheaper than whole-array NumPy operations (measured:
    ``benchmarks/bench_core.py``), and pymunk is touched only for the shapes whose coefficient
    changes.
    """

    def __init__(self, scene, units, layout, dt: float):
        contact = scene.contact
        self.mu_static, self.mu_kinetic = contact.mu_static, contact.mu_kinetic
        self.dt = dt
        n = len(layout.lower_bodies)
        self._set_friction = friction_setter(layout.lower_shapes)
        self._present = {}.keys()  # lower asperities in contact after the last update
        self._kernel = None  # the C step loop holding this state in its arrays (.kernel), if one does
        self._ints, self._touching = None, []  # the last contacts read, and what they touch
        self.slip_distance = (1e-3 * units.length if contact.slip_distance is None
                              else contact.slip_distance) / units.length
        if contact.stick_speed is not None:
            self.stick_speed = contact.stick_speed / units.velocity
        else:
            self.stick_speed = 1e-4
            if isinstance(scene.drive, SpringDrive):
                self.stick_speed = min(self.stick_speed, 0.1 * scene.drive.velocity / units.velocity)
        #: the per-contact law (asperity2d.contact_laws): its step() is the reference the C loop is held to
        self.law = contact_law(contact.law).from_contact(contact, units=units, stick_speed=self.stick_speed,
                                                         slip_distance=self.slip_distance, dt=dt)
        self.active = self.law.active
        self._state = [self.law.initial] * n
        self._mu = [self.law.idle] * n

    @property
    def state(self) -> np.ndarray:
        """Each lower asperity's law state, one row per asperity, one column per
        :attr:`~asperity2d.contact_laws.ContactLaw.state_names` (the law's initial state when
        not in contact)."""
        self._take_back()
        return np.array(self._state, dtype=float).reshape(len(self._state), len(self.law.state_names))

    @property
    def stuck(self) -> np.ndarray:
        """Whether each lower asperity's contact is stuck (the static/kinetic switch; False when
        not in contact, and for a law without a ``stuck`` state)."""
        self._take_back()
        if self.law.state_names[:1] != ("stuck",):
            return np.zeros(len(self._state), dtype=bool)
        return np.array([s[0] for s in self._state], dtype=bool)

    @property
    def slid(self) -> np.ndarray:
        """Distance each contact has slid since it last stuck (the static/kinetic switch; internal
        length units; 0 for a law without a ``slid`` state)."""
        self._take_back()
        if self.law.state_names[1:2] != ("slid",):
            return np.zeros(len(self._state))
        return np.array([s[1] for s in self._state], dtype=float)

    @property
    def mu(self) -> np.ndarray:
        """Each lower asperity's current friction coefficient."""
        self._take_back()
        return np.array(self._mu)

    def hand_to(self, kernel) -> None:
        """Let the C step loop ``kernel`` (:class:`.kernel.Kernel`) hold and update this state
        in its arrays until the Python side next needs it (:meth:`_take_back`)."""
        if self._kernel is kernel:
            return
        self._take_back()
        if self.law.kernel == "static-kinetic":  # its (stuck, slid) live in the C loop's arrays
            kernel.stuck[:] = [s[0] for s in self._state]
            kernel.slid[:] = [s[1] for s in self._state]
        elif self.law.kernel == "rate-state":  # its theta (NaN where not touching) likewise
            kernel.theta[:] = [s[0] for s in self._state]
        kernel.mu[:] = self._mu
        kernel.present[:] = 0
        kernel.present[list(self._present)] = 1
        self._kernel = kernel

    def _take_back(self) -> None:
        """The state from the C step loop's arrays into the lists, if the loop holds it."""
        k = self._kernel
        if k is None:
            return
        if self.law.kernel == "static-kinetic":
            self._state = [(bool(s), d) for s, d in zip(k.stuck.tolist(), k.slid.tolist())]
        elif self.law.kernel == "rate-state":
            self._state = [(t,) for t in k.theta.tolist()]
        self._mu = k.mu.tolist()
        self._present = dict.fromkeys(np.flatnonzero(k.present).tolist()).keys()
        self._kernel = None

    def copy_to(self, layout) -> "StickSlip":
        """This switch's state, re-pointed at the shapes of ``layout`` (a copied space)."""
        self._take_back()
        out = object.__new__(StickSlip)
        out.__dict__.update(self.__dict__)
        out._set_friction = friction_setter(layout.lower_shapes)
        out._state, out._mu = list(self._state), list(self._mu)
        out._present = dict.fromkeys(self._present).keys()
        out._ints, out._touching = None, []  # the copy's bodies have other ids
        return out

    def update(self, contacts: tuple[list[int], list[float]], rows: np.ndarray, layout) -> None:
        """Set each lower asperity's coefficient by the contact law from what its contact did.

        ``contacts`` is one read of the contacts (:meth:`.native.Native.read_arbiters`, what
        :class:`Arbiters` holds); ``rows`` are the bodies' ``[x, y, vx, vy]`` after the step
        (internal units). Each touching asperity's signed slip speed (the slider over it along the
        +x tangent; the largest in magnitude over the tips touching it) and normal impulse (summed
        over them) go to the law's :meth:`~asperity2d.contact_laws.ContactLaw.step`.
        """
        self._take_back()
        ints, floats = contacts
        present = self._present
        if not ints and not present:
            return
        item = rows.item
        r = layout.slider_row
        svx, svy = item(r, 2), item(r, 3)
        if ints != self._ints:
            # the contacts (their bodies and point counts) changed: find each touching lower
            # asperity, its batch row and where its normal is in the float fields (as pairs());
            # most steps keep the last step's contacts, and this lookup with them
            slider_id, index, row_of = layout.slider_id, layout.lower_index, layout.lower_row_of
            touching = []
            for k in range(0, len(ints), 3):
                if ints[k + 2]:
                    i = index.get(ints[k] + ints[k + 1] - slider_id, -1)
                    if i >= 0:
                        touching.append((2 * k + 2, i, row_of[i]))
            self._ints, self._touching = ints, touching
        speeds: dict[int, float] = {}
        slips: dict[int, float] = {}
        impulses: dict[int, float] = {}
        for j, i, row in self._touching:
            jx, jy, nx, ny = floats[j - 2], floats[j - 1], floats[j], floats[j + 1]
            # the slip along the tangent (abs(ny), ty) that points to +x, ty = -nx if ny >= 0 else nx:
            # the same magnitude, bit for bit, as abs(dvx ny - dvy nx)
            slip = (svx - item(row, 2)) * ny - (svy - item(row, 3)) * nx
            if ny < 0:
                slip = -slip
            speed = abs(slip)
            impulses[i] = impulses.get(i, 0.0) + abs(jx * nx + jy * ny)
            if speed > speeds.get(i, -1.0):  # a lower asperity may touch two tips; NaN is not kept
                speeds[i], slips[i] = speed, slip
        state, mu_now = self._state, self._mu
        law = self.law
        step, idle, initial = law.step, law.idle, law.initial
        if present != slips.keys():  # (compared as sets) a contact may have been lost
            for i in present:
                if i not in slips:  # contact lost
                    state[i] = initial
                    if mu_now[i] != idle:
                        self._set_friction(i, idle)
                        mu_now[i] = idle
        for i, slip in slips.items():
            # the law's reference step (asperity2d.contact_laws), which the C loop is held to
            new = i not in present
            mu, state[i] = step(initial if new else state[i], slip, impulses[i], new)
            if mu_now[i] != mu:
                self._set_friction(i, mu)
                mu_now[i] = mu
        self._present = slips.keys()
