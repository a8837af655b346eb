"""Integrator-based phases: ramped belt speeds, velocity-dependent and state-variable laws.

When the motion between events is not linear with constant forcing (a belt
speed v_belt(t), a Stribeck or viscous slip force), the phases are
integrated with ``scipy.integrate.solve_ivp`` (stiff-capable LSODA / Radau by
default) under the *same* stick logic as the closed-form solver: stuck
masses move exactly with the belt (v = v_belt(t)), switches are located with
the same event functions on the dense output. Dahl and LuGre laws are
continuous through zero velocity and need no stick logic: their chains are
one smooth ODE with the bristle deflections z_i as extra states.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from ..errors import SimulationError
from .spec import link_force


def _fastest_rate(spec) -> float:
    n = spec.n
    A = np.zeros((2 * n, 2 * n))
    A[:n, n:] = np.eye(n)
    A[n:, :n] = -spec.stiffness_matrix() / spec.m[:, None]
    A[n:, n:] = -spec.damping_matrix() / spec.m[:, None]
    return float(max(np.max(np.abs(np.linalg.eigvals(A))), 1e-12))


def _scales(spec) -> tuple[float, float]:
    """(length m, velocity m/s) scales of the chain's motion, for absolute tolerances.

    The velocity scale is the slip-event scale of the exact solver (belt
    speed, initial speeds, the speed swing of a static-friction release);
    the length scale is that speed over the fastest natural frequency (at
    least the static deflection F_s / k) or the initial offsets. Separate
    scales matter at the micro scale, where positions are 1e-6 m and speeds
    10 m/s: one shared absolute tolerance is then coarser than the motion.
    """
    from .solver import velocity_scale

    v_scale = velocity_scale(spec)
    omega = np.sqrt(np.max(spec.k[:-1] + spec.k[1:]) / np.min(spec.m)) if spec.k.any() else 1.0
    length = max(float(np.max(np.abs(spec.x0))), v_scale / max(omega, 1e-300))
    return length, v_scale


def _atol(spec, rtol, atol):
    """Absolute tolerance for the state ``[x, v]``: given, or 1e-2 rtol of each part's scale."""
    if atol is not None:
        return atol
    length, speed = _scales(spec)
    n = spec.n
    return rtol * 1e-2 * np.concatenate([np.full(n, length), np.full(n, speed)])


def make_ode_phase(spec, *, rtol, atol, integrator):
    """Phase factory for :func:`asperity2d.belt.solver.event_loop`."""
    step = 0.4 / _fastest_rate(spec)
    atol = _atol(spec, rtol, atol)

    def factory(spec_, modes, x, v, V, *, t0):
        return OdePhase(spec, modes, x, v, t0, step, rtol, atol, integrator)

    return factory


class OdePhase:
    """One phase integrated numerically; evaluate(tau) extends the integration on demand."""

    def __init__(self, spec, modes, x, v, t0, step, rtol, atol, integrator):
        self.spec, self.t0, self.step = spec, t0, step
        self.modes = np.asarray(modes)
        self.stuck = self.modes == 0
        self.rtol, self.atol, self.integrator = rtol, atol, integrator
        self.chunks = []  # (t_start, t_stop, dense solution)
        self.y_end = np.concatenate([x, v])
        self.t_reached = t0

    def _slip_force(self, v_rel):
        """Kinetic friction on slipping masses (N), sign held by the phase's mode."""
        s = self.modes[:, None] if np.ndim(v_rel) == 2 else self.modes
        vr = np.where(s * v_rel > 0, v_rel, s * 1e-300)
        normal = self.spec.normal[:, None] if np.ndim(v_rel) == 2 else self.spec.normal
        return self.spec.law.force(vr, normal)

    def _rhs(self, t, y):
        spec, n = self.spec, self.spec.n
        x, v = y[:n], y[n:].copy()
        V = spec.belt_velocity(t)
        v[self.stuck] = V
        a = (link_force(spec.k, x) + link_force(spec.c, v) + self._slip_force(v - V)) / spec.m
        a[self.stuck] = spec.belt_acceleration(t)
        return np.concatenate([v, a])

    def _extend(self, t_target):
        while self.t_reached < t_target:
            t_stop = min(self.spec.t_end, max(t_target, self.t_reached + 64 * self.step))
            sol = solve_ivp(self._rhs, (self.t_reached, t_stop), self.y_end, method=self.integrator,
                            rtol=self.rtol, atol=self.atol, dense_output=True)
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
        tau = np.atleast_1d(np.asarray(tau, dtype=float))
        t = self.t0 + tau
        if t.size:
            self._extend(t.max())
        n = self.spec.n
        y = np.empty((2 * n, t.size))
        starts = np.array([c[0] for c in self.chunks])
        which = np.clip(np.searchsorted(starts, t, side="right") - 1, 0, max(len(starts) - 1, 0))
        for j in np.unique(which):
            sel = which == j
            y[:, sel] = self.chunks[j][2](t[sel]) if self.chunks else self.y_end[:, None]
        x, v = y[:n], y[n:]
        V = self.belt_velocity(tau)
        v[self.stuck] = V[None, :]
        spec = self.spec
        a = (link_force(spec.k, x) + link_force(spec.c, v) + self._slip_force(v - V[None, :])) / spec.m[:, None]
        a[self.stuck] = self.belt_acceleration(tau)[None, :]
        return x, v, a

    def friction_force(self, x, v, a, tau):
        spec = self.spec
        V = self.belt_velocity(tau)
        f = self._slip_force(v - V[None, :])
        f_req = spec.m[:, None] * a - (link_force(spec.k, x) + link_force(spec.c, v))
        f[self.stuck] = f_req[self.stuck]
        return f


