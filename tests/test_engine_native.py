"""The engine's direct Chipmunk calls (engine.native) against pymunk's public API.

``Native`` skips pymunk's per-call Python layer; it must make the very same C
calls, so two copies of one space stepped the two ways must agree to the bit.
"""

import math

import numpy as np
import pytest
from pymunk import batch

import asperity2d as a
from asperity2d.engine import Engine
from asperity2d.engine.contacts import ARBITER_FIELDS
from asperity2d.engine.core import BODY_FIELDS
from asperity2d.engine.native import Native
from asperity2d.run import default_dt


def _public_read(space):
    bodies, arbiters = batch.Buffer(), batch.Buffer()
    batch.get_space_bodies(space, BODY_FIELDS, bodies)
    batch.get_space_arbiters(space, ARBITER_FIELDS, arbiters)
    return (np.frombuffer(bodies.float_buf()).copy(), np.frombuffer(arbiters.int_buf(), dtype=np.uintp).tolist(),
            np.frombuffer(arbiters.float_buf()).tolist())


def _contacts(space, ints, floats):
    """Each contact as (place of body A, place of body B, count, its six floats), sorted:
    body ids are addresses (different in each copy) and the contacts come in hash order."""
    ids = batch.Buffer()
    batch.get_space_bodies(space, batch.BodyFields.BODY_ID, ids)
    place = {int(i): k for k, i in enumerate(np.frombuffer(ids.int_buf(), dtype=np.uintp))}
    return sorted((place.get(ints[k], -1), place.get(ints[k + 1], -1), ints[k + 2], *floats[2 * k: 2 * k + 6])
                  for k in range(0, len(ints), 3))


@pytest.mark.parametrize("track", ["fixed", "free"])
def test_native_calls_match_pymunks_public_api_to_the_bit(track):
    scene = a.make_scene(lower_count=6, upper_count=3, track=track, drive="force")
    engine = Engine(scene, default_dt(scene))
    engine.settle(10 * scene.slowest_period(), push=2e-3)
    one, two = engine.layout.copy(), engine.layout.copy()  # copies of one layout step alike
    n = 4 * len(one.space.bodies)
    native = Native(one.space, one.slider, batch.Buffer(), BODY_FIELDS, batch.Buffer(), ARBITER_FIELDS)
    store = np.zeros(n + 8)
    native._bodies.set_float_buf(store)
    dt, fx, fy = engine.dt_internal, 3e-3 / engine.units.force, -1e-3 / engine.units.force
    touched = 0
    for _ in range(400):
        native.step(dt, fx, fy)
        two.slider.force = (fx, fy)
        two.space.step(dt)
        native.read_bodies()
        ints, floats = native.read_arbiters()
        bodies, ints2, floats2 = _public_read(two.space)
        assert np.array_equal(store[:len(bodies)], bodies)
        assert _contacts(one.space, ints, floats) == _contacts(two.space, ints2, floats2)
        touched += any(ints[k + 2] for k in range(0, len(ints), 3))
    assert touched > 100  # the comparison covered contacts, not free flight
    # write_bodies puts the buffer back exactly as set_space_bodies does
    store[:n] = np.where(np.arange(n) % 4 == 2, 0.0, store[:n])  # stop every body in x
    native.write_bodies()
    rows = bodies.reshape(-1, 4).copy()
    rows[:, 2] = 0.0
    buf = batch.Buffer()
    buf.set_float_buf(rows.ravel().copy())
    batch.set_space_bodies(two.space, BODY_FIELDS, buf)
    assert np.array_equal(_public_read(one.space)[0], _public_read(two.space)[0])
    assert all(math.isfinite(v) for v in store[:n])


def test_native_refuses_a_body_pymunk_would_refuse():
    import pymunk

    space = pymunk.Space()
    body = pymunk.Body(0.0, 1.0)
    space.add(body)
    with pytest.raises(RuntimeError, match="mass"):
        Native(space, body, batch.Buffer(), BODY_FIELDS, batch.Buffer(), ARBITER_FIELDS)


def test_the_friction_setter_sets_what_the_shape_reports():
    """friction_setter makes pymunk's own cpShapeSetFriction call: the shapes read it back."""
    from asperity2d.engine.native import friction_setter

    scene = a.make_scene(lower_count=4, upper_count=1, drive="force")
    shapes = Engine(scene, default_dt(scene)).layout.lower_shapes
    before = [s.friction for s in shapes]
    assert 0.625 not in before
    set_friction = friction_setter(shapes)
    set_friction(2, 0.625)
    assert [s.friction for s in shapes] == before[:2] + [0.625] + before[3:]
