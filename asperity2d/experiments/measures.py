"""The named measures: one number per scene, what each one measures, and how far to trust it.

Each measure is a function ``measure(scene) -> float`` (module level, so worker
processes can run it) registered in :data:`MEASURES` as a :class:`Measure`
that carries its label, unit, drive, kind and verdict rule (the contract of a
new one is :class:`Measure`'s docstring); :func:`asperity2d.compare` and the command line's ``--measure`` take
them by name. The scene-level measures are named for what they do to a scene
(``critical_force_from_rest(scene)``, ``peak_stick_force_of_passes(scene)``),
distinct from the analysis functions of one result
(:func:`asperity2d.analysis.peak_stick_force`).

One step policy for all of them (:func:`measure_step`): each runs at the step where halving it
again moves it by less than its tolerance (:data:`STEP_TOLERANCE`), and its record names the
step. Two kinds, by how they behave when the step is refined:

* **Deterministic** -- the same number at its step and at half of it within
  1 %: the critical forces (bisection to 0.25 %; dt/2 from rest, dt/4 with a
  run-up), the quasi-static breakaway (a slow force ramp at dt/2, whose
  convergence in ramp rate each measurement reports), the first breakaway of
  a pass (the front tip meeting the first flank: nothing before it is
  chaotic; dt/2).
* **Distributions** -- the travel under a constant force (at its force's
  step): a stuck slider's travel on a random surface is deterministic per run
  but decided at a flank it barely reaches, so halving the step moves a few
  seeds' travel by a fifth to a third while the mean over seeds stays put;
  and the peak and mean stick force over a spring-driven
  pass. Where a slip ends decides where the slider sticks next, and a slip at
  4-6 km/s ends at whichever flank catches it: a change of 1e-6 in the drive
  speed, or halving dt, moves a slip end by a fraction of a pitch and the
  rest of the pass follows another sequence of sticks. Which stick positions
  a pass visits is chaotic; their forces are not (each is the quasi-static
  barrier where the slider stands). So :func:`stick_forces` runs an ensemble
  of passes whose drive speeds differ by at most 0.06 % (physically the same
  experiment) and these measures report its median; the record keeps every
  pass, so the spread is there to report.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from .. import analysis
from .._inputs import check_choice, check_int, check_positive, check_range
from .._registry import Registry
from ..critical import DT_FRACTION as CRITICAL_DT_FRACTION, critical_force, critical_force_brackets, settled_run
from ..errors import SceneError
from ..run import Run, Stuck, default_dt, default_duration, default_stops
from ..scene import ConstantForce, Scene, SpringDrive
from .verdicts import VerdictRule

#: The pass ensemble: drive speeds V (1 + PERTURBATION_STEP (j - (K - 1) / 2)), j = 0..K-1.
#: 2e-4 apart is far below anything the quasi-static drive resolves (the forces at the stick
#: limit do not depend on V there) and far above what decorrelates two passes (1e-6 already
#: changes the sticks of the second half of a pass: measured, seed 7301, 10/3 fixed track).
#: Measured over 6 random seeds x 7 passes (10/3 fixed track): one pass's peak stick force
#: spreads 10-25 % (sd) about the ensemble's mean, its mean stick force 5-10 %. Three passes
#: per scene (the studies use five) halve the spread a comparison over seeds sees.
PASSES = 3
PERTURBATION_STEP = 2e-4


#: The step policy, one for every named measure: each runs at this fraction of
#: ``default_dt``, chosen by one rule from the step table of the findings page (every measure at
#: dt, dt/2, dt/4 on 500 seeds of each track, 10/3 random, seeds 30001-30500, on the batched
#: engine; docs/data/measures/step_policy.json): a measure moves to a coarser step only where the
#: 95 % interval of its ensemble mean's shift against dt/4 lies inside its tolerance
#: (:data:`STEP_TOLERANCE`) on both tracks. Its record says which step it used. The critical
#: forces and the quasi-static breakaway: ``DT_FRACTION`` (dt/2 from rest, dt/4 with a run-up:
#: coarser, the fixed track's are 1.8 % and 1.04 % low). The peak and mean stick force of a pass:
#: :data:`STICK_DT_FRACTION`, dt (their intervals at dt: -1.96 to +1.31 % and -1.29 to +0.69 %,
#: against 5 %). The first breakaway: :data:`FIRST_BREAKAWAY_DT_FRACTION`. The travel under a
#: constant force: the step of the critical force from the same start (dt/4 with a run-up), see
#: :data:`TRAVEL_DT_FRACTION`. The distributions' precision at their step (how many seeds a 5 %
#: difference needs) is computed by docs/data/stick_precision.py for the findings page.
STICK_DT_FRACTION = 1.0
#: The first breakaway stays at dt/2 although its mean over seeds passes the rule at dt (-0.09 %
#: fixed, -0.08 to +0.11 % free): it is one number per seed, not a distribution, and one seed of
#: a free slider is 4.2 % low at dt (a contact lost for one step comes back kinetic and the slider
#: breaks away about 10 ns early), where dt/2 and dt/4 agree to 4e-5. tests/test_measures.py
#: holds each seed's value to 1 % between its step and half of it.
FIRST_BREAKAWAY_DT_FRACTION = 0.5
#: Figure 10's travel with a run-up, measured on 24 seeds never used (10/3 fixed track, half and
#: full triangles at 0.9 x the half triangles' run-up critical force, itself found at dt/4): the
#: stuck half slider stops on another asperity as dt changes, the half / full ratio (geometric
#: mean) 0.498 at dt, 0.469 at dt/2, 0.440 at dt/4, 0.444 at dt/8. At dt/4 20 of 24 seeds agree
#: with dt/8 within 1 % (one more within 1.1 %); the other three move 21-33 % (where a stuck slider stops is decided at
#: a flank it barely reaches, as chaotic as a pass's sticks), so the travel of one random seed is
#: a distribution and a comparison is made over seeds. The full slider, which passes, moves
#: under 1 % from dt/4 to dt/8 on every seed (one seed stopped at dt and passed from dt/2).
TRAVEL_DT_FRACTION = dict(CRITICAL_DT_FRACTION)
#: What halving a measure's step may move it by (relative): the deterministic measures 1 %; the
#: distributions 5 % in their mean over seeds (the stick forces' shifts are in the step table
#: above, inside it at dt on 500 seeds of each track). The travel (the 24 seeds above, half triangles, the stuck
#: slider): from its step (dt/4) to dt/8 the per-seed shifts average +1.2 +- 1.9 % (one standard
#: error; the mean travel moves +0.5 %) while 4 seeds move by more than 1 % (up to 30 %); the full
#: triangles, which pass, -0.05 +- 0.01 % (docs/data/measures/travel_dt.json).
#: Each built-in entry carries its own (``Measure.step_tolerance``); this table is read from them.
STEP_TOLERANCE: dict[str, float] = {}


#: The step of a measure that states no step policy (an outside one): the engine's own default
#: step, ``default_dt`` (T/50 of the shortest natural period, where the runs converged).
DEFAULT_DT_FRACTION = 1.0


def measure_step(name: str, scene: Scene, *, start: str | None = None) -> float:
    """The step (s) the named measure runs ``scene`` at under the step policy (``start`` for the
    travel: default ``"run-up"``): its entry's ``Measure.dt_fraction`` of ``default_dt``
    (``default_dt`` itself for a measure that states none, :attr:`Measure.step_policy` says so)."""
    entry = MEASURES.lookup(name, "name")
    if entry.name == "travel" and start is not None:
        fraction = TRAVEL_DT_FRACTION[check_choice("start", start, tuple(TRAVEL_DT_FRACTION))]
    else:
        fraction = DEFAULT_DT_FRACTION if entry.dt_fraction is None else entry.dt_fraction
    return fraction * default_dt(scene)


def _spring(scene: Scene) -> Scene:
    """``scene`` with a spring drive (the default one if it had a constant force)."""
    if not isinstance(scene, Scene):
        raise SceneError(f"`scene` must be a Scene (see make_scene), got {type(scene).__name__}")
    return scene if isinstance(scene.drive, SpringDrive) else scene.replace(drive=SpringDrive())


@dataclass(frozen=True)
class StickForces:
    """The stick forces of an ensemble of spring-driven passes of one scene (N).

    ``speeds`` (m/s) are the passes' drive speeds; per pass, ``first_breakaway``
    (the first stick-to-slip transition), ``peak`` (the largest) and ``mean``
    (the mean over the pass) -- NaN for a pass with no stick-to-slip
    transition -- and ``events`` (how many). ``dt`` is the step used (s).
    """

    speeds: tuple[float, ...]
    first_breakaway: tuple[float, ...]
    peak: tuple[float, ...]
    mean: tuple[float, ...]
    events: tuple[int, ...]
    dt: float

    def average(self, name: str) -> float:
        """Mean over the passes of ``name`` ("first_breakaway", "peak" or "mean"), NaN if no
        pass gave one. The mean, not the median: the peak of one pass takes a few discrete
        values (the barriers where the slider happened to stick), and a median jumps between
        them."""
        return float(np.mean(self._finite(name))) if len(self._finite(name)) else math.nan

    def _finite(self, name: str) -> np.ndarray:
        check_choice("name", name, ("first_breakaway", "peak", "mean"))
        values = np.asarray(getattr(self, name), dtype=float)
        return values[np.isfinite(values)]

    def spread(self, name: str) -> tuple[float, float]:
        """(smallest, largest) over the passes of ``name`` (N)."""
        values = self._finite(name)
        return (float(values.min()), float(values.max())) if len(values) else (math.nan, math.nan)


def pass_speeds(velocity: float, passes: int) -> tuple[float, ...]:
    """The ensemble's drive speeds (m/s) about ``velocity``: the middle one (odd ``passes``) is
    ``velocity`` itself."""
    passes = check_int("passes", passes, minimum=1, maximum=1000)
    middle = 0.5 * (passes - 1)
    return tuple(velocity * (1.0 + PERTURBATION_STEP * (j - middle)) for j in range(passes))


def stick_forces(scene: Scene, *, passes: int = PASSES, dt: float | None = None,
                 engine: str = "pymunk") -> StickForces:
    """Run ``passes`` spring-driven passes of ``scene`` (its drive made a spring if it was a
    constant force) whose drive speeds differ by 2e-4 of V each, and collect their stick forces.

    ``dt`` (s) is the step of every pass (default: the step policy's,
    :data:`STICK_DT_FRACTION` of ``default_dt``). ``engine``: the engine that runs the passes
    (``asperity2d.engine.ENGINES``; ``"batched"`` runs them all in one batch).
    """
    return stick_forces_of([scene], passes=passes, dt=dt, engine=engine)[0]


def stick_forces_of(scenes, *, passes: int = PASSES, dt: float | None = None,
                    engine: str = "pymunk") -> list[StickForces]:
    """:func:`stick_forces` of every scene of ``scenes``, in order; on ``engine="batched"`` every
    pass of every scene runs in one batch. A pass that diverged raises its own error (naming the
    scene), after every other pass has run."""
    from ..run import simulate_many

    scenes = [_spring(scene) for scene in scenes]
    runs, where = [], []
    for k, scene in enumerate(scenes):
        step = STICK_DT_FRACTION * default_dt(scene) if dt is None else dt
        for speed in pass_speeds(scene.drive.velocity, passes):
            runs.append((scene.replace(drive=dataclasses.replace(scene.drive, velocity=speed)), step))
            where.append(k)
    # per run: its events' peak forces and its step, kept instead of the run's record (a pass
    # records ~1.8 MB at dt: 155 seeds x 5 passes held at once would be 1.4 GB)
    kept: list = [None] * len(runs)
    failure = None
    for step in sorted({step for _, step in runs}):  # one step per call (all share one when dt is given)
        chosen = [j for j, (_, st) in enumerate(runs) if st == step]
        for start in range(0, len(chosen), BATCH_RUNS):
            part = chosen[start:start + BATCH_RUNS]
            for j, result in zip(part, simulate_many([runs[j][0] for j in part], dt=step, engine=engine)):
                if isinstance(result, Exception):
                    failure = failure or result
                    continue
                kept[j] = ([e.force_peak for e in analysis.stick_slip_events(result)], result.meta["dt"])
    if failure is not None:
        raise failure
    out = []
    for k, scene in enumerate(scenes):
        mine = [kept[j] for j in range(len(runs)) if where[j] == k]
        forces = {"first_breakaway": [], "peak": [], "mean": [], "events": []}
        for events, _ in mine:
            forces["first_breakaway"].append(events[0] if events else math.nan)
            forces["peak"].append(max(events) if events else math.nan)
            forces["mean"].append(float(np.mean(events)) if events else math.nan)
            forces["events"].append(len(events))
        out.append(StickForces(speeds=pass_speeds(scene.drive.velocity, passes),
                               dt=mine[-1][1] if mine else math.nan,
                               **{name: tuple(v) for name, v in forces.items()}))
    return out


#: The named measures a batch of scenes can run on an engine other than pymunk (``compare(...,
#: engine="batched")``): name -> ``f(scenes, engine) -> list of float``.
def _peak_of(scenes, engine: str) -> list[float]:
    return [f.average("peak") for f in stick_forces_of(scenes, engine=engine)]


def _mean_of(scenes, engine: str) -> list[float]:
    return [f.average("mean") for f in stick_forces_of(scenes, engine=engine)]


def _critical_of(scenes, engine: str) -> list[float]:
    return [b.value for b in critical_force_brackets(scenes, engine=engine)]


def _critical_run_up_of(scenes, engine: str) -> list[float]:
    return [b.value for b in critical_force_brackets(scenes, start="run-up", engine=engine)]


BATCHED = {"peak-stick": _peak_of, "mean-stick": _mean_of, "critical": _critical_of,
           "critical-run-up": _critical_run_up_of}
#: Runs handed to one engine call by :func:`stick_forces_of` (their records are reduced to their
#: stick forces before the next call).
BATCH_RUNS = 128


# -- the quasi-static breakaway -------------------------------------------------------------------

#: The ramp: the force rises from 0 to the flank-law estimate in this many slowest periods
#: (then on at the same rate), and again at half the rate; the rate is halved until the two
#: agree within RATE_TOL, up to MAX_RAMP_PERIODS. Measured on Ooten's 10/3 scenes: the
#: regular fixed track converges from above 100 periods (25.17, 25.56, 25.59 mN at 50, 100,
#: 200), the free slider wanders +-1.6 % up to 200 and settles within 0.3 % from 400.
RAMP_PERIODS = 100.0
MAX_RAMP_PERIODS = 1600.0
RATE_TOL = 0.005
#: Breakaway: the slider has moved this fraction of the lower surface's mean pitch from where it
#: rested. Not a speed: while the force rises, single contacts let go in micro-slips that reach
#: 30 m/s for a fraction of a nanosecond (1 % of sqrt(F base / M) on Ooten's scenes), which a
#: speed test took for a breakaway at 0.2-0.7 x the barrier (measured); before breaking loose
#: the slider creeps at most the interference's run up a flank (0.125 um of a 1.25 um pitch).
BREAKAWAY_PITCHES = 0.5


@dataclass(frozen=True)
class QuasiStaticBreakaway:
    """The drive force (N) at which a slowly ramped force breaks the slider loose from rest.

    ``force`` at the slowest ramp run (``ramp_time`` s from 0 to the flank-law
    estimate), ``force_fast`` at twice that rate; ``rate_change`` = (fast -
    slow) / slow is how much halving the rate moved it, the measurement's own
    convergence (the error shrinks with the rate), and ``converged`` says
    whether it is within :data:`RATE_TOL`. NaN when the slider did not break
    loose within three times the estimate. ``dt`` is the step used (s).
    """

    force: float
    force_fast: float
    ramp_time: float
    start: str
    dt: float = math.nan

    @property
    def rate_change(self) -> float:
        return (self.force_fast - self.force) / self.force

    @property
    def converged(self) -> bool:
        return abs(self.rate_change) <= RATE_TOL


class _Ramp:
    """Stop condition that also drives: sets the force to ``rate x t`` at every sample and
    stops once the slider has moved ``distance`` (m) from where it started."""

    name = "breakaway"

    def __init__(self, run, rate: float, distance: float):
        self.run, self.rate, self.distance, self.force = run, rate, distance, 0.0

    def __call__(self, probe) -> bool:
        if probe.x - probe.x_start > self.distance:
            return True
        self.force = self.rate * probe.t
        self.run.set_drive_force(self.force)
        return False


def quasi_static_breakaway(scene: Scene, *, start: str = "rest", ramp_periods: float = RAMP_PERIODS,
                           dt: float | None = None) -> QuasiStaticBreakaway:
    """The quasi-static breakaway force (N): a constant-force drive ramped slowly from zero,
    on the slider settled as :func:`asperity2d.critical_force` settles it for ``start``.

    :func:`asperity2d.critical_force` from rest applies each force at once -- a step load,
    which overshoots the static deflection and passes at about half the barrier
    (n k delta tan(theta + atan mu_k) / 2 on a regular fixed track, undamped). This raises
    the force over ``ramp_periods`` slowest periods up to the flank-law estimate, so the
    slider breaks loose (moves half a pitch) at the barrier itself: n k delta tan(theta +
    atan mu_s) on the regular fixed track, L tan(theta + atan mu_s) on the free slider. It is
    run at that rate and at twice it, and the rate is halved until the two agree within
    :data:`RATE_TOL` (or ``ramp_periods`` reaches :data:`MAX_RAMP_PERIODS`); the record
    reports the last pair. ``dt`` (s) defaults to the critical force's
    (``measure_dt``: half the default step from rest, where the
    regular fixed track's breakaway is the flank law to 0.2 %; at the default step the tips
    sink into the flanks and it reads 1.2 % low).
    """
    from ..critical import flank_estimate, measure_dt

    check_choice("start", start, ("rest", "entry", "run-up"))
    ramp_periods = check_positive("ramp_periods", ramp_periods)
    if not isinstance(scene, Scene):
        raise SceneError(f"`scene` must be a Scene (see make_scene), got {type(scene).__name__}")
    dt = measure_dt(scene, start) if dt is None else dt
    base = settled_run(scene, start=start, dt=dt)
    estimate = flank_estimate(scene)
    distance = BREAKAWAY_PITCHES * scene.lower.spacing.mean_pitch

    def ramped(periods: float) -> float:
        ramp_time = periods * scene.slowest_period()
        run = base.fork()
        ramp = _Ramp(run, estimate / ramp_time, distance)
        status = run.advance(3.0 * ramp_time, stop=ramp, record=False)
        return ramp.force if status == ramp.name else math.nan

    periods, fast = ramp_periods, ramped(0.5 * ramp_periods)
    while True:
        slow = ramped(periods)
        record = QuasiStaticBreakaway(force=slow, force_fast=fast, ramp_time=periods * scene.slowest_period(),
                                      start=start, dt=dt)
        if not math.isfinite(slow) or record.converged or 2.0 * periods > MAX_RAMP_PERIODS:
            return record
        periods, fast = 2.0 * periods, slow


# -- travel under a constant force ----------------------------------------------------------------

def travel_under_force(scene: Scene, *, force: float | None = None, start: str = "run-up",
                       dt: float | None = None) -> tuple[float, str]:
    """Ooten's figure 10: how far (m) a constant ``force`` (N; default the scene's own
    constant drive force) carries the slider from ``start`` before it is stuck for good,
    and how the run ended (``"stuck"``, ``"passed"``: the whole surface, or ``"time limit"``).

    ``start`` as :func:`asperity2d.critical_force`: ``"run-up"`` (default) from where the
    builder puts the slider, as the seed's Working Model runs began; ``"rest"`` settled on the
    surface. A slider that passes travels the whole surface (the travel to the pass point).
    ``dt`` (s) defaults to the step policy's (:func:`measure_step`): the step of the critical
    force from the same start, so a force found at that step pushes at it (at the default step a
    stuck half slider stopped on another asperity: see :data:`TRAVEL_DT_FRACTION`).
    """
    if not isinstance(scene, Scene):
        raise SceneError(f"`scene` must be a Scene (see make_scene), got {type(scene).__name__}")
    if force is None:
        if not isinstance(scene.drive, ConstantForce):
            raise SceneError("`force` must be given for a scene without a constant-force drive "
                             "(make_scene(drive=\"force\", drive_force=...))")
        force = scene.drive.force
    pushed = scene.replace(drive=ConstantForce(force=force))
    check_choice("start", start, tuple(TRAVEL_DT_FRACTION))
    dt = measure_step("travel", scene, start=start) if dt is None else dt
    run = settled_run(scene, start=start, dt=dt)
    run.set_drive_force(pushed.drive.force)
    x0 = run.engine.slider_state()[0]
    status = run.advance(default_duration(pushed), stop=default_stops(pushed), record=False)
    travel = run.engine.slider_state()[0] - x0
    return float(travel), ("time limit" if status == "duration" else status)


# -- the named measures (module level: worker processes import them) ------------------------------

def critical_force_from_rest(scene: Scene) -> float:
    """Critical constant force (N) from rest on the surface: a step load
    (:func:`asperity2d.critical_force`, ``start="rest"``)."""
    return critical_force(scene)


def critical_force_with_run_up(scene: Scene) -> float:
    """Critical constant force (N) with the builder's run-up (``start="run-up"``): a momentum
    threshold."""
    return critical_force(scene, start="run-up")


def quasi_static_breakaway_force(scene: Scene) -> float:
    """Force (N) at which a slowly ramped force breaks the slider loose from rest
    (:func:`quasi_static_breakaway`)."""
    return quasi_static_breakaway(scene).force


def first_breakaway_of_pass(scene: Scene) -> float:
    """Drive force (N) at the first stick-to-slip transition of one spring-driven pass (the
    nominal drive speed, at the step policy's step); NaN if the slider never broke away."""
    from ..run import simulate

    scene = _spring(scene)
    try:
        return float(analysis.breakaway_force(simulate(scene, dt=measure_step("first-breakaway", scene),
                                                       progress=False)))
    except SceneError:  # no stick-to-slip transition in the pass
        return math.nan


_ENSEMBLES: dict = {}


def _stick_forces_cached(scene: Scene) -> StickForces:
    """:func:`stick_forces` of ``scene``, remembered for the last few scenes (the peak and the
    mean of one scene come from the same passes)."""
    if scene not in _ENSEMBLES:
        if len(_ENSEMBLES) >= 4:
            _ENSEMBLES.pop(next(iter(_ENSEMBLES)))
        _ENSEMBLES[scene] = stick_forces(scene)
    return _ENSEMBLES[scene]


def peak_stick_force_of_passes(scene: Scene) -> float:
    """Largest drive force (N) at a stick-to-slip transition of a pass, averaged over the
    :data:`PASSES` passes of :func:`stick_forces` (one pass's value is chaotic: see the module
    doc). A distribution: compare it over seeds; its step bias and per-seed precision (how many
    seeds a 5 % difference needs) are measured on the findings page."""
    return _stick_forces_cached(scene).average("peak")


def mean_stick_force_of_passes(scene: Scene) -> float:
    """Mean drive force (N) at the stick-to-slip transitions of a pass, averaged over the
    :data:`PASSES` passes of :func:`stick_forces`. A distribution, like
    :func:`peak_stick_force_of_passes`: its precision is measured on the findings page."""
    return _stick_forces_cached(scene).average("mean")


def travel_distance(scene: Scene) -> float:
    """Travel (m) under the scene's constant drive force from the run-up start
    (:func:`travel_under_force`)."""
    return travel_under_force(scene)[0]


# -- the registry ------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Measure:
    """A named measure and everything the rest of the package needs to know about it.

    The registry :data:`MEASURES` maps each name to one of these; :func:`register_measure`
    adds one. Contract -- a new measure must:

    1. be a function ``function(scene) -> float`` of one :class:`~asperity2d.scene.Scene`
       (NaN when the scene gives no value: the statistics skip it), defined at module level so
       worker processes can import it (:func:`asperity2d.compare` runs it in a process pool);
    2. depend on nothing but the scene: the same scene gives the same number (bit for bit), so
       a comparison does not depend on the executor and a seed-independent variant is
       measured once;
    3. state its ``unit`` (SI symbol, ``"N"``, ``"m"``; printed with SI prefixes), a
       ``label`` that reads in a sentence ("critical force from rest (step load)"), and the
       ``drive`` its scenes need: ``"force"`` (a constant force) or ``"spring"`` (a spring
       drive) -- the command line builds the scenes with it;
    4. say its ``kind``: ``"number"`` (deterministic: the same value at dt and dt/2 within
       about 1 %) or ``"distribution"`` (one value is chaotic; report an ensemble's mean and
       compare over seeds as a distribution);
    5. carry its verdict ``rule`` (:class:`~asperity2d.experiments.verdicts.VerdictRule`:
       alpha, direction, smallest effect), fixed before any number is looked at:
       :meth:`Comparison.verdict <asperity2d.experiments.compare.Comparison.verdict>` judges
       by it;
    6. state its step policy: ``dt_fraction``, the fraction of ``default_dt`` its runs use
       (the step where halving it again moves the measure by less than ``step_tolerance``,
       relative). A measure that states none runs at ``default_dt`` and says so
       (:attr:`step_policy`); :func:`measure_step` gives the step of a scene.

    Nothing else is needed: ``asperity2d measures`` lists it, ``asperity2d compare --measure
    NAME`` and ``compare("NAME", ...)`` run it, plots and verdicts use its label and unit.
    """

    name: str
    function: Callable[[Scene], float]
    label: str
    unit: str = "N"
    drive: str = "force"
    kind: str = "number"
    rule: VerdictRule = VerdictRule()
    description: str = ""
    dt_fraction: float | None = None
    step_tolerance: float | None = None

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name or self.name.strip() != self.name:
            raise SceneError(f"`name` of a measure must be a non-empty string, got {self.name!r}")
        if not callable(self.function):
            raise SceneError(f"`function` of measure {self.name!r} must be callable, got {self.function!r}")
        check_choice("drive", self.drive, DRIVES)
        check_choice("kind", self.kind, KINDS)
        if not isinstance(self.rule, VerdictRule):
            raise SceneError(f"`rule` of measure {self.name!r} must be a VerdictRule, got {self.rule!r}")
        if self.dt_fraction is not None:
            check_range("dt_fraction", self.dt_fraction, 1e-6, 1.0)
        if self.step_tolerance is not None:
            check_range("step_tolerance", self.step_tolerance, 0.0, 1.0)

    @property
    def step_policy(self) -> str:
        """The step its scenes run at, in words: ``"dt/2"`` (a fraction of ``default_dt``), or
        ``"default dt (no step policy stated)"`` for a measure that states none."""
        if self.dt_fraction is None:
            return "default dt (no step policy stated)"
        if self.dt_fraction == 1.0:
            return "dt"
        inverse = 1.0 / self.dt_fraction
        return f"dt/{inverse:g}" if inverse == round(inverse) else f"{self.dt_fraction:g} dt"

    @property
    def distribution(self) -> bool:
        """True for a measure whose single value is chaotic (compared as a distribution)."""
        return self.kind == "distribution"

    # (function, label) unpacking and indexing, as the registry's entries were before they
    # carried metadata: ``fn, label = MEASURES[name]`` keeps working.
    def __iter__(self):
        return iter((self.function, self.label))

    def __getitem__(self, index):
        return (self.function, self.label)[index]

    def to_dict(self) -> dict:
        """The metadata as JSON values (the function by its qualified name)."""
        return {"name": self.name, "label": self.label, "unit": self.unit, "drive": self.drive,
                "kind": self.kind, "function": f"{self.function.__module__}.{self.function.__qualname__}",
                "rule": {"alpha": self.rule.alpha, "direction": self.rule.direction,
                         "min_effect": self.rule.min_effect},
                "description": self.description, "dt_fraction": self.dt_fraction,
                "step": self.step_policy, "step_tolerance": self.step_tolerance}


#: What a measure's scenes are driven by: a constant force or a spring.
DRIVES = ("force", "spring")
#: A measure's kind: one deterministic number, or the mean of a chaotic distribution.
KINDS = ("number", "distribution")

def _check_measure(measure) -> "Measure":
    if not isinstance(measure, Measure):
        raise SceneError(f"`measure` must be a Measure, got {type(measure).__name__}")
    return measure


def _adapt_measure(obj, name: str) -> "Measure":
    """What an entry point or ``"module:function"`` names, made a Measure: a Measure as it is; a
    plain function ``scene -> float`` under that name, labelled by its name, with no unit and no
    step policy stated (a constant-force drive)."""
    if isinstance(obj, Measure) or not callable(obj) or isinstance(obj, type):
        return obj
    label = getattr(obj, "__name__", name).replace("_", " ")
    return Measure(name, obj, label, unit="", description=(getattr(obj, "__doc__", None) or "").strip()[:200])


#: The registry of named measures: name -> :class:`Measure`. The CLI's ``--measure``,
#: ``compare(measure="...")``, plots and verdicts read it; :func:`register_measure` adds one, and
#: an installed package adds its own through the entry-point group ``asperity2d.measures``
#: (a ``Registry`` (``asperity2d._registry``): ``"module:function"`` works wherever a name does).
MEASURES: Registry = Registry("measure", "asperity2d.measures", key=lambda m: m.name, check=_check_measure,
                              adapt=_adapt_measure)


def register_measure(measure: Measure, *, replace: bool = False) -> Measure:
    """Add ``measure`` to :data:`MEASURES` under its name (see :class:`Measure` for the
    contract); a name already taken raises ``SceneError`` unless ``replace``. Returns it.

    Examples
    --------
    >>> from asperity2d.experiments.measures import Measure, register_measure, unregister_measure
    >>> def pitch(scene):
    ...     return scene.lower.spacing.pitch
    >>> entry = register_measure(Measure("pitch", pitch, "mean pitch", unit="m"))
    >>> entry.step_policy
    'default dt (no step policy stated)'
    >>> register_measure(entry)
    Traceback (most recent call last):
    ...
    asperity2d.errors.SceneError: `measure` 'pitch' is already registered (pass replace=True)
    >>> unregister_measure("pitch").name
    'pitch'
    """
    return MEASURES.register(measure, replace=replace)


def unregister_measure(name: str) -> Measure:
    """Remove the measure ``name`` from :data:`MEASURES` and return it."""
    return MEASURES.unregister(name)


for _entry in (
    Measure("critical", critical_force_from_rest, "critical force from rest (step load)",
            description="constant force that moves the slider across from rest on the surface, a step load",
            dt_fraction=CRITICAL_DT_FRACTION["rest"], step_tolerance=0.01),
    Measure("critical-run-up", critical_force_with_run_up, "critical force with a run-up",
            description="the same with the builder's run-up: a momentum threshold",
            dt_fraction=CRITICAL_DT_FRACTION["run-up"], step_tolerance=0.01),
    Measure("quasi-static-breakaway", quasi_static_breakaway_force, "quasi-static breakaway force",
            description="force at which a slowly ramped force breaks the slider loose",
            dt_fraction=CRITICAL_DT_FRACTION["rest"], step_tolerance=0.01),
    Measure("first-breakaway", first_breakaway_of_pass, "first breakaway force", drive="spring",
            description="drive force at the first stick-to-slip transition of a spring-driven pass",
            dt_fraction=FIRST_BREAKAWAY_DT_FRACTION, step_tolerance=0.01),
    Measure("peak-stick", peak_stick_force_of_passes, "peak stick force over a pass", drive="spring",
            kind="distribution", description="largest stick force of spring-driven passes (ensemble mean)",
            dt_fraction=STICK_DT_FRACTION, step_tolerance=0.05),
    Measure("mean-stick", mean_stick_force_of_passes, "mean stick force over a pass", drive="spring",
            kind="distribution", description="mean stick force of spring-driven passes (ensemble mean)",
            dt_fraction=STICK_DT_FRACTION, step_tolerance=0.05),
    Measure("travel", travel_distance, "travel under a constant force", unit="m", kind="distribution",
            description="distance travelled under the scene's constant drive force (where a stuck slider "
                        "stops is chaotic: compared over seeds)",
            dt_fraction=TRAVEL_DT_FRACTION["run-up"], step_tolerance=0.05),
):
    register_measure(_entry)
del _entry
STEP_TOLERANCE.update({name: m.step_tolerance for name, m in MEASURES.loaded().items()})

#: Measures whose single value is chaotic (reported as the mean of an ensemble of passes,
#: compared over seeds as a distribution): the built-in ones (:attr:`Measure.distribution`
#: says it of any registered measure).
DISTRIBUTIONS = tuple(name for name, m in MEASURES.loaded().items() if m.distribution)


def find_measure(name: str) -> Measure | None:
    """The registered measure called ``name`` or whose function is called ``name`` (a
    :class:`~asperity2d.experiments.compare.Comparison` records the function's name); None
    if there is none."""
    if name in MEASURES:
        return MEASURES[name]
    for entry in MEASURES.values():
        if getattr(entry.function, "__name__", None) == name:
            return entry
    return None


def measure_label(name: str) -> str:
    """A plain-language label of a measure's name (the name itself if it is not standard)."""
    entry = find_measure(name)
    return entry.label if entry is not None else name.replace("_", " ")


def measure_unit(name: str) -> str:
    """The SI unit of a measure (by its name or its function's name); ``""`` if it is not
    registered (a plain callable's unit is unknown)."""
    entry = find_measure(name)
    return entry.unit if entry is not None else ""
