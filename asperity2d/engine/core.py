"""The asperity engine: a scene built in pymunk, stepped with a fixed dt (part of :mod:`asperity2d.engine`).

:class:`Engine` composes the built space (:class:`~.space.Layout`), the drive,
the stick/slip switch (:class:`~.contacts.StickSlip`) and the track
projection. It applies the drive and the normal load before every step
(pymunk resets body forces after each step) and after every step reads all
bodies once with ``pymunk.batch`` (a Python loop over bodies would cost
milliseconds at N = 1000); that one read serves the projection, the switch,
the next step's drive force and the recorder.

Where the optional C extension was built, :class:`~.kernel.Kernel` runs the
steps themselves (drive, ``cpSpaceStep``, read, projection, switch) in one C
call per run of steps, bit-identical to the Python loop here.

Its public surface is SI (``time``, ``slider_state``, ``drive_position``,
``drive_force``, ``set_drive_velocity``, ``set_drive_force``); the few
internal-unit read-outs used by the run loop and the energy meter say so in
their names (``*_internal``).
"""

from __future__ import annotations

import math
from operator import sub

import numpy as np
import pymunk
from pymunk import batch

from ..scene import Scene, SpringDrive
from ..units import Units, check_scales
from .contacts import ARBITER_FIELDS, Arbiters, StickSlip
from .kernel import C_LAWS, KERNEL, Kernel
from .native import Native, stepper
from .space import build
from .run_checks import check_scene

PYMUNK_VERSION = pymunk.version
BODY_FIELDS = batch.BodyFields.POSITION | batch.BodyFields.VELOCITY
TRACK_TOLERANCE = 1e-9  # track drift (base lengths) left to the groove joint alone
#: Up to this many lower asperities the projection's drift check runs in plain Python (measured:
#: 1.9 us against 3.3 us for NumPy's three calls at N = 16; NumPy wins from N ~ 40). Both compute
#: the same IEEE differences and maximum, so the results are identical.
SMALL_N = 32


class Drive:
    """The drive in internal units: a spring (``k``, ``c``) whose far end moves at ``v`` from
    ``origin``, or a constant force ``force`` (``k`` = 0)."""

    def __init__(self, scene: Scene, units: Units):
        drive = scene.drive
        self.spring = isinstance(drive, SpringDrive)
        if self.spring:
            self.k, self.c, self.v = (drive.stiffness / units.stiffness, drive.damping / units.damping,
                                      drive.velocity / units.velocity)
            self.preload, self.force = drive.preload / units.force, 0.0
        else:
            self.k = self.c = self.v = self.preload = 0.0
            self.force = drive.force / units.force
        self.origin = 0.0

    def position(self, step: int, dt: float) -> float:
        """Far end of the spring after ``step`` steps (internal units)."""
        return self.origin + self.v * step * dt

    def start(self, slider_x: float) -> None:
        """Put the far end where the spring holds its preload with the slider at ``slider_x``."""
        self.origin = slider_x + (self.preload / self.k if self.spring else 0.0)


