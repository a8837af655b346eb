"""Initial-condition basins: which long-run motion each starting state ends in.

**Belt chains** (:func:`chain_basins`): a grid over two coordinates of the
initial state, named ``"x1"``..``"xn"`` (m) and ``"v1"``..``"vn"`` (m/s),
1-based like the multi-DOF belt thesis' x_1, x_2, x_3; the other coordinates keep the
chain's ``x0`` / ``v0``. Every grid point is one run of the exact solver,
classified by :func:`classify_chain` on the last half of the run:

* ``rest``: every velocity swings by less than ``osc_tol`` times the velocity
  scale over the last quarter (steady sliding, or stuck on a still surface);
* ``pure slip``: still oscillating, but no mass is stuck for more than
  ``stick_fraction`` of the last half (the quasi-harmonic regime);
* ``stick-slip``: a mass sticks, and the stick-onset Poincaré section repeats
  (:func:`~asperity2d.dynamics.cycles.chain_cycle`): a period-n limit cycle;
* ``irregular``: a mass sticks, but the section does not repeat within the
  run (chaos, or a transient longer than the run: ``last_stick`` and a longer
  ``t_end`` tell them apart).

The thresholds are those of :func:`asperity2d.belt.regime.classify` (1e-3).
The grid runs through the sweep machinery (:mod:`asperity2d.sweep`): one
run per grid point in a resumable store, in local processes or on Dask.
Every run is bounded: a grid point gets at most :data:`RUN_CPU_LIMIT`
seconds of CPU (a median one takes ~0.1 s) and is recorded as failed
beyond that -- a guard against solver stalls that never count as events.
The limit is a process timer, so it applies where the run executes in a
process's main thread (local processes, in-process); Dask runs tasks in
threads, where it is not set.

Asperity runs have their own scan over the drive preload in
:mod:`.asperity_basins` (the same classes, the same store and executors).
"""

from __future__ import annotations

import contextlib
import json
import signal
import tempfile
import threading
from dataclasses import dataclass

import numpy as np

from .._inputs import check_tolerance
from ..errors import SceneError, SimulationError
from .cycles import chain_cycle

LABELS = ("rest", "pure slip", "stick-slip", "irregular")
RUN_CPU_LIMIT = 60.0  # s of CPU per grid point
RUN = "asperity2d.dynamics.basins:chain_basin_run"


def coordinate(name: str, n: int, *, param: str = "axis") -> tuple[str, int]:
    """``("x0"|"v0", index)`` of a coordinate name like ``"x2"`` or ``"v1"`` (1-based) in an n-mass chain.

    ``param`` is the parameter named in the error message.
    """
    if not isinstance(name, str) or len(name) < 2 or name[0] not in "xv" or not name[1:].isdigit():
        raise SceneError(f"`{param}` must name a coordinate x1..x{n} or v1..v{n}, got {name!r}")
    i = int(name[1:])
    if not 1 <= i <= n:
        raise SceneError(f"`{param}` {name!r} is out of range: the chain has {n} masses (x1..x{n}, v1..v{n})")
    return ("x0" if name[0] == "x" else "v0"), i - 1


def with_initial(chain: dict, name: str, value: float) -> dict:
    """``chain`` (simulate_chain kwargs) with coordinate ``name`` of its initial state set to ``value``."""
    key, i = coordinate(name, len(chain["masses"]))
    out = dict(chain)
    vec = [float(a) for a in out[key]]
    vec[i] = float(value)
    out[key] = vec
    return out


def classify_chain(result, *, rtol: float = 1e-6, stick_fraction: float = 1e-3, osc_tol: float = 1e-3) -> dict:
    """Class of a belt run (module docstring) and its numbers, as plain floats.

    Keys: ``label`` (index into ``LABELS``), ``multiplicity`` and ``period``
    (s; 0 and NaN unless stick-slip), ``stick_fraction`` (largest fraction of
    the last half any mass is stuck), ``last_stick`` (s, last stick onset; 0
    if none), ``amplitude`` (half the largest peak-to-peak position of a mass
    over the last quarter, m), ``events``.
    """
    t = result.t
    t_half = t[0] + 0.5 * (t[-1] - t[0])
    span = t[-1] - t_half
    stuck = [sum(max(0.0, min(b, t[-1]) - max(a, t_half)) for a, b in per) for per in result.stick_intervals]
    fraction = float(max(stuck) / span) if span > 0 else 0.0
    onsets = [e.t for e in result.events if e.kind == "stick"]
    tail = t >= t[0] + 0.75 * (t[-1] - t[0])
    V = abs(float(result.chain.v_belt)) if result.chain is not None and not callable(result.chain.v_belt) else 0.0
    scale = max(V, float(np.max(np.abs(result.v))), 1e-300)
    swing = float(np.max(np.ptp(result.v[:, tail], axis=1)))
    out = {"multiplicity": 0.0, "period": float("nan"), "stick_fraction": fraction,
           "last_stick": float(max(onsets)) if onsets else 0.0,
           "amplitude": 0.5 * float(np.max(np.ptp(result.x[:, tail], axis=1))), "events": float(len(result.events))}
    if swing <= osc_tol * scale:
        return {"label": 0.0, **out}
    if fraction <= stick_fraction:
        return {"label": 1.0, **out}
    cycle = chain_cycle(result, rtol=rtol)
    if cycle.periodic:
        return {"label": 2.0, **out, "multiplicity": float(cycle.multiplicity), "period": cycle.period}
    return {"label": 3.0, **out}


