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
import os
from dataclasses import dataclass
from typing import Callable, Iterable

import numpy as np

from ._format import si
from ._inputs import check_finite, check_int, check_positive
from ._version import __version__
from .engine import PYMUNK_VERSION, Engine
from .engine.registry import DEFAULT as DEFAULT_ENGINE, ENGINES, check_engine, refuse
from .engine.energy import ContactWork, EnergyMeter
from .engine.recorder import MAX_OVERLAP, Recorder
from .engine.run_checks import off_surface_message, surface_end
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
#: The asperity energy books (``energy=True``) must close to this fraction of the drive work
#: (measured 1e-14 - 1e-13 on ordinary scenes, and within it on every fuzzed scene).
ENERGY_TOLERANCE = 1e-6
#: The books close by construction: whatever the method does to the energy (position correction,
#: track projection, the integrator's bounded term, the grooves' drift) is a channel of them. How
#: good a metered run is, is the share of the drive work those numerical channels took
#: (``numerical_fraction``); a run above this is flagged (``checks["energy_numerical"]``, the
#: result unsuccessful). Derived from a dt study on the validation page's scene (free slider, 3/1,
#: mu 0, undamped, 50 m/s; no stick-slip chaos, so the run is the same at every step): the share is
#: 1.31 %, 0.81 %, 0.26 % at dt, dt/2, dt/4 (3.6 % at 2.5 dt, the coarsest step allowed), and each
#: halving of dt moves the physical books (the impact loss) by 0.40-0.68 of the share at the
#: coarser step (0.52 %, 0.55 % of the drive work). Above 2.5 % one halving would move them by
#: 1.0-1.7 %: past the 1 % the step policy allows a measure. At the default step the test scenes
#: take 1.0-2.2 % frictionless and undamped (3/1, both set-ups and drives), 1.1 % on Ooten's free
#: 6/2 and 0.2 % on the fixed 6/2.
NUMERICAL_ENERGY_TOLERANCE = 0.025
#: Default step budget of one run (settling included): about 5 minutes at N = 16.
MAX_STEPS = 10_000_000
#: Up to this many asperities (both surfaces: Ooten's 16 + 4) a step counts as one in the
#: budget; a larger scene's step counts as its asperity count over this (see :func:`step_cost`).
COST_ASPERITIES = 20


@dataclass
class Probe:
    """What stop conditions see at each recorded sample (SI units).

    ``rear_apex_x`` is the x of the slider's rearmost tip and ``last_apex_x``
    that of the lower surface's last apex, so ``rear_apex_x > last_apex_x``
    means the slider has passed the whole surface. ``x_start`` is where the
    slider was when the run (the current :meth:`Run.advance`) started.
    ``energy`` is a function returning the energy books so far (the report of
    ``EnergyMeter``, J) when the run is metered
    (``simulate(..., energy=True)``, :meth:`Run.meter_energy`), else None.
    Observers (``simulate(..., observers=[...])``) see the same object.
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
    energy: Callable[[], dict] | None = None


class Passed:
    """Stop when the slider's rear tip is half a base past the last lower apex.

    A stop condition for :func:`~asperity2d.simulate`'s ``stop`` (a default when ``duration`` is None).

    See Also
    --------
    asperity2d.Stuck, asperity2d.Travelled

    Examples
    --------
    >>> import asperity2d as a
    >>> scene = a.make_scene(lower_count=4, upper_count=2)
    >>> a.simulate(scene, 1e-6, stop=a.Passed()).status
    'passed'
    """

    name = "passed"

    def __call__(self, p: Probe) -> bool:
        return p.rear_apex_x > p.last_apex_x + 0.5 * p.base


class Stuck:
    """Stop when abs(v) stays below ``speed`` (m/s) for ``dwell`` seconds.

    It remembers when the slider became slow; ``reset()`` (called by the run
    at the start of every :meth:`Run.advance`) forgets it, so one instance can
    serve several runs.

    Parameters
    ----------
    speed : float
        Speed (m/s) below which the slider counts as slow, > 0.
    dwell : float
        How long (s) it must stay slow, >= 0.

    See Also
    --------
    asperity2d.Passed, asperity2d.Travelled

    Examples
    --------
    The spring-driven slider rests until the spring has pulled hard enough:

    >>> import asperity2d as a
    >>> scene = a.make_scene(lower_count=4, upper_count=2)
    >>> a.simulate(scene, stop=a.Stuck(speed=1.0, dwell=20e-9))
    Result(1190 samples, t_end=131.5 ns, status='stuck')
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
    """Stop once the slider has moved ``distance`` (m) from its start.

    Parameters
    ----------
    distance : float
        Distance (m), > 0.

    See Also
    --------
    asperity2d.Passed, asperity2d.Stuck

    Examples
    --------
    >>> import asperity2d as a
    >>> scene = a.make_scene(lower_count=4, upper_count=2)
    >>> a.simulate(scene, stop=a.Travelled(1e-6)).status
    'travelled'
    """

    name = "travelled"

    def __init__(self, distance: float):
        self.distance = check_positive("distance", distance)

    def __call__(self, p: Probe) -> bool:
        return abs(p.x - p.x_start) >= self.distance


