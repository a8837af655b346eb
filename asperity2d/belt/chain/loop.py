"""The event-driven loop shared by the closed-form and the integrated back-ends.

Phases (a :class:`~.chain.linear.LinearPhase` or an :class:`~.chain.hybrid.OdePhase`)
alternate with switching instants located by :func:`.phases.finder.find_event` and
resolved by :func:`.chain.modes.resolve_modes`. Samples, event states and the energy
integrals are taken from each phase before it is discarded:

* belt work      W_b = ∫ Σ F_i·V dt         (power the belt delivers through the contacts, J)
* friction loss  D_f = ∫ Σ F_i·(V - v_i) dt  (>= 0; zero on stuck masses, J)
* damper loss    D_c = ∫ Σ c_j·(Δv_j)² dt   (J)
* stored energy  E = Σ ½ m v² + Σ ½ k Δx²  so that E - E(0) = W_b - D_f - D_c.

(see :mod:`.chain.energy` for how each phase integrates them).
"""

from __future__ import annotations

import numpy as np

from ...errors import SimulationError
from ..backend import Event, RawRun
from ..phases.events import ModalEvents, SampledEvents
from ..phases.finder import find_event
from .modes import resolve_modes

def event_loop(spec, options, make_phase) -> RawRun:
    """Run phases and switches from t = 0 to ``spec.t_end``.

    ``make_phase(modes, x, v, t)`` builds the phase that starts at time ``t`` (s)
    from positions ``x`` (m) and velocities ``v`` (m/s).
    """
    v_scale = spec.velocity_scale
    samples = options.samples
    x = np.array(spec.x0)
    modes, v, _ = resolve_modes(spec, x, np.array(spec.v0), spec.belt_velocity(0.0), spec.belt_acceleration(0.0),
                                np.where(np.array(spec.v0) >= spec.belt_velocity(0.0), 1, -1), v_scale)
    t, switches, zero_steps, next_sample, opened = 0.0, 0, 0, 0, False
    rec = {key: [] for key in ("t", "x", "v", "state", "friction", "work")}
    work = np.zeros(3)
    events: list[Event] = []
    stick_start = [0.0 if modes[i] == 0 else None for i in range(spec.n)]
    intervals: list[list] = [[] for _ in range(spec.n)]
    with options.watching(lambda: t):  # loops deep in a phase watch the wall clock too
        while True:
            phase = make_phase(modes, x, v, t)
            rows = ModalEvents(phase) if phase.motion is not None else SampledEvents(phase)
            horizon = spec.t_end - t
            found = find_event(rows, horizon, phase.step, clock=lambda tau, t=t: options.check_clock(t + tau))
            tau_e, touching, contradicted = (None, (), ()) if found is None else found
            t1 = spec.t_end if tau_e is None else t + tau_e
            stop = samples.searchsorted(t1, side="right" if tau_e is None else "left")
            taus = samples[next_sample:stop] - t
            next_sample = stop
            if opened and options.include_events and (not taus.size or taus[0] > 0):
                taus = np.concatenate([[0.0], taus])
            work, x, v = _record(phase, taus, t, horizon if tau_e is None else tau_e, work, rec)
            if tau_e is None:
                break
            switches += 1
            options.check_clock(t1)
            # switches that do not move time on (below 1e-12 of the sampling step): a few happen when
            # several masses switch at one instant; a long run of them is a cycle of modes at one
            # instant, refused at once rather than after max_events switches
            zero_steps = zero_steps + 1 if tau_e <= 1e-12 * phase.step else 0
            if zero_steps > 64:
                raise SimulationError(f"switching did not progress at t = {t1:.17g} s (65 switches in a row, "
                                      f"each moving time less than {1e-12 * phase.step:.1g} s); hint: check for a degenerate chain "
                                      "(coincident switches of many masses, forces on the friction limit)", time=t1)
            if switches > options.max_events:
                raise SimulationError(f"more than `max_events` = {options.max_events:,} switches before "
                                      f"t = {t1:.6g} s; raise `max_events` or shorten `t_end`", time=t1)
            t = float(t1)
            new, v, grazing = resolve_modes(spec, x, v, spec.belt_velocity(t), spec.belt_acceleration(t), modes,
                                            v_scale, touching, contradicted)
            for i in ((new != modes) & spec.frictional).nonzero()[0]:  # a frictionless mass's mode is moot
                kind = "stick" if new[i] == 0 else ("slip" if modes[i] == 0 else "reverse")
                events.append(Event(t=t, mass=int(i), kind=kind, x=float(x[i])))
                if new[i] == 0:
                    stick_start[i] = t
                elif modes[i] == 0:
                    intervals[i].append((stick_start[i], t))
                    stick_start[i] = None
            events += [Event(t=t, mass=int(i), kind="graze", x=float(x[i])) for i in grazing]
            modes, opened = new, True
    for i in range(spec.n):
        if stick_start[i] is not None:
            intervals[i].append((stick_start[i], spec.t_end))
    out = RawRun(
        t=np.concatenate(rec["t"]), x=np.concatenate(rec["x"], axis=1), v=np.concatenate(rec["v"], axis=1),
        state=_states(rec["state"]), friction_force=np.concatenate(rec["friction"], axis=1),
        work=np.concatenate(rec["work"], axis=1), events=events, stick_intervals=intervals,
        meta={"n_events": sum(e.kind != "graze" for e in events), "n_grazes": sum(e.kind == "graze" for e in events),
              "v_scale": v_scale})
    for name in ("x", "v", "friction_force", "work"):
        if not np.all(np.isfinite(getattr(out, name))):
            raise SimulationError(f"the solution became non-finite ({name}); the chain's scales are too far apart "
                                  "for double precision", time=float(t))
    return out


def _record(phase, taus, t0, length, work, rec):
    """Append samples at ``taus`` (s from the phase start); return the cumulative work (3,) and x, v at ``length``."""
    x, v, fric, w = phase.sample(np.concatenate((taus, [length])))
    w = work[:, None] + w
    m = taus.size
    if m:
        rec["t"].append(t0 + taus)
        rec["x"].append(x[:, :m])
        rec["v"].append(v[:, :m])
        rec["friction"].append(fric[:, :m])
        rec["work"].append(w[:, :m])
        rec["state"].append((phase.modes, m))
    return w[:, -1], x[:, -1], v[:, -1]


def _states(recorded):
    """The mode of every mass at every sample (n, T) from each phase's (modes, sample count)."""
    modes, counts = zip(*recorded)
    return np.repeat(np.stack(modes, axis=1), counts, axis=1)
