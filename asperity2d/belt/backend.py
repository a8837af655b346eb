"""The belt back-end contract: what every solver back-end receives and what it returns.

A back-end is a :class:`Backend` -- a function ``run(spec, options) -> RawRun`` with the
predicate ``accepts(spec)`` that says which chains it solves -- listed under a method name in
``asperity2d.belt.METHODS``. ``simulate_chain`` builds one spec and runs the first back end of
the chosen method that accepts it. The contract:

1. ``spec`` is validated (SI, with its scales): a :class:`~asperity2d.belt.spec.ChainSpec`
   for a tangential chain, or a ``ContactSpec`` (``asperity2d.belt.ContactSpec``: the chain,
   its ``NormalContact`` and the initial gaps ``y0`` / ``vy0``) when ``simulate_chain`` was
   given a normal contact. ``accepts`` must return False, not raise, for a spec of the kind
   its back end cannot run.
2. ``options`` is :class:`RunOptions`, the validated run settings (sample times, tolerances,
   budgets); a long loop calls :func:`watch` now and then so the wall-clock budget holds.
3. ``run`` returns, for a ChainSpec, a :class:`RawRun`: the sampled motion (SI) and the
   switching record; :func:`asperity2d.belt.result.assemble` adds the derived forces and
   energies and makes a ``BeltResult``. For a ContactSpec it returns the contact's raw run
   (``ContactRun``: the state [x; y; v; vy], the modes, the normal force, four energy books,
   the separation intervals), which becomes a ``ContactResult``. Either result's energy books
   are checked against its stored energy: a back end whose books do not close is refused.
4. ``settings`` names the :class:`RunOptions` fields the back end uses that the result's meta
   records (``rtol``, ``integrator`` by default; none for a back end that integrates nothing).
5. Back-ends never print, never write files and raise only ``SceneError`` (bad input) or
   ``SimulationError`` (a run that went wrong or over its budget).
"""

from __future__ import annotations

import contextlib
import contextvars
import math
import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..errors import SceneError, SimulationError
from .._inputs import check_choice, check_flag, check_int, check_real, check_vector, show
from . import limits

INTEGRATORS = ("LSODA", "Radau", "BDF", "DOP853", "RK45")
#: Default wall-clock budget of one run (s): a chain that needs longer says so and names
#: ``max_wall_time`` (the step and event budgets are counted; this one is the backstop for
#: work neither counts well: a chattering sign() solve, a stiff friction law, a huge chain).
MAX_WALL_TIME = 30.0


@dataclass(frozen=True)
class Backend:
    """One solver back-end: ``run(spec, options) -> RawRun`` for the chains ``accepts(spec)`` is
    True for (the module's contract); ``settings``: the run settings the result's meta records.

    Examples
    --------
    >>> from asperity2d import belt
    >>> [b.name for b in belt.METHODS["exact"]]  # in order of preference; the first that accepts runs
    ['closed-form contact phases', 'state-variable ODE (Dahl, LuGre)', 'closed-form phases', 'integrated phases']
    >>> r = belt.simulate_chain([1.0], [100.0, 0.0], [0.0, 0.0], mu_s=0.4, mu_k=0.3, v_belt=0.1, x0=[0.0],
    ...                         v0=[0.1], t_end=2.0)
    >>> r.meta["backend"], r.meta["rtol"]  # its `settings` are recorded
    ('closed-form phases', 1e-08)
    """

    name: str
    accepts: Callable[[object], bool]
    run: Callable[[object, "RunOptions"], object]
    settings: tuple = ("rtol", "integrator")


@dataclass(frozen=True)
class Event:
    """A switch of one mass at time ``t`` (s) at position ``x`` (m).

    ``kind`` is "stick", "slip", "reverse" (slip direction flips through belt
    speed) or "graze": the mass touched belt speed tangentially and the stick
    condition held only at that instant, so it kept slipping (see
    ``asperity2d.belt.chain.modes`` for the rule).

    Attributes
    ----------
    t : float
        Time (s).
    mass : int
        Index of the mass (0 first).
    kind : {"stick", "slip", "reverse", "graze"}
        The switch.
    x : float
        Position of the mass (m).

    See Also
    --------
    asperity2d.belt.simulate_chain : ``result.events`` lists them.

    Examples
    --------
    >>> from asperity2d import belt
    >>> r = belt.simulate_chain([1.0], [100.0, 0.0], [0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...                         v_belt=0.1, x0=[0.0], v0=[0.1], t_end=2.0)
    >>> r.events[0]
    Event(t=0.39239999999999997, mass=0, kind='slip', x=0.03924)
    """

    t: float
    mass: int
    kind: str
    x: float


