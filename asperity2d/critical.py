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
from dataclasses import dataclass

from ._validate import check_choice, check_int, check_positive
from .errors import SceneError
from .scene import ConstantForce, Scene
from .run import MAX_STEPS, Run, default_duration, default_stops

STARTS = ("rest", "entry", "run-up")
#: The settling push of ``start="rest"``, as a fraction of the flank-law estimate.
PUSH_FRACTION = 0.01


@dataclass(frozen=True)
class CriticalForce:
    """Bracket of the critical force (N).

    ``stops`` is the largest force tried with which the slider did not pass,
    ``passes`` the smallest with which it did; ``runs`` simulations were used;
    ``start`` is how each began (``"rest"`` or ``"run-up"``).
    """

    stops: float
    passes: float
    runs: int
    start: str = "rest"

    @property
    def value(self) -> float:
        """The critical force estimate: the smallest force seen to pass (N)."""
        return self.passes

    @property
    def relative_width(self) -> float:
        return (self.passes - self.stops) / self.passes


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
        run.settle(push=PUSH_FRACTION * flank_estimate(scene))
    elif scene.slider.track == "free":
        run.settle()
    return run


def passes(base, force: float) -> bool:
    """Does a constant ``force`` (N), applied to a fork of the settled run ``base``, carry the
    slider over the whole lower surface?"""
    run = base.fork()
    run.set_drive_force(force)
    scene = base.scene.replace(drive=ConstantForce(force=force))
    return run.advance(default_duration(scene), stop=default_stops(scene), record=False) == "passed"


def critical_force_bracket(scene: Scene, *, start: str = "rest", rel_tol: float = 0.01,
                           max_runs: int = 60, dt: float | None = None, iterations: int = 20,
                           max_steps: int | None = None) -> CriticalForce:
    """Bisect the constant drive force until the bracket is ``rel_tol`` wide.

    Assumes passing is monotone in the force (true quasi-statically; with
    inertia a force just below the boundary can occasionally pass, which the
    bracket then reports). Raises :class:`SceneError` if no bracket is found
    within ``max_runs`` runs. ``dt``, ``iterations`` and ``max_steps`` (per
    run) are those of :func:`asperity2d.simulate`.
    """
    if not isinstance(scene, Scene):
        raise SceneError(f"`scene` must be a Scene, got {type(scene).__name__}")
    rel_tol = check_positive("rel_tol", rel_tol)
    if rel_tol >= 1:
        raise SceneError(f"`rel_tol` must be < 1, got {rel_tol!r}")
    max_runs = check_int("max_runs", max_runs, minimum=2)
    base = settled_run(scene, start=start, dt=dt, iterations=iterations, max_steps=max_steps)
    runs = 0

    def test(force):
        nonlocal runs
        runs += 1
        if runs > max_runs:
            raise SceneError(f"`max_runs` = {max_runs} runs did not bracket the critical force")
        return passes(base, force)

    force = flank_estimate(scene)
    lo = hi = None
    while lo is None or hi is None:
        if test(force):
            hi = force
            force = force / 2.0
        else:
            lo = force
            force = force * 2.0
    while (hi - lo) / hi > rel_tol:
        mid = 0.5 * (lo + hi)
        if test(mid):
            hi = mid
        else:
            lo = mid
    return CriticalForce(stops=lo, passes=hi, runs=runs, start=start)


def critical_force(scene: Scene, *, start: str = "rest", rel_tol: float = 0.01, max_runs: int = 60,
                   dt: float | None = None, iterations: int = 20, max_steps: int | None = None) -> float:
    """The smallest constant drive force (N) with which the slider passes the whole lower surface.

    ``start="rest"`` (default): the slider at rest on the surface, every tip
    against its flank; ``"entry"``: at rest against the first flank at the
    entrance; ``"run-up"``: from the builder's start position, a tenth of a
    base before the surface on the fixed track (see the module doc for what
    each measures). Bisection over constant-force runs to relative tolerance
    ``rel_tol`` (default 1 %), each stopped as soon as the slider is stuck or
    has passed. See :func:`critical_force_bracket` for the bracket itself.
    """
    return critical_force_bracket(scene, start=start, rel_tol=rel_tol, max_runs=max_runs, dt=dt,
                                  iterations=iterations, max_steps=max_steps).value
