"""``simulate_chain``: masses on a moving belt with exact stick/slip switching.

The event loop alternates phases (closed form from :mod:`.linear` for a
constant belt speed and piecewise-constant friction, an integrator from
:mod:`.hybrid` otherwise) with switching instants located by
:mod:`.events`. Samples, event states and the energy integrals are taken
from each phase before it is discarded:

* belt work      W_b = ∫ Σ F_i·V dt       (power the belt delivers through the contacts, J)
* friction loss  D_f = ∫ Σ F_i·(V - v_i) dt  (>= 0; zero on stuck masses, J)
* damper loss    D_c = ∫ Σ c_j·(Δv_j)² dt  (J)
* stored energy  E = Σ ½ m v² + Σ ½ k Δx²  so that E - E(0) = W_b - D_f - D_c.

The integrals use Gauss-Legendre quadrature on pieces shorter than 1/16 of
the fastest period, which is exact to rounding for these entire functions.
"""

from __future__ import annotations

import time as _time

import numpy as np

from ..errors import SceneError, SimulationError
from .events import EventFunctions, event_rows, find_event, resolve_modes
from .linear import LinearPhase
from .result import BeltResult, Event, assemble
from .spec import ChainSpec

_GL_X, _GL_W = np.polynomial.legendre.leggauss(10)


def simulate_chain(
    masses,
    springs,
    dampers,
    *,
    mu_s=None,
    mu_k=None,
    v_belt,
    x0,
    v0,
    t_end,
    g=9.81,
    normal_load=None,
    friction=None,
    method="exact",
    n_samples=2001,
    t_eval=None,
    include_events=True,
    rtol=1e-8,
    atol=None,
    integrator="LSODA",
    max_events=1_000_000,
) -> BeltResult:
    """Simulate n masses (kg) on a belt at ``v_belt`` (m/s, or a callable of t) for ``t_end`` s.

    ``springs`` (N/m) and ``dampers`` (N·s/m) have n+1 entries: wall-m1,
    m1-m2, ..., mn-wall (0 removes a link). ``mu_s`` / ``mu_k`` are the static
    and kinetic coefficients (``mu_k`` defaults to ``mu_s``); ``friction`` a
    law from :mod:`asperity2d.friction` replaces them. The normal load per mass
    is ``normal_load`` (N) or m·g.

    ``method="exact"``: event-driven non-smooth integration -- closed-form
    phases for a constant belt speed with Coulomb / static-kinetic friction,
    ``solve_ivp`` (``integrator``, ``rtol``) phases with the same stick logic
    otherwise, a smooth stiff ODE for Dahl / LuGre. ``method="sign"``: the
    thesis' raw sign() friction through an adaptive solver (chatter included).

    Output is sampled at ``t_eval`` (s) or ``n_samples`` uniform times, plus
    every event time when ``include_events``.
    """
    if friction is None and mu_s is None:
        raise SceneError("`mu_s` is required unless `friction` is given")
    spec = ChainSpec(masses, springs, dampers, 0.0 if mu_s is None else mu_s, mu_k, v_belt,
                     x0, v0, t_end, g, normal_load, friction)
    samples = _sample_times(spec.t_end, n_samples, t_eval)
    for name, val in (("rtol", rtol), ("max_events", max_events)):
        if not np.isfinite(val) or val <= 0:
            raise SceneError(f"`{name}` must be > 0, got {val!r}")
    if integrator not in ("LSODA", "Radau", "BDF", "DOP853", "RK45"):
        raise SceneError(f"`integrator` must be LSODA, Radau, BDF, DOP853 or RK45, got {integrator!r}")
    clock = _time.perf_counter()
    if method == "sign":
        from .sign import run_sign

        out = run_sign(spec, samples, rtol=rtol, atol=atol, integrator=integrator)
    elif method == "exact":
        if spec.law.has_state:
            from .hybrid import run_state_law

            out = run_state_law(spec, samples, rtol=rtol, atol=atol, integrator=integrator)
        elif spec.constant_belt and spec.law.piecewise_constant:
            cache: dict = {}
            out = event_loop(spec, samples, lambda *a, t0: LinearPhase(*a, cache=cache), include_events, max_events)
        else:
            from .hybrid import make_ode_phase

            factory = make_ode_phase(spec, rtol=rtol, atol=atol, integrator=integrator)
            out = event_loop(spec, samples, factory, include_events, max_events)
    else:
        raise SceneError(f"`method` must be 'exact' or 'sign', got {method!r}")
    out["meta"].update(method=method, wall_time=_time.perf_counter() - clock, rtol=rtol, integrator=integrator)
    return assemble(spec, out)


def _sample_times(t_end, n_samples, t_eval):
    if t_eval is not None:
        t = np.asarray(t_eval, dtype=float)
        if t.ndim != 1 or t.size == 0 or not np.all(np.isfinite(t)):
            raise SceneError("`t_eval` must be a non-empty 1-D array of finite times")
        if np.any(np.diff(t) <= 0) or t[0] < 0 or t[-1] > t_end:
            raise SceneError(f"`t_eval` must increase strictly within [0, t_end={t_end}]")
        return t
    if isinstance(n_samples, bool) or not isinstance(n_samples, (int, np.integer)) or n_samples < 2:
        raise SceneError(f"`n_samples` must be an integer >= 2, got {n_samples!r}")
    return np.linspace(0.0, t_end, int(n_samples))


def velocity_scale(spec) -> float:
    """A velocity (m/s) that normalises the slip event functions."""
    V = spec.belt_velocity(0.0)
    omega = np.sqrt(np.max(spec.k[:-1] + spec.k[1:]) / np.min(spec.m)) if spec.k.any() else 1.0
    swing = np.max(spec.law.static_coefficient * spec.normal / spec.m) / max(omega, 1e-300)
    return float(max(abs(V), np.max(np.abs(spec.v0)), swing, 1e-12))


