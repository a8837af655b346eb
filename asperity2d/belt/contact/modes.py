"""The mode of every mass of a contact chain at a switching instant: separated, sliding or sticking.

Decided from the state, in three steps, with the tolerances of the event
functions (``SWITCH_TOL`` times the gap, velocity, normal-force and
static-limit scales):

1. **Impacts** (rigid contact). A separated mass at the surface (y within the
   tolerance of 0) that moves towards it faster than the velocity tolerance collides (slower, it
   lands: the sign of a speed within the tolerance is rounding's, and decides nothing): y'+ = -e·y'-
   (Newton), the normal impulse is P_n = m·(y'+ - y'-), the kinetic energy
   ½·m·(y'-² - y'+²) is booked as the impact loss. A Coulomb friction impulse
   -sign(u)·mu_k·P_n acts on the tangential relative velocity u = v - V, unless
   less would stop the slip (then u+ = 0): the belt does P_t·V of work and the
   friction dissipates P_t·(V - (v- + v+)/2) >= 0. **Zeno rule**: a rebound
   that cannot rise beyond the gap tolerance -- y'+ below the velocity tolerance,
   or its apex y'+²/(2·a) under the pull-back a = N/m below SWITCH_TOL·gap_scale,
   the touch rule's band -- is a landing (y'+ = 0). The infinite bounce sequence
   of e < 1 (ever shorter flights accumulating at a finite time) is cut there:
   its remaining flights, each within the tolerance of the surface, would last
   2·y'+/(a·(1 - e)) in all; the kinetic energy they carry, ½·m·y'+², is booked
   as impact loss.
2. **Normal state.** A rigid contact is closed when the mass is on the surface
   at rest in y and the force the contact must give, N = W + (K_s·q + C_s·q')_y, is
   positive (within the tolerance: when it grows); it opens when that force is
   negative (within the tolerance: when it falls). A compliant contact is closed
   when the mass is below the surface, or on it and moving (or, at rest,
   accelerating) into it.
3. **Tangential state** of each mass in contact, as :mod:`.chain.modes` decides it
   with the static limit mu_s·N of the *actual* normal force: at belt speed it
   sticks when the force it needs is within the limit (at the limit itself, when
   the margin mu_s·N - |F| is growing), else it slips the way the net force
   pushes it.

**Grazes** (the touch rule of :mod:`.phases.finder`): a gap whose dip's lowest point
is within the tolerance of zero has touched the surface without closing (a
rigid contact there would have to pull, a compliant one stays unloaded); a
normal force whose dip touches zero has not opened. Those rows keep their
state and the instant is reported as a ``graze-gap`` / ``graze-normal`` event,
like a ``graze`` of belt speed. A row the finder reports as contradicted (it
left zero the wrong way at once, below the resolution of the tests above) is
turned round.
"""

from __future__ import annotations

import numpy as np

from .phase import GAP, NORMAL, SLIP, STICK
from ..phases.finder import SWITCH_TOL
from ..normal import SEPARATED


