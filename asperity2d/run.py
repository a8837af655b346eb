"""The run loop: fixed dt, recording, stop conditions, divergence checks.

``simulate(scene, duration, ...) -> Result`` in the spirit of SciPy's
``solve_ivp``: stop conditions are plain callables evaluated on every
recorded sample; the first that returns true ends the run and names itself in
``result.status``. Underneath is :class:`Run`, the one run loop of the
package: it settles a scene, advances it by a duration, changes its drive,
records samples and can be forked from a settled state, so the tribometer's
strokes and the critical force's bisection share it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Iterable

import numpy as np

from ._validate import check_finite, check_int, check_positive
from ._version import __version__
from .engine import PYMUNK_VERSION, Engine
from .engine.energy import EnergyMeter
from .errors import SceneError, SimulationError
from .result import Result
from .scene import ConstantForce, Scene, SpringDrive

#: Default step: this fraction of the shortest natural period (T/50 converged,
#: T/20 is the coarsest that did, T/10 is silently wrong, T/6 blows up).
DT_FRACTION = 1.0 / 50.0
COARSEST_DT_FRACTION = 1.0 / 20.0
#: The drive damper is applied as a force (explicitly): c dt / M must stay
#: well under 2 for it to be stable. Default dt keeps it <= 0.2; coarser than
#: 0.5 is refused. (pymunk integrates the track and lattice dampers exactly.)
DAMPER_DT_FRACTION = 0.2
COARSEST_DAMPER_DT_FRACTION = 0.5
#: Default step budget of one run (settling included): about 5 minutes at N = 16.
MAX_STEPS = 10_000_000
#: Divergence: deepest overlap (asperity bases); kinetic energy above this
#: multiple of the energy the scene held at t = 0 plus all the drive has put in.
MAX_OVERLAP = 0.5
ENERGY_FACTOR = 10.0
_COLUMNS = ("t", "x", "v", "y", "vy", "drive_x", "drive_force", "normal_force", "friction_force",
            "tangential_force", "contact_count")


@dataclass
class Probe:
    """What stop conditions see at each recorded sample (SI units).

    ``rear_apex_x`` is the x of the slider's rearmost tip and ``last_apex_x``
    that of the lower surface's last apex, so ``rear_apex_x > last_apex_x``
    means the slider has passed the whole surface.
    """

    t: float = 0.0
    x: float = 0.0
    v: float = 0.0
    y: float = 0.0
    drive_force: float = 0.0
    x_start: float = 0.0
    rear_apex_x: float = 0.0
    last_apex_x: float = 0.0
    base: float = 1.0


class Passed:
    """Stop when the slider's rear tip is half a base past the last lower apex."""

    name = "passed"

    def __call__(self, p: Probe) -> bool:
        return p.rear_apex_x > p.last_apex_x + 0.5 * p.base


class Stuck:
    """Stop when |v| stays below ``speed`` (m/s) for ``dwell`` seconds.

    It remembers when the slider became slow; :meth:`reset` (called by the run
    at the start of every :meth:`Run.advance`) forgets it, so one instance can
    serve several runs.
    """

    name = "stuck"

    def __init__(self, speed: float, dwell: float):
        self.speed = check_positive("speed", speed)
        self.dwell = check_positive("dwell", dwell)
        self._since = None

    def reset(self) -> None:
        self._since = None

    def __call__(self, p: Probe) -> bool:
        if abs(p.v) >= self.speed:
            self._since = None
            return False
        if self._since is None:
            self._since = p.t
        return p.t - self._since >= self.dwell


class Travelled:
    """Stop once the slider has moved ``distance`` (m) from its start."""

    name = "travelled"

    def __init__(self, distance: float):
        self.distance = check_positive("distance", distance)

    def __call__(self, p: Probe) -> bool:
        return abs(p.x - p.x_start) >= self.distance


def default_stops(scene: Scene) -> list[Callable[[Probe], bool]]:
    """Passed for every drive; for a constant force also Stuck (speed under 1 %
    of the speed gained over one base, for two of the slowest periods)."""
    stops: list = [Passed()]
    if isinstance(scene.drive, ConstantForce) and scene.drive.force != 0:
        v_char = math.sqrt(abs(scene.drive.force) * scene.base / scene.slider.mass)
        stops.append(Stuck(speed=0.01 * v_char, dwell=2.0 * scene.slowest_period()))
    return stops


