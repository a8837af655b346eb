"""The run loop: fixed dt, recorders, stop conditions, divergence checks.

``simulate(scene, duration, ...) -> Result`` in the spirit of SciPy's
``solve_ivp``: stop conditions are plain callables evaluated on every
recorded sample; the first that returns true ends the run and names itself in
``result.status``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Iterable

import numpy as np

from . import __version__
from ._validate import check_finite, check_int, check_positive
from .engine import PYMUNK_VERSION, Engine
from .errors import SceneError, SimulationError
from .result import Result
from .scene import ConstantForce, Scene, SpringDrive

#: Default step: this fraction of the shortest natural period (T/50 converged,
#: T/20 is the coarsest that did, T/10 is silently wrong, T/6 blows up).
DT_FRACTION = 1.0 / 50.0
COARSEST_DT_FRACTION = 1.0 / 20.0
#: Divergence bounds (internal units: base lengths, base * omega).
MAX_SPEED = 1e4
MAX_OVERLAP = 0.5


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
    """Stop when |v| stays below ``speed`` (m/s) for ``dwell`` seconds."""

    name = "stuck"

    def __init__(self, speed: float, dwell: float):
        self.speed = check_positive("speed", speed)
        self.dwell = check_positive("dwell", dwell)
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
    lower_x = scene.lower.centers()
    span = (lower_x[-1] - lower_x[0]) + scene.slider.centers()[-1] + 4 * scene.lower.spacing.mean_pitch
    if isinstance(scene.drive, SpringDrive):
        return 2.0 * span / scene.drive.velocity + 20.0 * scene.slowest_period()
    force = max(abs(scene.drive.force), 1e-300)
    return 20.0 * scene.slowest_period() + 10.0 * math.sqrt(2.0 * span * scene.slider.mass / force)


def simulate(scene: Scene, duration: float | None = None, *, dt: float | None = None,
             record_every: int = 10, stop: Callable | Iterable[Callable] | None = None,
             settle: bool | None = None, iterations: int = 20, unsafe_dt: bool = False,
             progress: bool | None = None, energy: bool = False) -> Result:
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
        Let a free slider settle under its load (x held, damped) first.
        Default: True for a free slider.
    iterations : int
        pymunk solver iterations.
    progress : bool, optional
        Show a progress bar (default: only on a terminal, for long runs).
    energy : bool
        Meter every step's energy flows from the settled state on
        (:class:`asperity2d.engine.energy.EnergyMeter`) and store its report
        in ``result.meta["energy"]`` (costs about one more step's time per step).

    Raises
    ------
    SceneError
        Bad arguments (named in the message).
    SimulationError
        The run diverged (non-finite state, runaway speed, deep penetration).
    """
    if not isinstance(scene, Scene):
        raise SceneError(f"`scene` must be a Scene (see make_scene), got {type(scene).__name__}")
    period = scene.shortest_period()
    if dt is None:
        dt = DT_FRACTION * period
    else:
        check_positive("dt", dt)
        if dt > COARSEST_DT_FRACTION * period and not unsafe_dt:
            raise SceneError(
                f"`dt` = {dt:.3g} s is coarser than T/20 = {COARSEST_DT_FRACTION * period:.3g} s "
                f"(T = {period:.3g} s, the shortest natural period): coarser steps do not converge "
                "and T/6 blows up; use dt <= T/20 (default T/50) or pass unsafe_dt=True"
            )
    record_every = check_int("record_every", record_every, minimum=1)
    iterations = check_int("iterations", iterations, minimum=1)
    stops = [] if stop is None else ([stop] if callable(stop) else list(stop))
    for s in stops:
        if not callable(s):
            raise SceneError(f"`stop` entries must be callables, got {s!r}")
    if duration is None:
        stops = default_stops(scene) + stops
        duration = default_duration(scene)
    else:
        check_finite("duration", duration)
        check_positive("duration", duration)

    engine = Engine(scene, dt, iterations=iterations)
    if settle is None:
        settle = scene.slider.track == "free"
    settle_time = 0.0
    if settle:
        settle_time = 10.0 * scene.slowest_period()
        engine.settle(settle_time / engine.units.time)
    recorder = _Recorder(engine, duration, dt, record_every)
    meter = None
    if energy:
        from .engine.energy import EnergyMeter

        meter = EnergyMeter(engine)
    result = recorder.run(stops, progress, meta={"settle_time": settle_time, "iterations": iterations})
    if meter is not None:
        result.meta["energy"] = meter.report()
    return result


