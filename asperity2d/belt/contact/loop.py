"""The event-driven run of a chain with a normal degree of freedom (separated, sliding, sticking).

Phases (:class:`~.contact.phase.ContactPhase`, closed form) alternate with
switching instants located by :func:`.phases.finder.find_event` -- the same grid screen,
root finder and touch rule as the tangential solver -- and resolved by
:func:`.contact.modes.resolve_contact`. A phase whose motion grows (flutter) is
restarted from its end state, with the same modes, before any of its modes has
doubled: the screen's bound on the event functions' fourth derivative is taken
for that span (no event is recorded at a restart).

The energy books (J, cumulative from t = 0):

* belt work      W_b = ∫ Σ F_i·V dt + Σ P_t·V           (friction forces and impulses at belt speed)
* friction loss  D_f = ∫ Σ F_i·(V - v_i) dt + Σ P_t·(V - v̄)   (>= 0)
* damper loss    D_c = ∫ q'ᵀ·C_s·q' dt
* impact loss    D_i = Σ ½·m·(y'-² - y'+²)               (rigid contacts)

so that the stored energy (:class:`~.contact.result.ContactResult`) obeys
E - E(0) = W_b - D_f - D_c - D_i.

Event kinds (:class:`~.backend.Event`): ``stick``, ``slip``, ``reverse``, ``graze`` as
for the tangential solver; ``open`` (the contact force reached zero: separation),
``close`` (the gap closed: contact again), ``impact`` (a rigid contact's collision,
also when it rebounds), ``graze-gap`` (the gap touched zero without closing) and
``graze-normal`` (the normal force touched zero without opening).
"""

from __future__ import annotations

import numpy as np

from ...errors import SimulationError
from .. import limits
from ..backend import ContactRun, Event
from .modes import resolve_contact
from .phase import GAP, NORMAL, SLIP, STICK, ContactPhase, ContactTemplate
from ..phases.finder import SWITCH_TOL, find_event
from ..normal import SEPARATED

#: bounded memory: at most this many cached mode patterns (and at most :data:`~.limits.CACHE_BYTES`)
CACHE_SIZE = limits.CACHE_SIZE


