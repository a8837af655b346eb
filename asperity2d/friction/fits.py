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
* :func:`fit_dahl`: the reversal loops (force against slider displacement). The
  asperity scenes give rigid stick and micro-slips there, not Dahl's smooth
  exponential branch; the residual (63 % on Table 1 steel) says so.
* :func:`fit_lugre`: sigma0 from the loops with the fitted Stribeck curve as
  g(v); sigma1 = 0 (the loops are quasi-static, where sigma1 does not act:
  it is not identifiable from them); sigma2 and the Stribeck part from
  :func:`fit_stribeck`.
* :func:`fit_stick_slip`: a static/kinetic law from the stick-slip cycles of
  a spring-driven asperity run (:func:`stick_slip_cycles`). The steady
  curve cannot give the period of stick-slip: a slip ends when the tips are
  caught by a flank, at a re-stick force set by the flank geometry, not by
  the mean force of steady sliding. The cycle does: mu_s is the breakaway
  force / load, and mu_k is the level about which a Coulomb oscillator's
  slip is symmetric, mu_s - (breakaway - re-stick force) / (2 load).

:func:`asperity2d.belt.period.belt_period` runs a fitted law in the exact belt solver
(:func:`asperity2d.belt.simulate_chain`) for the mass, drive spring, load and
speed of a spring-driven asperity scene and returns the stick-slip period.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from ..errors import SceneError
from .laws import CoulombViscous, Dahl, FrictionLaw, LuGre, StaticKinetic, Stribeck


@dataclass(frozen=True)
class Fit:
    """A fitted law and its residuals (per unit normal load).

    Parameters
    ----------
    law : FrictionLaw
        The fitted law.
    rms : float
        RMS residual (force per unit normal load).
    relative_rms : float
        ``rms`` over the RMS of the data.
    points : int
        The number of points fitted.

    Examples
    --------
    >>> from asperity2d import friction
    >>> fit = friction.Fit(friction.Coulomb(0.2), rms=0.0, relative_rms=0.0, points=3)
    >>> fit.to_dict()["points"]
    3
    """

    law: FrictionLaw
    rms: float
    relative_rms: float
    points: int

    def to_dict(self) -> dict:
        return {**self.law.to_dict(), "rms": self.rms, "relative_rms": self.relative_rms,
                "points": self.points}


def _fit(residual, x0, bounds, data) -> tuple[np.ndarray, float, float]:
    sol = least_squares(residual, x0, bounds=bounds, x_scale="jac")
    r = residual(sol.x)
    rms = float(np.sqrt(np.mean(r**2)))
    return sol.x, rms, rms / float(np.sqrt(np.mean(np.asarray(data) ** 2)))


#: Least fraction of a window's samples in contact for a steady-sliding point.
MIN_CONTACT_FRACTION = 0.9


def steady_mask(curve) -> np.ndarray:
    """Points of steady contact sliding, the ones the fits use.

    A point qualifies with a nonzero force, a per-pitch spread below 30 % of
    it, and the slider in contact for at least ``MIN_CONTACT_FRACTION`` (0.9)
    of the window. From a few hundred m/s the slider lifts off the tips (its
    load cannot pull it back down within a pitch): on the Table 1 tribometer
    it is in contact 99 % of the time at 100 m/s, 20-40 % at 300 m/s and
    0-5 % at 1000 m/s. A one-pitch window has no spread, so the contact
    fraction is what excludes those points there.

    Parameters
    ----------
    curve : SteadyCurve
        The tribometer's steady-sliding curve (:func:`asperity2d.experiments.tribometer.steady_curve`).

    Returns
    -------
    numpy.ndarray of bool
        One flag per point of the curve.

    Examples
    --------
    >>> import numpy as np
    >>> from asperity2d import friction
    >>> from asperity2d.experiments.tribometer import SteadyCurve
    >>> curve = SteadyCurve(np.array([-1.0, 1.0, 300.0]), np.array([-1e-3, 1e-3, 1e-3]),
    ...                     np.zeros(3), 4e-3, contact=np.array([1.0, 1.0, 0.3]))
    >>> friction.steady_mask(curve)  # at 300 m/s the slider is off the tips 70 % of the time
    array([ True,  True, False])
    """
    f, s = np.abs(curve.force), np.asarray(curve.spread)
    keep = (f > 0) & (s < 0.3 * f)
    if getattr(curve, "contact", None) is not None:
        keep &= np.asarray(curve.contact) >= MIN_CONTACT_FRACTION
    return keep


