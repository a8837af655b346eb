"""Quasi-static acceleration of slow drives, with a convergence check.

Seed 000's steel drive, 5e-3 m/s, is 4.4e-7 of base x omega: stepping it in
real time costs ~1.8e7 steps per micrometre. Stick-slip at such a speed is
quasi-static: the stick phase is a slow elastic loading and the slip a fast
event whose course does not depend on the loading rate. So a run may drive
``factor`` times faster, provided the headline numbers no longer depend on
the drive speed. :func:`convergence_check` runs the scene at ``factor`` and
``factor / 2`` and calls the result converged when halving the acceleration
changes the mean stick-slip peak force and the mean slip distance by less
than ``tolerance`` (relative).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ._validate import check_positive
from .errors import SceneError
from .scene import Scene, SpringDrive

#: Seed 000's drive speed (m/s), the reference of the acceleration factor.
SEED_DRIVE_VELOCITY = 5e-3
#: Default tolerance of the convergence check (relative change on halving).
TOLERANCE = 0.02


def accelerated(scene: Scene, *, factor: float, reference_velocity: float = SEED_DRIVE_VELOCITY) -> Scene:
    """``scene`` with its spring drive's far end moving at ``factor`` x ``reference_velocity`` (m/s)."""
    check_positive("factor", factor)
    check_positive("reference_velocity", reference_velocity)
    if not isinstance(scene.drive, SpringDrive):
        raise SceneError("`scene` must have a spring drive to be accelerated")
    drive = dataclasses.replace(scene.drive, velocity=factor * reference_velocity)
    return scene.replace(drive=drive)


def stick_slip_measures(result) -> dict:
    """Stick-slip headline numbers of a spring-driven run (SI).

    ``peak_force_N``: mean drive force at breakaway over the complete events.
    ``slip_distance_m``: mean slider advance per stick-slip cycle, from one
    breakaway to the next. The slider barely moves while stuck (below half
    the drive speed), so this is the distance slid per slip; unlike the
    detector's per-event ``slip_distance`` it does not depend on where in the
    rattle after landing the re-stick is declared (that scatters by ±5 % from
    event to event on 45° flanks). ``event_slip_distance_m`` is that mean.
    """
    from .analysis import stick_slip_events

    events = [e for e in stick_slip_events(result) if e.complete]
    out = {"peak_force_N": math.nan, "slip_distance_m": math.nan,
           "event_slip_distance_m": math.nan, "events": len(events)}
    if not events:
        return out
    out["peak_force_N"] = float(np.mean([e.force_peak for e in events]))
    out["event_slip_distance_m"] = float(np.mean([e.slip_distance for e in events]))
    if len(events) >= 2:
        x_slip = np.interp([e.t_slip for e in events], result.t, result.x)
        out["slip_distance_m"] = float((x_slip[-1] - x_slip[0]) / (len(events) - 1))
    return out


@dataclass(frozen=True)
class ConvergenceCheck:
    """Outcome of :func:`convergence_check` (forces N, distances m)."""

    factor: float
    tolerance: float
    fast: dict  # stick_slip_measures at ``factor``, plus run diagnostics
    slow: dict  # the same at ``factor / 2``
    peak_force_change: float  # |fast - slow| / |slow|
    slip_distance_change: float

    @property
    def converged(self) -> bool:
        return bool(self.peak_force_change < self.tolerance and self.slip_distance_change < self.tolerance)

    def as_dict(self) -> dict:
        return {"acceleration_factor": self.factor, "tolerance": self.tolerance,
                "converged": self.converged, "peak_force_change": self.peak_force_change,
                "slip_distance_change": self.slip_distance_change, "fast": self.fast, "slow": self.slow}


def _relative(a: float, b: float) -> float:
    if not (math.isfinite(a) and math.isfinite(b)) or b == 0:
        return math.inf
    return abs(a - b) / abs(b)


def run_measures(scene: Scene, **simulate_options) -> tuple[dict, object]:
    """Simulate ``scene`` and return (measures + diagnostics, result)."""
    import time

    from .simulate import simulate

    clock = time.perf_counter()
    result = simulate(scene, **simulate_options)
    wall = time.perf_counter() - clock
    out = stick_slip_measures(result)
    out.update(drive_velocity_m_per_s=scene.drive.velocity, status=result.status,
               steps=int(result.meta["steps"]), wall_time_s=wall,
               max_overlap_fraction=result.meta["max_overlap_fraction"],
               max_track_drift_fraction=result.meta["max_track_drift_fraction"])
    return out, result


def convergence_check(scene: Scene, *, factor: float, tolerance: float = TOLERANCE,
                      reference_velocity: float = SEED_DRIVE_VELOCITY,
                      **simulate_options) -> tuple[ConvergenceCheck, object, object]:
    """Run ``scene`` accelerated by ``factor`` and by ``factor / 2``.

    Returns ``(check, result_fast, result_slow)``. ``simulate_options`` go to
    :func:`asperity2d.simulate` .
    """
    check_positive("tolerance", tolerance)
    fast, r_fast = run_measures(accelerated(scene, factor=factor, reference_velocity=reference_velocity),
                                **simulate_options)
    slow, r_slow = run_measures(accelerated(scene, factor=factor / 2, reference_velocity=reference_velocity),
                                **simulate_options)
    check = ConvergenceCheck(
        factor=float(factor), tolerance=float(tolerance), fast=fast, slow=slow,
        peak_force_change=_relative(fast["peak_force_N"], slow["peak_force_N"]),
        slip_distance_change=_relative(fast["slip_distance_m"], slow["slip_distance_m"]))
    return check, r_fast, r_slow


def real_time_rate(scene: Scene, *, steps: int = 20_000, velocity: float = SEED_DRIVE_VELOCITY) -> dict:
    """Step ``scene`` with its drive at ``velocity`` (m/s) and report the real-time cost.

    Returns steps per second, steps per micrometre of drive travel at
    ``velocity`` and the implied wall time per micrometre (s).
    """
    import time

    from .simulate import Run

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


def plot_position_velocity(result, path, *, title: str = "", dpi: int = 120):
    """Seed 000 figure 17 analogue: slider position (µm) and velocity (m/s) against time (µs).

    The velocity panel shows the collision spikes where the slider hits a
    lower flank. Matplotlib is imported lazily.
    """
    from .render.plots import figure, save

    fig, (ax_x, ax_v) = figure(2, height=2.4)
    t = np.asarray(result.t) * 1e6
    ax_x.plot(t, (np.asarray(result.x) - result.x[0]) * 1e6, lw=1.0, label="slider")
    if np.isfinite(result.drive_x).any():
        ax_x.plot(t, (np.asarray(result.drive_x) - result.x[0]) * 1e6, lw=0.8, ls="--",
                  label="drive spring end")
    ax_x.set_ylabel("position (µm)")
    ax_x.legend(loc="upper left", fontsize=8)
    ax_v.plot(t, result.v, lw=0.8, color="C3")
    ax_v.set_ylabel("velocity (m/s)")
    ax_v.set_xlabel("time (µs)")
    if title:
        ax_x.set_title(title, fontsize=9)
    return save(fig, path, dpi)