@dataclass(frozen=True)
class RunOptions:
    """Validated run settings shared by all back-ends.

    ``samples`` (s) are the output times; ``include_events`` adds every switching
    instant; ``rtol`` / ``atol`` / ``integrator`` drive ``solve_ivp`` where one is
    used; ``max_events`` bounds the switches and ``max_steps`` the work (scan
    steps or right-hand-side evaluations) of one run.
    """

    samples: np.ndarray
    include_events: bool = True
    rtol: float = 1e-8
    atol: float | None = None
    integrator: str = "LSODA"
    max_events: int = 1_000_000
    max_steps: int = 1_000_000
    max_wall_time: float = MAX_WALL_TIME
    #: when the run's wall-clock budget ends (``time.perf_counter()``), set by :meth:`build`
    deadline: float = math.inf

    @classmethod
    def build(cls, spec, *, n_samples, t_eval, include_events, rtol, atol, integrator, max_events, max_steps,
              max_wall_time=MAX_WALL_TIME):
        """Check every setting against ``spec`` (names the parameter the user wrote); the wall-clock
        budget starts now."""
        max_steps = check_int("max_steps", max_steps, minimum=1, maximum=None)
        max_wall_time = check_real("max_wall_time", max_wall_time, positive=True)
        samples = _sample_times(spec, n_samples, t_eval)
        limits.budget(spec, samples.size, max_steps)
        rtol = check_real("rtol", rtol, positive=True)
        if not 1e-13 <= rtol <= 0.1:
            raise SceneError(f"`rtol` must be within [1e-13, 0.1], got {show(rtol)}")
        return cls(
            samples=samples,
            include_events=check_flag("include_events", include_events),
            rtol=rtol,
            atol=None if atol is None else check_real("atol", atol, positive=True),
            integrator=check_choice("integrator", integrator, INTEGRATORS),
            max_events=check_int("max_events", max_events, minimum=1, maximum=None),
            max_steps=max_steps,
            max_wall_time=max_wall_time,
            deadline=time.perf_counter() + max_wall_time,
        )

    @contextlib.contextmanager
    def watching(self, now):
        """Within this block :func:`watch` checks the wall-clock budget (``now()``: the simulated time
        reached, s): the event loops set it, so that loops deep inside a phase (a Taylor grid
        propagated over millions of steps) stop in time too."""
        token = _WATCH.set(lambda: self.check_clock(now()))
        try:
            yield
        finally:
            _WATCH.reset(token)

    def check_clock(self, t: float) -> None:
        """Raise SimulationError naming ``max_wall_time`` once the run's wall-clock budget is spent
        (``t``: the simulated time reached, s)."""
        if time.perf_counter() > self.deadline:
            raise SimulationError(
                f"the run used its wall-clock budget `max_wall_time` = {self.max_wall_time:g} s and had "
                f"reached t = {t:.6g} s; raise `max_wall_time`, shorten `t_end`, or make the chain less "
                "stiff (its rates, friction law and belt speed set the work per simulated second)", time=t)


#: the running solve's wall-clock check (:meth:`RunOptions.watching`), None outside a solve
_WATCH: contextvars.ContextVar = contextvars.ContextVar("asperity2d_belt_watch", default=None)


def watch() -> None:
    """Raise SimulationError naming ``max_wall_time`` if the running solve is over its wall-clock
    budget (nothing outside a solve). Cheap (~0.1 us): call it every few thousand steps of a loop."""
    check = _WATCH.get()
    if check is not None:
        check()


def _sample_times(spec, n_samples, t_eval) -> np.ndarray:
    if t_eval is not None:
        t = check_vector("t_eval", t_eval, nonneg=True, as_array=True)
        # (t[i+1] <= t[i] exactly where their difference is <= 0: the same test as np.diff's, one NumPy call)
        if np.count_nonzero(t[1:] <= t[:-1]) or t[-1] > spec.t_end:
            raise SceneError(f"`t_eval` must increase strictly within [0, t_end={spec.t_end!r}]")
        return t
    n = check_int("n_samples", n_samples, minimum=2, maximum=limits.MAX_VALUES)
    return np.linspace(0.0, spec.t_end, n)


@dataclass(frozen=True)
class RawRun:
    """What a back-end returns (SI).

    ``t`` (T,) sample times; ``x``, ``v`` (n, T) positions and velocities;
    ``state`` (n, T) 0 stuck, ±1 slipping faster / slower than the belt;
    ``friction_force`` (n, T) N; ``work`` (3, T) cumulative belt work, friction
    and damper dissipation (J); ``events`` the switches; ``stick_intervals``
    per mass the (start, end) times (s); ``meta`` diagnostics.
    """

    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    state: np.ndarray
    friction_force: np.ndarray
    work: np.ndarray
    events: list = field(default_factory=list)
    stick_intervals: list = field(default_factory=list)
    meta: dict = field(default_factory=dict)


@dataclass(frozen=True)
class ContactRun:
    """What a back-end returns for a ContactSpec (SI): samples ``t`` (T,), state ``Z`` (4n, T) = [x; y; v; vy],
    ``modes`` (n, T), ``friction_force`` and ``normal_force`` (n, T, N), ``work`` (4, T, J: belt,
    friction, dampers, impacts), ``events``, ``stick_intervals`` and ``separation_intervals`` (per
    mass, (start, end) s), ``meta``."""

    t: np.ndarray
    Z: np.ndarray
    modes: np.ndarray
    friction_force: np.ndarray
    normal_force: np.ndarray
    work: np.ndarray
    events: list = field(default_factory=list)
    stick_intervals: list = field(default_factory=list)
    separation_intervals: list = field(default_factory=list)
    meta: dict = field(default_factory=dict)


class StepBudget:
    """Counts right-hand-side evaluations of an integrator against ``max_steps``, and watches the
    wall-clock budget of ``options`` (:meth:`RunOptions.check_clock`)."""

    def __init__(self, options: "RunOptions"):
        self.left = self.max_steps = options.max_steps
        self.options = options

    def spend(self, t: float) -> None:
        self.left -= 1
        if not self.left % 256:  # a clock reading costs ~50 ns, an evaluation tens of us
            self.options.check_clock(t)
        if self.left < 0:
            raise SimulationError(f"the integrator needed more than `max_steps` = {self.max_steps:,} right-hand-side "
                                  f"evaluations before t = {t:.6g} s; raise `max_steps` or shorten `t_end`", time=t)


def intervals_from_state(t, state) -> list:
    """Stick intervals (t_start, t_end) per mass from a sampled state array (0 = stuck)."""
    out = []
    for row in state:
        stuck = np.concatenate([[False], row == 0, [False]])
        edges = np.flatnonzero(np.diff(stuck.astype(int)))
        out.append([(float(t[a]), float(t[b - 1])) for a, b in zip(edges[::2], edges[1::2]) if b - 1 > a])
    return out