def resolve_contact(spec, Z, previous, touched=(), contradicted=()):
    """(modes, Z, events, work) at a switching instant.

    ``Z`` (4n,) the state [x; y; v; vy] (m, m/s); ``previous`` (n,) the modes before;
    ``touched`` / ``contradicted``: (role, mass) pairs from the finder. ``events`` is a
    list of (mass, kind); ``work`` (3,) the impulsive belt work, friction loss and
    impact loss (J) of this instant. Masses that end stuck get v = V exactly, rigid
    contacts y = y' = 0 exactly.
    """
    n, D = spec.n, 2 * spec.n
    Z = np.array(Z, dtype=float)
    q, qd = Z[:D], Z[D:]  # views: changes below write into Z
    y, vx, vy = q[n:], qd[:n], qd[n:]
    previous = np.asarray(previous, dtype=int)
    nc, law, m = spec.normal, spec.chain.law, spec.chain.m
    V = float(spec.chain.v_belt)
    mu_s, mu_k = law.static_coefficient, law.kinetic_coefficient
    Ks, Cs = spec.stiffness_matrix, spec.damping_matrix
    # per mass (its own gap and force scales), as the phases' event functions
    tols_y, tol_v, tols_n = (SWITCH_TOL * spec.gap_scales, SWITCH_TOL * spec.velocity_scale,
                             SWITCH_TOL * spec.normal_scales)
    touched, contradicted = set(touched), set(contradicted)
    events, work = [], np.zeros(3)
    was = previous != SEPARATED
    contact = was.copy()
    frictional = (mu_s > 0) | (mu_k > 0)

    def required(i):
        """(N, dN/dt) a rigid contact must give to hold mass i at y = y' = 0 (N, N/s)."""
        return spec.load[i] + Ks[n + i] @ q + Cs[n + i] @ qd, Ks[n + i] @ qd

    for i in range(n):
        tol_y, tol_n = tols_y[i], tols_n[i]
        if (GAP, i) in touched and not was[i] or (NORMAL, i) in touched and was[i]:
            continue  # a graze: the state holds (reported below)
        if nc.rigid:
            if was[i]:
                y[i] = vy[i] = 0.0
                N, dN = required(i)
                contact[i] = not ((NORMAL, i) in contradicted or N < -tol_n or (N <= tol_n and dN < 0))
                continue
            if y[i] <= tol_y and vy[i] < -tol_v:
                y[i] = 0.0
                pull = required(i)[0] / m[i]  # the pull back onto the surface (m/s²) once the rebound starts
                work += _impact(spec, i, Z, V, mu_k if frictional else 0.0, tol_v, pull * tol_y)
                events.append((i, "impact"))
            if y[i] <= tol_y and vy[i] <= tol_v:
                y_keep, vy_keep = y[i], vy[i]
                y[i] = vy[i] = 0.0
                N, dN = required(i)
                contact[i] = (GAP, i) in contradicted or N > tol_n or (N >= -tol_n and dN > 0)
                if not contact[i]:
                    y[i], vy[i] = max(y_keep, 0.0), max(vy_keep, 0.0)
                elif vy_keep < 0:
                    # an approach within the velocity tolerance is no impact (its sign is rounding's
                    # choice: an event kind must not hang on it); its kinetic energy, at most
                    # ½·m·tol_v², is booked as impact loss all the same
                    work[2] += 0.5 * m[i] * vy_keep * vy_keep
            continue
        if (GAP, i) in contradicted or (NORMAL, i) in contradicted:
            contact[i] = not was[i]
            continue
        if abs(y[i]) > tol_y:
            contact[i] = y[i] < 0
        elif abs(vy[i]) > tol_v:
            contact[i] = vy[i] < 0
        else:
            push = -spec.load[i] - Ks[n + i] @ q - Cs[n + i] @ qd  # the force towards +y besides the contact
            if push != 0:
                contact[i] = push < 0
    N = _normal_force(spec, Z, contact)

    # -- tangential state of the masses in contact (as modes.resolve_modes, with the actual N) --
    rel = vx - V
    modes = np.where(contact, np.where(rel >= 0, 1, -1), SEPARATED)
    at_belt = contact & frictional & (np.abs(rel) <= tol_v)
    qd_at = qd.copy()
    qd_at[:n][at_belt] = V
    f_req = Ks[:n] @ q + Cs[:n] @ qd_at  # friction that would keep x'' = 0
    if at_belt.any():
        limit = mu_s * N
        tol_f = SWITCH_TOL * spec.limit_scale
        size = np.abs(f_req)
        outside = at_belt & (size > limit + tol_f)
        modes[at_belt] = 0
        modes[outside] = -np.sign(f_req[outside]).astype(int)
        border = at_belt & ~outside & (size >= limit - tol_f)
        if border.any():
            a = _acceleration(spec, q, qd_at, modes, contact, N)
            df_req = Ks[:n] @ qd_at + Cs[:n] @ a
            dN = _normal_rate(spec, qd_at, a, contact)
            shrinking = np.where(f_req != 0, mu_s * dN - np.sign(f_req) * df_req, mu_s * dN - np.abs(df_req))
            leaving = border & (shrinking < 0)
            modes[leaving] = -np.sign(np.where(f_req != 0, f_req, df_req)[leaving]).astype(int)
    for i in range(n):
        if contact[i] and was[i] and ((SLIP, i) in contradicted or (STICK, i) in contradicted) \
                and modes[i] == previous[i]:
            modes[i] = -previous[i] if previous[i] != 0 else (-int(np.sign(f_req[i])) or 1)
    snap = at_belt & ((modes != previous) | (modes == 0))
    vx[snap] = V

    for i in range(n):
        if was[i] and not contact[i]:
            events.append((i, "open"))
        elif contact[i] and not was[i]:
            events.append((i, "close"))
            if modes[i] == 0 and frictional:
                events.append((i, "stick"))
        elif contact[i] and frictional and modes[i] != previous[i]:
            events.append((i, "stick" if modes[i] == 0 else "slip" if previous[i] == 0 else "reverse"))
        elif contact[i] and (SLIP, i) in touched and modes[i] == previous[i] and modes[i] != 0:
            events.append((i, "graze"))
        elif contact[i] and (NORMAL, i) in touched:
            events.append((i, "graze-normal"))
        elif not contact[i] and (GAP, i) in touched:
            events.append((i, "graze-gap"))
    return modes, Z, events, work


