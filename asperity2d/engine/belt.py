"""Masses on a moving belt built in pymunk (part of the adapter).

An independent check of the exact event-driven solver in
:mod:`asperity2d.belt`: the same chain as rigid bodies. Each mass is a box
resting under gravity on a static segment whose ``surface_velocity`` is the
belt speed (a conveyor: no moving geometry, so runs of any length work);
horizontal ``DampedSpring`` links join the masses to each other and to the
two walls. Static > kinetic friction uses the same rule as the asperity
engine: a stuck mass keeps ``mu_s`` until it has slid ``slip_distance``
without pause relative to the belt, and sticks again below ``stick_speed``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pymunk

from .._validate import check_int, check_nonnegative, check_positive, per_item
from ..errors import SceneError

_SPACING = 1.0  # m between rest positions (geometry only: springs are linear in x)
_BOX = (0.2, 0.1)  # m, width and height of each mass


@dataclass(frozen=True)
class RigidChainRun:
    """Samples of a rigid-body chain: ``t`` (T,), ``x``, ``v``, ``stuck`` (n, T), SI."""

    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    stuck: np.ndarray
    dt: float

    def stick_intervals(self) -> list[list[tuple[float, float]]]:
        """Per mass, the (start, end) times (s) of each stretch spent stuck to the belt."""
        out = []
        for flags in self.stuck:
            edges = np.flatnonzero(np.diff(np.concatenate(([0], flags.astype(np.int8), [0]))))
            starts, ends = edges[::2], edges[1::2] - 1
            out.append([(float(self.t[a]), float(self.t[b])) for a, b in zip(starts, ends)])
        return out


def simulate_chain_rigid(masses, springs, dampers, *, mu_s: float, mu_k: float | None = None,
                         v_belt: float, x0, v0, t_end: float, g: float = 9.81,
                         dt: float | None = None, record_every: int = 1,
                         slip_distance: float = 1e-6, stick_speed: float | None = None,
                         iterations: int = 30) -> RigidChainRun:
    """Run the chain in pymunk with a fixed step (default T/400 of the fastest mode).

    Arguments as :func:`asperity2d.belt.simulate_chain` (SI; ``x0`` are the
    displacements from the rest positions where every spring is unstretched).
    """
    m = per_item("masses", masses, len(np.atleast_1d(masses)), allow_zero=False)
    n = len(m)
    k = per_item("springs", springs, n + 1, allow_zero=True)
    c = per_item("dampers", dampers, n + 1, allow_zero=True)
    try:
        x0 = np.broadcast_to(np.asarray(x0, dtype=float), (n,))
        v0 = np.broadcast_to(np.asarray(v0, dtype=float), (n,))
    except ValueError:
        raise SceneError(f"`x0` and `v0` must have {n} entries (one per mass)") from None
    if not (np.isfinite(x0).all() and np.isfinite(v0).all()):
        raise SceneError("`x0` and `v0` must be finite")
    mu_k = mu_s if mu_k is None else mu_k
    check_nonnegative("mu_s", mu_s)
    check_nonnegative("mu_k", mu_k)
    if mu_k > mu_s:
        raise SceneError(f"`mu_s` ({mu_s!r}) must be >= `mu_k` ({mu_k!r})")
    check_positive("t_end", t_end)
    check_positive("g", g)
    record_every = check_int("record_every", record_every, minimum=1)
    rows = np.array(k[:-1]) + np.array(k[1:]) + np.abs(k[:-1]) + np.abs(k[1:])
    omega = math.sqrt(max(float(np.max(rows / np.array(m))), 1e-12))
    dt = (2 * math.pi / omega) / 400 if dt is None else check_positive("dt", dt)
    v_stick = 1e-3 * max(abs(v_belt), 1e-3) if stick_speed is None else stick_speed

    space = pymunk.Space(threaded=False)
    space.gravity = (0.0, -g)
    space.iterations = iterations
    space.collision_slop = 1e-5
    belt = pymunk.Segment(space.static_body, (-1e4, 0.0), (1e4, 0.0), 0.0)
    belt.friction, belt.surface_velocity = 1.0, (v_belt, 0.0)
    space.add(belt)
    rest = _SPACING * np.arange(n)
    h = _BOX[1] / 2
    stuck = [abs(v0[i] - v_belt) < v_stick for i in range(n)]
    bodies, shapes = [], []
    for i in range(n):
        body = pymunk.Body(m[i], math.inf)
        body.position = (rest[i] + x0[i], h)
        body.velocity = (float(v0[i]), 0.0)
        shape = pymunk.Poly.create_box(body, _BOX)
        shape.friction = mu_s if stuck[i] else mu_k
        space.add(body, shape)
        bodies.append(body)
        shapes.append(shape)
    for j in range(n + 1):
        if k[j] == 0 and c[j] == 0:
            continue
        if j == 0:
            link = pymunk.DampedSpring(space.static_body, bodies[0], (rest[0] - _SPACING, h), (0, 0),
                                       _SPACING, k[j], c[j])
        elif j == n:
            link = pymunk.DampedSpring(bodies[-1], space.static_body, (0, 0), (rest[-1] + _SPACING, h),
                                       _SPACING, k[j], c[j])
        else:
            link = pymunk.DampedSpring(bodies[j - 1], bodies[j], (0, 0), (0, 0), _SPACING, k[j], c[j])
        space.add(link)

    slid = [0.0] * n
    steps = int(math.ceil(t_end / dt - 1e-9))
    samples = steps // record_every + 1
    t_out, x_out = np.empty(samples), np.empty((n, samples))
    v_out, s_out = np.empty((n, samples)), np.empty((n, samples), dtype=bool)

    def record(j, step):
        t_out[j] = step * dt
        for i, body in enumerate(bodies):
            x_out[i, j] = body.position.x - rest[i]
            v_out[i, j] = body.velocity.x
            s_out[i, j] = stuck[i]

    record(0, 0)
    for step in range(1, steps + 1):
        space.step(dt)
        for i, body in enumerate(bodies):
            slip = abs(body.velocity.x - v_belt)
            if stuck[i]:
                slid[i] = slid[i] + slip * dt if slip > v_stick else 0.0
                if slid[i] > slip_distance:
                    stuck[i] = False
                    shapes[i].friction = mu_k
            elif slip < v_stick:
                stuck[i], slid[i] = True, 0.0
                shapes[i].friction = mu_s
        if step % record_every == 0:
            record(step // record_every, step)
    return RigidChainRun(t=t_out, x=x_out, v=v_out, stuck=s_out, dt=dt)
