"""Quasi-static acceleration of slow drives, with its convergence shown on a ladder of speed-ups.

Ooten's steel drive, 5e-3 m/s, is 4.4e-7 of base x omega: stepping it in
real time costs ~1.8e7 steps per micrometre. Stick-slip at such a speed is
quasi-static: the stick phase is a slow elastic loading and the slip a fast
event whose course should not depend on the loading rate. So a run may drive
``factor`` times faster -- provided its numbers no longer depend on the drive
speed, which :func:`convergence_ladder` shows rather than assumes: it runs
the scene at a ladder of speed-ups (default x4000, x2000, x1000, x500) and
measures at every rung (:func:`stick_slip_measures`) quantities set by the
loading (stick force, slip distance) and by the dynamics of the slip (its
duration, the force drop, the energy dissipated per cycle).

Each quantity's *error* at a rung is its relative difference from the
slowest rung. Where the successive changes shrink, the ladder also gives the
observed order p = log2(change(2s -> s) ... ) of the three slowest rungs and
the Richardson-extrapolated limit. A quantity is *converged* at a rung when
its error there is below ``tolerance`` and its changes shrink from that rung
down the ladder (each halving of the speed-up changes it no more than the
previous one did, or by less than a noise floor of ``tolerance / 10``);
:attr:`Ladder.converged` means every quantity is converged at the ladder's
production factor (its fastest rung by default).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from .._inputs import check_positive
from ..errors import SceneError
from ..scene import Scene, SpringDrive

#: Ooten's drive speed (m/s), the reference of the acceleration factor.
SEED_DRIVE_VELOCITY = 5e-3
#: Default tolerance of the convergence check (relative error against the slowest rung).
TOLERANCE = 0.02
#: Default ladder of speed-ups (fastest first): each rung halves the drive speed.
LADDER = (4000.0, 2000.0, 1000.0, 500.0)
#: A slip's duration is its rise time: from this fraction of its advance to 1 minus it. (A speed
#: threshold relative to the slip's peak speed would be set by impact spikes, which scatter the
#: peak by 15 % and the duration by 3 % from one slip to the next on the fixed track.)
SLIP_RISE_FRACTION = 0.1
#: The ladder's quantities: name -> what it measures (unit in the name).
QUANTITIES = {
    "stick_force_N": "mean drive force at breakaway over the steady events",
    "first_breakaway_N": "drive force at the first breakaway",
    "force_drop_N": "mean force drop per slip over the steady events",
    "slip_distance_m": "mean slider advance per stick-slip cycle (breakaway to breakaway)",
    "slip_duration_s": f"mean rise time of a slip: from {SLIP_RISE_FRACTION:.0%} to "
                       f"{1 - SLIP_RISE_FRACTION:.0%} of its advance",
    "energy_per_cycle_J": "mean drive work per stick-slip cycle (breakaway to breakaway): all "
                          "dissipated, as the state repeats each cycle on a regular surface",
}


def accelerated(scene: Scene, *, factor: float, reference_velocity: float = SEED_DRIVE_VELOCITY) -> Scene:
    """``scene`` with its spring drive's far end moving at ``factor`` x ``reference_velocity`` (m/s)."""
    check_positive("factor", factor)
    check_positive("reference_velocity", reference_velocity)
    if not isinstance(scene.drive, SpringDrive):
        raise SceneError("`scene` must have a spring drive to be accelerated")
    drive = dataclasses.replace(scene.drive, velocity=factor * reference_velocity)
    return scene.replace(drive=drive)


def _slip_duration(t: np.ndarray, x: np.ndarray, start: int, stop: int) -> float:
    """Rise time (s) of the slip in samples [start, stop): from 10 % to 90 % of its advance,
    each crossing interpolated linearly between samples."""
    seg_t, seg_x = t[start:stop], x[start:stop] - x[start]
    total = seg_x[-1] if len(seg_x) else 0.0
    if len(seg_x) < 3 or not total > 0:
        return math.nan

    def when(fraction: float) -> float:
        level = fraction * total
        k = int(np.argmax(seg_x >= level))  # first sample at or past the level (k >= 1)
        return float(np.interp(level, (seg_x[k - 1], seg_x[k]), (seg_t[k - 1], seg_t[k])))

    return when(1.0 - SLIP_RISE_FRACTION) - when(SLIP_RISE_FRACTION)