def default_duration(scene: Scene) -> float:
    """Time limit (s) when ``duration=None``: long enough to cross the surface."""
    lower_x = scene.lower.tips()
    span = (lower_x[-1] - lower_x[0]) + scene.slider.tips()[-1] + 4 * scene.lower.spacing.mean_pitch
    if isinstance(scene.drive, SpringDrive):
        return 2.0 * span / scene.drive.velocity + 20.0 * scene.slowest_period()
    force = max(abs(scene.drive.force), 1e-300)
    return 20.0 * scene.slowest_period() + 10.0 * math.sqrt(2.0 * span * scene.slider.mass / force)


def _damper_time(scene: Scene) -> float:
    """M / c of the drive damper (s); inf without one."""
    drive = scene.drive
    if isinstance(drive, SpringDrive) and drive.damping > 0:
        return scene.slider.mass / drive.damping
    return math.inf


def default_dt(scene: Scene) -> float:
    """Default step (s): 1/50 of the shortest natural period, and at most 0.2 M/c of the
    drive damper (applied explicitly, it must be resolved to be stable)."""
    return min(DT_FRACTION * scene.shortest_period(), DAMPER_DT_FRACTION * _damper_time(scene))


def _slowest_source(scene: Scene) -> str:
    """Which parameters set the scene's slowest period (for budget messages)."""
    k, m = np.asarray(scene.lower.stiffness), np.asarray(scene.lower.mass)
    periods = {"`stiffness` and `mass`": 2 * math.pi / float(np.min(np.sqrt(k / m))),
               "`slider_mass` (on one lower spring)": 2 * math.pi * math.sqrt(scene.slider.mass / float(np.min(k)))}
    if isinstance(scene.drive, SpringDrive):
        periods["`slider_mass` and `drive_stiffness`"] = 2 * math.pi * math.sqrt(
            scene.slider.mass / scene.drive.stiffness)
    return max(periods, key=periods.get)


def _fastest_source(scene: Scene) -> str:
    """Which parameters set the default dt (for budget messages)."""
    if DAMPER_DT_FRACTION * _damper_time(scene) < DT_FRACTION * scene.shortest_period():
        return "`drive_damping` and `slider_mass`"
    freqs = scene.natural_frequencies()
    return {"lower": "`stiffness` and `mass`", "lattice": "`lateral_stiffness` and `mass`",
            "drive": "`drive_stiffness` and `slider_mass`"}[max(freqs, key=freqs.get)]