def intervals_from_state(t, state):
    """Stick intervals (t_start, t_end) per mass from a sampled state array (0 = stuck)."""
    out = []
    for row in state:
        stuck = np.concatenate([[False], row == 0, [False]])
        edges = np.flatnonzero(np.diff(stuck.astype(int)))
        out.append([(float(t[a]), float(t[b - 1])) for a, b in zip(edges[::2], edges[1::2]) if b - 1 > a])
    return out


def run_state_law(spec, samples, *, rtol, atol, integrator):
    """Dahl / LuGre chains: one smooth stiff ODE in (x, v, z) plus the energy accumulators."""
    n, law = spec.n, spec.law
    normal = spec.normal

    def rhs(t, y):
        x, v, z = y[:n], y[n : 2 * n], y[2 * n : 3 * n]
        V = spec.belt_velocity(t)
        vr = v - V
        fric = law.state_force(z, vr, normal)
        a = (link_force(spec.k, x) + link_force(spec.c, v) + fric) / spec.m
        dv = np.diff(np.concatenate([[0.0], v, [0.0]]))
        power = [np.sum(fric * V), np.sum(fric * (V - v)), np.sum(spec.c * dv**2)]
        return np.concatenate([v, a, law.state_derivative(z, vr), power])

    y0 = np.concatenate([spec.x0, spec.v0, np.zeros(n), np.zeros(3)])
    method = integrator if integrator in ("Radau", "BDF", "LSODA") else "Radau"
    if atol is None:
        # x and v from their scales, the bristle deflections z at the length
        # scale, the three work accumulators at force scale x length scale
        length, _ = _scales(spec)
        work = float(np.max(law.static_coefficient * normal)) * length
        atol = np.concatenate([_atol(spec, rtol, None), np.full(n, rtol * 1e-2 * length),
                               np.full(3, rtol * 1e-2 * work)]) * 1e-3
    sol = solve_ivp(rhs, (0.0, spec.t_end), y0, method=method, t_eval=samples, rtol=rtol, atol=atol)
    if not sol.success:
        raise SimulationError(f"integrator failed: {sol.message}", time=float(sol.t[-1]))
    x, v, z = sol.y[:n], sol.y[n : 2 * n], sol.y[2 * n : 3 * n]
    V = spec.belt_velocity(sol.t)
    from .solver import velocity_scale

    vr = v - V[None, :]
    state = np.where(np.abs(vr) <= 1e-6 * velocity_scale(spec), 0, np.sign(vr)).astype(int)
    return {
        "t": sol.t, "x": x, "v": v, "state": state,
        "friction_force": law.state_force(z, vr, normal[:, None]),
        "work": sol.y[3 * n :], "events": [],
        "stick_intervals": intervals_from_state(sol.t, state),
        "meta": {"n_events": 0, "nfev": int(sol.nfev), "bristle_z_end": z[:, -1].tolist(),
                 "stick_note": "state 0 where |v - v_belt| <= 1e-6 * velocity scale (smooth law)"},
    }
