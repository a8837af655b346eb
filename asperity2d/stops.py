"""Stop conditions: the callables that end a run, and the ``[run]`` table's ``stop_*`` keys.

A stop condition is ``stop(probe) -> bool``, asked at every recorded sample with the SI view of
the state (:class:`Probe`); the first that holds ends the run and names itself in
``result.status`` (``name``). One with a ``reset()`` is reset at the start of every
:meth:`~asperity2d.Run.advance`, so one instance can serve several runs. ``asperity2d.run``
re-exports every name here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

from ._inputs import check_finite, check_positive
from .errors import SceneError
from .scene import ConstantForce, Scene, SpringDrive


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
