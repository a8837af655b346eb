"""Critical force: the smallest constant drive force that carries the slider across.

Ooten's Working Model runs pushed the slider with a constant force; it
either stopped on a flank or ran away. The boundary between the two is the
critical force, found here by bisection over constant-force runs, each stopped
as soon as the slider is stuck or has passed the last lower apex. Three starts:

* ``start="rest"`` (default): the top surface at rest *on* the bottom one, as
  Ooten describes it ("the force required to move the top surface over the
  bottom surface"; its abstract's breakaway force): the slider over the
  surface (on the fixed track its track is lowered into place), every tip
  settled against its flank by a gentle push (1 % of the flank-law
  estimate), then the force applied from rest.
* ``start="entry"``: at rest against the first flank at the entrance of the
  surface. Only the front tip is in contact, so this measures the first lower
  asperity alone: the same for every spacing (like the first breakaway).
* ``start="run-up"``: the slider where the builder puts it (on the fixed track
  a tenth of a base before the surface), the force applied from there: it
  hits the first flank with the momentum of that run-up, a momentum
  threshold (~1.5 mN on the default scene, far below the ~8.6 mN that pushes
  one tip over quasi-statically).

A free slider starts on the surface and first comes down under its load
(every start; ``"entry"`` is then the same as ``"rest"``).
The scene is settled once and every bisection run is a fork of that settled
run (:meth:`asperity2d.run.Run.fork`), so forks are bit-identical to each
other and settling is not repeated.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

from ._inputs import check_choice, check_int, check_positive, check_tolerance
from .errors import SceneError
from .engine.registry import check_engine, refuse
from .scene import ConstantForce, Scene
from .run import (MAX_STEPS, Run, Stuck, check_scenes, default_dt, default_duration, default_stops,
                  settle_cap)

STARTS = ("rest", "entry", "run-up")
#: The settling push of ``start="rest"``, as a fraction of the flank-law estimate.
PUSH_FRACTION = 0.01
#: At most this many settling phases to bring the pushed slider against a flank.
MAX_PUSHES = 20
#: Default bracket width (relative) of the bisection: a quarter of the 1 % a measure may move
#: between dt and dt/2, so the search itself uses little of it.
REL_TOL = 0.0025
#: The bracket check: forces this far apart (relative to the bisected value) ...
SCAN_STEP = 0.02
#: ... over this window below it (and above it, for the band) are tried as well. Passing is
#: not monotone in the force when the slider arrives with momentum: on the undamped regular
#: run-up (10/3) 0.94 x the bisected force passes, 0.95-0.97 x and 0.99 x do not (measured on
#: a 1 % grid). A passing band narrower than SCAN_STEP, or more than SCAN_WINDOW below the
#: bisected force, can still be missed; the record says what was checked.
SCAN_WINDOW = 0.10
#: The first force the search tries, as a power of two of the flank-law estimate, by track and
#: start. The estimate is the quasi-static barrier of every tip at once; the free slider passes
#: near it (0.77-0.92 of it from every start: regular and 2 random seeds, 16/4), but a fixed
#: track passes far below it: from rest at the step load, about half the barrier (0.45 on the
#: regular 16/4) and less where random spacing puts fewer tips on their flanks at once
#: (0.11-0.35); from the entry the front tip alone (0.115), and with a run-up at a momentum
#: threshold (0.045-0.064). Starting at the power of two just above those saves the runs that
#: halve down to it (1-4 of ~22). The forces tried are the estimate times powers of two either
#: way, so the bracket -- and with it the bisection and the answer -- is the same whichever
#: power the search starts from, as long as passing is monotone over those powers (a factor of
#: 2 apart). Checked against the search from the estimate: the same bits (passes, stops, band)
#: on 42 fixed-track searches (16/4 and 10/3; regular and every random spacing, seeds 9001 and
#: 9002; every start), with 864 runs instead of 978.
FIRST_POWER = {("free", "rest"): 0, ("free", "entry"): 0, ("free", "run-up"): 0,
               ("fixed", "rest"): -2, ("fixed", "entry"): -3, ("fixed", "run-up"): -4}
#: A slider that still passes under this fraction of the flank-law estimate meets nothing that
#: resists it (on a rough surface the only asperities tall enough to reach a fixed track can be
#: behind it): the search stops there and reports the bracket (0, that force).
FORCE_FLOOR = 2.0 ** -20


#: The step of the critical-force runs, as a fraction of ``default_dt``.
#: At the default step the fixed track's thresholds sit low -- the tips sink into the flanks
#: they press (pymunk removes 10 % of an overlap per step, so the overlap left under a load
#: shrinks with dt) -- by 1.2-1.6 % from rest and 0.4-4.6 % with a run-up (measured on 10/3,
#: regular and 4 random seeds, against dt/2, dt/4, dt/8; second order: each halving cuts the
#: change about 4 x). From rest dt/2 is within 0.32 % of dt/4; the run-up, a momentum
#: threshold decided at an impact, needs dt/4 (within 0.2 % of dt/8; dt/2 is 1.0 % off).
DT_FRACTION = {"rest": 0.5, "entry": 0.5, "run-up": 0.25}


def measure_dt(scene: Scene, start: str) -> float:
    """The step (s) :func:`~asperity2d.critical_force` uses from ``start`` when given none."""
    check_choice("start", start, STARTS)
    return DT_FRACTION[start] * default_dt(scene)


class NonMonotoneWarning(UserWarning):
    """Passing is not monotone in the force: some force below the critical force's upper
    neighbours passes while larger ones stop (see :attr:`CriticalForce.band`)."""


@dataclass(frozen=True)
class CriticalForce:
    """Bracket of the critical force (N): the smallest constant force seen to pass.

    ``passes`` is the smallest force with which the slider passed, ``stops``
    the largest force below it with which it did not (bisected to ``rel_tol``);
    ``runs`` simulations were used; ``start`` is how each began (``"rest"``,
    ``"entry"`` or ``"run-up"``). ``band`` is ``(lowest passing, highest
    stopping)`` force when passing is not monotone in the force (a force above
    ``passes`` stopped), else None. ``checked`` is the relative window below
    and above ``passes`` that the bracket check scanned at ``SCAN_STEP``;
    ``tried`` every (force, passed) pair, in the order run. ``dt`` is the step every run used (s).

    Attributes
    ----------
    stops, passes : float
        The bracket (N): the largest force that stopped, the smallest that passed.
    runs : int
        Simulations used.
    start : {"rest", "entry", "run-up"}
        How each run began.
    band : tuple of float or None
        ``(lowest passing, highest stopping)`` force (N) when passing is not monotone.
    checked : float
        Relative window scanned around ``passes``.
    tried : tuple of (float, bool)
        Every force tried (N) and whether it passed.
    dt : float
        The step every run used (s).

    See Also
    --------
    asperity2d.critical_force_bracket : makes one.

    Examples
    --------
    >>> import asperity2d as a
    >>> bracket = a.critical_force_bracket(a.make_scene(lower_count=4, upper_count=2))
    >>> f"{bracket.stops * 1e3:.4g} mN < F_c <= {bracket.passes * 1e3:.4g} mN"
    '7.59 mN < F_c <= 7.607 mN'
    >>> bracket.monotone, bracket.runs
    (True, 20)
    """

    stops: float
    passes: float
    runs: int
    start: str = "rest"
    band: tuple[float, float] | None = None
    checked: float = 0.0
    tried: tuple[tuple[float, bool], ...] = ()
    dt: float = math.nan

    @property
    def value(self) -> float:
        """The critical force estimate: the smallest force seen to pass (N)."""
        return self.passes

    @property
    def relative_width(self) -> float:
        return (self.passes - self.stops) / self.passes

    @property
    def monotone(self) -> bool:
        """True when no force above ``passes`` was seen to stop."""
        return self.band is None


def flank_estimate(scene: Scene) -> float:
    """Quasi-static flank-law estimate of the critical force (N).

    Free slider: ``L tan(theta + atan mu_s)`` (all of the load on front
    flanks). Fixed track: every upper tip pushing a lower spring down by the
    interference at once, ``n k delta tan(theta + atan mu_s)``.
    """
    theta = math.radians(max(scene.lower.profile.flank_angle, 1.0))
    phi = math.atan(scene.contact.mu_static)
    wedge = math.tan(min(theta + phi, math.radians(89.0)))
    if scene.slider.track == "free":
        return scene.slider.normal_load * wedge + 1e-300
    k = max(scene.lower.stiffness)
    return scene.slider.count * k * scene.slider.interference * wedge


def settled_run(scene: Scene, *, start: str = "rest", dt: float | None = None, iterations: int = 20,
                max_steps: int | None = None):
    """A :class:`~asperity2d.run.Run` of ``scene`` with its drive replaced by a zero
    constant force, settled for ``start`` (see the module doc): fork it and set the force."""
    check_choice("start", start, STARTS)
    run = Run(scene.replace(drive=ConstantForce(force=0.0)), dt=dt, iterations=iterations,
              max_steps=MAX_STEPS if max_steps is None else max_steps, engaged=start == "rest")
    if start in ("rest", "entry"):
        push = PUSH_FRACTION * flank_estimate(scene)
        x0 = run.engine.slider_state()[0]
        run.settle(push=push)
        # The gentle push, slowed by the settling damping, may not carry the slider across a
        # wide valley within one settling phase: at mu <= 0.2 on Ooten's 10/3 fixed track it
        # stopped 0.2-0.5 um short of the flanks, so "from rest" was partly a run-up (0.42-0.79
        # x the step-load law). Push again until a tip rests against a flank -- but no farther
        # than two mean pitches: on a rough surface whose only asperity tall enough to reach the
        # fixed track is behind the tip nothing is ahead to touch.
        reach = 2.0 * scene.lower.spacing.mean_pitch  # m
        for _ in range(MAX_PUSHES):
            if len(run.engine.arbiters_internal()) or run.engine.slider_state()[0] - x0 > reach:
                break
            run.settle(push=push)
    elif scene.slider.track == "free":
        run.settle()
    return run


def passes(base, force: float) -> bool:
    """Does a constant ``force`` (N), applied to a fork of the settled run ``base``, carry the
    slider over the whole lower surface?"""
    run = base.fork()
    run.set_drive_force(force)
    scene = base.scene.replace(drive=ConstantForce(force=force))
    # A small force gets a long time limit (it grows as 1/sqrt(F)). A slider still moving at the
    # limit has not been decided: where friction grows with speed (the viscous law) it crawls at a
    # terminal speed and passes late, and counting that as "stopped" measured the time to cross,
    # not a force. So the run goes on, limit by limit, until it passes or stops, within the run's
    # step budget: a slider neither past nor stopped when the budget is spent has not passed (a force
    # of a nanonewton creeps for ever; the budget is the search's bound).
    stops, limit = default_stops(scene), default_duration(scene)
    while True:
        room = 0.999 * (run.max_steps - run.engine.step_count) * run.dt
        if room < run.dt:
            return False
        status = run.advance(min(limit, room), stop=stops, record=False)
        if status != "duration":
            return status == "passed"


def smallest_passing(test, estimate: float, *, rel_tol: float = REL_TOL, scan_step: float = SCAN_STEP,
                     window: float = SCAN_WINDOW, first: int = 0
                     ) -> tuple[float, float, tuple[float, float] | None, list]:
    """The smallest force ``f`` with ``test(f)`` true, searched from ``estimate`` (> 0).

    1. Bracket: double (or halve) ``estimate`` until one force stops and one passes (below
       :data:`FORCE_FLOOR` x ``estimate`` the search stops: ``(0, that force)``). The first
       force tried is ``estimate * 2**first``: the forces tried are ``estimate`` times powers
       of two either way, so when passing is monotone the bracket is the same whichever
       power it starts from (only the runs to reach it differ).
    2. Bisect to a bracket ``rel_tol`` wide (relative to its upper end).
    3. Bracket check: try the forces ``scan_step``, 2 ``scan_step``, ... below the
       upper end, down to ``window`` below it; if one passes, bisect again below the lowest
       such force and check below that. Then try as many above it, for the band.

    ``test`` is any predicate of a force (the simulations of :func:`~asperity2d.critical_force_bracket`,
    or a toy with a known answer). Returns ``(stops, passes, band, tried)``: the final
    bracket, ``(lowest passing, highest stopping)`` if some force above ``passes`` stopped
    (else None), and every ``(force, passed)`` pair in the order tried. (The search itself is
    :func:`searching`, which many searches run in lockstep on the batched engine.)
    """
    search = searching(estimate, rel_tol=rel_tol, scan_step=scan_step, window=window, first=first)
    try:
        force = next(search)
        while True:
            force = search.send(bool(test(force)))
    except StopIteration as done:
        return done.value


def searching(estimate: float, *, rel_tol: float = REL_TOL, scan_step: float = SCAN_STEP,
              window: float = SCAN_WINDOW, first: int = 0):
    """:func:`smallest_passing`'s search as a generator: it yields each force to try, is sent
    whether that force passed, and returns ``(stops, passes, band, tried)``. A force tried
    once is never yielded again."""
    tried: list[tuple[float, bool]] = []
    seen: dict[float, bool] = {}

    def run(force: float):
        if force not in seen:
            seen[force] = bool((yield force))
            tried.append((force, seen[force]))
        return seen[force]

    first = check_int("first", first, minimum=-60, maximum=60)
    force = math.ldexp(estimate, first)  # exact: a power of two
    lo = hi = None
    while lo is None or hi is None:
        if (yield from run(force)):
            hi = force
            if force < FORCE_FLOOR * estimate:  # nothing ahead resists: (0, this force)
                return 0.0, hi, None, tried
            force = force / 2.0
        else:
            lo = force
            force = force * 2.0

    def bisect(lo: float, hi: float):
        while (hi - lo) / hi > rel_tol:
            mid = 0.5 * (lo + hi)
            if (yield from run(mid)):
                hi = mid
            else:
                lo = mid
        return lo, hi

    lo, hi = yield from bisect(lo, hi)
    steps = int(round(window / scan_step))
    while True:
        below = [hi * (1.0 - j * scan_step) for j in range(1, steps + 1)]
        passing = []
        for f in below:
            if f > 0 and (yield from run(f)):
                passing.append(f)
        if not passing:
            break
        lowest = min(passing)
        under = [f for f, ok in seen.items() if f < lowest and not ok]
        lo, hi = yield from bisect(max(under) if under else lowest / 2.0, lowest)
        if not under:  # nothing below it stopped yet: bracket it from below first
            lo, hi = yield from _bracket_below(run, hi)
            lo, hi = yield from bisect(lo, hi)
    for j in range(1, steps + 1):
        yield from run(hi * (1.0 + j * scan_step))
    stopping_above = [f for f, ok in seen.items() if f > hi and not ok]
    band = (hi, max(stopping_above)) if stopping_above else None
    return lo, hi, band, tried


def _bracket_below(run, hi: float):
    """Halve ``hi`` (a passing force) until a force stops: the bracket (stop, smallest pass)."""
    force = hi
    while (yield from run(force)):
        hi, force = force, force / 2.0
    return force, hi


def critical_force_bracket(scene: Scene, *, start: str = "rest", rel_tol: float = REL_TOL,
                           max_runs: int = 80, dt: float | None = None, iterations: int = 20,
                           max_steps: int | None = None) -> CriticalForce:
    """The smallest constant drive force that carries the slider across, and its bracket.

    Bisection to a bracket ``rel_tol`` wide, checked by trying forces 2 %, 4 %,
    ... 10 % below and above it (``smallest_passing``): with inertia
    passing is not always monotone in the force, and a smaller force that
    passes moves the search there. ``band`` reports the forces with mixed
    outcomes. Raises :class:`~asperity2d.SceneError` if more than ``max_runs`` runs are
    needed. ``dt`` (s) defaults to ``measure_dt`` (half the simulation's
    default step from rest, a quarter with a run-up: converged to 0.3 %);
    ``iterations`` and ``max_steps`` (per run) are those of
    :func:`asperity2d.simulate`.

    Parameters
    ----------
    scene : Scene
        The scene; its drive is replaced by constant forces.
    start : {"rest", "entry", "run-up"}, default "rest"
        How each run begins (see :func:`~asperity2d.critical_force`).
    rel_tol : float, default 0.0025
        Relative width of the bracket, in (0, 1).
    max_runs : int, default 80
        Most simulations allowed (>= 2).
    dt : float, optional
        Step (s); default half the simulation's default step from rest, a quarter with a
        run-up.
    iterations : int, default 20
        pymunk solver iterations.
    max_steps : int, optional
        Step budget of each run.

    Returns
    -------
    CriticalForce
        The bracket, the runs used and every force tried.

    Raises
    ------
    SceneError
        A bad parameter (named), or more than ``max_runs`` runs needed.

    See Also
    --------
    asperity2d.critical_force : the value alone, warning when passing is not monotone.

    Examples
    --------
    >>> import asperity2d as a
    >>> bracket = a.critical_force_bracket(a.make_scene(lower_count=4, upper_count=2))
    >>> f"{bracket.value * 1e3:.4g} mN, {bracket.relative_width:.1%} wide"
    '7.607 mN, 0.2% wide'
    """
    if not isinstance(scene, Scene):
        raise SceneError(f"`scene` must be a Scene, got {type(scene).__name__}")
    rel_tol, max_runs = _check_search(rel_tol, max_runs, start)
    base = settled_run(scene, start=start, dt=measure_dt(scene, start) if dt is None else dt,
                       iterations=iterations, max_steps=max_steps)
    runs = 0

    def test(force):
        nonlocal runs
        runs += 1
        if runs > max_runs:
            raise SceneError(f"`max_runs` = {max_runs} runs did not bracket the critical force")
        return passes(base, force)

    lo, hi, band, tried = smallest_passing(test, flank_estimate(scene), rel_tol=rel_tol,
                                           first=FIRST_POWER[scene.slider.track, start])
    return CriticalForce(stops=lo, passes=hi, runs=runs, start=start, band=band, checked=SCAN_WINDOW,
                         tried=tuple(tried), dt=float(base.dt))


def _check_search(rel_tol, max_runs, start) -> tuple[float, int]:
    rel_tol = check_tolerance("rel_tol", rel_tol)
    max_runs = check_int("max_runs", max_runs, minimum=2)
    halvings = math.ceil(math.log2(1.0 / rel_tol))  # bisections from a factor-2 bracket at least
    if halvings > max_runs:
        raise SceneError(f"`rel_tol` = {rel_tol:g} needs at least {halvings} runs to bisect, more than "
                         f"`max_runs` = {max_runs}: raise one or the other")
    check_choice("start", start, STARTS)
    return rel_tol, max_runs


def critical_force_brackets(scenes, *, start: str = "rest", rel_tol: float = REL_TOL, max_runs: int = 80,
                            dt: float | None = None, iterations: int = 20, max_steps: int | None = None,
                            engine: str = "batched") -> list[CriticalForce]:
    """:func:`critical_force_bracket` of every scene of ``scenes``, in order, on ``engine``.

    On ``"batched"`` the searches run in lockstep: every scene is settled as the reference
    settles it (``critical.settled_run``), all at once, then every round runs each unfinished
    search's next force as a fork of its settled scene, all in one batch, with the run loop's
    stops (passed; stuck; a free slider off the surface) and the reference's time limits and step
    budget (``critical.passes``), until each search has its bracket. The search is the one the
    reference runs (``critical.searching``), so a scene's bracket differs from the reference's
    only where a trial run's outcome does. On ``"pymunk"`` the scenes run one after the other
    (:func:`~asperity2d.critical_force_bracket`).

    Parameters
    ----------
    scenes : iterable of Scene
        The scenes; each one's drive is replaced by constant forces.
    start : {"rest", "entry", "run-up"}, default "rest"
        How each run begins (see :func:`~asperity2d.critical_force`).
    rel_tol : float, default 0.0025
        Relative width of each bracket, in (0, 1).
    max_runs : int, default 80
        Most simulations allowed per scene (>= 2).
    dt : float, optional
        Step (s); default half the simulation's default step from rest, a quarter with a run-up.
    iterations : int, default 20
        Contact solver iterations.
    max_steps : int, optional
        Step budget of each run.
    engine : str, default "batched"
        The engine (``asperity2d.engine.ENGINES``).

    Returns
    -------
    list of CriticalForce
        One bracket per scene, in order.

    Raises
    ------
    SceneError
        A bad parameter (named), an option the engine does not implement, or more than
        ``max_runs`` runs needed.

    Examples
    --------
    >>> import asperity2d as a
    >>> scenes = [a.make_scene(lower_count=4, upper_count=2, spacing="random", seed=s) for s in (1, 2)]
    >>> [f"{b.value * 1e3:.4g} mN" for b in a.critical_force_brackets(scenes, engine="pymunk")]
    ['6.949 mN', '3.846 mN']
    """
    scenes = check_scenes(scenes)
    engine = check_engine(engine)
    if engine == "pymunk":
        return [critical_force_bracket(scene, start=start, rel_tol=rel_tol, max_runs=max_runs, dt=dt,
                                       iterations=iterations, max_steps=max_steps) for scene in scenes]
    if engine != "batched":  # an installed package's engine: its runs have no settle and forks here
        raise SceneError(f"critical forces run on engine=\"pymunk\" and engine=\"batched\", not engine={engine!r}")
    rel_tol, max_runs = _check_search(rel_tol, max_runs, start)
    max_steps = MAX_STEPS if max_steps is None else check_int("max_steps", max_steps, minimum=1, maximum=None)
    for scene in scenes:
        refuse(engine, scene, settle=True)
    return _batched_brackets(scenes, start, rel_tol, max_runs, dt, iterations, max_steps)


def _batched_brackets(scenes, start, rel_tol, max_runs, dt, iterations, max_steps) -> list[CriticalForce]:
    import numpy as np

    from .engine.batched import Batch

    bare = [scene.replace(drive=ConstantForce(force=0.0)) for scene in scenes]
    dts = [measure_dt(scene, start) if dt is None else check_positive("dt", dt) for scene in scenes]
    base = Batch(bare, dts, iterations=check_int("iterations", iterations, minimum=1, maximum=10_000),
                 engaged=start == "rest")
    caps = [settle_cap(scene) for scene in bare]  # as Run.settle: the scene under a constant force
    if start in ("rest", "entry"):  # settled_run's pushes, every scene at once
        push = np.array([PUSH_FRACTION * flank_estimate(scene) for scene in scenes])
        x0 = [base.sp[b, 0] * base.units[b].length for b in range(len(scenes))]
        reach = [2.0 * scene.lower.spacing.mean_pitch for scene in scenes]
        base.settle(push, caps)
        for _ in range(MAX_PUSHES):
            again = [b for b in range(len(scenes)) if not (base.c_n[b].any()
                     or base.sp[b, 0] * base.units[b].length - x0[b] > reach[b])]
            if not again:
                break
            base.settle(push, [caps[b] if b in again else None for b in range(len(scenes))])
    elif any(scene.slider.track == "free" for scene in scenes):
        base.settle(np.zeros(len(scenes)), [cap if s.slider.track == "free" else None for s, cap in zip(scenes, caps)])
    for b in range(len(scenes)):
        err = base.error(b)
        if err is not None:
            raise err
    searches = [searching(flank_estimate(scene), rel_tol=rel_tol, first=FIRST_POWER[scene.slider.track, start])
                for scene in scenes]
    force = {b: next(search) for b, search in enumerate(searches)}
    out: dict[int, CriticalForce] = {}
    runs = [0] * len(scenes)
    while force:
        rows = sorted(force)
        for b in rows:
            runs[b] += 1
            if runs[b] > max_runs:
                raise SceneError(f"`max_runs` = {max_runs} runs did not bracket the critical force")
        passed = _trials(base, rows, [force[b] for b in rows], max_steps)
        for b, ok in zip(rows, passed):
            try:
                force[b] = searches[b].send(ok)
            except StopIteration as done:
                del force[b]
                lo, hi, band, tried = done.value
                out[b] = CriticalForce(stops=lo, passes=hi, runs=runs[b], start=start, band=band,
                                       checked=SCAN_WINDOW, tried=tuple(tried), dt=float(dts[b]))
    return [out[b] for b in range(len(scenes))]


def _trials(base, rows, forces, max_steps) -> list[bool]:
    """:func:`passes` for each ``forces[k]`` on a fork of ``base``'s scene ``rows[k]``, all in one
    batch: limit by limit (the time limit of that force), until it passes or stops, within the
    step budget ``max_steps``."""
    trials = base.forks(forces, rows)
    scenes = trials.scenes
    stuck = [next((s.speed, s.dwell) for s in default_stops(scene) if isinstance(s, Stuck)) for scene in scenes]
    trials.set_stops(passed=[True] * len(scenes), stuck=stuck)
    limits = [default_duration(scene) for scene in scenes]
    outcome: list[bool | None] = [None] * len(scenes)
    while any(o is None for o in outcome):
        durations = []
        for k, scene in enumerate(scenes):
            dt = float(trials.dt_s[k])
            room = 0.999 * (max_steps - int(trials.nstep[k])) * dt
            if outcome[k] is None and room < dt:
                outcome[k] = False
            durations.append(min(limits[k], room) if outcome[k] is None else 0.0)
        if all(o is not None for o in outcome):
            break
        statuses = trials.advance_for(durations)
        for k, status in enumerate(statuses):
            if outcome[k] is not None:
                continue
            err = trials.error(k)
            if err is not None:
                raise err
            if status != "duration":
                outcome[k] = status == "passed"
    return [bool(o) for o in outcome]


def critical_force(scene: Scene, *, start: str = "rest", rel_tol: float = REL_TOL, max_runs: int = 80,
                   dt: float | None = None, iterations: int = 20, max_steps: int | None = None,
                   engine: str = "pymunk") -> float:
    """The smallest constant drive force (N) with which the slider passes the whole lower surface.

    ``start="rest"`` (default): the slider at rest on the surface, every tip
    against its flank; ``"entry"``: at rest against the first flank at the
    entrance; ``"run-up"``: from the builder's start position, a tenth of a
    base before the surface on the fixed track (see the module doc for what
    each measures). Bisection over constant-force runs to relative tolerance
    ``rel_tol`` (default 0.25 %), each stopped as soon as the slider is stuck or
    has passed, then checked 2-10 % below and above. When passing is not
    monotone in the force (some force above the returned one stops) it warns
    with ``NonMonotoneWarning``, naming the band; see
    :func:`~asperity2d.critical_force_bracket` for the record.

    Parameters
    ----------
    scene : Scene
        The scene (:func:`~asperity2d.make_scene`); its drive is replaced by constant forces, so a
        spring-driven scene gives the same value as its ``drive="force"`` twin.
    start : {"rest", "entry", "run-up"}, default "rest"
        How each run begins (above).
    rel_tol : float, default 0.0025
        Relative width of the bisection bracket, in (0, 1).
    max_runs : int, default 80
        Most simulations allowed (>= 2).
    dt : float, optional
        Step (s); default half the simulation's default step from rest, a quarter with a
        run-up.
    iterations : int, default 20
        pymunk solver iterations.
    max_steps : int, optional
        Step budget of each run.
    engine : str, default "pymunk"
        The engine (``asperity2d.engine.ENGINES``): ``"batched"`` settles and forks as the
        reference does (:func:`critical_force_brackets`; many scenes at once are its use).

    Returns
    -------
    float
        The smallest force seen to pass (N).

    Raises
    ------
    SceneError
        A bad parameter (named), or more than ``max_runs`` runs needed.

    Warns
    -----
    NonMonotoneWarning
        Some force above the returned one stopped.

    See Also
    --------
    asperity2d.critical_force_bracket : the bracket and every force tried.
    asperity2d.peak_stick_force, asperity2d.mean_stick_force : the spring-driven measures.

    Examples
    --------
    >>> import asperity2d as a
    >>> scene = a.make_scene(lower_count=4, upper_count=2, drive="force")
    >>> f"{a.critical_force(scene) * 1e3:.3g} mN"
    '7.61 mN'

    From rest against the first flank only, the entry force is smaller:

    >>> f"{a.critical_force(scene, start='entry') * 1e3:.3g} mN"
    '3.83 mN'
    """
    if not isinstance(scene, Scene):
        raise SceneError(f"`scene` must be a Scene, got {type(scene).__name__}")
    bracket = critical_force_brackets([scene], start=start, rel_tol=rel_tol, max_runs=max_runs, dt=dt,
                                      iterations=iterations, max_steps=max_steps, engine=engine)[0]
    if bracket.band is not None:
        low, high = bracket.band
        warnings.warn(f"passing is not monotone in the force (start={start!r}): {low:.4g} N passes, "
                      f"{high:.4g} N does not; returned the smallest passing force found",
                      NonMonotoneWarning, stacklevel=2)
    return bracket.value