def _impact(spec, i, Z, V, mu, tol_v, apex):
    """Newton impact of mass i on the belt (rigid contact), in place on Z; returns (belt work, friction loss,
    impact loss) in J. ``apex`` (m²/s²) is pull·tolerance: a rebound with v²/2 below it cannot rise beyond
    the gap tolerance."""
    n = spec.n
    D = 2 * n
    m = spec.chain.m[i]
    v_in = Z[D + n + i]
    v_out = -spec.normal.restitution * v_in
    if v_out <= tol_v or 0.5 * v_out * v_out <= apex:
        v_out = 0.0  # the Zeno rule: a rebound that stays within the tolerance of the surface is a landing
    P_n = m * (v_out - v_in)
    Z[n + i], Z[D + n + i] = 0.0, v_out
    out = np.array([0.0, 0.0, 0.5 * m * (v_in * v_in - v_out * v_out)])
    u = Z[D + i] - V
    if mu > 0 and u != 0:
        cap = mu * P_n
        P_t = -m * u if m * abs(u) <= cap else -np.sign(u) * cap
        v_before = Z[D + i]
        v_after = V if m * abs(u) <= cap else v_before + P_t / m
        Z[D + i] = v_after
        out[0] += P_t * V
        out[1] += P_t * (V - 0.5 * (v_before + v_after))
    return out


def _normal_force(spec, Z, contact):
    """Normal force (n,) of each mass in the given contact states (0 when separated, >= 0)."""
    n, D = spec.n, 2 * spec.n
    q, qd = Z[:D], Z[D:]
    if spec.normal.rigid:
        N = spec.load + spec.stiffness_matrix[n:] @ q + spec.damping_matrix[n:] @ qd
    else:
        N = -spec.normal.contact_stiffness * q[n:]
    return np.where(contact, np.maximum(N, 0.0), 0.0)


def _acceleration(spec, q, qd, modes, contact, N):
    """q'' (2n,) under the tentative ``modes`` (stuck x'' = 0, rigid contact y'' = 0)."""
    n = spec.n
    law = spec.chain.law
    free = spec.constant_force - spec.stiffness_matrix @ q - spec.damping_matrix @ qd
    a = free / spec.mass_vector
    slip = contact & (modes != 0)
    a[:n][slip] += -modes[slip] * law.kinetic_coefficient * N[slip] / spec.chain.m[slip]
    a[:n][modes == 0] = 0.0
    if spec.normal.rigid:
        a[n:][contact] = 0.0
    else:
        a[n:][contact] += N[contact] / spec.chain.m[contact]
    return a


def _normal_rate(spec, qd, a, contact):
    """dN/dt (n,) of the masses in contact."""
    n = spec.n
    if spec.normal.rigid:
        dN = spec.stiffness_matrix[n:] @ qd + spec.damping_matrix[n:] @ a
    else:
        dN = -spec.normal.contact_stiffness * qd[n:]
    return np.where(contact, dN, 0.0)