def chain_basin_run(*, chain: str, x_name: str, x_value: float, y_name: str, y_value: float,
                    rtol: float = 1e-6, seed: int = 0) -> dict:
    """Sweep run function: one grid point (``chain`` is the JSON of simulate_chain kwargs; ``seed`` unused)."""
    from ..belt import simulate_chain

    kwargs = _decode_chain(chain)
    kwargs = with_initial(with_initial(kwargs, x_name, x_value), y_name, y_value)
    with cpu_limit(RUN_CPU_LIMIT):
        result = simulate_chain(**kwargs)
    return classify_chain(result, rtol=rtol)


@contextlib.contextmanager
def cpu_limit(seconds: float):
    """Raise SimulationError if the block uses more than ``seconds`` of CPU (main thread, POSIX only)."""
    usable = hasattr(signal, "setitimer") and threading.current_thread() is threading.main_thread()
    if not usable:
        yield
        return

    def expire(signum, frame):
        raise SimulationError(f"the run used more than {seconds:g} s of CPU (RUN_CPU_LIMIT); "
                              "hint: the solver may be stalled at a switching instant")

    previous = signal.signal(signal.SIGPROF, expire)
    signal.setitimer(signal.ITIMER_PROF, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
        signal.signal(signal.SIGPROF, previous)


def _encode_chain(chain: dict) -> str:
    """The JSON of ``simulate_chain`` kwargs: the chain's document (``spec``, the model's own
    record: :func:`asperity2d.belt.chainfile.document`) and the other arguments as given."""
    from ..belt.chainfile import REQUIRED, OPTIONAL, document
    from ..belt.spec import spec_of

    if callable(chain.get("v_belt")):
        raise SceneError("`v_belt` must be a constant for a basin map")
    law = chain.get("friction")
    if law is not None and not hasattr(law, "to_dict"):
        raise SceneError(f"`friction` must be a law from asperity2d.friction, got {law!r}")
    keys = set(REQUIRED + OPTIONAL)
    rest = {k: v for k, v in chain.items() if k not in keys}
    try:
        return json.dumps({"spec": document(spec_of({k: v for k, v in chain.items() if k in keys})), **rest},
                          sort_keys=True)
    except TypeError as exc:
        raise SceneError(f"`chain` must hold numbers and lists only: {exc}") from None


def _decode_chain(text: str) -> dict:
    """``simulate_chain`` kwargs of :func:`_encode_chain`'s JSON (the spec rebuilt by ``ChainSpec.from_dict``)."""
    from ..belt.spec import ChainSpec

    data = json.loads(text)
    return {**ChainSpec.from_dict(data.pop("spec")).arguments(), **data}


@dataclass(frozen=True)
class BasinMap:
    """A basin map: ``values[name][i, j]`` at ``x_values[i]``, ``y_values[j]`` (SI).

    ``values`` has ``label`` (index into ``LABELS``; -1 for a failed run),
    ``multiplicity``, ``period``, ``stick_fraction``, ``last_stick``,
    ``amplitude``, ``events``; ``wall_time`` is the summed run time (s).
    """

    x_name: str
    x_values: np.ndarray
    y_name: str
    y_values: np.ndarray
    values: dict
    t_end: float
    failed: int
    wall_time: float

    def counts(self) -> dict:
        """Grid points per class, with stick-slip split by multiplicity (``"stick-slip period-2"``)."""
        lab, mult = self.values["label"], self.values["multiplicity"]
        out = {name: int(np.sum(lab == i)) for i, name in enumerate(LABELS) if name != "stick-slip"}
        for n in sorted({int(m) for m in mult[lab == 2]}):
            out[f"stick-slip period-{n}"] = int(np.sum((lab == 2) & (mult == n)))
        out["failed"] = self.failed
        return out

    def to_dict(self) -> dict:
        lab = self.values["label"]
        stick = lab == 2
        done = lab >= 0
        out = {
            "x_name": self.x_name, "x_range": [float(self.x_values[0]), float(self.x_values[-1])],
            "y_name": self.y_name, "y_range": [float(self.y_values[0]), float(self.y_values[-1])],
            "shape": list(lab.shape), "t_end_s": self.t_end, "counts": self.counts(),
            "periods_s": sorted({round(float(p), 9) for p in self.values["period"][stick]}),
            "run_seconds_total": self.wall_time, "run_seconds_mean": self.wall_time / max(int(done.sum()), 1),
        }
        if "last_stick" in self.values:
            last = self.values["last_stick"][done]
            out["last_stick_s"] = {"median": float(np.median(last)) if last.size else None,
                                   "max": float(np.max(last)) if last.size else None}
        return out


def chain_basins(chain: dict, *, x: tuple, y: tuple, t_end: float | None = None, rtol: float = 1e-6,
                 store=None, workers: int | None = None, scheduler: str | None = None,
                 progress: bool = True) -> BasinMap:
    """Basin map of a belt chain over ``x = (name, values)`` and ``y = (name, values)``.

    ``chain`` holds ``simulate_chain``'s keyword arguments (e.g. from
    :func:`asperity2d.belt.presets.preset`); ``t_end`` (s) overrides its
    duration. ``store`` is the sweep's results directory: run again with the
    same store and only unfinished grid points are computed (default: a
    temporary directory, not resumable). ``workers`` / ``scheduler`` as in
    :func:`asperity2d.sweep.run_study`.
    """
    from ..belt import simulate_chain
    from ..sweep import Study

    chain = dict(chain)
    if t_end is not None:
        chain["t_end"] = t_end
    (x_name, xs), (y_name, ys) = _axis(x, "x"), _axis(y, "y")
    n = len(chain.get("masses", ()))
    coordinate(x_name, n, param="x"), coordinate(y_name, n, param="y")
    if x_name == y_name:
        raise SceneError(f"`x` and `y` must be different coordinates, got {x_name!r} twice")
    duration = chain.get("t_end")
    if isinstance(duration, bool) or not isinstance(duration, (int, float)) or not 0 < duration < np.inf:
        raise SceneError(f"`t_end` must be > 0, got {duration!r}")
    try:  # validate the chain once here (a moment of simulated time), not in every worker
        simulate_chain(**{**chain, "t_end": 1e-9 * duration, "n_samples": 2})
    except TypeError as exc:
        raise SceneError(f"`chain` is not a set of simulate_chain arguments: {exc}") from None
    rtol = check_tolerance("rtol", rtol)
    study = Study(name="basins", run=RUN, grid={"x_value": xs, "y_value": ys},
                  fixed={"chain": _encode_chain(chain), "x_name": x_name, "y_name": y_name, "rtol": float(rtol)})
    ix, iy = {v: i for i, v in enumerate(xs)}, {v: j for j, v in enumerate(ys)}
    values, failed, wall = _run(study, store, workers, scheduler, progress, (len(xs), len(ys)), _CHAIN_KEYS,
                                lambda spec: (ix[spec.params["x_value"]], iy[spec.params["y_value"]]))
    return BasinMap(x_name, np.array(xs), y_name, np.array(ys), values, float(chain["t_end"]), failed, wall)


_CHAIN_KEYS = ("label", "multiplicity", "period", "stick_fraction", "last_stick", "amplitude", "events")


def _axis(axis, which):
    try:
        name, values = axis
        values = tuple(float(v) for v in values)
    except (TypeError, ValueError):
        raise SceneError(f"`{which}` must be (coordinate name, values), got {axis!r}") from None
    if not values or not all(np.isfinite(values)):
        raise SceneError(f"`{which}` values must be finite and non-empty")
    if len(set(values)) != len(values):
        raise SceneError(f"`{which}` values must be distinct")
    return name, values


def _run(study, store, workers, scheduler, progress, shape, keys, locate):
    """Run ``study`` into ``store`` (a temporary one if None) and gather ``keys`` into arrays of ``shape``.

    ``locate(spec)`` gives the grid index of a run. Failed runs get label -1 and NaN elsewhere.
    """
    from ..sweep import ResultStore, run_study

    with tempfile.TemporaryDirectory(prefix="asperity2d-basins-") as tmp:
        rs = ResultStore(store if store is not None else tmp)
        run_study(study, store=rs, workers=workers, scheduler=scheduler, progress=progress)
        records = rs.records(study)
    values = {k: np.full(shape, np.nan) for k in keys}
    values["label"][:] = -1
    failed, wall = 0, 0.0
    for spec in study.runs():
        rec = records.get(spec.key)
        if rec is None or rec.status != "done":
            failed += 1
            continue
        wall += rec.wall_time
        ij = locate(spec)
        for k in keys:
            values[k][ij] = rec.quantities[k]
    return values, failed, wall
