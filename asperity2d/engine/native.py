"""The per-step calls into Chipmunk, without pymunk's per-call Python layer (part of the adapter).

A run makes four calls into the physics engine every step: set the slider's
force, ``cpSpaceStep``, read every body and read every contact (and sets the
friction coefficient of the shapes whose stick/slip state changed). Through
pymunk's public API each call also pays for its Python bookkeeping:
``Space.step`` checks for bodies added since the last step and for objects
queued for removal or post-step callbacks (the adapter adds and removes
nothing while it steps), ``Body.force`` goes through an attribute-type
wrapper, and each ``pymunk.batch`` read builds a new ``pmBatchedData``.
Measured on Ooten's 16/4 scene (a ~18 us Chipmunk step), that
bookkeeping was ~3 us for the step and force and ~1.5 us for each batch read. :class:`Native` holds the raw handles of one space and
makes the same C calls directly: the numbers are bit-identical (the same C
functions on the same data; ``tests/test_engine_native.py`` checks it
against pymunk's public API).

It relies on pymunk's internals (``Space._space``, ``Body._body``,
``Shape._shape``, ``Buffer._float_arr`` / ``_int_arr`` and the batch iterator
functions of ``pymunk._chipmunk``), which pymunk may change in any release. So
the fast path is chosen by a capability check when this module is imported
(:data:`NATIVE`): the attributes exist, and a small probe scene stepped through
them and through pymunk's public API agrees to the bit. Otherwise -- or with the
environment variable ``ASPERITY2D_PYMUNK_NATIVE=0`` -- the engine makes the same
calls through the public API (:class:`Public`: ``Space.step``, ``Body.force``,
``pymunk.batch``, ``Shape.friction``), bit-identical and ~5 us a step slower;
:data:`NATIVE_REASON` says why. :func:`stepper` and :func:`friction_setter` give
whichever applies.
"""

from __future__ import annotations

import gc
import os

import numpy as np
from pymunk import batch

#: The environment variable that forces pymunk's public API ("0"; anything else: choose by the check).
SWITCH = "ASPERITY2D_PYMUNK_NATIVE"


class Native:
    """Raw Chipmunk handles of ``space``: step it, push ``body``, read bodies into ``bodies``
    and contacts into ``arbiters`` (``pymunk.batch`` buffers, ``*_fields`` their fields).

    pymunk's one-time check of newly added bodies (positive, finite mass and
    moment) is done here, as ``Space.step`` would on its next call.
    """

    __slots__ = ("_space", "_body", "_bodies", "_body_data", "_arbiters", "_arb_data")

    def __init__(self, space, body, bodies: batch.Buffer, body_fields, arbiters: batch.Buffer,
                 arbiter_fields):
        if space.threaded:
            raise RuntimeError("the engine never uses pymunk's threaded stepping")
        if space._add_later or space._remove_later or space._post_step_callbacks:
            raise RuntimeError("objects queued in the space: step it once through pymunk first")
        for b in space._bodies_to_check:
            if b.body_type == b.DYNAMIC and not (0 < b.mass < float("inf") and b.moment > 0):
                raise RuntimeError(f"a dynamic body has mass {b.mass} and moment {b.moment}")
        space._bodies_to_check.clear()
        self._space, self._body = space._space, body._body
        self._bodies, self._body_data = bodies, _data(bodies, body_fields)
        self._arbiters, self._arb_data = arbiters, _data(arbiters, arbiter_fields)

    def step(self, dt: float, fx: float, fy: float) -> None:
        """Set the body's force to ``(fx, fy)``, advance the space by ``dt`` and read every
        body into the bodies buffer (as :meth:`read_bodies`)."""
        lib.cpBodySetForce(self._body, (fx, fy))
        lib.cpSpaceStep(self._space, dt)
        self._bodies._float_arr.num = 0
        lib.cpSpaceEachBody(self._space, _GET_BODY, self._body_data)

    def read_bodies(self) -> None:
        """Every body's fields into the bodies buffer (as ``batch.get_space_bodies``)."""
        self._bodies._float_arr.num = 0
        lib.cpSpaceEachBody(self._space, _GET_BODY, self._body_data)

    def write_bodies(self) -> None:
        """The bodies buffer back into every body (as ``batch.set_space_bodies``)."""
        arr = self._bodies._float_arr
        num, arr.num = arr.num, 0
        lib.cpSpaceEachBody(self._space, _SET_BODY, self._body_data)
        arr.num = num

    def read_arbiters(self) -> tuple[list[int], list[float]]:
        """Every cached contact's fields (as ``batch.get_space_arbiters``), returned as two
        flat lists: the integer fields and the float fields, contact after contact."""
        ints, floats = self._arbiters._int_arr, self._arbiters._float_arr
        ints.num = floats.num = 0
        lib.cpSpaceEachCachedArbiter(self._space, _GET_ARBITER, self._arb_data)
        return ffi.unpack(ints.arr, ints.num), ffi.unpack(floats.arr, floats.num)


