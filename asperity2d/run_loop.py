"""The run loop: :class:`Run`, one asperity scene being simulated (settle, advance, change the
drive, record, fork), and the checks its result carries (``result.meta["checks"]``).

The one run loop of the package: :func:`~asperity2d.simulate` drives it for a whole run, the
tribometer's strokes and the critical force's bisection drive it piece by piece.
``asperity2d.run`` re-exports :class:`Run` and the energy tolerances.
"""

from __future__ import annotations

import math
from typing import Callable, Iterable

import numpy as np

from ._format import si
from ._inputs import check_finite, check_int, check_positive
from ._version import __version__
from .engine import PYMUNK_VERSION, Engine
from .engine.energy import ContactWork, EnergyMeter
from .engine.recorder import MAX_OVERLAP, Recorder
from .engine.run_checks import off_surface_message, surface_end
from .errors import SceneError
from .result import Result
from .scene import Scene
from .steps import (COARSEST_DAMPER_DT_FRACTION, COARSEST_DT_FRACTION, MAX_STEPS, _damper_time, check_budget,
                    resolve_dt, settle_cap)
from .stops import Probe

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

