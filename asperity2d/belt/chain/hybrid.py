"""Integrator-based back-ends: ramped belt speeds, velocity-dependent and state-variable laws.

When the motion between switches is not linear with constant forcing (a belt
speed v_belt(t), a Stribeck or viscous slip force), the phases are integrated
with ``scipy.integrate.solve_ivp`` (stiff-capable LSODA / Radau by default)
under the *same* stick logic as the closed-form solver: stuck masses move
exactly with the belt (v = v_belt(t)), switches are located with the same
event functions on the dense output. Dahl and LuGre laws are continuous
through zero velocity and need no stick logic: their chains are one smooth
ODE with the bristle deflections z_i as extra states.

Absolute tolerances come from the chain's scales: ``rtol``·1e-2 of
``spec.length_scale`` for positions and of ``spec.velocity_scale`` for
velocities. Separate scales matter at the micro scale, where positions are
1e-6 m and speeds 10 m/s: one shared absolute tolerance is then coarser than
the motion. The belt work and the friction and damper losses are integrated
with the motion as three extra states (the energy books then close to the
integrator's tolerance whatever the sampling). Every right-hand-side
evaluation counts against ``max_steps``.
"""

from __future__ import annotations

import math

import numpy as np

from ...errors import SimulationError
from ..backend import RawRun, StepBudget, intervals_from_state
from .loop import event_loop
from ..spec import link_force


def _atol(spec, rtol, atol):
    """Absolute tolerance for ``[x, v]``: given, or 1e-2 rtol of each part's scale."""
    if atol is not None:
        return np.full(2 * spec.n, atol)
    n = spec.n
    return rtol * 1e-2 * np.concatenate([np.full(n, spec.length_scale), np.full(n, spec.velocity_scale)])


def _work_atol(spec, rtol):
    """Absolute tolerance (J) of the three work integrals: 1e-2 rtol of the chain's energy scale (> 0)."""
    return np.full(3, rtol * 1e-2 * spec.energy_scale)


def run_ode_phases(spec, options) -> RawRun:
    """Event-driven run whose phases are integrated (ramped belt, smooth slip laws)."""
    rate = spec.fastest_rate
    step = 2 * math.pi / (16 * rate) if rate > 0 else spec.t_end
    atol = np.concatenate([_atol(spec, options.rtol, options.atol), _work_atol(spec, options.rtol)])
    budget = StepBudget(options)

    def make_phase(modes, x, v, t):
        return OdePhase(spec, modes, x, v, t, step, options, atol, budget)

    return event_loop(spec, options, make_phase)


class OdePhase:
    """One phase integrated numerically; evaluate(tau) extends the integration on demand."""

    motion = None  # no closed form: event functions are sampled

    def __init__(self, spec, modes, x, v, t0, step, options, atol, budget):
        self.spec, self.t0, self.step = spec, t0, step
        self.modes = np.asarray(modes)
        self.stuck = self.modes == 0
        self.options, self.atol, self.budget = options, atol, budget
        self.chunks = []  # (t_start, t_stop, dense solution)
        self.y_end = np.concatenate([x, v, np.zeros(3)])  # state and the work integrals since t0
        self.t_reached = t0

    def _slip_force(self, v_rel):
        """Kinetic friction on slipping masses (N), sign held by the phase's mode."""
        s = self.modes[:, None] if np.ndim(v_rel) == 2 else self.modes
        vr = np.where(s * v_rel > 0, v_rel, s * 1e-300)
        normal = self.spec.normal[:, None] if np.ndim(v_rel) == 2 else self.spec.normal
        return self.spec.law.force(vr, normal)

    def _rhs(self, t, y):
        """d/dt of [x, v, belt work, friction loss, damper loss] (the powers integrated alongside)."""
        self.budget.spend(t)
        spec, n = self.spec, self.spec.n
        x, v = y[:n], y[n : 2 * n].copy()
        V, a_belt = spec.belt_velocity(t), spec.belt_acceleration(t)
        v[self.stuck] = V
        f_sd = link_force(spec.k, x) + link_force(spec.c, v)
        fric = self._slip_force(v - V)
        fric[self.stuck] = spec.m[self.stuck] * a_belt - f_sd[self.stuck]  # the static force that holds them
        a = (f_sd + fric) / spec.m
        dv = np.diff(v, prepend=0.0, append=0.0)
        power = [V * fric.sum(), fric @ (V - v), spec.c @ (dv * dv)]
        return np.concatenate([v, a, power])

    def _extend(self, t_target):
        from scipy.integrate import solve_ivp  # lazily: keeps `import asperity2d.belt` free of SciPy

        opt = self.options
        while self.t_reached < t_target:
            t_stop = min(self.spec.t_end, max(t_target, self.t_reached + 64 * self.step))
            if t_stop - self.t_reached <= 64 * np.finfo(float).eps * abs(t_stop):
                # a few ulps short of the end: no step fits (solve_ivp needs increasing times);
                # the last dense output covers it
                self.t_reached = t_stop
                break
            sol = solve_ivp(self._rhs, (self.t_reached, t_stop), self.y_end, method=opt.integrator,
                            rtol=opt.rtol, atol=self.atol, dense_output=True)
            if not sol.success:
                raise SimulationError(f"integrator failed at t = {sol.t[-1]:.6g} s: {sol.message}", time=sol.t[-1])
            self.chunks.append((self.t_reached, t_stop, sol.sol))
            self.t_reached, self.y_end = t_stop, sol.y[:, -1]
            if t_stop >= self.spec.t_end:
                break

    def belt_velocity(self, tau):
        return np.atleast_1d(self.spec.belt_velocity(self.t0 + np.atleast_1d(tau)))

    def belt_acceleration(self, tau):
        return np.array([self.spec.belt_acceleration(self.t0 + s) for s in np.atleast_1d(tau)])

    def evaluate(self, tau):
        """Positions, velocities, accelerations (each (n, T)) at ``tau`` (s) after the phase start."""
        tau = np.atleast_1d(np.asarray(tau, dtype=float))
        t = self.t0 + tau
        if t.size:
            self._extend(t.max())
        y = self._dense(t)
        n = self.spec.n
        x, v = y[:n], y[n : 2 * n]
        V = self.belt_velocity(tau)
        v[self.stuck] = V[None, :]
        spec = self.spec
        a = (link_force(spec.k, x) + link_force(spec.c, v) + self._slip_force(v - V[None, :])) / spec.m[:, None]
        a[self.stuck] = self.belt_acceleration(tau)[None, :]
        return x, v, a

    def _dense(self, t):
        """Integrated state (2n + 3, T) at absolute times ``t`` (s)."""
        y = np.empty((self.y_end.size, t.size))
        starts = np.array([c[0] for c in self.chunks])
        which = np.clip(np.searchsorted(starts, t, side="right") - 1, 0, max(len(starts) - 1, 0))
        for j in np.unique(which):
            sel = which == j
            y[:, sel] = self.chunks[j][2](t[sel]) if self.chunks else self.y_end[:, None]
        return y

    def sample(self, tau):
        """Positions, velocities, friction forces (n, T) and work integrals (3, T, J) at ``tau`` (s).

        The work integrals are integrated with the motion (to the integrator's tolerance).
        """
        tau = np.asarray(tau, dtype=float)
        x, v, a = self.evaluate(tau)
        return x, v, self.friction_force(x, v, a, tau), self._dense(self.t0 + tau)[2 * self.spec.n :]

    def friction_force(self, x, v, a, tau):
        spec = self.spec
        V = self.belt_velocity(tau)
        f = self._slip_force(v - V[None, :])
        f_req = spec.m[:, None] * a - (link_force(spec.k, x) + link_force(spec.c, v))
        f[self.stuck] = f_req[self.stuck]
        return f