class Engine:
    """A :class:`~asperity2d.scene.Scene` built in pymunk, stepped with a fixed ``dt`` (s).

    ``iterations`` is pymunk's solver iteration count. ``step_hooks`` are
    callables run after every step (after projection and the friction
    switch), e.g. :class:`asperity2d.engine.energy.EnergyMeter`;
    ``projection_hooks`` are called with the bodies' rows just before the
    track projection (so a meter can see what the projection removes).
    ``engaged`` starts a fixed-track slider over the surface, its track
    raised, for :meth:`settle` to lower it into contact.
    """

    def __init__(self, scene: Scene, dt: float, *, iterations: int = 20, engaged: bool = False):
        self.scene = scene
        self.units = u = Units.for_scene(scene)
        check_scales(scene, u)  # before pymunk sees a value it cannot represent
        check_scene(scene, dt, u)  # nor a motion its step cannot resolve, nor a load it cannot carry
        self.dt = dt  # s
        self.dt_internal = dt / u.time
        self.layout = build(scene, u, self.dt_internal, iterations=iterations,
                            friction=scene.contact.mu_kinetic, engaged=engaged)
        self.switch = StickSlip(scene, u, self.layout, self.dt_internal)
        self.drive = Drive(scene, u)
        self.load_internal = scene.slider.normal_load / u.force if scene.slider.track == "free" else 0.0
        self.step_count = 0
        self.max_solver_drift = 0.0  # largest drift off a track before projection (base units)
        self.step_hooks: list = []
        self.projection_hooks: list = []
        self._native = None  # raw handles of the space (.native), made with the body buffer
        self._kernel = None  # ... and the C step loop bound to them (.kernel), where it is usable
        #: why this engine steps in Python although the C loop is built (None: it may use C)
        self.loop_reason: str | None = None
        self._contacts = None  # the last step's contacts as read (Native.read_arbiters), if read
        self._arbiters = None  # ... and as Arbiters, made when asked for
        self._changes = 0  # counts what changes the space: forks of an unchanged engine share a snapshot
        self._snapshot = None
        self._read_bodies()
        self.drive.start(self._slider[0])

    # -- state --------------------------------------------------------------
    @property
    def _slider(self) -> list[float]:
        """The slider's ``[x, y, vx, vy]`` after the last step (internal units)."""
        return self._rows[self.layout.slider_row].tolist()

    @property
    def time(self) -> float:
        """Simulated time since the start of the run (s); settling is before t = 0."""
        return self.step_count * self.dt

    def slider_state(self) -> tuple[float, float, float, float]:
        """Slider ``(x, y, vx, vy)`` (m, m, m/s, m/s)."""
        u = self.units
        x, y, vx, vy = self._slider
        return x * u.length, y * u.length, vx * u.velocity, vy * u.velocity

    def drive_position(self) -> float:
        """Far end of the drive spring (m); NaN for a constant force."""
        if not self.drive.spring:
            return math.nan
        return self.drive.position(self.step_count, self.dt_internal) * self.units.length

    def drive_force(self) -> float:
        """Horizontal drive force on the slider in its current state (N)."""
        return self.drive_force_internal(self._slider[0], self._slider[2]) * self.units.force

    def drive_force_internal(self, x: float, vx: float) -> float:
        """Drive force (internal units) with the slider at ``x`` moving at ``vx`` (internal units)."""
        d = self.drive
        if not d.spring:
            return d.force
        return d.k * (d.position(self.step_count, self.dt_internal) - x) + d.c * (d.v - vx)

    def set_drive_velocity(self, velocity: float) -> None:
        """Change the spring drive's far-end velocity to ``velocity`` (m/s, any sign).

        The far end stays where it is (its path is continuous; only its speed
        changes), so a drive can reverse (the virtual tribometer's strokes).
        """
        d = self.drive
        if not d.spring:
            raise TypeError("set_drive_velocity needs a spring drive")
        x_now = d.position(self.step_count, self.dt_internal)
        d.v = velocity / self.units.velocity
        d.origin = x_now - d.v * self.step_count * self.dt_internal

    def set_drive_force(self, force: float) -> None:
        """Change a constant drive force to ``force`` (N) from the next step on."""
        if self.drive.spring:
            raise TypeError("set_drive_force needs a constant-force drive")
        self.drive.force = force / self.units.force

    def bodies_internal(self) -> np.ndarray:
        """All dynamic bodies' ``[x, y, vx, vy]`` rows after the last step (internal units, a view)."""
        return self._rows

    def arbiters_internal(self):
        """The slider's contacts after the last step (:class:`~.contacts.Arbiters`, internal units)."""
        if self._arbiters is None:
            if self._contacts is None:
                self._contacts = self._native.read_arbiters()
            self._arbiters = Arbiters(self._contacts, self.layout)
        return self._arbiters

    # -- stepping -----------------------------------------------------------
    def step(self, n: int = 1) -> None:
        """Advance ``n`` steps, applying the drive and the load before each."""
        layout, d, dt, load = self.layout, self.drive, self.dt_internal, self.load_internal
        native, switch = self._native, self.switch
        hooks, before_projection = self.step_hooks, self.projection_hooks
        rows, slider_row = self._rows, layout.slider_row
        self._changes += 1
        if self._kernel is not None and not hooks and not before_projection:
            # the same steps in C (bit-identical); the contacts are read again when asked for
            self._kernel.steps(self, n)
            self._arbiters = self._contacts = None
            return
        for _ in range(n):
            if d.spring:
                # Symplectic Euler: pymunk moves bodies with the old velocity
                # before it applies forces, so take the spring at the position
                # the step will end at. (From the start position it would be
                # forward Euler, which feeds energy into the slider's
                # oscillation on the drive spring.)
                x, vx = rows.item(slider_row, 0), rows.item(slider_row, 2)
                x_d = d.origin + d.v * (self.step_count + 1) * dt
                native.step(dt, d.k * (x_d - (x + vx * dt)) + d.c * (d.v - vx), -load)
            else:
                native.step(dt, d.force, -load)  # the step reads every body into rows
            self.step_count += 1
            for hook in before_projection:
                hook(rows)
            self._project(rows)
            self._arbiters = None
            if switch.active:
                self._contacts = contacts = native.read_arbiters()
                switch.update(contacts, rows, layout)
            else:
                self._contacts = None
            for hook in hooks:
                hook()

    def _read_bodies(self) -> np.ndarray:
        """Read every body into ``self._rows`` (a preallocated array pymunk writes into)."""
        native = self._native
        if native is None:
            # Sized with room to spare: pymunk grows (reallocates) its array when a
            # write comes within two entries of the end, which must never happen to ours.
            n = 4 * self.layout.n_rows
            self._row_store = np.zeros(n + 8)
            self._rows = self._row_store[:n].reshape(-1, 4)
            buf = batch.Buffer()
            buf.set_float_buf(self._row_store)
            self._native = native = stepper(self.layout.space, self.layout.slider, buf, BODY_FIELDS,
                                            batch.Buffer(), ARBITER_FIELDS)
            rows = self.layout.lower_rows
            if not isinstance(rows, slice):  # pymunk keeps bodies in insertion order
                raise RuntimeError("the lower asperities are not contiguous in the batch rows")
            law = self.switch.law
            if law.kernel not in C_LAWS:  # the C loop implements only its own laws: this one steps in Python
                self.loop_reason = f"the contact law {type(law).__name__} has no C implementation"
            elif KERNEL and isinstance(native, Native):
                self._kernel = Kernel(self, native, TRACK_TOLERANCE)
            self._lower_x = self._rows[rows, 0]  # a view: it follows every read
            # the drift check in _project: track positions as a list for a few asperities,
            # else a scratch array for NumPy
            small = len(self.layout.lower_bodies) <= SMALL_N
            self._lower_x0 = self.layout.lower_x0.tolist() if small else None
            self._lower_off = None if small else np.empty(len(self.layout.lower_bodies))
        native.read_bodies()
        return self._rows

    def _project(self, rows: np.ndarray) -> None:
        """Put bodies back on their tracks: lower asperities at x = x0 (vx = 0), a
        fixed-track slider at y = y0 (vy = 0).

        pymunk's iterative solver lets a groove joint drift off its line under
        hard impacts (measured: up to 0.6 % of a base, insensitive to
        iterations and bias). Projecting positions and velocities onto the
        constraint after each step (post-stabilisation) keeps the tracks within
        ``TRACK_TOLERANCE`` of a base; the groove still carries the reaction
        force during the step. The largest drift removed is ``max_solver_drift``.
        """
        layout = self.layout
        drift = 0.0
        if layout.tracked and len(layout.lower_bodies):
            if self._lower_x0 is not None:  # a few asperities: plain Python beats three NumPy calls
                x, x0 = self._lower_x.tolist(), self._lower_x0
                # on their tracks to the last bit (most steps: only touched ones move), the
                # differences are all zero; the list comparison is 3x cheaper than taking them
                drift = 0.0 if x == x0 else max(map(abs, map(sub, x, x0)))
            else:
                off = self._lower_off
                np.subtract(self._lower_x, layout.lower_x0, out=off)
                np.abs(off, out=off)
                drift = float(np.maximum.reduce(off))
        if layout.fixed_slider:
            drift = max(drift, abs(rows.item(layout.slider_row, 1) - layout.slider_y_track))
        if drift > self.max_solver_drift:
            self.max_solver_drift = drift
        if drift > TRACK_TOLERANCE:
            # Written back only when a body has drifted. All tracked bodies are
            # then put back (snapping only the drifted ones was measured no faster
            # and changes results in the last digits).
            if layout.tracked:
                rows[layout.lower_rows, 0] = layout.lower_x0
                rows[layout.lower_rows, 2] = 0.0
            if layout.fixed_slider:
                rows[layout.slider_row, 1] = layout.slider_y_track
                rows[layout.slider_row, 3] = 0.0
            self._native.write_bodies()

    def settle(self, max_time: float, *, push: float = 0.0, damping_per_period: float = 0.5,
               rest_speed: float = 1e-7, on_steps=None) -> float:
        """Bring the scene to rest before t = 0, in phases; return the time spent (s).

        * a free slider comes down onto the surface under its load, its x held;
          a fixed-track slider started over the surface (``engaged``) has its
          track lowered into place over one slowest period, its x held;
        * with a spring drive, x is then released so the slider finds its
          equilibrium against the spring's preload;
        * with ``push`` (N), x is released and the slider pushed along +x with
          that force until it rests against the lower flanks (the "from rest in
          contact" start of :func:`asperity2d.critical_force`).

        Global velocity damping removes the ringing (settling undamped leaves
        the asperities ringing and lowers a measured critical force by ~20 %):
        half the velocity per fastest period, but never more than critical
        damping of the slowest mode (a heavier damping overdamps a heavy
        slider so much that it creeps for thousands of periods).
        A phase ends when every body has stayed slower than ``rest_speed``
        (internal units, base x omega) for one slowest period, or when it has
        used its share of ``max_time`` (s). ``on_steps(n)`` reports progress.
        """
        layout, d, dt = self.layout, self.drive, self.dt_internal
        space, body, native = layout.space, layout.slider, self._native
        self._changes += 1
        free = self.scene.slider.track == "free"
        lowering = layout.fixed_slider and layout.slider_y_track != layout.slider_y0
        phases = (["drop"] if free or lowering else []) + (["spring"] if d.spring else []) + \
            (["push"] if push else [])
        if not phases:
            return 0.0
        period = max(1, int(self.scene.slowest_period() / self.dt))
        window = max(1, period // 4)  # checks per slowest period: 4
        share = max(2, int(max_time / self.dt) // len(phases))
        load, push_i = self.load_internal, push / self.units.force
        rate = -math.log(damping_per_period) / (2.0 * math.pi)  # per internal time unit
        slowest = 2.0 * math.pi * self.units.time / self.scene.slowest_period()
        space.damping = math.exp(-min(rate, 2.0 * slowest))
        d.start(self._slider[0])
        x_hold = self._slider[0]
        hold = pymunk.GrooveJoint(space.static_body, body, (x_hold, -1e6), (x_hold, 1e6), (0.0, 0.0))
        held = False
        spent = 0
        for phase in phases:
            if phase == "drop" and not held:
                space.add(hold)
                held = True
            elif phase != "drop" and held:
                space.remove(hold)
                held = False
            calm, done = 0, 0
            while done < share and calm < 4:
                n = min(window, share - done)
                if phase == "drop" and lowering:
                    self._lower_track(min(1.0, (done + n) / period))
                extra = push_i if phase == "push" else 0.0
                if self._kernel is not None:  # the same steps in C (bit-identical)
                    self._kernel.settle_steps(self, n, extra)
                else:
                    for _ in range(n):
                        fx = d.k * (d.origin - self._slider[0]) if d.spring else 0.0
                        native.step(dt, fx + extra, -load)
                        self._project(self._rows)
                done += n
                calm = calm + 1 if float(np.abs(self._rows[:, 2:]).max()) < rest_speed else 0
                if on_steps is not None:
                    on_steps(n)
            spent += done
        if held:
            space.remove(hold)
        space.damping = 1.0
        for b in layout.lower_bodies:
            b.velocity = (0.0, 0.0)
        body.velocity = (0.0, 0.0)
        rows = self._read_bodies()
        self._contacts = self._arbiters = None  # the contacts have changed since the last read
        if self.switch.active:  # contacts at rest start stuck, with mu_static
            self._contacts = self._native.read_arbiters()
            self.switch.update(self._contacts, rows, layout)
        return spent * self.dt

    def _lower_track(self, fraction: float) -> None:
        """Move the fixed track ``fraction`` of the way from its start to its working height."""
        layout = self.layout
        y = layout.slider_y_start + fraction * (layout.slider_y0 - layout.slider_y_start)
        layout.slider_groove.groove_a = (-1e6, y)
        layout.slider_groove.groove_b = (1e6, y)
        layout.slider_y_track = y

    def copy(self) -> "Engine":
        """An independent engine continuing from this one's state (hooks are not copied).

        Copies of one engine step bit-identically to each other (they differ
        from the original in the last bits: pymunk rebuilds the contact cache).
        """
        if self._snapshot is None or self._snapshot[0] != self._changes:
            self._snapshot = (self._changes, self.layout.snapshot())
        out = object.__new__(Engine)
        out.__dict__.update(self.__dict__)
        out.layout = self.layout.copy(self._snapshot[1])
        out.switch = self.switch.copy_to(out.layout)
        out.drive = object.__new__(Drive)
        out.drive.__dict__.update(self.drive.__dict__)
        out.step_hooks, out.projection_hooks = [], []
        out._native = out._kernel = None
        out._contacts = out._arbiters = None
        out._read_bodies()
        return out