def _curve_data(curve, use):
    v = np.asarray(curve.velocity, dtype=float)
    y = np.asarray(curve.force, dtype=float) / curve.normal_load
    keep = steady_mask(curve) if use is None else np.asarray(use, bool)
    return v[keep], y[keep]


def fit_coulomb_viscous(curve, *, use=None) -> Fit:
    """Coulomb + viscous law, F/N = mu sign(v) + sigma2 v, fitted to the steady curve.

    Parameters
    ----------
    curve : SteadyCurve
        The tribometer's steady-sliding curve (:func:`asperity2d.experiments.tribometer.steady_curve`).
    use : numpy.ndarray of bool, optional
        The points to fit; default those of :func:`steady_mask`.

    Returns
    -------
    Fit
        The law (per unit normal load), its RMS residual, relative RMS and point count.

    Examples
    --------
    A curve made from a known law (what the tribometer measures, here without noise):

    >>> import numpy as np
    >>> from asperity2d import friction
    >>> from asperity2d.experiments.tribometer import SteadyCurve
    >>> v = np.concatenate([-np.logspace(-2, 2, 9)[::-1], np.logspace(-2, 2, 9)])  # m/s
    >>> law = friction.CoulombViscous(mu=0.2, sigma2=1e-3)
    >>> curve = SteadyCurve(v, law.curve(v) * 4e-3, np.zeros(len(v)), normal_load=4e-3)
    >>> fit = friction.fit_coulomb_viscous(curve)
    >>> round(float(fit.law.mu), 6), round(float(fit.law.sigma2), 6), fit.points
    (0.2, 0.001, 18)
    """
    v, y = _curve_data(curve, use)

    def residual(p):
        return CoulombViscous(p[0], p[1]).curve(v) - y

    p, rms, rel = _fit(residual, [float(np.median(np.abs(y))), 1e-5], ([0, 0], [np.inf, np.inf]), y)
    return Fit(CoulombViscous(*p), rms, rel, len(v))