class Run:
    """One asperity scene being simulated: settle, advance, change the drive, record.

    ::

        run = Run(scene)                  # built, at rest, t = 0
        run.settle()                      # optional: a free slider comes down onto the surface
        run.advance(1e-6, stop=Passed())  # returns the status: "duration" or a stop's name
        run.set_drive_velocity(-5.0)      # reverse a spring drive (m/s)
        run.advance(1e-6)
        result = run.result()             # everything recorded so far, SI

    ``fork()`` returns an independent run continuing from the current state
    with an empty record: settle once, run many (forks of one run are
    bit-identical to each other). ``engaged=True`` starts a fixed-track slider
    over the surface instead of before it (:meth:`settle` lowers its track
    into contact); a free slider always starts on the surface.
    """

    def __init__(self, scene: Scene, *, dt: float | None = None, record_every: int = 10,
                 iterations: int = 20, unsafe_dt: bool = False, max_steps: int = MAX_STEPS,
                 engaged: bool = False):
        if not isinstance(scene, Scene):
            raise SceneError(f"`scene` must be a Scene (see make_scene), got {type(scene).__name__}")
        period = scene.shortest_period()
        if dt is None:
            dt = default_dt(scene)
        else:
            dt = check_positive("dt", dt)
            if dt > COARSEST_DT_FRACTION * period and not unsafe_dt:
                raise SceneError(
                    f"`dt` = {dt:.3g} s is coarser than T/20 = {COARSEST_DT_FRACTION * period:.3g} s "
                    f"(T = {period:.3g} s, the shortest natural period): coarser steps do not converge "
                    "and T/6 blows up; use dt <= T/20 (default T/50) or pass unsafe_dt=True")
            if dt > COARSEST_DAMPER_DT_FRACTION * _damper_time(scene) and not unsafe_dt:
                raise SceneError(
                    f"`dt` = {dt:.3g} s is coarser than half the drive damper's time M/c = "
                    f"{_damper_time(scene):.3g} s (`slider_mass` / `drive_damping`): it is applied "
                    "explicitly and would be unstable; use a smaller dt or pass unsafe_dt=True")
        self.record_every = check_int("record_every", record_every, minimum=1)
        self.iterations = check_int("iterations", iterations, minimum=1, maximum=10_000)
        self.max_steps = check_int("max_steps", max_steps, minimum=1, maximum=None)
        self.scene, self.dt = scene, dt
        self.engine = Engine(scene, dt, iterations=self.iterations, engaged=engaged)
        self.settle_time = 0.0
        self.status, self.message = "duration", "nothing run yet"
        self._reset_record()

    # -- budget ---------------------------------------------------------------
    def settle_cap(self) -> float:
        """Longest settling (s): 10 slowest periods."""
        return 10.0 * self.scene.slowest_period()

    def check_budget(self, *, settle: float = 0.0, duration: float = 0.0) -> None:
        """Refuse, before running, a settle and run that would exceed ``max_steps`` (SceneError
        naming what makes it long)."""
        steps_settle = settle / self.dt
        steps_run = duration / self.dt
        total = self.engine.step_count + steps_settle + steps_run
        if total <= self.max_steps:
            return
        if steps_settle > steps_run:
            why = (f"settling takes up to {steps_settle:.3g} steps (10 slowest periods, "
                   f"{settle:.3g} s, set by {_slowest_source(self.scene)})")
            fix = "bring those closer to the other masses and stiffnesses, pass settle=False"
        else:
            why = f"`duration` = {duration:.3g} s is {steps_run:.3g} steps"
            fix = "shorten `duration`"
        raise SceneError(
            f"the run needs {total:.3g} steps, over `max_steps` = {self.max_steps:,}: {why} of "
            f"dt = {self.dt:.3g} s (set by {_fastest_source(self.scene)}); {fix}, or raise `max_steps`")

    # -- the record ---------------------------------------------------------
    def _reset_record(self) -> None:
        n = self.scene.lower.count
        self._cols = np.empty((len(_COLUMNS), 64))
        self._lower = np.empty((3, n, 64))
        self._size = 0
        self._last_sampled_step = -1
        self.max_overlap = 0.0
        self.max_drift = 0.0
        self._energy = None  # the divergence guard's books, opened at the first sample

    def _check_energy(self, rows: np.ndarray, drive_force: float) -> None:
        """Raise SimulationError if the bodies hold far more kinetic energy than the scene
        had at the first sample plus every joule the drive, the load and gravity could have
        put in since (internal units; also catches NaN and inf)."""
        e = self.engine
        layout, d = e.layout, e.drive
        v = rows[:, 2:]
        kinetic = 0.5 * float(np.dot(layout.masses, np.einsum("ij,ij->i", v, v)))
        b = self._energy
        if b is None:
            sx, sy = rows.item(layout.slider_row, 0), rows.item(layout.slider_row, 1)
            k = np.asarray(self.scene.lower.stiffness) / e.units.stiffness
            potential = 0.5 * float(np.dot(k, rows[layout.lower_rows, 1] ** 2))
            if d.spring:
                potential += 0.5 * d.k * (d.position(e.step_count, e.dt_internal) - sx) ** 2
            floor = 1e-3 * 0.5 * float(k.min()) * layout.lower_height ** 2
            self._energy = {"held": kinetic + potential + floor, "input": 0.0, "x": sx, "y": sy,
                            "f": abs(drive_force), "step": e.step_count, "heights": rows[:, 1].copy(),
                            "g": -layout.space.gravity.y}
            return
        r = layout.slider_row
        sx, sy, svx, svy = rows.item(r, 0), rows.item(r, 1), rows.item(r, 2), rows.item(r, 3)
        steps = e.step_count - b["step"]
        g = b["g"]
        if d.spring:  # the far end's power |F| |v| over the samples' interval, F at its larger end
            b["input"] += max(b["f"], abs(drive_force)) * abs(d.v) * steps * e.dt_internal
        else:
            b["input"] += abs(d.force) * abs(sx - b["x"])
        b["input"] += e.load_internal * abs(sy - b["y"])
        if g:  # gravity's work on every body
            b["input"] += g * float(np.dot(layout.masses, np.abs(rows[:, 1] - b["heights"])))
            b["heights"] = rows[:, 1].copy()
        b["x"], b["y"], b["f"], b["step"] = sx, sy, abs(drive_force), e.step_count
        # pymunk moves a body with its old velocity, then updates the velocity: kinetic energy is
        # ahead of the displacement that paid for it by one step, so allow one step of that work
        # (gravity's share only with gravity: without, a NaN or inf velocity already makes the
        # kinetic energy fail the test below)
        ahead = e.dt_internal * ((0.0 if d.spring else abs(d.force * svx)) + e.load_internal * abs(svy)
                                 + (g * float(np.dot(layout.masses, np.abs(rows[:, 3]))) if g else 0.0))
        limit = ENERGY_FACTOR * (b["held"] + b["input"] + ahead)
        if not kinetic <= limit:  # also true for NaN
            u = e.units
            raise SimulationError(
                f"run diverged at t = {e.time:.6g} s: kinetic energy {kinetic * u.energy:.3g} J is over "
                f"{ENERGY_FACTOR:g} x the {limit / ENERGY_FACTOR * u.energy:.3g} J the scene held and "
                f"was given; use a smaller dt (now {self.dt:.3g} s, default T/50) or more iterations",
                time=e.time)

    def _guard(self, rows: np.ndarray, drive_force: float, overlap: float) -> None:
        """Raise SimulationError if the run has diverged: kinetic energy (:meth:`_check_energy`)
        or asperities overlapping by ``overlap`` (base lengths) over ``MAX_OVERLAP``."""
        self._check_energy(rows, drive_force)
        if overlap > MAX_OVERLAP:
            e = self.engine
            raise SimulationError(
                f"run diverged at t = {e.time:.6g} s: asperities overlap by {overlap:.2f} of a base; "
                f"use a smaller dt (now {self.dt:.3g} s) or more iterations", time=e.time)
        if overlap > self.max_overlap:
            self.max_overlap = overlap

    def _check(self) -> None:
        """The divergence guard alone on the engine's current state (a run that keeps no record)."""
        e = self.engine
        rows, r = e.bodies_internal(), e.layout.slider_row
        self._guard(rows, e.drive_force_internal(rows.item(r, 0), rows.item(r, 2)),
                    e.arbiters_internal().max_overlap())

    def _sample(self) -> None:
        """Record the engine's current state (internal units) and check it has not diverged."""
        e = self.engine
        if e.step_count == self._last_sampled_step:
            return
        rows = e.bodies_internal()
        layout = e.layout
        sx, sy, svx, svy = rows[layout.slider_row].tolist()
        drive_force = e.drive_force_internal(sx, svx)
        arbiters = e.arbiters_internal()
        fx, fy, ft, count, overlap = arbiters.forces(e.dt_internal)
        self._guard(rows, drive_force, overlap)
        lower = rows[layout.lower_rows]
        dx = lower[:, 0] - layout.lower_x0
        drift = float(np.abs(dx).max()) if len(dx) and layout.tracked else 0.0
        if layout.fixed_slider:
            drift = max(drift, abs(sy - layout.slider_y_track))
        self.max_drift = max(self.max_drift, drift)
        i = self._size
        if i == self._cols.shape[1]:
            self._cols = np.concatenate([self._cols, np.empty_like(self._cols)], axis=1)
            self._lower = np.concatenate([self._lower, np.empty_like(self._lower)], axis=2)
        drive_x = e.drive.position(e.step_count, e.dt_internal) if e.drive.spring else math.nan
        self._cols[:, i] = (e.step_count, sx, svx, sy, svy, drive_x, drive_force, fy, -fx, ft, count)
        self._lower[0, :, i] = dx
        self._lower[1, :, i] = lower[:, 1]
        self._lower[2, :, i] = arbiters.touched(len(dx))
        self._size = i + 1
        self._last_sampled_step = e.step_count

    def _probe(self, probe: Probe) -> None:
        """What the stop conditions see, read from the engine's current state (SI)."""
        e = self.engine
        u = e.units
        sx, sy, svx, _ = e.bodies_internal()[e.layout.slider_row].tolist()
        probe.t = e.step_count * self.dt
        probe.x, probe.v, probe.y = sx * u.length, svx * u.velocity, sy * u.length
        probe.drive_force = e.drive_force_internal(sx, svx) * u.force
        probe.rear_apex_x = (sx + e.layout.upper_apex[0]) * u.length

    # -- running ------------------------------------------------------------
    def settle(self, *, push: float = 0.0, max_time: float | None = None,
               progress: bool | None = None) -> float:
        """Bring the scene to rest before t = 0 (see :meth:`Engine.settle`); return the time (s).

        A free slider comes down under its load (x held, damped) and, with a
        spring drive, finds its equilibrium against the spring's preload;
        ``push`` (N) then presses the slider along +x until it rests against
        the lower flanks. Each phase ends once the motion has decayed, within
        ``max_time`` (s, default :meth:`settle_cap`: 10 slowest periods).
        """
        from tqdm.auto import tqdm

        if self.engine.step_count:
            raise SceneError("`settle` must come before the run advances")
        push = check_finite("push", push)
        max_time = self.settle_cap() if max_time is None else check_positive("max_time", max_time)
        self.check_budget(settle=max_time)
        steps = int(max_time / self.dt)
        disable = (None if steps > 200_000 else True) if progress is None else not progress
        with tqdm(total=steps, unit="step", desc="settling", disable=disable, leave=False,
                  mininterval=0.5) as bar:
            spent = self.engine.settle(max_time, push=push, on_steps=bar.update)
        self.settle_time += spent
        return spent

    def advance(self, duration: float, *, stop: Callable | Iterable[Callable] | None = None,
                progress: bool | None = None, record_every: int | None = None,
                record: bool = True) -> str:
        """Step for ``duration`` (s), recording every ``record_every`` steps (default: the
        run's), until a stop condition holds. Returns (and sets) ``status``:
        ``"duration"`` or the stop's name.

        ``record=False`` keeps nothing: every ``record_every`` steps the stop conditions
        and the divergence guard still see the state, exactly as when recording (so the
        run stops at the same step), but no sample is added to :meth:`result` (the
        critical force's bisection runs, which only need their outcome)."""
        from tqdm.auto import tqdm

        check_finite("duration", duration)
        check_positive("duration", duration)
        k = self.record_every if record_every is None else check_int("record_every", record_every,
                                                                      minimum=1)
        stops = [] if stop is None else ([stop] if callable(stop) else list(stop))
        for s in stops:
            if not callable(s):
                raise SceneError(f"`stop` entries must be callables, got {s!r}")
            if hasattr(s, "reset"):
                s.reset()
        e = self.engine
        self.check_budget(duration=duration)
        n_steps = int(math.ceil(duration / self.dt - 1e-9))
        probe = Probe(base=self.scene.base,
                      last_apex_x=float(e.layout.lower_apex_x[-1]) * e.units.length)
        sample = self._sample if record else self._check
        sample()
        if stops:
            self._probe(probe)
            probe.x_start = probe.x
        self.status, self.message = "duration", "reached the requested duration"
        disable = (None if n_steps > 200_000 else True) if progress is None else not progress
        bar = tqdm(total=n_steps, unit="step", disable=disable, leave=False, mininterval=0.5)
        done = 0
        try:
            while done < n_steps:
                n = min(k, n_steps - done)
                e.step(n)
                done += n
                sample()
                bar.update(n)
                if stops:
                    self._probe(probe)
                    hit = next((s for s in stops if s(probe)), None)
                    if hit is not None:
                        self.status = getattr(hit, "name", type(hit).__name__)
                        self.message = f"stop condition {self.status!r} met at t = {probe.t:.6g} s"
                        break
        finally:
            bar.close()
        return self.status

    def fork(self) -> "Run":
        """An independent run from the current state, with an empty record (and its own
        divergence books)."""
        out = object.__new__(Run)
        out.__dict__.update(self.__dict__)
        out.engine = self.engine.copy()
        out._reset_record()
        return out

    def set_drive_velocity(self, velocity: float) -> None:
        """Change the spring drive's far-end speed (m/s, any sign); its position is continuous."""
        self.engine.set_drive_velocity(check_finite("velocity", velocity))

    def set_drive_force(self, force: float) -> None:
        """Change the constant drive force (N) from the next step on."""
        self.engine.set_drive_force(check_finite("force", force))

    @property
    def time(self) -> float:
        """Simulated time (s) since t = 0."""
        return self.engine.time

    @property
    def samples(self) -> int:
        """Number of samples recorded so far."""
        return self._size

    def result(self, *, start: int = 0) -> Result:
        """The samples recorded so far (from sample ``start`` on) as a :class:`Result` (SI)."""
        e, m = self.engine, self._size
        u = e.units
        c = self._cols[:, start:m]
        scale = {"t": self.dt, "x": u.length, "v": u.velocity, "y": u.length, "vy": u.velocity,
                 "drive_x": u.length, "drive_force": u.force, "normal_force": u.force,
                 "friction_force": u.force, "tangential_force": u.force, "contact_count": 1.0}
        arrays = {name: c[j] * scale[name] for j, name in enumerate(_COLUMNS)}
        meta = {
            "settle_time": self.settle_time, "iterations": self.iterations, "dt": self.dt,
            "record_every": self.record_every, "status": self.status, "message": self.message,
            "steps": e.step_count, "max_overlap_fraction": self.max_overlap,
            "max_track_drift_fraction": self.max_drift,
            "max_solver_drift_fraction": e.max_solver_drift,  # removed by projection each step
            "units": u.as_dict(), "asperity2d_version": __version__,
            "pymunk_version": PYMUNK_VERSION, "numpy_version": np.__version__,
        }
        return Result(**arrays, lower_dx=self._lower[0, :, start:m] * u.length,
                      lower_dy=self._lower[1, :, start:m] * u.length,
                      lower_contact=self._lower[2, :, start:m] > 0, scene=self.scene, meta=meta)


