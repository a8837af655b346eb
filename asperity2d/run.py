"""Running a scene in one call: :func:`simulate`, :class:`Simulation` (the same run in pieces)
and :func:`simulate_many` (many scenes on one engine).

``simulate(scene, duration, ...) -> Result`` in the spirit of SciPy's
``solve_ivp``: stop conditions are plain callables evaluated on every
recorded sample; the first that returns true ends the run and names itself in
``result.status``. This module holds the entry points (:func:`simulate`,
:class:`Simulation`, :func:`simulate_many`); the parts they drive live in one
module per role and are re-exported here, so ``asperity2d.run.X`` keeps
working for every name below:

* ``asperity2d.run_loop``: :class:`Run`, the one run loop (settle, advance,
  change the drive, record, fork) and the checks a result carries;
* ``asperity2d.stops``: the stop conditions (:class:`Probe`, :class:`Passed`,
  :class:`Stuck`, :class:`Travelled`, ``ForceCrossed``, ``FirstSlip``,
  ``stops_from_settings``);
* ``asperity2d.steps``: the step size and the step budget (``default_dt``,
  ``resolve_dt``, ``check_budget``, ``default_duration``).
"""

from __future__ import annotations

import os
from typing import Callable, Iterable

from ._inputs import check_finite, check_int, check_positive
from .engine.registry import DEFAULT as DEFAULT_ENGINE, ENGINES, check_engine, refuse
from .errors import SceneError, SimulationError
from .result import Result
from .run_loop import ENERGY_TOLERANCE, NUMERICAL_ENERGY_TOLERANCE, Run, _callables, _checks  # noqa: F401
from .scene import ConstantForce, Scene
from .steps import (COARSEST_DAMPER_DT_FRACTION, COARSEST_DT_FRACTION, COST_ASPERITIES,  # noqa: F401
                    DAMPER_DT_FRACTION, DT_FRACTION, MAX_STEPS, check_budget, default_dt, default_duration,
                    resolve_dt, settle_cap, step_cost)
from .stops import (STOP_SETTINGS, FirstSlip, ForceCrossed, Passed, Probe, Stuck, Travelled,  # noqa: F401
                    default_stops, stops_from_settings)


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


def check_scenes(scenes) -> list:
    """``scenes`` as a non-empty list of :class:`~asperity2d.scene.Scene` (a ``SceneError`` line
    otherwise): what every function of many scenes takes."""
    scenes = list(scenes)
    for scene in scenes:
        if not isinstance(scene, Scene):
            raise SceneError(f"`scenes` must hold Scene objects (see make_scene), got {type(scene).__name__}")
    if not scenes:
        raise SceneError("`scenes` is empty: give at least one scene")
    return scenes


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
    scenes = check_scenes(scenes)
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
    dts, durations, passed, stuck, settles = [], [], [], [], []
    for scene in scenes:
        settles_here = scene.slider.track == "free" if settle is None else bool(settle)
        refuse(engine, scene, settle=settles_here)
        step = resolve_dt(scene, dt, unsafe_dt)
        span = default_duration(scene) if duration is None else check_positive("duration", check_finite("duration", duration))
        cap = settle_cap(scene) if settles_here else None
        check_budget(scene, step, max_steps, settle=cap or 0.0, duration=span)
        dts.append(step)
        durations.append(span)
        passed.append(duration is None)
        # the default stops' Stuck (a constant force), as (speed, dwell)
        rule = next((s for s in default_stops(scene) if isinstance(s, Stuck)), None) if duration is None else None
        stuck.append(None if rule is None else (rule.speed, rule.dwell))
        settles.append(cap)
    results = ENGINES[engine].run(scenes, dts, durations, record_every=record_every, iterations=iterations,
                                  passed=passed, stuck=stuck, settle=settles)
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