def _native_friction_setter(shapes):
    """``set(i, mu)``: the same ``cpShapeSetFriction`` call as ``shapes[i].friction = mu``
    without its Python layer."""
    handles = [shape._shape for shape in shapes]
    set_friction = lib.cpShapeSetFriction

    def set(i: int, mu: float) -> None:
        set_friction(handles[i], mu)

    return set


def _data(buf: batch.Buffer, fields):
    data = ffi.new("pmBatchedData *")
    data.fields = fields.value
    data.floatArray = buf._float_arr
    data.intArray = buf._int_arr
    return data


class Public:
    """The same calls as :class:`Native` through pymunk's public API (the fallback): ``Body.force``
    and ``Space.step``, ``pymunk.batch`` reads and writes, ``Shape.friction``."""

    __slots__ = ("_space", "_body", "_bodies", "_body_fields", "_arbiters", "_arbiter_fields")

    def __init__(self, space, body, bodies: batch.Buffer, body_fields, arbiters: batch.Buffer,
                 arbiter_fields):
        if space.threaded:
            raise RuntimeError("the engine never uses pymunk's threaded stepping")
        self._space, self._body = space, body
        self._bodies, self._body_fields = bodies, body_fields
        self._arbiters, self._arbiter_fields = arbiters, arbiter_fields

    def step(self, dt: float, fx: float, fy: float) -> None:
        """Set the body's force, step the space, read every body (as :meth:`Native.step`)."""
        self._body.force = (fx, fy)
        self._space.step(dt)
        self.read_bodies()

    def read_bodies(self) -> None:
        self._bodies.clear()
        batch.get_space_bodies(self._space, self._body_fields, self._bodies)

    def write_bodies(self) -> None:
        batch.set_space_bodies(self._space, self._body_fields, self._bodies)

    def read_arbiters(self) -> tuple[list[int], list[float]]:
        buf = self._arbiters
        buf.clear()
        batch.get_space_arbiters(self._space, self._arbiter_fields, buf)
        return (np.frombuffer(buf.int_buf(), dtype=np.uintp).tolist(),
                np.frombuffer(buf.float_buf(), dtype=np.float64).tolist())


def _public_friction_setter(shapes):
    """``set(i, mu)``: ``shapes[i].friction = mu``."""
    shapes = list(shapes)

    def set(i: int, mu: float) -> None:
        shapes[i].friction = mu

    return set


def _probe() -> str | None:
    """None if the fast path is usable here; else why not (the fallback is used)."""
    if os.environ.get(SWITCH, "").strip() == "0":
        return f"{SWITCH}=0"
    import pymunk

    global ffi, lib, _GET_BODY, _SET_BODY, _GET_ARBITER
    try:
        from pymunk._chipmunk import ffi, lib

        _GET_BODY = ffi.addressof(lib, "pmSpaceBodyGetIteratorFuncBatched")
        _SET_BODY = ffi.addressof(lib, "pmSpaceBodySetIteratorFuncBatched")
        _GET_ARBITER = ffi.addressof(lib, "pmSpaceArbiterIteratorFuncBatched")
        # behave: a box pushed along a floor, stepped both ways, must agree to the bit
        body_fields = batch.BodyFields.POSITION | batch.BodyFields.VELOCITY
        arbiter_fields = (batch.ArbiterFields.BODY_A_ID | batch.ArbiterFields.BODY_B_ID
                          | batch.ArbiterFields.CONTACT_COUNT | batch.ArbiterFields.TOTAL_IMPULSE
                          | batch.ArbiterFields.NORMAL | batch.ArbiterFields.DISTANCE_1)
        reads = []
        for kind in (Native, Public):
            space = pymunk.Space()
            space.gravity = (0.0, -1.0)
            floor = pymunk.Segment(space.static_body, (-5.0, 0.0), (5.0, 0.0), 0.0)
            body = pymunk.Body(1.0, float("inf"))
            body.position = (0.0, 0.55)
            box = pymunk.Poly.create_box(body, (1.0, 1.0))
            floor.friction = box.friction = 0.5
            space.add(floor, body, box)
            space.step(1e-3)  # pymunk's own first step: its bookkeeping of the new bodies
            store = np.zeros(16)
            bodies = batch.Buffer()
            bodies.set_float_buf(store)
            calls = kind(space, body, bodies, body_fields, batch.Buffer(), arbiter_fields)
            setter = (_native_friction_setter if kind is Native else _public_friction_setter)([box])
            out = []
            for k in range(40):
                calls.step(0.01, 0.3, 0.0)
                setter(0, 0.5 + 0.01 * (k % 3))
                ints, floats = calls.read_arbiters()
                out.append((store[:4].tolist(), ints[2::3], floats, box.friction))
            store[2] = 0.0
            calls.write_bodies()
            calls.read_bodies()
            out.append(store[:4].tolist())
            reads.append(out)
            # Tear the probe scene down now, with free_fast's clean-up (checked here: it must
            # empty the space), before any of its objects goes: left to the cycle collector, a
            # Space can be freed after its bodies at whatever allocation triggers a collection,
            # and Chipmunk's cpSpaceFree then touches freed bodies (a segfault seen in spawned
            # sweep workers importing the engine); an empty space is freed safely in any order.
            _empty(space._space)
            if (lib.cpSpaceContainsShape(space._space, box._shape)
                    or lib.cpSpaceContainsBody(space._space, body._body)):
                return "its clean-up calls do not empty a probe space"
            del calls, setter, space, floor, body, box
            gc.collect()
        if reads[0] != reads[1]:
            return "its direct calls do not agree with pymunk's public API on a probe scene"
    except Exception as exc:  # noqa: BLE001 - any missing or changed internal means: do not use it
        return f"pymunk's internals are not as expected ({type(exc).__name__}: {exc})"
    return None