class ForceCrossed:
    """Stop once the drive force has crossed ``force`` (N), in either direction from where it
    started.

    Parameters
    ----------
    force : float
        The drive force (N) to watch for, finite.

    See Also
    --------
    asperity2d.run.FirstSlip, asperity2d.Travelled

    Examples
    --------
    >>> import asperity2d as a
    >>> from asperity2d.run import ForceCrossed
    >>> scene = a.make_scene(lower_count=4, upper_count=2)
    >>> r = a.simulate(scene, stop=ForceCrossed(5e-3))
    >>> r.status, bool(abs(r.drive_force[-1]) >= 5e-3)
    ('force crossed', True)
    """

    name = "force crossed"

    def __init__(self, force: float):
        self.force = check_finite("force", force)
        self._side = None

    def reset(self) -> None:
        self._side = None

    def __call__(self, p: Probe) -> bool:
        side = p.drive_force >= self.force
        if self._side is None:
            self._side = side
            return False
        return side != self._side


class FirstSlip:
    """Stop at the first slip: the slider faster than ``slip_speed`` (m/s) after it has been
    slower than ``stick_speed`` (a stick). The thresholds of :func:`asperity2d.stick_slip_events`
    (0.5 and 3 times the drive velocity) are :meth:`for_scene`'s defaults for a spring drive.

    Parameters
    ----------
    slip_speed : float
        Speed (m/s) above which the slider slips, > 0.
    stick_speed : float, optional
        Speed (m/s) below which it sticks (default ``slip_speed / 6``), below ``slip_speed``.

    See Also
    --------
    asperity2d.stick_slip_events : the events this stops at the first of.

    Examples
    --------
    >>> import asperity2d as a
    >>> from asperity2d.run import FirstSlip
    >>> scene = a.make_scene(lower_count=4, upper_count=2)
    >>> a.simulate(scene, stop=FirstSlip.for_scene(scene)).status
    'first slip'
    """

    name = "first slip"

    def __init__(self, slip_speed: float, stick_speed: float | None = None):
        self.slip_speed = check_positive("slip_speed", slip_speed)
        self.stick_speed = (self.slip_speed / 6.0 if stick_speed is None
                            else check_positive("stick_speed", stick_speed))
        if not self.stick_speed < self.slip_speed:
            raise SceneError(f"`stick_speed` must be below `slip_speed` ({self.slip_speed!r} m/s), "
                             f"got {self.stick_speed!r}")
        self._stuck = False

    @classmethod
    def for_scene(cls, scene: Scene) -> "FirstSlip":
        """The thresholds for ``scene``: 3 and 0.5 times the drive velocity (a spring drive, as
        :func:`asperity2d.stick_slip_events`); under a constant force, 0.05 and 0.01 of the speed
        gained over one base, sqrt(F b / M)."""
        if isinstance(scene.drive, SpringDrive):
            return cls(3.0 * scene.drive.velocity, 0.5 * scene.drive.velocity)
        v_char = math.sqrt(max(abs(scene.drive.force), 1e-300) * scene.base / scene.slider.mass)
        return cls(0.05 * v_char, 0.01 * v_char)

    def reset(self) -> None:
        self._stuck = False

    def __call__(self, p: Probe) -> bool:
        if abs(p.v) < self.stick_speed:
            self._stuck = True
            return False
        return self._stuck and p.v > self.slip_speed


#: Stop settings of a ``[run]`` table (and the workbench's "stop when"): key -> what it means.
STOP_SETTINGS = {
    "stop_pitches": "stop once the slider has moved this many mean pitches of the lower surface",
    "stop_force": "stop once the drive force crosses this value (N)",
    "stop_first_slip": "stop at the first slip (true)",
    "stop_stuck": "stop once the slider has stopped (true): slower than 1 % of its drive speed for "
                  "two of the slowest periods",
}


def stops_from_settings(scene: Scene, settings: dict) -> list[Callable[[Probe], bool]]:
    """The stop conditions a ``[run]`` table's ``stop_*`` keys ask for (:data:`STOP_SETTINGS`),
    each checked and named in a SceneError when wrong; other keys are ignored.

    Examples
    --------
    >>> import asperity2d as a
    >>> from asperity2d.run import stops_from_settings
    >>> scene = a.make_scene(lower_count=4, upper_count=2)
    >>> [s.name for s in stops_from_settings(scene, {"stop_pitches": 2, "stop_first_slip": True})]
    ['travelled', 'first slip']
    """
    stops: list = []
    for key in ("stop_pitches", "stop_force"):
        value = settings.get(key)
        if value is None:
            continue
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise SceneError(f"`{key}` must be a finite number, got {value!r}")
        if key == "stop_pitches":
            stops.append(Travelled(check_positive(key, float(value)) * scene.lower.spacing.mean_pitch))
        else:
            stops.append(ForceCrossed(float(value)))
    for key in ("stop_first_slip", "stop_stuck"):
        value = settings.get(key)
        if value is None or value is False:
            continue
        if value is not True:
            raise SceneError(f"`{key}` must be true or false, got {value!r}")
        if key == "stop_first_slip":
            stops.append(FirstSlip.for_scene(scene))
        else:
            if isinstance(scene.drive, SpringDrive):
                speed = 0.01 * scene.drive.velocity
            else:
                speed = 0.01 * math.sqrt(max(abs(scene.drive.force), 1e-300) * scene.base / scene.slider.mass)
            stops.append(Stuck(speed=speed, dwell=2.0 * scene.slowest_period()))
    return stops


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


