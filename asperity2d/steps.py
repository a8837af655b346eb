"""The step and the budget of a run: the default ``dt`` and the coarsest allowed, the default
duration, the settling cap and the step budget (``max_steps``), each refusal a ``SceneError``
naming the parameter that sets it. Needs no engine: a run is checked before it is built.
``asperity2d.run`` re-exports every name here.
"""

from __future__ import annotations

import math

import numpy as np

from ._inputs import check_positive
from .errors import SceneError
from .scene import Scene, SpringDrive

#: Default step: this fraction of the shortest natural period (T/50 converged,
#: T/20 is the coarsest that did, T/10 is silently wrong, T/6 blows up).
DT_FRACTION = 1.0 / 50.0
COARSEST_DT_FRACTION = 1.0 / 20.0
#: The drive damper is applied as a force (explicitly): c dt / M must stay
#: well under 2 for it to be stable. Default dt keeps it <= 0.2; coarser than
#: 0.5 is refused. (pymunk integrates the track and lattice dampers exactly.)
DAMPER_DT_FRACTION = 0.2
COARSEST_DAMPER_DT_FRACTION = 0.5
#: Default step budget of one run (settling included): about 5 minutes at N = 16.
MAX_STEPS = 10_000_000
#: Up to this many asperities (both surfaces: Ooten's 16 + 4) a step counts as one in the
#: budget; a larger scene's step counts as its asperity count over this (see :func:`step_cost`).
COST_ASPERITIES = 20


def default_duration(scene: Scene) -> float:
    """Time limit (s) when ``duration=None``: long enough to cross the surface."""
    lower_x = scene.lower.tips()
    span = (lower_x[-1] - lower_x[0]) + scene.slider.tips()[-1] + 4 * scene.lower.spacing.mean_pitch
    if scene.slider.start is not None:  # a start of its own: the way to the surface as well
        span += max(0.0, float(lower_x[0]) - scene.slider.start)
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
        if scene.slider.start is not None:  # the default duration covers the way from it
            fix += " or move `slider_start` closer to the surface"
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