def stepper(space, body, bodies: batch.Buffer, body_fields, arbiters: batch.Buffer, arbiter_fields):
    """The per-step calls for ``space``: :class:`Native` if :data:`NATIVE`, else :class:`Public`."""
    return (Native if NATIVE else Public)(space, body, bodies, body_fields, arbiters, arbiter_fields)


def friction_setter(shapes):
    """A function ``set(i, mu)`` that sets ``shapes[i]``'s friction coefficient (the direct
    ``cpShapeSetFriction`` call if :data:`NATIVE`, else ``shapes[i].friction = mu``)."""
    return (_native_friction_setter if NATIVE else _public_friction_setter)(shapes)


def free_fast(space):
    """Have ``space`` emptied in linear time when it is garbage collected.

    pymunk frees a space by removing its shapes, then its constraints, then its bodies, each in
    the order Chipmunk lists them; Chipmunk finds each in an array by a linear search from the
    front and in the static body's list of constraints (newest first) by a walk from the head,
    so that order costs O(n^2) (measured: 12 s for a 20,000-asperity scene, over 5 minutes for
    100,000). Here, just before pymunk's own clean-up (a ``weakref.finalize`` on the space runs
    while its objects are still alive), the constraints are removed first-then-last-to-second
    (each is then found at the front of the array, and all but the first at the head of the
    static body's list) and the dynamic bodies likewise: O(n) (0.5 s at 20,000). pymunk's
    clean-up then finds an empty space. Needs the fast path's internals; without them (the
    public API fallback) pymunk frees the space its own way. Returns the finalizer (None then).
    """
    if not NATIVE:
        return None
    import weakref

    return weakref.finalize(space, _empty, space._space)


def _each(each, iterator, cp_space) -> list:
    found = []
    each(cp_space, iterator, ffi.new_handle(found))
    return found


def _front_first(items: list) -> list:
    """The order that removes ``items`` (an array's order) from the array's front every time."""
    return items[:1] + items[:0:-1]


def _empty(cp_space) -> None:
    """Remove every shape, constraint and body of the Chipmunk space ``cp_space`` (see :func:`free_fast`)."""
    for shape in _each(lib.cpSpaceEachShape, lib.ext_cpSpaceShapeIteratorFunc, cp_space):
        lib.cpSpaceRemoveShape(cp_space, shape)
    for constraint in _front_first(_each(lib.cpSpaceEachConstraint, lib.ext_cpSpaceConstraintIteratorFunc,
                                         cp_space)):
        lib.cpSpaceRemoveConstraint(cp_space, constraint)
    bodies = _each(lib.cpSpaceEachBody, lib.ext_cpSpaceBodyIteratorFunc, cp_space)
    dynamic = [b for b in bodies if lib.cpBodyGetType(b) == lib.CP_BODY_TYPE_DYNAMIC]
    for body in _front_first(dynamic) + [b for b in bodies if lib.cpBodyGetType(b) != lib.CP_BODY_TYPE_DYNAMIC]:
        lib.cpSpaceRemoveBody(cp_space, body)


ffi = lib = _GET_BODY = _SET_BODY = _GET_ARBITER = None
#: Why the public API is used (None: the fast path is), decided once at import.
NATIVE_REASON: str | None = None
#: True when the direct Chipmunk calls are used.
NATIVE = False


def _choose() -> None:
    global NATIVE, NATIVE_REASON
    NATIVE_REASON = _probe()
    NATIVE = NATIVE_REASON is None


_choose()