def stick_slip_measures(result) -> dict:
    """The ladder's quantities (:data:`QUANTITIES`, SI) of a spring-driven run.

    The first event is reported alone (``first_breakaway_N``): on the fixed
    track it is the front tip entering the surface. The *steady* events are
    the later ones, less rebounds (an event whose stick force is below half
    the median: a bounce off a flank, not a stick). Every other quantity is
    taken over the steady *cycles*: a steady breakaway, its slip, and the
    stick up to the next steady breakaway -- so the last slip of the pass,
    which runs off the end of the surface, never counts. ``events`` counts
    the cycles.
    """
    from ..analysis import stick_slip_events

    events = stick_slip_events(result)
    out = dict.fromkeys(QUANTITIES, math.nan) | {"events": 0}
    if not events:
        return out
    out["first_breakaway_N"] = float(events[0].force_peak)
    later = events[1:]
    if len(later) < 2:
        return out
    median = float(np.median([e.force_peak for e in later]))
    steady = [e for e in later if e.force_peak >= 0.5 * median]
    cycles = [e for e in steady[:-1] if e.complete]  # each followed by another steady breakaway
    if not cycles:
        return out
    out["events"] = len(cycles)
    t, x, f = (np.asarray(a, dtype=float) for a in (result.t, result.x, result.drive_force))
    out["stick_force_N"] = float(np.mean([e.force_peak for e in cycles]))
    out["force_drop_N"] = float(np.mean([e.force_drop for e in cycles]))
    index = np.searchsorted(t, [(e.t_slip, e.t_end) for e in cycles])
    out["slip_duration_s"] = float(np.nanmean([_slip_duration(t, x, i, j + 1) for i, j in index]))
    following = {id(a): b for a, b in zip(steady[:-1], steady[1:])}
    starts = np.searchsorted(t, [(e.t_slip, following[id(e)].t_slip) for e in cycles])
    out["slip_distance_m"] = float(np.mean([x[j] - x[i] for i, j in starts]))
    velocity = result.scene.drive.velocity
    out["energy_per_cycle_J"] = float(np.mean([np.trapezoid(f[i:j + 1], t[i:j + 1]) * velocity
                                               for i, j in starts]))
    return out


def run_measures(scene: Scene, **simulate_options) -> tuple[dict, object]:
    """Simulate ``scene`` and return (measures + diagnostics, result)."""
    import time

    from ..run import simulate

    clock = time.process_time()
    result = simulate(scene, **simulate_options)
    cpu = time.process_time() - clock
    out = stick_slip_measures(result)
    out.update(drive_velocity_m_per_s=scene.drive.velocity, status=result.status,
               steps=int(result.meta["steps"]), cpu_time_s=cpu,
               max_overlap_fraction=result.meta["max_overlap_fraction"],
               max_track_drift_fraction=result.meta["max_track_drift_fraction"])
    return out, result


def _relative(a: float, b: float) -> float:
    if not (math.isfinite(a) and math.isfinite(b)) or b == 0:
        return math.inf
    return abs(a - b) / abs(b)


