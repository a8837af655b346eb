"""Critical force: the smallest constant drive force that carries the slider across.

Seed 000's Working Model runs pushed the slider with a constant force; it
either stopped on a flank or ran away. The boundary between the two is the
critical force, found here by bisection over constant-force runs, each stopped
as soon as the slider is stuck or has passed the last lower apex.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ._validate import check_int, check_positive
from .errors import SceneError
from .scene import ConstantForce, Scene


@dataclass(frozen=True)
class CriticalForce:
    """Bracket of the critical force (N).

    ``stops`` is the largest force tried with which the slider did not pass,
    ``passes`` the smallest with which it did; ``runs`` simulations were used.
    """

    stops: float
    passes: float
    runs: int

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
    interference at once.
    """
    theta = math.radians(max(scene.lower.profile.flank_angle, 1.0))
    phi = math.atan(scene.contact.mu_static)
    wedge = math.tan(min(theta + phi, math.radians(89.0)))
    if scene.slider.track == "free":
        return scene.slider.normal_load * wedge + 1e-300
    k = max(scene.lower.stiffness)
    return scene.slider.count * k * scene.slider.interference * wedge


def passes(scene: Scene, force: float, **simulate_kw) -> bool:
    """Does a constant ``force`` (N) carry the slider over the whole lower surface?"""
    from .simulate import simulate

    result = simulate(scene.replace(drive=ConstantForce(force=force)), **simulate_kw)
    return result.status == "passed"


def critical_force_bracket(scene: Scene, *, rel_tol: float = 0.01, max_runs: int = 60,
                           **simulate_kw) -> CriticalForce:
    """Bisect the constant drive force until the bracket is ``rel_tol`` wide.

    Assumes passing is monotone in the force (true quasi-statically; with
    inertia a force just below the boundary can occasionally pass, which the
    bracket then reports). Raises :class:`SceneError` if no bracket is found
    within ``max_runs`` runs.
    """
    check_positive("rel_tol", rel_tol)
    check_int("max_runs", max_runs, minimum=2)
    if not isinstance(scene, Scene):
        raise SceneError(f"`scene` must be a Scene, got {type(scene).__name__}")
    runs = 0

    def test(force):
        nonlocal runs
        runs += 1
        if runs > max_runs:
            raise SceneError(f"`max_runs` = {max_runs} runs did not bracket the critical force")
        return passes(scene, force, **simulate_kw)

    guess = flank_estimate(scene)
    lo, hi = None, None
    force = guess
    while hi is None or lo is None:
        if test(force):
            hi = force
            force = force / 2.0 if lo is None else force
        else:
            lo = force
            force = force * 2.0 if hi is None else force
        if lo is not None and hi is not None:
            break
    while (hi - lo) / hi > rel_tol:
        mid = 0.5 * (lo + hi)
        if test(mid):
            hi = mid
        else:
            lo = mid
    return CriticalForce(stops=lo, passes=hi, runs=runs)


def critical_force(scene: Scene, *, rel_tol: float = 0.01, **kw) -> float:
    """The smallest constant drive force (N) with which the slider passes the whole lower surface.

    Bisection over constant-force runs to relative tolerance ``rel_tol``
    (default 1 %); each run is settled under load first and stopped as soon as
    the slider is stuck or has passed. See :func:`critical_force_bracket` for
    the bracket itself.
    """
    return critical_force_bracket(scene, rel_tol=rel_tol, **kw).value
