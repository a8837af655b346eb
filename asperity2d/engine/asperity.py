"""Asperity scenes in pymunk (part of the adapter, :mod:`asperity2d.engine`).

:class:`Engine` turns a :class:`~asperity2d.scene.Scene` (SI) into a pymunk
``Space`` in internal units (:mod:`asperity2d.units`), steps it with a fixed
dt, applies the drive and the normal load before every step (pymunk resets
body forces after each step), and reads the state back in SI with
``pymunk.batch`` (a Python loop over bodies would cost milliseconds at
N = 1000).

Bodies (seed 000 figures 5-8, DESIGN.md section 5):

* each lower asperity is ``Body(m, inf)`` (it cannot rotate) on a vertical
  ``GrooveJoint`` (the track, limited to the travel) with a vertical
  ``DampedSpring`` to ground;
* the slider is one ``Body(M, inf)`` carrying every upper triangle, either on
  a horizontal groove (fixed height) or free vertically under a normal load;
* a static floor at the bottom of the lower tracks stops upper tips from
  falling through wide gaps; it touches only the slider;
* shape filters keep lower asperities from touching each other.

Building the space lives in :mod:`.build`; static > kinetic friction and the
batch read-outs in :mod:`.contacts` (all mixed into :class:`Engine`).
"""

from __future__ import annotations

import math

import numpy as np
import pymunk
from pymunk import batch

from ..scene import ConstantForce, Scene, SpringDrive
from ..units import Units, per_step_bias
from .build import SpaceBuilder
from .contacts import _BODY_FIELDS, Readout, StickSlipSwitch

PYMUNK_VERSION = pymunk.version

#: Solver settings in internal units (DESIGN.md section 5).
COLLISION_SLOP = 1e-3  # base lengths of overlap left uncorrected
CORRECTION_PER_STEP = 0.1  # fraction of overlap / joint error removed per step
TRACK_TOLERANCE = 1e-9  # track drift (base lengths) left to the groove joint alone