@dataclass(frozen=True)
class Ladder:
    """Outcome of :func:`convergence_ladder`.

    ``factors``: the speed-ups, fastest first; ``rungs``: each rung's
    :func:`run_measures` dict; ``production``: the factor whose convergence
    :attr:`converged` reports.
    """

    factors: tuple[float, ...]
    rungs: tuple[dict, ...]
    tolerance: float
    production: float

    def values(self, name: str) -> np.ndarray:
        return np.array([r[name] for r in self.rungs], dtype=float)

    def errors(self, name: str) -> np.ndarray:
        """Relative difference of every rung from the slowest (inf where undefined)."""
        v = self.values(name)
        return np.array([_relative(x, v[-1]) for x in v])

    def changes(self, name: str) -> np.ndarray:
        """Relative change from each rung to the next slower one (len - 1 values)."""
        v = self.values(name)
        return np.array([_relative(a, b) for a, b in zip(v[:-1], v[1:])])

    def richardson(self, name: str) -> dict:
        """Observed order and extrapolated limit from the three slowest rungs (NaN unless the
        changes shrink there)."""
        v = self.values(name)
        out = {"order": math.nan, "limit": math.nan, "error_slowest": math.nan}
        if len(v) < 3 or not np.all(np.isfinite(v[-3:])):
            return out
        fast, slow = abs(v[-3] - v[-2]), abs(v[-2] - v[-1])
        if slow > 0 and fast > slow and (v[-3] - v[-2]) * (v[-2] - v[-1]) > 0:  # one-sided approach
            p = math.log2(fast / slow)
            limit = v[-1] + (v[-1] - v[-2]) / (2.0 ** p - 1.0)
            out.update(order=p, limit=float(limit), error_slowest=_relative(v[-1], limit))
        return out

    def converged_at(self, name: str, factor: float) -> bool:
        """Error below tolerance at ``factor``, and shrinking changes from there down the ladder."""
        k = self.factors.index(factor)
        if not np.all(np.isfinite(self.values(name)[k:])) or not self.errors(name)[k] < self.tolerance:
            return False
        steps = self.changes(name)[k:]
        floor = self.tolerance / 10.0
        return bool(all(b <= a or b < floor for a, b in zip(steps[:-1], steps[1:])))

    def converged_from(self, name: str) -> float:
        """The fastest factor at which ``name`` is converged (NaN if none but the slowest)."""
        return next((f for f in self.factors[:-1] if self.converged_at(name, f)), math.nan)

    @property
    def converged(self) -> bool:
        """Every quantity converged at the production factor."""
        return all(self.converged_at(name, self.production) for name in QUANTITIES)

    def to_dict(self) -> dict:
        quantities = {}
        for name, meaning in QUANTITIES.items():
            quantities[name] = {
                "meaning": meaning, "values": self.values(name).tolist(),
                "error_vs_slowest": self.errors(name).tolist(), "change_per_halving": self.changes(name).tolist(),
                "richardson": self.richardson(name),
                "converged_at_production": self.converged_at(name, self.production),
                "converged_from_factor": self.converged_from(name)}
        return {"factors": list(self.factors), "production_factor": self.production,
                "tolerance": self.tolerance, "converged": self.converged,
                "converged_means": (f"every quantity within {self.tolerance:.0%} of the slowest rung at "
                                    f"x{self.production:g}, with changes that shrink down the ladder"),
                "quantities": quantities, "rungs": list(self.rungs)}


def convergence_ladder(scene: Scene, *, factors=LADDER, production: float | None = None,
                       tolerance: float = TOLERANCE, reference_velocity: float = SEED_DRIVE_VELOCITY,
                       on_rung=None, **simulate_options) -> Ladder:
    """Run ``scene`` accelerated by each of ``factors`` (fastest first; each rung half the previous
    speed) and return the :class:`Ladder`. ``production`` (default the fastest) is the factor whose
    convergence is judged; ``on_rung(factor, result)`` is called after each run;
    ``simulate_options`` go to :func:`asperity2d.simulate`."""
    check_positive("tolerance", tolerance)
    factors = tuple(float(check_positive("factors", f)) for f in factors)
    if len(factors) < 3 or any(not math.isclose(a, 2.0 * b) for a, b in zip(factors[:-1], factors[1:])):
        raise SceneError(f"`factors` must be at least three speed-ups, fastest first, each half the "
                         f"previous, got {factors}")
    production = factors[0] if production is None else float(production)
    if production not in factors[:-1]:
        raise SceneError(f"`production` must be one of the faster rungs {factors[:-1]}, got {production}")
    rungs = []
    for factor in factors:
        measures, result = run_measures(accelerated(scene, factor=factor, reference_velocity=reference_velocity),
                                        **simulate_options)
        rungs.append(measures | {"factor": factor})
        if on_rung is not None:
            on_rung(factor, result)
    return Ladder(factors=factors, rungs=tuple(rungs), tolerance=float(tolerance), production=production)


def real_time_rate(scene: Scene, *, steps: int = 20_000, velocity: float = SEED_DRIVE_VELOCITY) -> dict:
    """Step ``scene`` with its drive at ``velocity`` (m/s) and report the real-time cost.

    Returns steps per second, steps per micrometre of drive travel at
    ``velocity`` and the implied wall time per micrometre (s).
    """
    import time

    from ..run import Run

    scene = accelerated(scene, factor=1.0, reference_velocity=velocity)
    run = Run(scene)
    dt = run.dt
    if scene.slider.track == "free":
        run.settle()
    clock = time.perf_counter()
    run.advance(steps * dt, record_every=steps)
    wall = time.perf_counter() - clock
    rate = steps / wall
    per_um = 1e-6 / (velocity * dt)
    return {"drive_velocity_m_per_s": velocity, "dt_s": dt, "steps": steps, "steps_per_s": rate,
            "steps_per_um": per_um, "wall_time_per_um_s": per_um / rate,
            "distance_m": velocity * dt * steps}