def event_loop(spec: ChainSpec, samples, make_phase, include_events=True, max_events=1_000_000) -> dict:
    """Run phases and switches from t = 0 to ``spec.t_end``; return raw arrays for :func:`assemble`."""
    n = spec.n
    v_scale = velocity_scale(spec)
    x = np.array(spec.x0)
    V0 = spec.belt_velocity(0.0)
    modes, v = resolve_modes(spec, x, np.array(spec.v0), V0, spec.belt_acceleration(0.0),
                             np.sign(np.array(spec.v0) - V0).astype(int), v_scale)
    t = 0.0
    rec = {key: [] for key in ("t", "x", "v", "state", "friction", "work")}
    work = np.zeros(3)
    events: list[Event] = []
    stick_start = [0.0 if modes[i] == 0 else None for i in range(n)]
    intervals: list[list] = [[] for _ in range(n)]
    next_sample = 0
    opened_by_event = False
    zero_steps = 0
    while True:
        phase = make_phase(spec, modes, x, v, spec.belt_velocity(t), t0=t)
        funcs = EventFunctions(phase, event_rows(spec, modes), v_scale)
        horizon = spec.t_end - t
        tau_e = find_event(funcs, horizon, phase.step) if horizon > 0 else None
        t1 = spec.t_end if tau_e is None else t + tau_e
        # samples in [t, t1) (and t_end itself in the last phase)
        stop = np.searchsorted(samples, t1, side="right" if tau_e is None else "left")
        taus = list(samples[next_sample:stop] - t)
        next_sample = stop
        if opened_by_event and include_events and (not taus or taus[0] > 0):
            taus.insert(0, 0.0)
        work = _record(phase, np.asarray(taus), t, tau_e if tau_e is not None else horizon, work, rec)
        if tau_e is None:
            break
        zero_steps = zero_steps + 1 if tau_e == 0 else 0
        if zero_steps > 8 or len(events) >= max_events:
            raise SimulationError(
                f"switching did not progress at t = {t1:.17g} s (events: {len(events)}); "
                "hint: check for a degenerate chain or raise `max_events`", time=t1)
        x, v, _ = phase.evaluate(np.array([tau_e]))
        x, v = x[:, 0], v[:, 0]
        t = t1
        new, v = resolve_modes(spec, x, v, spec.belt_velocity(t), spec.belt_acceleration(t), modes, v_scale)
        for i in np.flatnonzero(new != modes):
            kind = "stick" if new[i] == 0 else ("slip" if modes[i] == 0 else "reverse")
            events.append(Event(t=t, mass=int(i), kind=kind, x=float(x[i])))
            if new[i] == 0:
                stick_start[i] = t
            elif modes[i] == 0:
                intervals[i].append((stick_start[i], t))
                stick_start[i] = None
        modes = new
        opened_by_event = True
    for i in range(n):
        if stick_start[i] is not None:
            intervals[i].append((stick_start[i], spec.t_end))
    return {
        "t": np.concatenate(rec["t"]),
        "x": np.concatenate(rec["x"], axis=1),
        "v": np.concatenate(rec["v"], axis=1),
        "state": np.concatenate(rec["state"], axis=1),
        "friction_force": np.concatenate(rec["friction"], axis=1),
        "work": np.concatenate(rec["work"], axis=1),
        "events": events,
        "stick_intervals": intervals,
        "meta": {"n_events": len(events), "v_scale": v_scale},
    }


def _record(phase, taus, t0, length, work, rec):
    """Append samples at ``taus`` and integrate the energy flows over [0, length]; return work at the end."""
    spec = phase.spec
    marks = np.concatenate([[0.0], taus, [length]])
    gaps = np.diff(marks)
    pieces = np.maximum(1, np.ceil(gaps / phase.step).astype(int)) if np.isfinite(phase.step) else np.ones_like(gaps, dtype=int)
    pieces[gaps <= 0] = 0
    starts = np.repeat(marks[:-1], pieces)
    widths = np.repeat(np.where(pieces > 0, gaps / np.maximum(pieces, 1), 0.0), pieces)
    nodes = (starts[:, None] + 0.5 * widths[:, None] * (_GL_X[None, :] + 1)).ravel()
    eval_t = np.concatenate([taus, nodes])
    x, v, a = phase.evaluate(eval_t)
    V = phase.belt_velocity(eval_t)
    fric = phase.friction_force(x, v, a, eval_t)
    dv = np.diff(np.concatenate([np.zeros((1, eval_t.size)), v, np.zeros((1, eval_t.size))]), axis=0)
    power = np.vstack([
        (fric * V[None, :]).sum(axis=0),
        (fric * (V[None, :] - v)).sum(axis=0),
        (spec.c[:, None] * dv**2).sum(axis=0),
    ])
    m = taus.size
    piece_int = (power[:, m:].reshape(3, -1, _GL_X.size) * _GL_W).sum(axis=2) * 0.5 * widths
    cum = np.column_stack([np.zeros(3), np.cumsum(piece_int, axis=1)])
    at_marks = np.column_stack([np.zeros(3), cum[:, np.cumsum(pieces)]])  # integral up to each mark
    work_marks = work[:, None] + at_marks
    if m:
        rec["t"].append(t0 + taus)
        rec["x"].append(x[:, :m])
        rec["v"].append(v[:, :m])
        state = np.repeat(phase.modes[:, None], m, axis=1)
        rec["state"].append(state)
        rec["friction"].append(fric[:, :m])
        rec["work"].append(work_marks[:, 1 : m + 1])
    return work_marks[:, -1]