class Engine(SpaceBuilder, StickSlipSwitch, Readout):
    """A scene built in pymunk, stepped with a fixed ``dt`` (s).

    ``iterations`` is pymunk's solver iteration count. Everything the caller
    sees is SI.
    """

    def __init__(self, scene: Scene, dt: float, *, iterations: int = 20):
        self.scene = scene
        self.units = u = Units.for_scene(scene)
        self.dt = dt / u.time
        self.space = space = pymunk.Space(threaded=False)
        space.iterations = iterations
        space.gravity = (0.0, -scene.gravity / u.acceleration)
        space.collision_slop = COLLISION_SLOP
        space.collision_bias = per_step_bias(CORRECTION_PER_STEP, self.dt)
        self._error_bias = per_step_bias(CORRECTION_PER_STEP, self.dt)
        self._build_lower()
        self._build_slider()
        self._build_floor()
        self._install_friction()
        self._prepare_batch()
        s = scene.slider
        self._load = s.normal_load / u.force if s.track == "free" else 0.0
        drive = scene.drive
        if isinstance(drive, SpringDrive):
            self._k = drive.stiffness / u.stiffness
            self._c = drive.damping / u.damping
            self._vd = drive.velocity / u.velocity
        else:
            self._force = drive.force / u.force
        self._set_drive_origin()
        self._slider_fixed = s.track == "fixed"
        self._projected = self.tracked or self._slider_fixed
        self.step_count = 0
        self.max_drift = 0.0  # largest solver drift off a track before projection (base units)
        #: Callables run after every step (after projection and friction
        #: update), e.g. :class:`asperity2d.engine.energy.EnergyMeter`; empty
        #: by default, which costs nothing.
        self.step_hooks: list = []

    def _set_drive_origin(self) -> None:
        # The spring's far end starts where the spring holds its preload.
        x = self.slider.position.x
        if isinstance(self.scene.drive, SpringDrive):
            x += self.scene.drive.preload / self.units.force / self._k
        self.drive_origin = x

    # -- stepping ------------------------------------------------------------
    def drive_position(self) -> float:
        """Far end of the drive spring (internal units) at the current step."""
        return self.drive_origin + self._vd * self.step_count * self.dt

    def step(self, n: int = 1) -> None:
        """Advance ``n`` steps, applying the drive and the load before each."""
        body, space, dt, load = self.slider, self.space, self.dt, self._load
        spring = isinstance(self.scene.drive, SpringDrive)
        if not spring:
            force = (self._force, -load)
        for _ in range(n):
            if spring:
                # Symplectic Euler: pymunk moves bodies with the old velocity
                # before it applies forces, so take the spring at the position
                # the step will end at. (From the start position it would be
                # forward Euler, which feeds energy into the slider's
                # oscillation on the drive spring.)
                x_d = self.drive_origin + self._vd * (self.step_count + 1) * dt
                vx = body.velocity.x
                x = body.position.x + vx * dt
                fx = self._k * (x_d - x) + self._c * (self._vd - vx)
                body.force = (fx, -load)
            else:
                body.force = force
            space.step(dt)
            self.step_count += 1
            self._project_tracks()
            if self.two_coefficients:
                self._update_friction()
            if self.step_hooks:
                for hook in self.step_hooks:
                    hook()

    def set_drive_velocity(self, velocity: float) -> None:
        """Change the spring drive's far-end velocity to ``velocity`` (m/s, any sign).

        The far end stays where it is (its path is continuous; only its
        speed changes), so a drive can reverse: used by the virtual
        tribometer for sliding in -x and pre-sliding reversals.
        """
        if not isinstance(self.scene.drive, SpringDrive):
            raise TypeError("set_drive_velocity needs a spring drive")
        x_now = self.drive_position()
        self._vd = velocity / self.units.velocity
        self.drive_origin = x_now - self._vd * self.step_count * self.dt

    def _project_tracks(self) -> None:
        """Put bodies back on their tracks: lower asperities at x = x0 (vx = 0),
        a fixed-track slider at y = y0 (vy = 0).

        pymunk's iterative solver lets a groove joint drift off its line under
        hard impacts (measured: up to 0.6 % of a base, insensitive to
        iterations and bias). Projecting positions and velocities onto the
        constraint after each step (post-stabilisation) keeps the tracks within
        ``TRACK_TOLERANCE`` of a base; the groove still carries the reaction
        force during the step. The largest drift removed is ``max_drift``.
        """
        if not self._projected:
            return
        buf = self._body_buf
        buf.clear()
        batch.get_space_bodies(self.space, _BODY_FIELDS, buf)
        rows = np.frombuffer(buf.float_buf(), dtype=np.float64).reshape(-1, 4)
        drift = 0.0
        if self.tracked and len(self.lower_bodies):
            lower = self._lower_rows
            drift = float(np.abs(rows[lower, 0] - self.lower_x0).max())
        if self._slider_fixed:
            drift = max(drift, abs(rows[self._slider_row, 1] - self.slider_y0))
        if drift > self.max_drift:
            self.max_drift = drift
        if drift > TRACK_TOLERANCE:
            if self.tracked:
                rows[self._lower_rows, 0] = self.lower_x0
                rows[self._lower_rows, 2] = 0.0
            if self._slider_fixed:
                rows[self._slider_row, 1] = self.slider_y0
                rows[self._slider_row, 3] = 0.0
            batch.set_space_bodies(self.space, _BODY_FIELDS, buf)

    def drive_force(self, x: float | None = None, vx: float | None = None) -> float:
        """Horizontal drive force on the slider (internal units) with the slider at
        ``x`` moving at ``vx`` (default: its current state)."""
        if isinstance(self.scene.drive, ConstantForce):
            return self._force
        x = self.slider.position.x if x is None else x
        vx = self.slider.velocity.x if vx is None else vx
        return self._k * (self.drive_position() - x) + self._c * (self._vd - vx)

    def settle(self, duration: float, *, damping_per_period: float = 0.5) -> None:
        """Bring a free slider to rest under its load (``duration`` in internal time).

        The slider's x is held while it comes down onto the surface. With a
        spring drive, x is released for the second half so the slider finds
        its equilibrium against the spring's preload; a constant-force slider
        stays held (its force, not applied while settling, is applied
        suddenly at t = 0). Global velocity damping removes the ringing
        (settling undamped leaves the asperities ringing and lowers a
        measured critical force by ~20 %).
        """
        space, body = self.space, self.slider
        x0 = body.position.x
        hold = pymunk.GrooveJoint(space.static_body, body, (x0, -1e6), (x0, 1e6), (0.0, 0.0))
        space.add(hold)
        space.damping = damping_per_period ** (1.0 / (2.0 * math.pi))
        load = self._load
        spring = isinstance(self.scene.drive, SpringDrive)
        self._set_drive_origin()
        steps = max(2, int(round(duration / self.dt)))
        for i in range(steps):
            if spring and i == steps // 2:
                space.remove(hold)
            fx = self._k * (self.drive_origin - body.position.x) if spring else 0.0
            body.force = (fx, -load)
            space.step(self.dt)
            self._project_tracks()
        if not spring:
            space.remove(hold)
        space.damping = 1.0
        for b in self.lower_bodies:
            b.velocity = (0.0, 0.0)
        body.velocity = (0.0, 0.0)
        if self.two_coefficients:
            self._update_friction()  # contacts at rest start stuck, with mu_static

    # -- reading -------------------------------------------------------------