def settle_cap(scene: Scene) -> float:
    """Longest settling (s): 10 slowest periods."""
    return 10.0 * scene.slowest_period()


def step_cost(scene: Scene) -> float:
    """What one step of ``scene`` counts for in ``max_steps``: 1 up to :data:`COST_ASPERITIES`
    asperities (both surfaces), else its asperity count over that (a step's cost grows with the
    asperity count: measured ~40 us at 20 asperities, 1.3 ms at 1,000, 0.5 s at 100,000)."""
    return max(1.0, (scene.lower.count + scene.slider.count) / COST_ASPERITIES)


def check_budget(scene: Scene, dt: float, max_steps: int, *, done: int = 0, settle: float = 0.0,
                 duration: float = 0.0) -> None:
    """Refuse a settle of up to ``settle`` s and a run of ``duration`` s at step ``dt`` (s), after
    ``done`` steps, that would exceed ``max_steps`` (SceneError naming what makes it long). Each
    step counts :func:`step_cost`. Needs no engine: :func:`~asperity2d.simulate` checks before building."""
    cost = step_cost(scene)
    steps_settle = settle / dt
    steps_run = duration / dt
    total = (done + steps_settle + steps_run) * cost
    if total <= max_steps:
        return
    if steps_settle > steps_run:
        why = (f"settling takes up to {steps_settle:.3g} steps (10 slowest periods, "
               f"{settle:.3g} s, set by {_slowest_source(scene)})")
        fix = "bring those closer to the other masses and stiffnesses, pass settle=False"
    else:
        why = f"`duration` = {duration:.3g} s is {steps_run:.3g} steps"
        fix = "shorten `duration`"
    size = ""
    if cost > 1:
        size = (f"; each step of these {scene.lower.count + scene.slider.count:,} asperities counts "
                f"{cost:.3g} steps (its cost grows with the asperity count)")
        fix += ", use fewer asperities"
    raise SceneError(
        f"the run needs {total:.3g} steps, over `max_steps` = {max_steps:,}: {why} of "
        f"dt = {dt:.3g} s (set by {_fastest_source(scene)}){size}; {fix}, or raise `max_steps`")