def simulate(scene: Scene, duration: float | None = None, *, dt: float | None = None,
             record_every: int = 10, stop: Callable | Iterable[Callable] | None = None,
             settle: bool | None = None, iterations: int = 20, unsafe_dt: bool = False,
             progress: bool | None = None, energy: bool = False, max_steps: int = MAX_STEPS) -> Result:
    """Run ``scene`` with a fixed step and return its :class:`Result`.

    Parameters
    ----------
    duration : float or None
        Simulated time (s) after settling. ``None``: until the slider has
        passed the lower surface, or (constant force) is stuck for good, or a
        time limit long enough to cross it has run out (``status`` says which).
    dt : float, optional
        Step (s). Default: 1/50 of the shortest natural period. A step coarser
        than 1/20 of it is refused unless ``unsafe_dt=True``.
    record_every : int
        Record every k-th step (the first sample is the settled state).
    stop : callable or list of callables, optional
        ``stop(probe) -> bool`` evaluated at every sample; extra to the
        defaults when ``duration`` is None. See :class:`Passed`,
        :class:`Stuck`, :class:`Travelled`.
    settle : bool, optional
        Let a free slider settle under its load (x held, damped) first, until
        its motion has decayed (at most 10 slowest periods). Default: True for
        a free slider.
    iterations : int
        pymunk solver iterations.
    progress : bool, optional
        Show a progress bar (default: only on a terminal, for long runs).
    energy : bool
        Meter every step's energy flows from the settled state on
        (:class:`asperity2d.engine.energy.EnergyMeter`) and store its report
        in ``result.meta["energy"]`` (a metered step costs about 7 plain steps).
    max_steps : int
        Step budget (settling included), checked before anything runs.

    Raises
    ------
    SceneError
        Bad arguments (named in the message), or a run over ``max_steps``
        (naming the parameter that makes it long).
    SimulationError
        The run diverged: non-finite state, kinetic energy far beyond what the
        scene held and was given, or deep penetration.
    """
    run = Run(scene, dt=dt, record_every=record_every, iterations=iterations, unsafe_dt=unsafe_dt,
              max_steps=max_steps)
    stops = [] if stop is None else ([stop] if callable(stop) else list(stop))
    if duration is None:
        stops = default_stops(scene) + stops
        duration = default_duration(scene)
    else:
        check_finite("duration", duration)
        check_positive("duration", duration)
    if settle is None:
        settle = scene.slider.track == "free"
    run.check_budget(settle=run.settle_cap() if settle else 0.0, duration=duration)
    if settle:
        run.settle(progress=progress)
    meter = None
    if energy:
        meter = EnergyMeter(run.engine)
    run.advance(duration, stop=stops, progress=progress)
    if stops and run.status == "duration":
        run.status, run.message = "time limit", "reached the time limit before any stop condition"
    result = run.result()
    if meter is not None:
        result.meta["energy"] = meter.report()
    return result