class _Recorder:
    """Steps an engine and records samples into growing SI arrays."""

    def __init__(self, engine: Engine, duration: float, dt: float, record_every: int):
        self.engine, self.dt, self.k = engine, dt, record_every
        self.n_steps = int(math.ceil(duration / dt - 1e-9))
        self.capacity = min(self.n_steps // record_every + 2, 4096)
        n = engine.scene.lower.count
        self.cols = np.empty((11, self.capacity))
        self.lower = np.empty((3, n, self.capacity))
        self.size = 0
        u = engine.units
        s = engine.scene
        self.probe = Probe(base=s.base, last_apex_x=float(engine.lower_apex_x[-1]) * u.length)
        self.max_overlap = 0.0
        self.max_drift = 0.0
        # unit scales as plain floats: Units computes them on every access
        self._m, self._mps, self._n = u.length, u.velocity, u.force
        self._spring = isinstance(s.drive, SpringDrive)
        self._fixed = s.slider.track == "fixed"

    def _grow(self):
        self.capacity *= 2
        self.cols = np.concatenate([self.cols, np.empty_like(self.cols)], axis=1)
        self.lower = np.concatenate([self.lower, np.empty_like(self.lower)], axis=2)

    def sample(self) -> None:
        e = self.engine
        m, mps, n = self._m, self._mps, self._n
        rows = e.bodies()
        t = e.step_count * self.dt
        if not np.abs(rows[:, 2:]).max() <= MAX_SPEED:  # also true for NaN
            raise SimulationError(
                f"run diverged at t = {t:.6g} s (non-finite or runaway speed); "
                f"use a smaller dt (now {self.dt:.3g} s, default T/50)", time=t)
        fx, fy, ft, count, overlap, touched = e.contacts()
        if overlap > MAX_OVERLAP:
            raise SimulationError(
                f"run diverged at t = {t:.6g} s: asperities overlap by {overlap:.2f} of a base; "
                f"use a smaller dt (now {self.dt:.3g} s) or more iterations", time=t)
        sx, sy, svx, svy = rows[e._slider_row].tolist()
        lower = rows[e._lower_rows]
        dx = lower[:, 0] - e.lower_x0
        drift = float(np.abs(dx).max()) if len(dx) and e.tracked else 0.0
        if self._fixed:
            drift = max(drift, abs(sy - e.slider_y0))
        if drift > self.max_drift:
            self.max_drift = drift
        if overlap > self.max_overlap:
            self.max_overlap = overlap
        if self.size == self.capacity:
            self._grow()
        i = self.size
        fd = e.drive_force(sx, svx) * n
        x, v, y = sx * m, svx * mps, sy * m
        self.cols[:, i] = (t, x, v, y, svy * mps, e.drive_position() * m if self._spring else np.nan, fd,
                           fy * n, -fx * n, ft * n, count)
        self.lower[0, :, i] = dx * m
        self.lower[1, :, i] = lower[:, 1] * m
        flags = self.lower[2, :, i]
        flags[:] = 0.0
        flags[touched] = 1.0
        self.size += 1
        p = self.probe
        p.t, p.x, p.v, p.y, p.drive_force = t, x, v, y, fd
        p.rear_apex_x = (sx + e.upper_apex[0]) * m

    def run(self, stops, progress, meta) -> Result:
        from tqdm.auto import tqdm

        e = self.engine
        self.sample()
        self.probe.x_start = self.probe.x
        status, message = "duration", "reached the requested duration"
        if progress is None:
            disable = None if self.n_steps > 200_000 else True  # None: only on a terminal
        else:
            disable = not progress
        bar = tqdm(total=self.n_steps, unit="step", disable=disable, leave=False, mininterval=0.5)
        done = 0
        while done < self.n_steps:
            n = min(self.k, self.n_steps - done)
            e.step(n)
            done += n
            self.sample()
            bar.update(n)
            hit = next((s for s in stops if s(self.probe)), None)
            if hit is not None:
                status = getattr(hit, "name", type(hit).__name__)
                message = f"stop condition {status!r} met at t = {self.probe.t:.6g} s"
                break
        else:
            if stops:
                status, message = "time limit", "reached the time limit before any stop condition"
        bar.close()
        m = self.size
        c = self.cols[:, :m]
        names = ("t", "x", "v", "y", "vy", "drive_x", "drive_force", "normal_force",
                 "friction_force", "tangential_force", "contact_count")
        arrays = {name: c[j].copy() for j, name in enumerate(names)}
        meta = dict(meta)
        meta.update({
            "dt": self.dt, "record_every": self.k, "status": status, "message": message,
            "steps": e.step_count, "max_overlap_fraction": self.max_overlap,
            "max_track_drift_fraction": self.max_drift,
            "max_solver_drift_fraction": e.max_drift,  # removed by projection each step
            "units": e.units.as_dict(),
            "asperity2d_version": __version__, "pymunk_version": PYMUNK_VERSION,
            "numpy_version": np.__version__,
        })
        return Result(**arrays, lower_dx=self.lower[0, :, :m].copy(),
                      lower_dy=self.lower[1, :, :m].copy(),
                      lower_contact=self.lower[2, :, :m] > 0, scene=e.scene, meta=meta)
