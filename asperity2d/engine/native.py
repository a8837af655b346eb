"""The per-step calls into Chipmunk, without pymunk's per-call Python layer (part of the adapter).

A run makes four calls into the physics engine every step: set the slider's
force, ``cpSpaceStep``, read every body and read every contact (and sets the
friction coefficient of the shapes whose stick/slip state changed). Through
pymunk's public API each call also pays for its Python bookkeeping:
``Space.step`` checks for bodies added since the last step and for objects
queued for removal or post-step callbacks (the adapter adds and removes
nothing while it steps), ``Body.force`` goes through an attribute-type
wrapper, and each ``pymunk.batch`` read builds a new ``pmBatchedData``.
Measured on seed 000's 16/4 scene (a ~18 us Chipmunk step), that
bookkeeping was ~3 us for the step and force and ~1.5 us for each batch read. :class:`Native` holds the raw handles of one space and
makes the same C calls directly: the numbers are bit-identical (the same C
functions on the same data; ``tests/test_engine_native.py`` checks it
against pymunk's public API).

It relies on pymunk 7's internals (``Space._space``, ``Body._body``,
``Buffer._float_arr`` / ``_int_arr`` and the batch iterator functions of
``pymunk._chipmunk``); ``pyproject.toml`` pins ``pymunk>=7.1,<8``.
"""

from __future__ import annotations

from pymunk import batch
from pymunk._chipmunk import ffi, lib


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


def friction_setter(shapes):
    """A function ``set(i, mu)`` that sets ``shapes[i]``'s friction coefficient, the same
    ``cpShapeSetFriction`` call as ``shapes[i].friction = mu`` without its Python layer."""
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


_GET_BODY = ffi.addressof(lib, "pmSpaceBodyGetIteratorFuncBatched")
_SET_BODY = ffi.addressof(lib, "pmSpaceBodySetIteratorFuncBatched")
_GET_ARBITER = ffi.addressof(lib, "pmSpaceArbiterIteratorFuncBatched")