def resolve_dt(scene: Scene, dt: float | None, unsafe_dt: bool) -> float:
    """The step (s) a run of ``scene`` uses: ``dt``, checked (a ``SceneError`` for one coarser than
    T/20 or than half the drive damper's time, unless ``unsafe_dt``), or the default."""
    period = scene.shortest_period()
    if dt is None:
        return default_dt(scene)
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
    return dt


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

    Parameters
    ----------
    scene : Scene
        What to run.
    dt, record_every, iterations, unsafe_dt, max_steps, record_lower, record_to
        As for :func:`~asperity2d.simulate`.
    engaged : bool, default False
        Start a fixed-track slider over the surface rather than before it.

    Raises
    ------
    SceneError
        Bad arguments, named (as :func:`~asperity2d.simulate`).

    See Also
    --------
    asperity2d.simulate : the whole run in one call.

    Examples
    --------
    Run, then reverse the drive on a fork of the same state:

    >>> import asperity2d as a
    >>> run = a.Run(a.make_scene(lower_count=4, upper_count=2))
    >>> run.advance(100e-9, stop=a.Passed())
    'duration'
    >>> back = run.fork()
    >>> back.set_drive_velocity(-5.0)
    >>> back.advance(50e-9)
    'duration'
    >>> back.result()
    Result(454 samples, t_end=150.0 ns, status='duration')
    """

    def __init__(self, scene: Scene, *, dt: float | None = None, record_every: int = 10,
                 iterations: int = 20, unsafe_dt: bool = False, max_steps: int = MAX_STEPS,
                 engaged: bool = False, record_lower: bool = True, record_to=None):
        if not isinstance(scene, Scene):
            raise SceneError(f"`scene` must be a Scene (see make_scene), got {type(scene).__name__}")
        dt = resolve_dt(scene, dt, unsafe_dt)
        self.record_every = check_int("record_every", record_every, minimum=1)
        self.iterations = check_int("iterations", iterations, minimum=1, maximum=10_000)
        self.max_steps = check_int("max_steps", max_steps, minimum=1, maximum=None)
        if not isinstance(record_lower, bool):
            raise SceneError(f"`record_lower` must be True or False, got {record_lower!r}")
        self.record_lower = record_lower
        self.scene, self.dt = scene, dt
        self.engine = Engine(scene, dt, iterations=self.iterations, engaged=engaged)
        self.settle_time = 0.0
        self.status, self.message = "duration", "nothing run yet"
        self._meter = None
        self._sink = None
        #: Entries added to the result's ``meta`` (e.g. the energy books of :func:`~asperity2d.simulate`).
        self.extra_meta: dict = {}
        self._reset_record()
        if record_to is not None:
            self._stream(record_to)

    def _stream(self, path) -> None:
        """Stream the record to directory ``path`` from now on (``asperity2d.streamed``)."""
        from .streamed import Writer

        if self._record.size:
            raise SceneError("`record_to` must be set before the run records anything")
        self._sink = Writer(path, scene=self.scene, lower=self.record_lower, meta=self._meta())
        self._reset_record()

    # -- budget ---------------------------------------------------------------
    def settle_cap(self) -> float:
        """Longest settling (s): 10 slowest periods."""
        return settle_cap(self.scene)

    def check_budget(self, *, settle: float = 0.0, duration: float = 0.0) -> None:
        """Refuse, before running, a settle and run that would exceed ``max_steps`` (SceneError
        naming what makes it long; see :func:`check_budget`)."""
        check_budget(self.scene, self.dt, self.max_steps, done=self.engine.step_count, settle=settle,
                     duration=duration)

    # -- the record ---------------------------------------------------------
    def _reset_record(self, like: Recorder | None = None) -> None:
        # the engine's recorder keeps the samples (SI) and the divergence guard (internal units)
        self._record = Recorder(self.engine, lower=self.record_lower, sink=self._sink, like=like)

    @property
    def max_overlap(self) -> float:
        """Deepest overlap seen at the samples (asperity bases)."""
        return self._record.max_overlap

    @property
    def max_drift(self) -> float:
        """Largest drift off a track seen at the samples (asperity bases)."""
        return self._record.max_drift

    # -- running ------------------------------------------------------------
    def settle(self, *, push: float = 0.0, max_time: float | None = None,
               progress: bool | None = None) -> float:
        """Bring the scene to rest before t = 0 (see ``Engine.settle``); return the time (s).

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
                record: bool = True, observers: Iterable[Callable] = ()) -> str:
        """Step for ``duration`` (s), recording every ``record_every`` steps (default: the
        run's), until a stop condition holds. Returns (and sets) ``status``:
        ``"duration"``, the stop's name, or ``"off-surface"`` when the slider left the far end
        of the lower surface (a free slider's run ends there; a fixed-track one runs on).

        ``observers`` are called as ``observer(probe)`` at every sample, the first
        included, with the SI view of the state (``Probe``), before the stop
        conditions are asked; they watch and must not change the run.

        ``record=False`` keeps nothing: every ``record_every`` steps the stop conditions
        and the divergence guard still see the state, exactly as when recording (so the
        run stops at the same step), but no sample is added to :meth:`result` (the
        critical force's bisection runs, which only need their outcome)."""
        for _ in self.advancing(duration, stop=stop, progress=progress, record_every=record_every,
                                record=record, observers=observers):
            pass
        return self.status

    def advancing(self, duration: float, *, stop: Callable | Iterable[Callable] | None = None,
                  progress: bool | None = None, record_every: int | None = None,
                  record: bool = True, observers: Iterable[Callable] = (), every: int | None = None):
        """:meth:`advance` in pieces, a generator: the same steps and samples (the same loop:
        :meth:`advance` exhausts it), yielding this run each time ``every`` more samples have
        been recorded (``None``: never), so the caller can read the partial record
        (:meth:`result`, :attr:`samples`) or stop early by closing the generator (the run
        keeps what it recorded). Sets ``status`` as :meth:`advance` does when it ends."""
        if every is not None:
            every = check_int("every", every, minimum=1, maximum=None)
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
        observers = _callables("observers", observers)
        e, rec = self.engine, self._record
        self.check_budget(duration=duration)
        n_steps = int(math.ceil(duration / self.dt - 1e-9))
        probe = Probe(base=self.scene.base, last_apex_x=rec.last_apex_x(),
                      energy=None if self._meter is None else self._meter.report)
        sample = rec.sample if record else rec.check
        if record:
            rec.reserve(n_steps // k + 2)
        sample()
        look = bool(stops or observers)  # the SI view is read only when someone looks
        if look:
            rec.probe(probe)
            probe.x_start = probe.x
            for observe in observers:
                observe(probe)
        self.status, self.message = "duration", "reached the requested duration"
        # Past this slider x (internal) no lower face is under the slider: a free slider ends the
        # run there (it would fall to the guard floor); a fixed-track one coasts on, touching
        # nothing, and its run keeps its samples but ends "off-surface".
        if getattr(self, "_surface_end", None) is None:  # once per run (forks share it)
            self._surface_end = surface_end(e)[0]
        off_x, rows, row = self._surface_end, e.bodies_internal, e.layout.slider_row
        free, left = self.scene.slider.track == "free", None
        disable = (None if n_steps > 200_000 else True) if progress is None else not progress
        bar = tqdm(total=n_steps, unit="step", disable=disable, leave=False, mininterval=0.5)
        done, held = 0, rec.size
        try:
            while done < n_steps:
                n = min(k, n_steps - done)
                e.step(n)
                done += n
                sample()
                bar.update(n)
                if every and record and rec.size - held >= every:
                    held = rec.size
                    yield self
                if look:
                    rec.probe(probe)
                    for observe in observers:
                        observe(probe)
                    hit = next((s for s in stops if s(probe)), None)
                    if hit is not None:
                        self.status = getattr(hit, "name", type(hit).__name__)
                        self.message = f"stop condition {self.status!r} met at t = {si(probe.t, 's', 4)}"
                        break
                if left is None and rows().item(row, 0) > off_x:  # after the stops: one that holds wins
                    left = (rows().item(row, 0), e.time)
                    if free:
                        break
        finally:
            bar.close()
        if left is not None and self.status == "duration":
            self.status, self.message = "off-surface", off_surface_message(e, *left)
        return self.status

    def fork(self) -> "Run":
        """An independent run from the current state, with an empty record (and its own
        divergence books; not metered)."""
        out = object.__new__(Run)
        out.__dict__.update(self.__dict__)
        out.engine = self.engine.copy()
        out._meter = None
        out._sink = None  # a fork keeps its record in memory
        out.extra_meta = {}
        out._reset_record(like=self._record)
        return out

    def meter_energy(self) -> EnergyMeter:
        """Start metering every step's energy flows from now on; return the meter
        (``meter.report()``: the books in J, SI; ``meter.detach()`` stops it). A metered step
        costs about 7 plain steps."""
        self._meter = EnergyMeter(self.engine)
        return self._meter

    def meter_contact_work(self) -> ContactWork:
        """Start booking the work of the slider's contacts from now on (pushing it on,
        throwing it back, resisting it; the floor's); return the books (``.report()``, J)."""
        return ContactWork(self.engine)

    def slider_state(self) -> tuple[float, float, float, float]:
        """Slider ``(x, y, vx, vy)`` now (m, m, m/s, m/s)."""
        return self.engine.slider_state()

    def drive_position(self) -> float:
        """Far end of the drive spring now (m); NaN for a constant force."""
        return self.engine.drive_position()

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
        return self._record.size

    def _meta(self) -> dict:
        """The run's settings, diagnostics and checks (a result's ``meta``)."""
        e = self.engine
        meta = {
            "settle_time": self.settle_time, "iterations": self.iterations, "dt": self.dt,
            "record_every": self.record_every, "status": self.status, "message": self.message,
            "steps": e.step_count, "max_overlap_fraction": self.max_overlap,
            "max_track_drift_fraction": self.max_drift,
            "max_solver_drift_fraction": e.max_solver_drift,  # removed by projection each step
            "units": e.units.to_dict(), "asperity2d_version": __version__, "engine": "pymunk",
            "pymunk_version": PYMUNK_VERSION, "numpy_version": np.__version__,
            "record_lower": self.record_lower, **self.extra_meta,
        }
        meta["checks"] = _checks(self)
        for check in meta["checks"].values():
            if not check["passed"]:
                meta["message"] += f"; WARNING: {check['warning']}"
        return meta

    def result(self, *, start: int = 0) -> Result:
        """The samples recorded so far (from sample ``start`` on) as a :class:`~asperity2d.Result` (SI):
        views of the record, not copies. A run streamed to disk (``record_to``) writes what it
        has not written yet and returns the record read back from its files (memory maps)."""
        meta = self._meta()
        if self._sink is not None:
            from .streamed import read

            self._record.flush()
            self._sink.finish(meta)
            return read(self._sink.path, start=start)
        return Result(**self._record.arrays(start), scene=self.scene, meta=meta)

    def abort(self, reason: str) -> None:
        """A streamed record keeps what it has written, marked as stopped by ``reason``."""
        if self._sink is not None:
            self._record.flush()
            self._sink.abort(reason, self._meta())


def _checks(run: Run) -> dict:
    """What ``run`` passed (``result.meta["checks"]``): the divergence guard, the physical-validity
    checks (``asperity2d.engine.run_checks``) and the step size, each with its worst value and
    limit. A check that failed carries a ``warning`` (the result is marked unsuccessful): the step
    size (``unsafe_dt``) and a step resolution past ``STEP_WARNING``;
    the other failures raise."""
    coarse = max(run.dt / (COARSEST_DT_FRACTION * run.scene.shortest_period()),
                 run.dt / (COARSEST_DAMPER_DT_FRACTION * _damper_time(run.scene)))
    checks = {"divergence": {"passed": True, "worst": run.max_overlap, "limit": MAX_OVERLAP,
                             "what": "deepest overlap (bases); kinetic energy within what was given"},
              **run._record.validity.report(),
              "step_size": {"passed": coarse <= 1.0, "worst": coarse, "limit": 1.0,
                            "what": "dt / the coarsest converged step (T/20, M/c / 2)"}}
    if "energy" in run.extra_meta:  # a metered run (simulate raises if its books do not close)
        residual = run.extra_meta["energy"]["residual_fraction"]
        checks["energy_books"] = {
            "passed": bool(residual <= ENERGY_TOLERANCE), "worst": residual, "limit": ENERGY_TOLERANCE,
            "what": "energy books' residual / the larger of drive work and energy removed"}
        if not checks["energy_books"]["passed"]:
            checks["energy_books"]["warning"] = "the energy books do not close"
        share = run.extra_meta["energy"].get("numerical_fraction", 0.0)
        checks["energy_numerical"] = {
            "passed": bool(share <= NUMERICAL_ENERGY_TOLERANCE), "worst": share,
            "limit": NUMERICAL_ENERGY_TOLERANCE,
            "what": "numerical channels (position correction, projection, integrator, track drift) / drive work"}
        if not checks["energy_numerical"]["passed"]:
            checks["energy_numerical"]["warning"] = (
                f"the numerical method took {share:.3g} of the drive work (limit {NUMERICAL_ENERGY_TOLERANCE:g}): "
                "the physical energy channels are not converged; halve `dt`")
    if coarse > 1.0:
        checks["step_size"]["warning"] = (
            f"dt is {coarse:.3g} times the coarsest step that converges (unsafe_dt=True): contacts may "
            "have been skipped and the forces are not converged")
    return checks


def _callables(name: str, items) -> list:
    items = [items] if callable(items) else list(items or ())
    for item in items:
        if not callable(item):
            raise SceneError(f"`{name}` entries must be callables, got {item!r}")
    return items


def simulate(scene: Scene, duration: float | None = None, *, dt: float | None = None,
             record_every: int = 10, stop: Callable | Iterable[Callable] | None = None,
             settle: bool | None = None, iterations: int = 20, unsafe_dt: bool = False,
             progress: bool | None = None, energy: bool = False, max_steps: int = MAX_STEPS,
             observers: Iterable[Callable] = (), contact_work: bool = False,
             record_lower: bool = True, record_to: str | os.PathLike | None = None,
             engine: str = DEFAULT_ENGINE) -> Result:
    """Run ``scene`` with a fixed step and return its :class:`~asperity2d.Result`.

    Parameters
    ----------
    scene : Scene
        What to run (:func:`~asperity2d.make_scene`); SI units throughout.
    duration : float or None, default None
        Simulated time (s) after settling. ``None``: until the slider has
        passed the lower surface, or (constant force) is stuck for good, or a
        time limit long enough to cross it has run out (``status`` says which).
    dt : float, optional
        Step (s). Default: 1/50 of the shortest natural period. A step coarser
        than 1/20 of it is refused unless ``unsafe_dt=True``.
    record_every : int, default 10
        Record every k-th step (the first sample is the settled state).
    stop : callable or list of callables, optional
        ``stop(probe) -> bool`` evaluated at every sample; extra to the
        defaults when ``duration`` is None. See :class:`Passed`,
        :class:`Stuck`, :class:`Travelled`.
    settle : bool, optional
        Let a free slider settle under its load (x held, damped) first, until
        its motion has decayed (at most 10 slowest periods). Default: True for
        a free slider.
    iterations : int, default 20
        pymunk solver iterations.
    unsafe_dt : bool, default False
        Accept a ``dt`` coarser than 1/20 of the shortest natural period (the
        run's ``checks`` then report ``step_size`` as not passed).
    progress : bool, optional
        Show a progress bar (default: only on a terminal, for long runs).
    energy : bool, default False
        Meter every step's energy flows from the settled state on
        (``EnergyMeter``) and store its report
        in ``result.meta["energy"]`` (a metered step costs about 7 plain steps).
    contact_work : bool, default False
        Book the work of the slider's contacts by what each does, from the settled
        state on (``ContactWork``), in
        ``result.meta["contact_work"]`` (J).
    max_steps : int, default 10_000_000
        Step budget (settling included), checked before anything runs.
    observers : list of callables, default ()
        ``observer(probe)`` called at every sample (the settled state included),
        with the SI view of the state (``Probe``: time, slider position and
        velocity, drive force, the start position; ``probe.energy()`` the energy
        books so far when ``energy=True``), before the stop conditions. For
        studies that watch a run as it goes (e.g. the books when the slider
        first got somewhere); an observer watches, it must not change the run.
    record_lower : bool, default True
        Keep the lower asperities' displacements and contacts (``lower_dx``, ``lower_dy``,
        ``lower_contact``; 17 B per asperity and sample) besides the slider's eleven series
        (88 B a sample). False keeps only the slider's (the three then have no samples; the
        animations, which draw the asperities, refuse such a result).
    record_to : path, optional
        Stream the record to this directory as the run goes (``asperity2d.streamed``:
        one ``.npy`` per array and a JSON manifest, written a block of at most 4 MB at a
        time), so the run's memory stays flat whatever its length; the result returned reads
        the files lazily (memory maps), as ``asperity2d.load(record_to)`` does later. A run
        that is killed leaves the samples written so far, loaded with status
        ``"interrupted"``; one that raises leaves them too, its message saying why.
    engine : str, default "pymunk"
        The engine that steps it (``asperity2d.engine.ENGINES``): ``"pymunk"``, the
        reference, runs every option; ``"batched"`` (the ``[batch]`` extra) runs the model's
        common case in a compiled loop, without the energy books, observers, custom stops,
        streaming, settling or the lower asperities' records (each refused in one line).
        ``result.meta["engine"]`` names it.

    Returns
    -------
    Result
        The recorded run: time series in SI (``t``, ``x``, ``v``, ``drive_force``, ...),
        ``status`` (``"passed"``, ``"stuck"``, ``"duration"``, ...) and the scene it ran.
        A run whose slider left the far end of the lower surface ends ``"off-surface"``, its
        ``message`` saying where: a free slider stops there (it would fall to the guard floor),
        a fixed-track one coasts on, touching nothing, to the end of the run.

    Raises
    ------
    SceneError
        Bad arguments (named in the message), or a run over ``max_steps``
        (naming the parameter that makes it long).
    SimulationError
        The run diverged: non-finite state, kinetic energy far beyond what the
        scene held and was given, or deep penetration.

    See Also
    --------
    asperity2d.make_scene : the scene.
    asperity2d.stick_slip_events : measures of the run.
    asperity2d.peak_stick_force
    asperity2d.mean_stick_force
    asperity2d.breakaway_force
    asperity2d.critical_force : bisection over constant-force runs.
    asperity2d.render : pictures, animations and sounds of the run.
    asperity2d.Run : the same run step by step (fork, change the drive, advance).

    Examples
    --------
    >>> import asperity2d as a
    >>> scene = a.make_scene(lower_count=4, upper_count=2)
    >>> result = a.simulate(scene)
    >>> result
    Result(3731 samples, t_end=412.4 ns, status='passed')
    >>> f"{result.drive_force.max() * 1e3:.3g} mN"
    '17.2 mN'

    A fixed duration instead of "until the slider has passed":

    >>> a.simulate(scene, 100e-9).status
    'duration'

    Bad input is one line naming the parameter:

    >>> a.simulate("scene.toml")
    Traceback (most recent call last):
    ...
    asperity2d.errors.SceneError: `scene` must be a Scene (see make_scene), got str
    """
    if check_engine(engine) != DEFAULT_ENGINE:
        refused = [name for name, value, default in (
            ("stop", stop, None), ("energy", energy, False), ("contact_work", contact_work, False),
            ("record_to", record_to, None)) if value is not default and value != default]
        if tuple(observers):
            refused.append("observers")
        if refused:
            raise SceneError(f"`{refused[0]}` is not available on engine={engine!r}; engine=\"pymunk\" runs it")
        out = simulate_many([scene], duration, dt=dt, record_every=record_every, settle=settle,
                            iterations=iterations, unsafe_dt=unsafe_dt, max_steps=max_steps, engine=engine)[0]
        if isinstance(out, Exception):
            raise out
        return out
    gen = _simulation(scene, duration, dt=dt, record_every=record_every, stop=stop, settle=settle,
                      iterations=iterations, unsafe_dt=unsafe_dt, progress=progress, energy=energy,
                      max_steps=max_steps, observers=observers, contact_work=contact_work,
                      record_lower=record_lower, record_to=record_to, every=None)
    while True:
        try:
            next(gen)
        except StopIteration as done:
            return done.value


class Simulation:
    """:func:`simulate` in pieces: the same run (the same loop, the same numbers to the bit),
    yielding the :class:`Run` each time ``every`` more samples have been recorded, so a caller
    can read the partial record as it grows (``run.samples``, ``run.result(start=k)``) and stop
    early (``close()``, or stop iterating)::

        sim = Simulation(scene, every=200)
        for run in sim:
            show(run.result(start=shown))   # a view of the samples so far
        result = sim.result                 # what simulate(scene) returns

    Takes :func:`simulate`'s arguments. ``result`` is None until the iteration has ended.
    """

    def __init__(self, scene: Scene, duration: float | None = None, *, every: int = 200, **options):
        every = check_int("every", every, minimum=1, maximum=None)
        self._gen = _simulation(scene, duration, every=every, **options)
        self.result: Result | None = None
        self.run: Run | None = None

    def __iter__(self):
        return self

    def __next__(self) -> Run:
        try:
            self.run = next(self._gen)
        except StopIteration as done:
            self.result = done.value
            raise StopIteration from None
        return self.run

    def close(self) -> None:
        """Stop the run where it is (a streamed record keeps its samples)."""
        self._gen.close()


def _simulation(scene: Scene, duration: float | None = None, *, dt: float | None = None,
                record_every: int = 10, stop: Callable | Iterable[Callable] | None = None,
                settle: bool | None = None, iterations: int = 20, unsafe_dt: bool = False,
                progress: bool | None = None, energy: bool = False, max_steps: int = MAX_STEPS,
                observers: Iterable[Callable] = (), contact_work: bool = False,
                record_lower: bool = True, record_to: str | os.PathLike | None = None,
                every: int | None = None):
    """The body of :func:`simulate` as a generator (it returns the Result): yields the Run once
    built and settled, then every ``every`` samples (:meth:`Run.advancing`)."""
    if not isinstance(scene, Scene):
        raise SceneError(f"`scene` must be a Scene (see make_scene), got {type(scene).__name__}")
    stops = [] if stop is None else ([stop] if callable(stop) else list(stop))
    if duration is None:
        stops = default_stops(scene) + stops
        duration = default_duration(scene)
    else:
        check_finite("duration", duration)
        check_positive("duration", duration)
    if settle is None:
        settle = scene.slider.track == "free"
    observers = _callables("observers", observers)
    # the budget before anything is built (building 100,000 asperities takes seconds)
    check_budget(scene, default_dt(scene) if dt is None else check_positive("dt", dt),
                 check_int("max_steps", max_steps, minimum=1, maximum=None),
                 settle=settle_cap(scene) if settle else 0.0, duration=duration)
    run = Run(scene, dt=dt, record_every=record_every, iterations=iterations, unsafe_dt=unsafe_dt,
              max_steps=max_steps, record_lower=record_lower)
    if record_to is not None:  # after every check: a refused run leaves no directory behind
        run._stream(record_to)
    try:
        if settle:
            run.settle(progress=progress)
        meter = run.meter_energy() if energy else None
        books = run.meter_contact_work() if contact_work else None
        if every is not None:
            yield run
        yield from run.advancing(duration, stop=stops, progress=progress, observers=observers, every=every)
    except GeneratorExit:  # the caller stopped iterating: the run keeps what it recorded
        run.abort("stopped by the caller")
        raise
    except BaseException as exc:  # a streamed record keeps its samples, saying why it stopped
        run.abort(f"{type(exc).__name__}: {exc}")
        raise
    if stops and run.status == "duration":
        run.status, run.message = "time limit", "reached the time limit before any stop condition"
    if meter is not None:
        report = run.extra_meta["energy"] = meter.report()  # its check: see _checks
        if not report["residual_fraction"] <= ENERGY_TOLERANCE:  # also NaN
            error = SimulationError(
                f"the energy books do not close: the drive's work and the energy stored and removed "
                f"differ by {report['residual_fraction']:.3g} of the larger (tolerance {ENERGY_TOLERANCE:g}) "
                f"at t = {run.time:.6g} s: energy was created or lost by no modelled channel; use a smaller "
                "`dt` or more `iterations`", time=run.time)
            run.abort(str(error))
            raise error
    if books is not None:
        run.extra_meta["contact_work"] = books.report()
    return run.result()


def simulate_many(scenes: Iterable[Scene], duration: float | None = None, *, dt: float | None = None,
                  record_every: int = 10, settle: bool | None = None, iterations: int = 20,
                  unsafe_dt: bool = False, max_steps: int = MAX_STEPS, engine: str = "batched") -> list:
    """Run many scenes with one engine; one :class:`~asperity2d.Result` per scene, in order.

    The arguments are :func:`simulate`'s, for every scene (``dt``: one step for all, or None
    for each scene's default). On ``engine="batched"`` the scenes step together in one compiled
    loop; a scene that diverges stops alone: its entry is then its own
    :class:`~asperity2d.errors.SimulationError` (returned, not raised) and the others finish.
    On ``engine="pymunk"`` the scenes run one after the other (an error is returned likewise).

    Examples
    --------
    >>> import asperity2d as a
    >>> from asperity2d.run import simulate_many
    >>> scenes = [a.make_scene(lower_count=4, upper_count=2, spacing="random", seed=s) for s in (1, 2)]
    >>> [r.meta["engine"] for r in simulate_many(scenes, 50e-9, engine="pymunk")]
    ['pymunk', 'pymunk']
    """
    engine = check_engine(engine)
    scenes = list(scenes)
    for scene in scenes:
        if not isinstance(scene, Scene):
            raise SceneError(f"`scenes` must hold Scene objects (see make_scene), got {type(scene).__name__}")
    if not scenes:
        raise SceneError("`scenes` is empty: give at least one scene")
    if engine == DEFAULT_ENGINE:
        out = []
        for scene in scenes:
            try:
                out.append(simulate(scene, duration, dt=dt, record_every=record_every, settle=settle,
                                    iterations=iterations, unsafe_dt=unsafe_dt, max_steps=max_steps,
                                    progress=False))
            except SimulationError as exc:
                out.append(exc)
        return out
    record_every = check_int("record_every", record_every, minimum=1)
    iterations = check_int("iterations", iterations, minimum=1, maximum=10_000)
    max_steps = check_int("max_steps", max_steps, minimum=1, maximum=None)
    dts, durations, passed = [], [], []
    for scene in scenes:
        if duration is None and isinstance(scene.drive, ConstantForce) and scene.drive.force != 0:
            raise SceneError(f"`duration` = None with a constant force (the Stuck stop) is not available on "
                             f"engine={engine!r}: give a duration, or engine=\"pymunk\" runs it")
        refuse(engine, scene, settle=scene.slider.track == "free" if settle is None else bool(settle))
        step = resolve_dt(scene, dt, unsafe_dt)
        span = default_duration(scene) if duration is None else check_positive("duration", check_finite("duration", duration))
        check_budget(scene, step, max_steps, duration=span)
        dts.append(step)
        durations.append(span)
        passed.append(duration is None)
    results = ENGINES[engine].run(scenes, dts, durations, record_every=record_every, iterations=iterations,
                                  passed=passed)
    out = []
    for scene, record, stopped in zip(scenes, results, passed):
        if isinstance(record, Exception):
            out.append(record)
            continue
        arrays, meta = record
        if stopped and meta["status"] == "duration":
            meta.update(status="time limit", message="reached the time limit before any stop condition")
        out.append(Result(**arrays, scene=scene, meta=meta))
    return out