def fit_stribeck(curve, *, mu_s: float, use=None) -> Fit:
    """Stribeck law fitted to the steady curve: mu_k, v_s, delta and sigma2, the static level given.

    Parameters
    ----------
    curve : SteadyCurve
        The tribometer's steady-sliding curve (:func:`asperity2d.experiments.tribometer.steady_curve`).
    mu_s : float
        The static coefficient (e.g. the loops' largest force over the load).
    use : numpy.ndarray of bool, optional
        The points to fit; default those of :func:`steady_mask`.

    Returns
    -------
    Fit
        The law (per unit normal load), its RMS residual, relative RMS and point count.

    Examples
    --------
    A curve made from a known law (what the tribometer measures, here without noise):

    >>> import numpy as np
    >>> from asperity2d import friction
    >>> from asperity2d.experiments.tribometer import SteadyCurve
    >>> v = np.concatenate([-np.logspace(-2, 2, 9)[::-1], np.logspace(-2, 2, 9)])  # m/s
    >>> law = friction.Stribeck(mu_s=0.3, mu_k=0.2, v_s=1.0, delta=2.0, sigma2=1e-3)
    >>> curve = SteadyCurve(v, law.curve(v) * 4e-3, np.zeros(len(v)), normal_load=4e-3)
    >>> fit = friction.fit_stribeck(curve, mu_s=0.3)
    >>> [round(float(x), 4) for x in (fit.law.mu_k, fit.law.v_s, fit.law.delta)]
    [0.2, 1.0, 2.0]
    """
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

    Parameters
    ----------
    loops : ReversalLoops
        The tribometer's pre-sliding loops from rest (:func:`asperity2d.experiments.tribometer.reversal_loops`).
    reach : float, default 2.0
        Strokes up to this multiple of the breakaway displacement are used.

    Returns
    -------
    Fit
        The law (per unit normal load), its RMS residual, relative RMS and point count.

    Examples
    --------
    One stroke from rest made from a Dahl law (sigma0 1e8 1/m, mu 0.3): along it F/N = mu (1 -
    exp(-sigma0 x / mu)).

    >>> import numpy as np
    >>> from asperity2d import friction
    >>> from asperity2d.experiments.tribometer import ReversalLoops
    >>> x = np.linspace(0.0, 1e-8, 200)  # m
    >>> force = 4e-3 * 0.3 * (1 - np.exp(-1e8 * x / 0.3))  # N, under a 4 mN load
    >>> loops = ReversalLoops(x, force, drive=x, normal_load=4e-3, amplitudes=(1e-8,))
    >>> fit = friction.fit_dahl(loops)
    >>> f"{float(fit.law.sigma0):.4g} 1/m, mu {float(fit.law.mu):.4g}"
    '1e+08 1/m, mu 0.3'
    """
    x, y = _presliding(loops, reach)
    mu0 = float(np.max(np.abs(y)))
    k0 = mu0 / max(loops.breakaway_displacement(), 1e-30)

    def residual(p):
        return dahl_force(p[0], p[1], x) - y

    p, rms, rel = _fit(residual, [k0, mu0], ([1e-3 * k0, 1e-3 * mu0], [1e3 * k0, 1e2 * mu0]), y)
    return Fit(Dahl(*p), rms, rel, len(x))


def fit_lugre(loops, stribeck: Stribeck, *, reach: float = 2.0) -> Fit:
    """LuGre law: sigma0 fitted to the loops, g(v) from ``stribeck`` (delta -> 2), sigma1 = 0.

    Parameters
    ----------
    loops : ReversalLoops
        The tribometer's pre-sliding loops from rest (:func:`asperity2d.experiments.tribometer.reversal_loops`).
    stribeck : Stribeck
        A fitted Stribeck law (:func:`fit_stribeck`).
    reach : float, default 2.0
        Strokes up to this multiple of the breakaway displacement are used.

    Returns
    -------
    Fit
        The law (per unit normal load), its RMS residual, relative RMS and point count.

    Examples
    --------
    One stroke from rest made from a Dahl law (sigma0 1e8 1/m, mu 0.3): along it F/N = mu (1 -
    exp(-sigma0 x / mu)).

    >>> import numpy as np
    >>> from asperity2d import friction
    >>> from asperity2d.experiments.tribometer import ReversalLoops
    >>> x = np.linspace(0.0, 1e-8, 200)  # m
    >>> force = 4e-3 * 0.3 * (1 - np.exp(-1e8 * x / 0.3))  # N, under a 4 mN load
    >>> loops = ReversalLoops(x, force, drive=x, normal_load=4e-3, amplitudes=(1e-8,))
    >>> stribeck = friction.Stribeck(mu_s=0.3, mu_k=0.2, v_s=1.0, delta=2.0, sigma2=1e-3)
    >>> fit = friction.fit_lugre(loops, stribeck)
    >>> f"{float(fit.law.sigma0):.4g} 1/m"
    '1e+08 1/m'
    """
    x, y = _presliding(loops, reach)
    mu_s = stribeck.mu_s  # quasi-static loops: g(v) ~ mu_s at the reversal speed

    def residual(p):
        return dahl_force(p[0], mu_s, x) - y

    k0 = mu_s / max(loops.breakaway_displacement(), 1e-30)
    p, rms, rel = _fit(residual, [k0], ([1e-3 * k0], [1e3 * k0]), y)
    law = LuGre(float(p[0]), 0.0, stribeck.sigma2, stribeck.mu_s, max(stribeck.mu_k, 1e-12), stribeck.v_s)
    return Fit(law, rms, rel, len(x))


def stick_slip_cycles(result, *, skip: int = 1) -> dict:
    """Per-cycle forces (N) and period (s) of a spring-driven asperity run.

    Uses the complete events of :func:`asperity2d.stick_slip_events` after
    the first ``skip`` (the first slip starts from rest, not from a re-stick).
    Returns ``breakaway_N`` (drive force at each stick-to-slip transition),
    ``restick_N`` (drive force when that cycle's stick began), the periods
    (s, breakaway to breakaway), their mean ``period_s``, and ``normal_load_N``.

    Parameters
    ----------
    result : Result
        A spring-driven asperity run (:func:`asperity2d.simulate`).
    skip : int, default 1
        Complete events left out at the start.

    Returns
    -------
    dict
        The arrays and values named above.

    Raises
    ------
    SceneError
        Fewer than 2 complete cycles after ``skip``.

    Examples
    --------
    A spring-driven run of the tribometer's asperities (Table 1 steel) on a soft spring:

    >>> import asperity2d as a
    >>> from asperity2d import friction
    >>> from asperity2d.experiments.tribometer import make_tribometer_scene
    >>> run = a.simulate(make_tribometer_scene(drive_stiffness=1000.0, drive_velocity=10.0, lower_count=8))
    >>> cycles = friction.stick_slip_cycles(run)
    >>> len(cycles["breakaway_N"]), f"{cycles['period_s'] * 1e9:.0f} ns"
    (2, '250 ns')
    """
    from ..analysis import stick_slip_events

    events = [e for e in stick_slip_events(result) if e.complete][skip:]
    if len(events) < 2:
        raise SceneError(f"`result` has {len(events)} complete stick-slip cycles after the first {skip}; "
                         "at least 2 are needed (run longer or on more lower asperities)")
    t = np.asarray(result.t)
    restick = np.interp([e.t_stick for e in events], t, np.asarray(result.drive_force))
    periods = np.diff([e.t_slip for e in events])
    return {"breakaway_N": np.array([e.force_peak for e in events]), "restick_N": restick,
            "periods_s": periods, "period_s": float(np.mean(periods)),
            "normal_load_N": float(result.scene.slider.normal_load)}


def fit_stick_slip(result, *, skip: int = 1) -> Fit:
    """Static/kinetic law (per unit load) from the stick-slip cycles of ``result``.

    ``result`` is one spring-driven run or a sequence of them (same normal
    load), e.g. several seeds of a random surface: their cycles are pooled,
    so the law describes the surface's statistics, not one realisation.

    mu_s = mean breakaway force / load; mu_k = mu_s - mean(breakaway -
    re-stick) / (2 load): an undamped Coulomb oscillator on the same spring
    re-sticks at 2 F_k - F_s, so this law has the measured force drop, hence
    the measured stick time. The residuals are the RMS over cycles of the
    breakaway and half-drop deviations from the law (per unit load).

    Parameters
    ----------
    result : Result or sequence of Result
        Spring-driven asperity runs (one normal load).
    skip : int, default 1
        Complete events left out at the start of each run.

    Returns
    -------
    Fit
        A static/kinetic law (:class:`asperity2d.friction.StaticKinetic`) and its residuals.

    Examples
    --------
    A spring-driven run of the tribometer's asperities (Table 1 steel) on a soft spring:

    >>> import asperity2d as a
    >>> from asperity2d import friction
    >>> from asperity2d.experiments.tribometer import make_tribometer_scene
    >>> run = a.simulate(make_tribometer_scene(drive_stiffness=1000.0, drive_velocity=10.0, lower_count=8))
    >>> fit = friction.fit_stick_slip(run)
    >>> round(fit.law.mu_s, 2), round(fit.law.mu_k, 2), fit.points
    (1.86, 1.25, 2)
    """
    runs = [result] if hasattr(result, "drive_force") else list(result)
    if not runs:
        raise SceneError("`result` must be a run or a non-empty sequence of runs")
    cycles = [stick_slip_cycles(r, skip=skip) for r in runs]
    loads = {c["normal_load_N"] for c in cycles}
    if len(loads) > 1:
        raise SceneError(f"`result` runs must share one normal load, got {sorted(loads)}")
    load = loads.pop()
    breakaway = np.concatenate([c["breakaway_N"] for c in cycles])
    restick = np.concatenate([c["restick_N"] for c in cycles])
    peak = breakaway / load
    half_drop = (breakaway - restick) / (2.0 * load)
    mu_s = float(np.mean(peak))
    mu_k = mu_s - float(np.mean(half_drop))
    r = np.concatenate([peak - mu_s, half_drop - (mu_s - mu_k)])
    rms = float(np.sqrt(np.mean(r**2)))
    scale = float(np.sqrt(np.mean(np.concatenate([peak, half_drop]) ** 2)))
    return Fit(StaticKinetic(mu_s, min(max(mu_k, 0.0), mu_s)), rms, rms / scale, len(peak))