def run_contact(spec, options) -> ContactRun:
    """Run a :class:`~.normal.ContactSpec` from t = 0 to ``t_end`` with :class:`~.backend.RunOptions`."""
    limits.contact_masses(spec)  # up front: a ratio the rigid contact cannot resolve is refused, not tried
    n = spec.n
    chain = spec.chain
    templates: dict = {}
    sizes: dict = {}
    samples = options.samples
    Z = np.concatenate([chain.x0, spec.y0, chain.v0, spec.vy0]).astype(float)
    V = float(chain.v_belt)
    guess = np.where(np.array(chain.v0) >= V, 1, -1)
    # a rigid contact starts "separated at the surface" so that the resolver decides it as a landing
    # (rebound, rest in contact or lift-off); a compliant one by its gap
    y0 = np.array(spec.y0)
    guess = np.where(spec.normal.rigid | (y0 > 0) | ((y0 == 0) & (np.array(spec.vy0) > 0)), SEPARATED, guess)
    modes, Z, first, impulse = resolve_contact(spec, Z, guess)
    t, switches, zero_steps, restarts, next_sample, opened = 0.0, 0, 0, 0, 0, False
    rec = {key: [] for key in ("t", "Z", "modes", "F", "N", "work")}
    work = np.concatenate([impulse[:2], [0.0, impulse[2]]])
    events: list[Event] = []
    stick_start = [0.0 if modes[i] == 0 else None for i in range(n)]
    sep_start = [0.0 if modes[i] == SEPARATED else None for i in range(n)]
    sticks: list[list] = [[] for _ in range(n)]
    seps: list[list] = [[] for _ in range(n)]
    # t = 0 logs the impacts, and the openings: a mass that starts on the surface (rigid: y0 = 0;
    # compliant: y0 <= 0) and is out of contact once the start is resolved (moving away, or pulled
    # off by its load) leaves it at t = 0 like any later opening; a rebound is its impact's
    hit = [i for i, kind in first if kind == "impact"]
    events += [Event(t=0.0, mass=int(i), kind="impact", x=float(Z[i])) for i in hit]
    events += [Event(t=0.0, mass=int(i), kind="open", x=float(Z[i])) for i in range(n)
               if y0[i] <= 0 and modes[i] == SEPARATED and i not in hit]
    with options.watching(lambda: t):  # loops deep in a phase watch the wall clock too
        while True:
            key = np.asarray(modes, dtype=np.int8).tobytes()
            template = templates.get(key)
            if template is None:
                template = templates[key] = ContactTemplate(spec, modes)
                sizes[key] = limits.nbytes(template)
                limits.bound_cache(templates, sizes, CACHE_SIZE)
            phase = ContactPhase(template, Z)
            rows = phase.events()
            horizon = min(chain.t_end - t, phase.cap)
            found = find_event(rows, horizon, phase.step, clock=lambda tau, t=t: options.check_clock(t + tau))
            restart = found is None and horizon < chain.t_end - t
            tau_e, touching, contradicted = (None, (), ()) if found is None else found
            end = tau_e if tau_e is not None else horizon
            last = tau_e is None and not restart
            t1 = chain.t_end if last else t + end
            stop = np.searchsorted(samples, t1, side="right" if last else "left")
            taus = samples[next_sample:stop] - t
            next_sample = stop
            if opened and options.include_events and (not taus.size or taus[0] > 0):
                taus = np.concatenate([[0.0], taus])
            work, Z = _record(phase, taus, t, end, work, rec)
            if last:
                break
            if restart:
                restarts += 1
                t, opened = float(t1), False
                continue
            switches += 1
            options.check_clock(t1)
            zero_steps = zero_steps + 1 if tau_e <= 1e-12 * min(phase.step, chain.t_end) else 0
            if zero_steps > 64:
                raise SimulationError(f"switching did not progress at t = {t1:.17g} s (65 switches in a row); "
                                      "hint: check for a degenerate chain (coincident switches, forces on the "
                                      "friction limit, a contact held at zero force)", time=t1)
            if switches > options.max_events:
                raise SimulationError(f"more than `max_events` = {options.max_events:,} switches before "
                                      f"t = {t1:.6g} s; raise `max_events` or shorten `t_end`", time=t1)
            t = float(t1)
            label = [(template.role[r], int(template.owner[r])) for r in range(len(template.role))]
            new, Z, changes, impulse = resolve_contact(spec, Z, modes, [label[r] for r in touching],
                                                       [label[r] for r in contradicted])
            work = work + np.concatenate([impulse[:2], [0.0, impulse[2]]])
            for i, kind in changes:
                events.append(Event(t=t, mass=int(i), kind=kind, x=float(Z[i])))
            for i in range(n):
                if modes[i] == 0 and new[i] != 0:
                    sticks[i].append((stick_start[i], t))
                    stick_start[i] = None
                if modes[i] != 0 and new[i] == 0:
                    stick_start[i] = t
                if modes[i] != SEPARATED and new[i] == SEPARATED:
                    sep_start[i] = t
                if modes[i] == SEPARATED and new[i] != SEPARATED:
                    seps[i].append((sep_start[i], t))
                    sep_start[i] = None
            modes, opened = new, True
    for i in range(n):
        if stick_start[i] is not None:
            sticks[i].append((stick_start[i], chain.t_end))
        if sep_start[i] is not None:
            seps[i].append((sep_start[i], chain.t_end))
    out = ContactRun(
        t=np.concatenate(rec["t"]), Z=np.concatenate(rec["Z"], axis=1), modes=np.concatenate(rec["modes"], axis=1),
        friction_force=np.concatenate(rec["F"], axis=1), normal_force=np.concatenate(rec["N"], axis=1),
        work=np.concatenate(rec["work"], axis=1), events=events, stick_intervals=sticks, separation_intervals=seps,
        meta={"n_events": sum(not e.kind.startswith("graze") for e in events),
              "n_grazes": sum(e.kind.startswith("graze") for e in events), "restarts": restarts,
              "v_scale": spec.velocity_scale, "gap_scale": spec.gap_scale, "normal_scale": spec.normal_scale,
              "patterns": len(templates)})
    for name in ("Z", "friction_force", "normal_force", "work"):
        if not np.all(np.isfinite(getattr(out, name))):
            raise SimulationError(f"the solution became non-finite ({name}): the motion grew beyond double precision "
                                  "(an unstable chain run too long?)", time=float(t))
    return out


