"""Fit standard friction laws to the virtual tribometer's data (SciPy least squares).

All fits work per unit normal load (``force / normal_load``) and return a
:class:`Fit` with the law (:mod:`asperity2d.friction`), the RMS residual
(same unit as the data: dimensionless force / load) and the relative RMS
residual (RMS residual / RMS of the data).

* :func:`fit_coulomb_viscous` and :func:`fit_stribeck`: the steady-sliding
  curve (both directions). The steady curve does not reach v = 0, so the
  Stribeck static level ``mu_s`` is not fitted: it is the breakaway ratio of
  the reversal loops (the largest force / load the contact holds before
  sliding), passed in.
* :func:`fit_dahl`: the pre-sliding loops (force against slider displacement).
* :func:`fit_lugre`: sigma0 from the loops with the fitted Stribeck curve as
  g(v); sigma1 = 0 (the loops are quasi-static, where sigma1 does not act:
  it is not identifiable from them); sigma2 and the Stribeck part from
  :func:`fit_stribeck`.

:func:`belt_period` runs a fitted law in the exact belt solver
(:func:`asperity2d.belt.simulate_chain`) for the mass, drive spring, load and
speed of a spring-driven asperity scene and returns the stick-slip period.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from .friction import CoulombViscous, Dahl, FrictionLaw, LuGre, Stribeck


@dataclass(frozen=True)
class Fit:
    """A fitted law and its residuals (per unit normal load)."""

    law: FrictionLaw
    rms: float
    relative_rms: float
    points: int

    def as_dict(self) -> dict:
        return {**self.law.to_dict(), "rms": self.rms, "relative_rms": self.relative_rms,
                "points": self.points}


def _fit(residual, x0, bounds, data) -> tuple[np.ndarray, float, float]:
    sol = least_squares(residual, x0, bounds=bounds, x_scale="jac")
    r = residual(sol.x)
    rms = float(np.sqrt(np.mean(r**2)))
    return sol.x, rms, rms / float(np.sqrt(np.mean(np.asarray(data) ** 2)))


def steady_mask(curve) -> np.ndarray:
    """Points of steady contact sliding: nonzero force with per-pitch spread < 30 % of it.

    At drive speeds near 1000 m/s the slider lifts off the tips (its load
    cannot pull it back down within a pitch): those points are not steady
    sliding and are left out of the fits.
    """
    f, s = np.abs(curve.force), np.asarray(curve.spread)
    return (f > 0) & (s < 0.3 * f)


def _curve_data(curve, use):
    v = np.asarray(curve.velocity, dtype=float)
    y = np.asarray(curve.force, dtype=float) / curve.normal_load
    keep = steady_mask(curve) if use is None else np.asarray(use, bool)
    return v[keep], y[keep]


def fit_coulomb_viscous(curve, *, use=None) -> Fit:
    """F/N = mu sign(v) + sigma2 v on the steady curve (``use``: mask of points)."""
    v, y = _curve_data(curve, use)

    def residual(p):
        return CoulombViscous(p[0], p[1]).curve(v) - y

    p, rms, rel = _fit(residual, [float(np.median(np.abs(y))), 1e-5], ([0, 0], [np.inf, np.inf]), y)
    return Fit(CoulombViscous(*p), rms, rel, len(v))


def fit_stribeck(curve, *, mu_s: float, use=None) -> Fit:
    """Stribeck curve with the static level ``mu_s`` given; fits mu_k, v_s, delta, sigma2."""
    v, y = _curve_data(curve, use)
    vmin = float(np.min(np.abs(v)))

    def law(p):
        return Stribeck(mu_s, min(p[0], mu_s), p[1], p[2], p[3])

    def residual(p):
        return law(p).curve(v) - y

    x0 = [float(np.min(np.abs(y))), vmin, 1.0, 1e-5]
    bounds = ([0, 1e-3 * vmin, 0.2, 0], [mu_s, 1e3 * float(np.max(np.abs(v))), 5.0, np.inf])
    p, rms, rel = _fit(residual, x0, bounds, y)
    return Fit(law(p), rms, rel, len(v))


def dahl_force(sigma0: float, mu: float, displacement) -> np.ndarray:
    """Dahl force / load along a displacement path (m), starting from z = 0.

    Integrated exactly per segment: along a monotone stroke dz/dx = 1 -
    sigma0 sign(dx) z / mu relaxes z towards sign(dx) mu / sigma0 over the
    length mu / sigma0.
    """
    x = np.asarray(displacement, dtype=float)
    z = np.empty_like(x)
    zi = 0.0
    length = mu / sigma0
    prev = x[0]
    z[0] = zi
    for k in range(1, len(x)):
        dx = x[k] - prev
        if dx:
            zs = math.copysign(length, dx)
            zi = zs + (zi - zs) * math.exp(-abs(dx) / length)
        z[k] = zi
        prev = x[k]
    return sigma0 * z


def _presliding(loops, reach):
    """The loops up to the first stroke whose displacement exceeds ``reach`` x breakaway."""
    x = np.asarray(loops.displacement) - loops.displacement[0]
    y = np.asarray(loops.force) / loops.normal_load
    beyond = np.flatnonzero(np.abs(x) > reach * loops.breakaway_displacement())
    stop = int(beyond[0]) if len(beyond) else len(x)
    return x[:stop], y[:stop]


def fit_dahl(loops, *, reach: float = 2.0) -> Fit:
    """Dahl (sigma0 1/m, mu) fitted to the pre-sliding loops.

    Only the strokes up to ``reach`` x the breakaway displacement are used:
    beyond it the tips climb the next flanks and the force follows the
    flank geometry (the wedge law), which no single-state law describes.
    """
    x, y = _presliding(loops, reach)
    mu0 = float(np.max(np.abs(y)))
    k0 = mu0 / max(loops.breakaway_displacement(), 1e-30)

    def residual(p):
        return dahl_force(p[0], p[1], x) - y

    p, rms, rel = _fit(residual, [k0, mu0], ([1e-3 * k0, 1e-3 * mu0], [1e3 * k0, 1e2 * mu0]), y)
    return Fit(Dahl(*p), rms, rel, len(x))


def fit_lugre(loops, stribeck: Stribeck, *, reach: float = 2.0) -> Fit:
    """LuGre with sigma0 fitted to the loops, g(v) from ``stribeck`` (delta -> 2), sigma1 = 0."""
    x, y = _presliding(loops, reach)
    mu_s = stribeck.mu_s  # quasi-static loops: g(v) ~ mu_s at the reversal speed

    def residual(p):
        return dahl_force(p[0], mu_s, x) - y

    k0 = mu_s / max(loops.breakaway_displacement(), 1e-30)
    p, rms, rel = _fit(residual, [k0], ([1e-3 * k0], [1e3 * k0]), y)
    law = LuGre(float(p[0]), 0.0, stribeck.sigma2, stribeck.mu_s, max(stribeck.mu_k, 1e-12), stribeck.v_s)
    return Fit(law, rms, rel, len(x))


def belt_period(law: FrictionLaw, *, mass: float, stiffness: float, velocity: float,
                normal_load: float, cycles: int = 6) -> dict:
    """Stick-slip period (s) of one mass on a spring (N/m) over a belt at ``velocity`` (m/s).

    The belt frame of a spring-driven slider: the relative velocity is the
    same, so the periods are equal. Uses ``asperity2d.belt.simulate_chain``
    with ``friction=law`` (its exact event-driven solver for piecewise-
    constant laws, an ODE with the same stick logic otherwise).
    """
    from .belt import simulate_chain

    f_s = law.static_coefficient * normal_load
    t_est = 2.0 * f_s / (stiffness * velocity) + 2 * math.pi * math.sqrt(mass / stiffness)
    res = simulate_chain([mass], [stiffness, 0.0], [0.0, 0.0], friction=law, normal_load=[normal_load],
                         v_belt=velocity, x0=[0.0], v0=[velocity], t_end=(cycles + 2) * t_est,
                         n_samples=4001)
    starts = np.array([a for a, _ in res.stick_intervals[0]])
    ends = np.array([b for _, b in res.stick_intervals[0]])
    if len(ends) < 4:
        return {"period_s": math.nan, "cycles": int(len(ends))}
    ends = ends[:-1]  # the last stick interval is cut by t_end, not ended by a breakaway
    periods = np.diff(ends[1:])  # breakaway to breakaway, skipping the first (from rest)
    return {"period_s": float(np.mean(periods)), "cycles": int(len(periods)),
            "force_drop_N": float(stiffness * (ends[-1] - starts[-1]) * velocity) if len(starts) else math.nan}
