"""The stick-slip period of one mass on a spring over a belt, with any friction law.

How a fitted law is judged (:mod:`asperity2d.friction.fits`, the tribometer scenes): run it in
the belt solver and compare the period with the asperity run's. The belt frame of a
spring-driven slider has the same relative velocity, so the periods are equal.
"""

from __future__ import annotations

import math

import numpy as np

from ..friction.laws import FrictionLaw
from .solver import simulate_chain


def belt_period(law: FrictionLaw, *, mass: float, stiffness: float, velocity: float,
                normal_load: float, cycles: int = 6) -> dict:
    """Stick-slip period (s) of one mass on a spring (N/m) over a belt at ``velocity`` (m/s).

    The belt frame of a spring-driven slider: the relative velocity is the
    same, so the periods are equal. Uses ``asperity2d.belt.simulate_chain``
    with ``friction=law`` (its exact event-driven solver for piecewise-
    constant laws, an ODE with the same stick logic otherwise).

    Parameters
    ----------
    law : FrictionLaw
        The friction law (:mod:`asperity2d.friction`).
    mass, stiffness, velocity, normal_load : float
        kg, N/m, m/s, N.
    cycles : int, optional
        Stick-slip cycles to average over (default 6).

    Returns
    -------
    dict
        ``period_s`` (NaN if fewer than two whole cycles), ``cycles`` (counted) and
        ``force_drop_N`` (the spring force lost in a slip).

    Examples
    --------
    The force drop of a static/kinetic law is Den Hartog's 2 (mu_s - mu_k) N = 1.962 N:

    >>> from asperity2d import belt
    >>> from asperity2d.friction import StaticKinetic
    >>> p = belt.belt_period(StaticKinetic(0.4, 0.3), mass=1.0, stiffness=100.0, velocity=0.1,
    ...                      normal_load=9.81)
    >>> round(p["period_s"], 4), round(p["force_drop_N"], 4)
    (0.6694, 1.962)
    """
    f_s = law.static_coefficient * normal_load
    t_est = 2.0 * f_s / (stiffness * velocity) + 2 * math.pi * math.sqrt(mass / stiffness)
    t_end = (cycles + 2) * t_est
    res = simulate_chain([mass], [stiffness, 0.0], [0.0, 0.0], friction=law, normal_load=[normal_load],
                         v_belt=velocity, x0=[0.0], v0=[velocity], t_end=t_end, n_samples=4001)
    # a stick interval still open at t_end was not ended by a breakaway; the
    # first starts from rest
    intervals = [(a, b) for a, b in res.stick_intervals[0] if b < t_end * (1 - 1e-9)]
    if len(intervals) < 3:
        return {"period_s": math.nan, "cycles": max(len(intervals) - 1, 0), "force_drop_N": math.nan}
    ends = np.array([b for _, b in intervals[1:]])
    sticks = np.array([b - a for a, b in intervals[1:]])
    # stuck, the mass moves with the belt: the spring force rises k V per second
    return {"period_s": float(np.mean(np.diff(ends))), "cycles": int(len(ends) - 1),
            "force_drop_N": float(stiffness * velocity * np.mean(sticks))}
