"""Masses on a moving belt built in pymunk (a test oracle: tests may import pymunk directly).

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

from asperity2d._inputs import check_int, check_real
from asperity2d.belt.spec import ChainSpec
from asperity2d.errors import SceneError

_SPACING = 1.0  # m between rest positions (geometry only: springs are linear in x)
_BOX = (0.2, 0.1)  # m, width and height of each mass
#: fixed-step budget: a Python loop over pymunk steps runs ~1e5 steps per second
MAX_STEPS = 20_000_000


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
    displacements from the rest positions where every spring is unstretched),
    validated by the same :class:`~asperity2d.belt.spec.ChainSpec`; the belt
    speed must be a constant and ``g`` > 0 (gravity holds the boxes on the belt).
    """
    spec = ChainSpec(masses, springs, dampers, mu_s, mu_k, v_belt, x0, v0, t_end, g)
    if not spec.constant_belt:
        raise SceneError("`v_belt` must be a number for the rigid-body chain (no ramps)")
    if spec.g <= 0:
        raise SceneError(f"`g` must be > 0 for the rigid-body chain, got {spec.g!r}")
    m, k, c, n = spec.masses, spec.springs, spec.dampers, spec.n
    x0, v0, v_belt, g = np.array(spec.x0), np.array(spec.v0), spec.v_belt, spec.g
    mu_s, mu_k = spec.law.static_coefficient, spec.law.kinetic_coefficient
    record_every = check_int("record_every", record_every, minimum=1, maximum=None)
    iterations = check_int("iterations", iterations, minimum=1, maximum=10_000)
    slip_distance = check_real("slip_distance", slip_distance, positive=True)
    rows = np.array(k[:-1]) + np.array(k[1:]) + np.abs(k[:-1]) + np.abs(k[1:])
    omega = math.sqrt(max(float(np.max(rows / np.array(m))), 1e-12))
    dt = (2 * math.pi / omega) / 400 if dt is None else check_real("dt", dt, positive=True)
    steps = int(math.ceil(spec.t_end / dt - 1e-9))
    if steps > MAX_STEPS:
        raise SceneError(f"`t_end` / `dt` = {steps:,} steps, over the budget of {MAX_STEPS:,}; shorten `t_end` "
                         "or raise `dt`")
    v_stick = 1e-3 * max(abs(v_belt), 1e-3) if stick_speed is None else check_real("stick_speed", stick_speed,
                                                                                     positive=True)

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