def _record(phase, taus, t0, length, work, rec):
    """Append samples at ``taus`` (s from the phase start); return the cumulative work (4,) and Z at ``length``.

    Every sample and the end state are checked against the phase's own modes (:func:`check_modes`)."""
    Z, F, N, w = phase.sample(np.append(taus, length))
    check_modes(phase.template, Z, t0 + np.append(taus, length))
    w = np.vstack([w, np.zeros((1, w.shape[1]))]) + work[:, None]
    m = taus.size
    if m:
        rec["t"].append(t0 + taus)
        rec["Z"].append(Z[:, :m])
        rec["modes"].append(np.repeat(phase.modes[:, None], m, axis=1))
        rec["F"].append(F[:, :m])
        rec["N"].append(N[:, :m])
        rec["work"].append(w[:, :m])
    return w[:, -1], Z[:, -1]


#: a mode's own condition may be off by its touch band (a located crossing stops on the far side of
#: the zero, a touch is anywhere within the band): twice the band is a switch the scan missed
VIOLATION = 2 * SWITCH_TOL


def check_modes(template, Z, times):
    """Raise SimulationError where a state ``Z`` (4n, T) at ``times`` (s) breaks its phase's modes.

    The validity check of every contact run, as the asperity model's tunnelling check: each mode's
    event function (:mod:`.contact.phase`: the gap of a separated mass, the normal force of one in
    contact, the relative velocity of a slipping one, the static margin of a stuck one) must not be
    below zero by more than :data:`VIOLATION` (twice the touch band), each mass's on its own scale
    (:attr:`~.normal.ContactSpec.normal_scales`, ``gap_scales``). Beyond it a switch was missed
    -- a separated mass inside a rigid belt (or inside a compliant one, whose contact spring never
    took up the load), a contact that pulls, a slip the wrong way, a static force beyond its
    limit -- and the run is wrong whatever its energy books say: it fails, naming the mass and the
    time, rather than return.
    """
    G = template.ev_map @ Z + template.ev_offset[:, None]
    broken = (G < -VIOLATION).any(axis=0)
    if not broken.any():
        return
    col = int(np.argmax(broken))  # the first time at which a mode is broken, and its worst row there
    r = int(np.argmin(G[:, col]))
    spec, i, role, t = template.spec, int(template.owner[r]), template.role[r], float(times[col])
    n, D = spec.n, 2 * spec.n
    what = {GAP: f"is {-Z[n + i, col]:.3g} m inside the belt while separated (a landing was missed)",
            NORMAL: f"is held by a contact force of {float(G[r, col]) * spec.normal_scales[i]:.3g} N that pulls "
                    "(a lift-off was missed)",
            SLIP: f"slips against its friction at {abs(Z[D + i, col] - template.V):.3g} m/s from the belt speed "
                  "(a stick or reversal was missed)",
            STICK: "is held stuck beyond its static friction limit (a slip was missed)"}[role]
    raise SimulationError(f"invalid contact state at t = {t:.9g} s: mass {i} {what}; the run is refused rather "
                          "than returned wrong", time=t)