def run_state_law(spec, options) -> RawRun:
    """Dahl / LuGre chains: one smooth stiff ODE in (x, v, z) plus the energy accumulators."""
    from scipy.integrate import solve_ivp  # lazily: keeps `import asperity2d.belt` free of SciPy

    n, law, normal = spec.n, spec.law, spec.normal
    budget = StepBudget(options)

    def rhs(t, y):
        budget.spend(t)
        x, v, z = y[:n], y[n : 2 * n], y[2 * n : 3 * n]
        V = spec.belt_velocity(t)
        vr = v - V
        fric = law.state_force(z, vr, normal)
        a = (link_force(spec.k, x) + link_force(spec.c, v) + fric) / spec.m
        dv = np.diff(np.concatenate([[0.0], v, [0.0]]))
        power = [np.sum(fric * V), np.sum(fric * (V - v)), np.sum(spec.c * dv**2)]
        return np.concatenate([v, a, law.state_derivative(z, vr), power])

    y0 = np.concatenate([spec.x0, spec.v0, np.zeros(n), np.zeros(3)])
    method = options.integrator if options.integrator in ("Radau", "BDF", "LSODA") else "Radau"
    atol = options.atol
    if atol is None:
        # x and v from their scales, the bristle deflections z at the length
        # scale, the three work accumulators at force scale x length scale
        length = spec.length_scale
        work = float(np.max(spec.static_limit)) * length
        atol = np.concatenate([_atol(spec, options.rtol, None), np.full(n, options.rtol * 1e-2 * length),
                               np.full(3, options.rtol * 1e-2 * work)]) * 1e-3
    sol = solve_ivp(rhs, (0.0, spec.t_end), y0, method=method, t_eval=options.samples, rtol=options.rtol, atol=atol)
    if not sol.success:
        raise SimulationError(f"integrator failed: {sol.message}", time=float(sol.t[-1]))
    x, v, z = sol.y[:n], sol.y[n : 2 * n], sol.y[2 * n : 3 * n]
    vr = v - spec.belt_velocity(sol.t)[None, :]
    state = np.where(np.abs(vr) <= 1e-6 * spec.velocity_scale, 0, np.sign(vr)).astype(int)
    return RawRun(
        t=sol.t, x=x, v=v, state=state, friction_force=law.state_force(z, vr, normal[:, None]),
        work=sol.y[3 * n :], events=[], stick_intervals=intervals_from_state(sol.t, state),
        meta={"n_events": 0, "nfev": int(sol.nfev), "bristle_z_end": z[:, -1].tolist(),
              "stick_note": "state 0 where |v - v_belt| <= 1e-6 * velocity scale (smooth law)"})
