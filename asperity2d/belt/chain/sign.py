"""The multi-DOF belt thesis' method: raw sign() friction through an adaptive ODE solver.

The multi-DOF belt thesis integrates f_i = -mu0·m_i·g·sign(v_i - v_belt) with MATLAB's
``ode113`` (default AbsTol 1e-6, used here when ``atol`` is None). Here the same right-hand side goes through ``solve_ivp``
(LSODA by default, DOP853 also accepted). sign(0) = 0 as in MATLAB. There is
no static friction: the stick phase is represented by the solver chattering
about v = v_belt, which costs many tiny steps and never holds the velocity
exactly at belt speed -- compare with ``method="exact"``. With a
static/kinetic law only ``mu_k`` is used (sign() has one coefficient).
Every right-hand-side evaluation counts against ``max_steps``.
"""

from __future__ import annotations

import numpy as np

from ...errors import SimulationError
from ..backend import RawRun, StepBudget, intervals_from_state

#: samples within this fraction of the velocity scale of belt speed count as "stuck"
STICK_BAND = 1e-3


def run_sign(spec, options) -> RawRun:
    """Integrate the sign() model; samples within ``STICK_BAND`` of belt speed are marked stuck."""
    from scipy.integrate import solve_ivp  # lazily: keeps `import asperity2d.belt` free of SciPy

    n, law = spec.n, spec.law
    budget = StepBudget(options)
    normal = spec.normal
    mu = law.kinetic_coefficient if law.piecewise_constant else None

    def friction(vr):
        if mu is not None:
            return -mu * normal.reshape((-1,) + (1,) * (np.ndim(vr) - 1)) * np.sign(vr)
        return law.force(vr, normal.reshape((-1,) + (1,) * (np.ndim(vr) - 1)))

    K, C, minv, c = spec.stiffness_matrix(), spec.damping_matrix(), 1.0 / spec.m, spec.c
    const_v = None if callable(spec.v_belt) else float(spec.v_belt)
    out = np.empty(2 * n + 3)
    pad = np.zeros(n + 2)

    def rhs(t, y):  # lean: this is called millions of times while the solver chatters
        budget.spend(t)
        x, v = y[:n], y[n : 2 * n]
        V = const_v if const_v is not None else spec.belt_velocity(t)
        fric = friction(v - V)
        out[:n] = v
        out[n : 2 * n] = (fric - K @ x - C @ v) * minv
        pad[1:-1] = v
        dv = np.diff(pad)
        out[2 * n] = fric.sum() * V
        out[2 * n + 1] = fric @ (V - v)
        out[2 * n + 2] = c @ (dv * dv)
        return out.copy()

    y0 = np.concatenate([spec.x0, spec.v0, np.zeros(3)])
    atol_ = 1e-6 if options.atol is None else options.atol  # MATLAB ode113's default AbsTol
    sol = solve_ivp(rhs, (0.0, spec.t_end), y0, method=options.integrator, t_eval=options.samples, rtol=options.rtol,
                    atol=np.concatenate([np.full(2 * n, atol_), np.full(3, atol_ * 1e3)]))
    if not sol.success:
        raise SimulationError(f"sign() integration failed: {sol.message}", time=float(sol.t[-1]))
    x, v = sol.y[:n], sol.y[n : 2 * n]
    V = spec.belt_velocity(sol.t)
    vr = v - V[None, :]
    band = STICK_BAND * spec.velocity_scale
    near = np.where(np.abs(vr) <= band, 0, np.sign(vr)).astype(int)
    return RawRun(
        t=sol.t, x=x, v=v, state=np.sign(vr).astype(int), friction_force=friction(vr), work=sol.y[2 * n :],
        events=[], stick_intervals=intervals_from_state(sol.t, near),
        meta={"n_events": 0, "nfev": int(sol.nfev), "stick_band": band, "mu_used": mu,
              "note": "sign() mode: state is sign(v - v_belt); stick_intervals are samples within stick_band"})
