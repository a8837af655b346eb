"""The batched engine's compiled step loop (Numba): many asperity scenes advanced in lockstep.

Part of :mod:`asperity2d.engine` (imported only by :mod:`.batched`, only where Numba is
installed). One call advances every scene of a batch by its own number of steps with no Python
in between. Scenes are independent: no quantity is shared between them, so a scene's numbers do
not depend on what else is in the batch. Each thread (``prange``) steps a group of up to
:data:`LANES` consecutive scenes, its *lanes*, together: each lane's step to the sweeps, then the
sweeps of all lanes interleaved contact by contact, then each lane's end of step. A sweep is a
chain of dependent operations through the slider's velocity (about 110 instructions a contact
point, each reading what the one before wrote); the lanes' chains are independent, so the
processor overlaps them. Each lane's operations, and their order, are those of the scene alone.

Each step is Chipmunk's ``cpSpaceStep`` for this model, operation for operation where the model
allows (Chipmunk 7 as bundled with pymunk 7: ``cpSpaceStep.c``, ``cpArbiter.c``,
``cpCollision.c``, ``cpDampedSpring.c``, ``cpGrooveJoint.c``), then the adapter's track
projection and stick/slip switch (:mod:`.core`, :mod:`.contacts`):

1. the slider's force (the drive spring at the position the step will end at, or the constant
   force; the normal load on a free slider);
2. positions: ``p += (v + v_bias) dt``, ``v_bias = 0``;
3. contacts: every slider asperity (the last first, the order pymunk's broad phase reports
   them in, which decides the sequential solver's sweep) against every lower one whose
   bounding boxes overlap;
   the normal and depth by the separating-axis test (for two overlapping convex polygons --
   triangles, half triangles, flat tops, any strictly convex outline -- the
   same minimum-penetration axis GJK/EPA converges to), the contact points by Chipmunk's
   ``SupportEdgeForPoly`` / ``ContactPoints`` clipping (at most two per pair), warm-started from
   the previous step's impulses of the same vertex pair (contacts persist one step, as
   ``collision_persistence = 1`` makes them);
4. pre-step: contact masses, the position bias ``-bias min(0, d + slop) / dt``, the bounce;
   each track spring's force as an impulse and its exact damping coefficient
   ``1 - exp(-c dt / m)``; each groove's anchor, clamp and bias; a lattice's links (Chipmunk's
   damped springs between the peaks and to the walls, :mod:`.batched_links`), in the space's
   order after the tracks' springs;
5. velocities: ``v = v + (g + f / m) dt``;
6. cached impulses (contacts, grooves), then ``iterations`` sweeps of sequential impulses over
   the contacts, then the springs' damping and the grooves, then the links (each damping
   impulse taken through the spring's accumulated impulse, ``(jAcc + j) - jAcc``, as pymunk 7's
   Chipmunk takes it to clamp it to the spring's maximum force, here unbounded; a lattice has no
   grooves and all its bodies are one island). Two rearrangements that change no
   bit: a moving lower body without a contact is a system of its own (its spring and groove
   touch nothing else), so its sweeps run alone, in registers; the island -- the slider, its
   contacts and the bodies they touch -- is swept on per-lane copies (one row of fields per
   body, ``bd``, and per contact point, ``pt``), written back after. And a sweep that changes
   nothing (no accumulated impulse, no spring target, no damping impulse) is a fixed point,
   which the sweeps left would repeat exactly: that lane's sweeps stop there;
7. the projection back onto the tracks when a body drifted more than ``1e-9`` bases, and the
   static/kinetic switch with its hold rule (:class:`asperity2d.contact_laws.StaticKineticSwitch`),
   then the record and the run loop's stops (:mod:`.batched_rules`).

Everything is in the engine's internal units (:mod:`asperity2d.units`).
"""

from __future__ import annotations

import math

import numpy as np
from numba import get_num_threads, njit, prange

from .batched_collide import (DBL_MAX, KEY_BASE, N_REC, NONFINITE, OK, OVERLAP, PAIRS,  # noqa: F401
                              contact_points, penetration, placed, record, remember, static_pairs,
                              support_edge, warm_start)
from .batched_links import N_LINK, links_prestep, links_sweep
from .batched_rules import STOP_NONE, project, stop, switch

#: Contact points per pair (Chipmunk's CP_MAX_CONTACTS_PER_ARBITER).
MAX_CONTACTS = 2
#: Pairs in contact per scene and step the scratch arrays hold (a slider asperity touches at
#: most its two neighbouring lower flanks, and the lower asperity under it near an apex).
PAIRS_PER_TIP = 4
#: Static segments (the floor, a profile's valleys) a tip touches at once, at most.
STATIC_PER_TIP = 2
#: The divergence guard's deepest overlap (bases), as the pymunk path's (recorder.MAX_OVERLAP).
MAX_OVERLAP = 0.5

#: The island's per-body fields (``bd[lane, slot, field]``): inverse mass, velocity, bias
#: velocity, groove impulse, spring target, spring direction, damping coefficient, groove bias,
#: groove clamp, 1 / inverse mass, groove mass, the spring's accumulated impulse.
MI, V0, V1, B0, B1, G0, G1, TG, SX, SY, VC, GX, GY, CL, M1, KI, JA = range(17)
N_BODY = 17
#: The island's per-contact-point fields (``pt[lane, point, field]``): normal, friction
#: coefficient, normal and tangent masses, bias, bounce, accumulated bias, normal and tangent
#: impulses.
NX, NY, MU, NM, TM, CB, BO, JB, JN, JT = range(10)
N_POINT = 10

#: Scenes a thread steps together, interleaved in the sweeps (their independent chains of
#: dependent operations overlap in the processor). Measured on 16 seeds x 3 peak-stick passes,
#: 2 cores (AMD EPYC, Zen 1), four alternating pairs of runs: one scene a thread took 1.12-1.18x
#: the CPU of four; eight were no better than four (64 seeds: 83.0 against 83.9 CPU-s).
LANES = 4


@njit(cache=True, error_model="numpy")
def _step_group(b0, L, steps, rec_every, rec_at, rec, lp, lv, lvb, gj, sp, sv, svb, sgj,
                c_n, c_key, c_jn, c_jt, stuck, slid, mu, present, nstep, fail, fail_step,
                lx0, lverts, lnorms, nv_l, lm_inv, lk, lc, ldown, lup, n_lower,
                uverts, unorms, nv_u, n_upper, s_m_inv, fixed, track_y, g_x, g_y,
                spring, dk, dc, dv, dorigin, dforce, load,
                dt, iterations, slop, bias_coef, joint_bias_coef, restitution,
                mu_s, mu_k, v_stick, slip_dist, switch_on, seg_a, seg_b, seg_n, n_seg, seg_mu, s_n, s_key, s_jn, s_jt, stop_x, first,
                settling, damp, push, hold, hold_x, hold_j, hold_coef, stop_code, stuck_v, stuck_dwell,
                slow_since, v_unit, dt_s, off_x, lat, n_link, link_ab, link_p, link_kc):
    """Advance the ``L`` scenes ``b0 .. b0 + L - 1`` (the group's lanes) by ``steps[b]`` steps
    each (see the module docstring)."""
    Nm, Um = 1, 1
    for l in range(L):
        Nm = max(Nm, n_lower[b0 + l])
        Um = max(Um, n_upper[b0 + l])
    max_pairs = (PAIRS_PER_TIP + STATIC_PER_TIP) * Um
    # Per lane, what a step's sweeps and its end read: this step's pairs (tip j, lower i, normal,
    # count, per contact its key and impulses), the island (its bodies' slots and constants,
    # its contact points), the slider's velocities and its grooves' impulses
    a_j = np.empty((L, max_pairs), np.int64)
    a_i = np.empty((L, max_pairs), np.int64)
    a_nx = np.empty((L, max_pairs))
    a_ny = np.empty((L, max_pairs))
    a_cnt = np.empty((L, max_pairs), np.int64)
    key = np.empty((L, max_pairs, 2), np.int64)
    jn = np.empty((L, max_pairs, 2))
    jt = np.empty((L, max_pairs, 2))
    isl = np.empty((L, Nm), np.int64)
    # (one slot more: the static segments' body, which never moves)
    bd = np.empty((L, Nm + 1, N_BODY))  # per island body: BODY fields
    fs = np.empty((L, 2 * max_pairs), np.int64)
    pt = np.empty((L, 2 * max_pairs, N_POINT))  # per contact point: POINT fields
    na_ = np.zeros(L, np.int64)
    n_isl_ = np.zeros(L, np.int64)
    n_c_ = np.zeros(L, np.int64)
    r_s = np.empty((L, 8))  # s0, s1, sb0, sb1, sg0, sg1, hg0, hg1
    lq = np.empty((L, link_ab.shape[1], 2), np.int64)  # per lattice link its bodies' slots
    lf = np.empty((L, link_ab.shape[1], N_LINK))  # and its LINK fields
    sgb_y_ = np.zeros(L)
    hgb_x_ = np.zeros(L)
    # Shared by the lanes in turn (each lane's use ends within its part of a step): the
    # collision's and pre-step's scratch
    a_first = np.empty(max_pairs, np.bool_)
    a_u = np.empty(max_pairs)
    r1x = np.empty((max_pairs, 2))
    r1y = np.empty((max_pairs, 2))
    r2x = np.empty((max_pairs, 2))
    r2y = np.empty((max_pairs, 2))
    jb = np.empty((max_pairs, 2))
    nmass = np.empty((max_pairs, 2))
    tmass = np.empty((max_pairs, 2))
    cbias = np.empty((max_pairs, 2))
    bounce = np.empty((max_pairs, 2))
    sn_x = np.empty(Nm)
    sn_y = np.empty(Nm)
    s_target = np.empty(Nm)
    s_jacc = np.empty(Nm)
    in_contact = np.zeros(Nm, np.bool_)
    slot = np.zeros(Nm, np.int64)
    g_clamp = np.empty(Nm)
    g_bx = np.empty(Nm)
    g_by = np.empty(Nm)
    slips = np.empty(Nm)
    seen = np.zeros(Nm, np.bool_)
    touched = np.zeros(Nm, np.bool_)
    act = np.empty(Nm, np.int64)
    wvx = np.empty(lverts.shape[2])
    wvy = np.empty(lverts.shape[2])
    uvx = np.empty(uverts.shape[2])
    uvy = np.empty(uverts.shape[2])
    # per lane, constants of its scene: the highest point of any static segment (a tip above it
    # touches none); the lower outlines' x extents about their bodies (the broad phase's cheap
    # rejection: lp + min(v) rounds as min(lp + v), so it rejects exactly the pairs the full test
    # would); each spring's exact damping coefficient 1 - exp(-c dt / m)
    seg_top = np.empty(L)
    lxlo = np.empty((L, Nm))
    lxhi = np.empty((L, Nm))
    s_vcoef = np.empty((L, Nm))
    for l in range(L):
        b = b0 + l
        seg_top[l] = -np.inf
        for sg in range(n_seg[b]):
            seg_top[l] = max(seg_top[l], seg_a[b, sg, 1], seg_b[b, sg, 1])
        for i in range(n_lower[b]):
            lxlo[l, i], lxhi[l, i] = np.inf, -np.inf
            for q in range(nv_l[b, i]):
                lxlo[l, i] = min(lxlo[l, i], lverts[b, i, q, 0])
                lxhi[l, i] = max(lxhi[l, i], lverts[b, i, q, 0])
            s_vcoef[l, i] = 1.0 - math.exp(-lc[b, i] * dt[b] * lm_inv[b, i])
    local = np.zeros(L, np.int64)
    running = np.ones(L, np.bool_)
    live = np.zeros(L, np.bool_)  # the lanes whose step reached the sweeps
    sweep = np.zeros(L, np.bool_)  # the lanes still sweeping
    changed = np.zeros(L, np.bool_)
    while True:
        any_live = False
        for l in range(L):
            live[l] = False
            if not running[l]:
                continue
            b = b0 + l
            if local[l] >= steps[b] or fail[b] != OK:
                running[l] = False
                continue
            N = n_lower[b]
            U = n_upper[b]
            S = n_seg[b]
            h = dt[b]
            sm_inv = s_m_inv[b]
            settle = settling[b]
            dmp = damp[b]
            still = g_x[b] == 0.0 and g_y[b] == 0.0 and not lat[b]  # (a lattice's links move a body at rest)
            k = nstep[b]
            local[l] += 1
            # 1. the slider's force
            x, vx = sp[b, 0], sv[b, 0]
            if settle:  # Engine.settle's force: the spring towards its far end at rest, plus the push
                fx = (dk[b] * (dorigin[b] - x) if spring[b] else 0.0) + push[b]
            elif spring[b]:
                x_d = dorigin[b] + dv[b] * (k + 1) * h
                fx = dk[b] * (x_d - (x + vx * h)) + dc[b] * (dv[b] - vx)
            else:
                fx = dforce[b]
            fy = -load[b]
            # 2. positions
            sp[b, 0] = sp[b, 0] + (sv[b, 0] + svb[b, 0]) * h
            sp[b, 1] = sp[b, 1] + (sv[b, 1] + svb[b, 1]) * h
            svb[b, 0] = 0.0
            svb[b, 1] = 0.0
            n_act = 0
            for i in range(N):
                touched[i] = False
                in_contact[i] = False
                # Bodies at rest: a lower asperity exactly at its rest position, with no
                # velocity, no groove impulse and no contact, and no gravity, receives exactly
                # zero from every step of the solver (its spring force (100 - 100) k dt is 0,
                # its groove's bias and impulse are 0), so it is left out of the step's loops:
                # bit for bit the same numbers, for less work
                if (still and lp[b, i, 1] == 0.0 and lp[b, i, 0] == lx0[b, i] and lv[b, i, 0] == 0.0
                        and lv[b, i, 1] == 0.0 and lvb[b, i, 0] == 0.0 and lvb[b, i, 1] == 0.0
                        and gj[b, i, 0] == 0.0 and gj[b, i, 1] == 0.0):
                    continue  # at rest: its position step is p += 0
                touched[i] = True
                lp[b, i, 0] = lp[b, i, 0] + (lv[b, i, 0] + lvb[b, i, 0]) * h
                lp[b, i, 1] = lp[b, i, 1] + (lv[b, i, 1] + lvb[b, i, 1]) * h
                lvb[b, i, 0] = 0.0
                lvb[b, i, 1] = 0.0
            spx, spy = sp[b, 0], sp[b, 1]
            # 3. contacts (at most the scene's own number of pairs, whatever its lanes' sizes)
            na = 0
            room = (PAIRS_PER_TIP + STATIC_PER_TIP) * U
            # Chipmunk's broad phase reports the pairs of the slider's asperities last-added
            # first (measured: this order reproduces pymunk to 1e-16 through two tips meeting
            # their flanks in the same step; the x order left 2.7e-6 of the slider's speed, the
            # residual of 20 Gauss-Seidel sweeps that have not converged at a hard impact)
            for j in range(U - 1, -1, -1):
                nu = nv_u[b, j]
                ul, ur, ub, ut = placed(uverts[b, j], nu, spx, spy, uvx, uvy)
                # The static segments first (the floor; a profile's valleys): Chipmunk collides
                # the moving shapes with the static index before with each other
                if ub <= seg_top[l]:  # a segment can be under the tip
                    na = static_pairs(b, j, N, S, nu, uvx, uvy, ul, ur, ub, ut, spx, spy, uverts, unorms, seg_a,
                                      seg_b, seg_n, seg_mu, s_n, s_key, s_jn, s_jt, na, room, a_j[l],
                                      a_i[l], a_nx[l], a_ny[l], a_cnt[l], a_first, a_u, r1x, r1y, r2x, r2y,
                                      key[l], jn[l], jt[l], fail)
                    if fail[b] != OK:
                        break
                for i in range(N):
                    lpx, lpy = lp[b, i, 0], lp[b, i, 1]
                    if lpx + lxhi[l, i] < ul or lpx + lxlo[l, i] > ur:
                        c_n[b, j, i] = 0
                        continue
                    nl = nv_l[b, i]
                    ll, lr, lb, lt = placed(lverts[b, i], nl, lpx, lpy, wvx, wvy)
                    if not (ul <= lr and ll <= ur and ub <= lt and lb <= ut):
                        c_n[b, j, i] = 0
                        continue
                    best, mx, my = penetration(lnorms[b, i], nl, unorms[b, j], nu, wvx, wvy, uvx, uvy)
                    if best < 0.0:  # separated (d > 0)
                        c_n[b, j, i] = 0
                        continue
                    n_x, n_y = -mx, -my  # from the slider (a) to the lower body (b)
                    # ContactPoints(SupportEdgeForPoly(a, n), SupportEdgeForPoly(b, -n))
                    a0, a1 = support_edge(uverts[b, j, :, 0], uverts[b, j, :, 1], unorms[b, j, :, 0],
                                           unorms[b, j, :, 1], spx, spy, n_x, n_y, nu)
                    b0_, b1_ = support_edge(lverts[b, i, :, 0], lverts[b, i, :, 1], lnorms[b, i, :, 0],
                                            lnorms[b, i, :, 1], lpx, lpy, -n_x, -n_y, nl)
                    e1ax, e1ay, e1bx, e1by = uvx[a0], uvy[a0], uvx[a1], uvy[a1]
                    e2ax, e2ay, e2bx, e2by = wvx[b0_], wvy[b0_], wvx[b1_], wvy[b1_]
                    if na >= room:
                        fail[b] = PAIRS
                        break
                    q = contact_points(e1ax, e1ay, e1bx, e1by, e2ax, e2ay, e2bx, e2by, n_x, n_y)
                    cnt = 0
                    for w in range(2):
                        kept, p1x, p1y, p2x, p2y = q[:5] if w == 0 else q[5:]
                        if not kept:
                            continue
                        kk = a0 * KEY_BASE + b1_ if w == 0 else a1 * KEY_BASE + b0_
                        r1x[na, cnt], r1y[na, cnt] = p1x - spx, p1y - spy
                        r2x[na, cnt], r2y[na, cnt] = p2x - lpx, p2y - lpy
                        key[l, na, cnt] = kk
                        # warm start: the previous step's impulses of the same vertex pair
                        jn[l, na, cnt], jt[l, na, cnt] = warm_start(c_key[b, j, i], c_jn[b, j, i], c_jt[b, j, i],
                                                                    c_n[b, j, i], kk)
                        cnt += 1
                    if cnt == 0:
                        c_n[b, j, i] = 0
                        continue
                    a_first[na] = c_n[b, j, i] == 0
                    touched[i] = True
                    in_contact[i] = True
                    a_j[l, na], a_i[l, na], a_nx[l, na], a_ny[l, na], a_cnt[l, na] = j, i, n_x, n_y, cnt
                    a_u[na] = mu[b, i]
                    na += 1
                if fail[b] != OK:
                    break
            if fail[b] != OK:
                fail_step[b] = k + 1
                running[l] = False
                continue
            # 4. pre-step: contacts
            for a in range(na):
                i = a_i[l, a]
                n_x, n_y = a_nx[l, a], a_ny[l, a]
                if i < N:
                    m_sum = sm_inv + lm_inv[b, i]
                    bdx, bdy = lp[b, i, 0] - spx, lp[b, i, 1] - spy
                    vrx, vry = lv[b, i, 0] - sv[b, 0], lv[b, i, 1] - sv[b, 1]
                else:  # a static segment
                    m_sum = sm_inv + 0.0
                    bdx, bdy = 0.0 - spx, 0.0 - spy
                    vrx, vry = 0.0 - sv[b, 0], 0.0 - sv[b, 1]
                for c in range(a_cnt[l, a]):
                    nmass[a, c] = 1.0 / m_sum
                    tmass[a, c] = 1.0 / m_sum
                    dist = ((r2x[a, c] - r1x[a, c]) + bdx) * n_x + ((r2y[a, c] - r1y[a, c]) + bdy) * n_y
                    if dist < -MAX_OVERLAP:  # the divergence guard's deepest overlap
                        fail[b] = OVERLAP
                    cbias[a, c] = -bias_coef[b] * min(0.0, dist + slop) / h
                    jb[a, c] = 0.0
                    bounce[a, c] = (vrx * n_x + vry * n_y) * restitution[b]
            if fail[b] != OK:
                fail_step[b] = k + 1
                running[l] = False
                continue
            # the bodies this step moves, in index order (the constraints' order in the space)
            for i in range(N):
                if touched[i]:
                    act[n_act] = i
                    n_act += 1
            # pre-step: per lower body its spring (the impulse of its force), then its groove
            for q in range(n_act):
                i = act[q]
                m_inv = lm_inv[b, i]
                dx, dy = lp[b, i, 0] - lx0[b, i], lp[b, i, 1] - (-100.0)
                dist = math.sqrt(dx * dx + dy * dy)
                inv = 1.0 / dist
                sn_x[i], sn_y[i] = dx * inv, dy * inv
                s_target[i] = 0.0
                j_spring = (100.0 - dist) * lk[b, i] * h
                s_jacc[i] = j_spring
                lv[b, i, 0] = lv[b, i, 0] + sn_x[i] * j_spring * m_inv
                lv[b, i, 1] = lv[b, i, 1] + sn_y[i] * j_spring * m_inv
                # groove along y at x0 from -down to up; n = (-1, 0), td = y
                td = lp[b, i, 1]
                if td <= -ldown[b, i]:
                    g_clamp[i] = 1.0
                    ay = -ldown[b, i]
                elif td >= lup[b, i]:
                    g_clamp[i] = -1.0
                    ay = lup[b, i]
                else:
                    g_clamp[i] = 0.0
                    ay = td
                g_bx[i] = -(lp[b, i, 0] - lx0[b, i]) * joint_bias_coef[b] / h
                g_by[i] = -(lp[b, i, 1] - ay) * joint_bias_coef[b] / h
            if lat[b]:  # a lattice's links
                links_prestep(b, l, h, lp, lv, lm_inv, n_link, link_ab, link_p, link_kc, lf)
            if fixed[b]:  # the slider's groove along x at the track's height; n = (0, 1)
                sgb_y_[l] = -(sp[b, 1] - track_y[b]) * joint_bias_coef[b] / h
            if hold[b]:  # settling's hold: a groove along y at hold_x (added last); n = (-1, 0)
                hgb_x_[l] = -(sp[b, 0] - hold_x[b]) * hold_coef[b] / h
            # 5. velocities
            # (v damp + (g + f / m) dt: the space's damping, 1 but while settling)
            sv[b, 0] = sv[b, 0] * dmp + (g_x[b] + fx * sm_inv) * h
            sv[b, 1] = sv[b, 1] * dmp + (g_y[b] + fy * sm_inv) * h
            for q in range(n_act):
                i = act[q]
                lv[b, i, 0] = lv[b, i, 0] * dmp + g_x[b] * h
                lv[b, i, 1] = lv[b, i, 1] * dmp + g_y[b] * h
            # 6. cached impulses (dt / previous dt: 0 on a space's first step, else 1)
            coef = 0.0 if first[b] else 1.0
            for a in range(na):
                if a_first[a]:
                    continue
                i = a_i[l, a]
                n_x, n_y = a_nx[l, a], a_ny[l, a]
                for c in range(a_cnt[l, a]):
                    jx = (n_x * jn[l, a, c] - n_y * jt[l, a, c]) * coef
                    jy = (n_x * jt[l, a, c] + n_y * jn[l, a, c]) * coef
                    sv[b, 0] -= jx * sm_inv
                    sv[b, 1] -= jy * sm_inv
                    if i < N:
                        lv[b, i, 0] += jx * lm_inv[b, i]
                        lv[b, i, 1] += jy * lm_inv[b, i]
            for q in range(n_act):
                i = act[q]
                lv[b, i, 0] += gj[b, i, 0] * coef * lm_inv[b, i]
                lv[b, i, 1] += gj[b, i, 1] * coef * lm_inv[b, i]
            if fixed[b]:
                sv[b, 0] += sgj[b, 0] * coef * sm_inv
                sv[b, 1] += sgj[b, 1] * coef * sm_inv
            if hold[b]:
                sv[b, 0] += hold_j[b, 0] * coef * sm_inv
                sv[b, 1] += hold_j[b, 1] * coef * sm_inv
            first[b] = False
            # The sweeps. Only the island -- the slider, its contacts, the lower bodies they
            # touch -- is coupled; a moving lower body with no contact is its own system (its
            # spring and groove touch nothing else), so it iterates alone, in registers, with the
            # same operations in the same order (the order between independent bodies changes no
            # number). An iteration that changes nothing -- no accumulated impulse, no spring
            # target, no damping impulse -- leaves every velocity as it was, so the sweeps after
            # it would repeat it exactly: the loop stops there, bit for bit the result of all its
            # sweeps.
            n_isl = 0
            for q in range(n_act):
                i = act[q]
                if in_contact[i] or lat[b]:  # (a lattice's links join all its bodies)
                    isl[l, n_isl] = i
                    n_isl += 1
                    continue
                mi = lm_inv[b, i]
                v0, v1 = lv[b, i, 0], lv[b, i, 1]
                o0, o1 = gj[b, i, 0], gj[b, i, 1]
                tgt, ja = s_target[i], s_jacc[i]
                snx, sny, vco, bx, by, clamp = sn_x[i], sn_y[i], s_vcoef[l, i], g_bx[i], g_by[i], g_clamp[i]
                kinv = mi / (mi * mi)
                m_1 = 1.0 / mi
                for _it in range(iterations[b]):
                    vrn = v0 * snx + v1 * sny
                    v_damp = (tgt - vrn) * vco
                    tgt_new = vrn + v_damp
                    j_damp = (ja + v_damp * m_1) - ja  # through jAcc, as Chipmunk clamps it (to no bound)
                    ja += j_damp
                    v0 += snx * j_damp * mi
                    v1 += sny * j_damp * mi
                    jx = kinv * (bx - v0)
                    jy = kinv * (by - v1)
                    sx, sy = o0 + jx, o1 + jy
                    if not (clamp * sy > 0.0):
                        sy = 0.0
                    v0 += (sx - o0) * mi
                    v1 += (sy - o1) * mi
                    same = v_damp == 0.0 and tgt_new == tgt and sx == o0 and sy == o1
                    tgt, o0, o1 = tgt_new, sx, sy
                    if same:
                        break
                lv[b, i, 0], lv[b, i, 1] = v0, v1
                gj[b, i, 0], gj[b, i, 1] = o0, o1
                s_target[i] = tgt
            # the island's state copied into the lane's unit-stride rows (per island body and
            # per contact point) for the sweeps, which interleave the lanes
            for q in range(n_isl):
                i = isl[l, q]
                slot[i] = q
                bd[l, q, MI] = lm_inv[b, i]
                bd[l, q, V0], bd[l, q, V1] = lv[b, i, 0], lv[b, i, 1]
                bd[l, q, B0], bd[l, q, B1] = lvb[b, i, 0], lvb[b, i, 1]
                bd[l, q, G0], bd[l, q, G1] = gj[b, i, 0], gj[b, i, 1]
                bd[l, q, TG], bd[l, q, JA] = s_target[i], s_jacc[i]
                bd[l, q, SX], bd[l, q, SY], bd[l, q, VC] = sn_x[i], sn_y[i], s_vcoef[l, i]
                bd[l, q, GX], bd[l, q, GY], bd[l, q, CL] = g_bx[i], g_by[i], g_clamp[i]
                mi = bd[l, q, MI]
                bd[l, q, M1], bd[l, q, KI] = 1.0 / mi, mi / (mi * mi)
            for f in (MI, V0, V1, B0, B1):  # the static body's slot
                bd[l, n_isl, f] = 0.0
            for e in range(n_link[b]):  # the links' bodies' slots
                ia, ib = link_ab[b, e, 0], link_ab[b, e, 1]
                lq[l, e, 0], lq[l, e, 1] = slot[ia] if ia >= 0 else n_isl, slot[ib] if ib >= 0 else n_isl
            n_c = 0
            for a in range(na):
                q = slot[a_i[l, a]] if a_i[l, a] < N else n_isl
                for c in range(a_cnt[l, a]):
                    fs[l, n_c], pt[l, n_c, NX], pt[l, n_c, NY], pt[l, n_c, MU] = q, a_nx[l, a], a_ny[l, a], a_u[a]
                    pt[l, n_c, NM], pt[l, n_c, TM] = nmass[a, c], tmass[a, c]
                    pt[l, n_c, CB], pt[l, n_c, BO] = cbias[a, c], bounce[a, c]
                    pt[l, n_c, JB], pt[l, n_c, JN], pt[l, n_c, JT] = jb[a, c], jn[l, a, c], jt[l, a, c]
                    n_c += 1
            r_s[l, 0], r_s[l, 1], r_s[l, 2], r_s[l, 3] = sv[b, 0], sv[b, 1], svb[b, 0], svb[b, 1]
            r_s[l, 4], r_s[l, 5] = sgj[b, 0], sgj[b, 1]
            r_s[l, 6], r_s[l, 7] = hold_j[b, 0], hold_j[b, 1]
            na_[l], n_isl_[l], n_c_[l] = na, n_isl, n_c
            live[l] = True
            any_live = True
        if not any_live:
            break
        # 6. the island's sweeps, the lanes interleaved contact by contact (each lane's the same
        # operations in the same order as alone; the lanes' chains, independent, overlap)
        n_sweeps, c_max, q_max = 0, 0, 0
        for l in range(L):
            sweep[l] = live[l] and iterations[b0 + l] > 0
            if sweep[l]:
                n_sweeps = max(n_sweeps, iterations[b0 + l])
                c_max = max(c_max, n_c_[l])
                q_max = max(q_max, n_isl_[l])
        for it in range(n_sweeps):
            for l in range(L):
                changed[l] = False
            for m in range(c_max):
                for l in range(L):
                    if not sweep[l] or m >= n_c_[l]:
                        continue
                    sm_inv = s_m_inv[b0 + l]
                    q = fs[l, m]
                    n_x, n_y = pt[l, m, NX], pt[l, m, NY]
                    mi = bd[l, q, MI]
                    s0, s1, sb0, sb1 = r_s[l, 0], r_s[l, 1], r_s[l, 2], r_s[l, 3]
                    vrx = bd[l, q, V0] - s0
                    vry = bd[l, q, V1] - s1
                    vbn = (bd[l, q, B0] - sb0) * n_x + (bd[l, q, B1] - sb1) * n_y
                    vrn = vrx * n_x + vry * n_y
                    vrt = vrx * (-n_y) + vry * n_x
                    jbn = (pt[l, m, CB] - vbn) * pt[l, m, NM]
                    jb_old = pt[l, m, JB]
                    jb_ = max(jb_old + jbn, 0.0)
                    jn_new = -(pt[l, m, BO] + vrn) * pt[l, m, NM]
                    jn_old = pt[l, m, JN]
                    jn_ = max(jn_old + jn_new, 0.0)
                    jt_max = pt[l, m, MU] * jn_
                    jt_new = -vrt * pt[l, m, TM]
                    jt_old = pt[l, m, JT]
                    jt_ = min(max(jt_old + jt_new, -jt_max), jt_max)
                    if jb_ != jb_old or jn_ != jn_old or jt_ != jt_old:
                        changed[l] = True
                    pt[l, m, JB], pt[l, m, JN], pt[l, m, JT] = jb_, jn_, jt_
                    dbn = jb_ - jb_old
                    r_s[l, 2] = sb0 - n_x * dbn * sm_inv
                    r_s[l, 3] = sb1 - n_y * dbn * sm_inv
                    bd[l, q, B0] += n_x * dbn * mi
                    bd[l, q, B1] += n_y * dbn * mi
                    djn, djt = jn_ - jn_old, jt_ - jt_old
                    jx = n_x * djn - n_y * djt
                    jy = n_x * djt + n_y * djn
                    r_s[l, 0] = s0 - jx * sm_inv
                    r_s[l, 1] = s1 - jy * sm_inv
                    bd[l, q, V0] += jx * mi
                    bd[l, q, V1] += jy * mi
            for q in range(q_max):
                for l in range(L):
                    if not sweep[l] or q >= n_isl_[l]:
                        continue
                    mi = bd[l, q, MI]
                    # the spring's damping: exact decay of the velocity along it
                    vrn = bd[l, q, V0] * bd[l, q, SX] + bd[l, q, V1] * bd[l, q, SY]
                    v_damp = (bd[l, q, TG] - vrn) * bd[l, q, VC]
                    tgt_new = vrn + v_damp
                    if v_damp != 0.0 or tgt_new != bd[l, q, TG]:
                        changed[l] = True
                    bd[l, q, TG] = tgt_new
                    j_damp = (bd[l, q, JA] + v_damp * bd[l, q, M1]) - bd[l, q, JA]
                    bd[l, q, JA] += j_damp
                    bd[l, q, V0] += bd[l, q, SX] * j_damp * mi
                    bd[l, q, V1] += bd[l, q, SY] * j_damp * mi
                    if lat[b0 + l]:  # a lattice's bodies have no groove
                        continue
                    # the groove (its mass tensor is m I for a body that cannot rotate)
                    kinv = bd[l, q, KI]
                    jx = kinv * (bd[l, q, GX] - bd[l, q, V0])
                    jy = kinv * (bd[l, q, GY] - bd[l, q, V1])
                    ox, oy = bd[l, q, G0], bd[l, q, G1]
                    sx, sy = ox + jx, oy + jy
                    if not (bd[l, q, CL] * sy > 0.0):  # cross(j, n) = j.y for n = (-1, 0)
                        sy = 0.0  # projected onto n: (sx, 0)
                    if sx != ox or sy != oy:
                        changed[l] = True
                    bd[l, q, G0], bd[l, q, G1] = sx, sy
                    bd[l, q, V0] += (sx - ox) * mi
                    bd[l, q, V1] += (sy - oy) * mi
            any_sweep = False
            for l in range(L):
                if not sweep[l]:
                    continue
                b = b0 + l
                sm_inv = s_m_inv[b]
                if n_link[b] and links_sweep(n_link[b], lq[l], lf[l], bd[l], MI, V0, V1):  # the lattice's, in order
                    changed[l] = True
                if fixed[b]:
                    s0, s1 = r_s[l, 0], r_s[l, 1]
                    kinv = sm_inv / (sm_inv * sm_inv)
                    jx = kinv * (0.0 - s0)
                    jy = kinv * (sgb_y_[l] - s1)
                    ox, oy = r_s[l, 4], r_s[l, 5]
                    sx, sy = 0.0, oy + jy  # never at the track's ends: projected onto n = (0, 1)
                    if sx != ox or sy != oy:
                        changed[l] = True
                    r_s[l, 4], r_s[l, 5] = sx, sy
                    r_s[l, 0] = s0 + (sx - ox) * sm_inv
                    r_s[l, 1] = s1 + (sy - oy) * sm_inv
                if hold[b]:
                    s0, s1 = r_s[l, 0], r_s[l, 1]
                    kinv = sm_inv / (sm_inv * sm_inv)
                    jx = kinv * (hgb_x_[l] - s0)
                    ox, oy = r_s[l, 6], r_s[l, 7]
                    sx, sy = ox + jx, 0.0  # never at the groove's ends: projected onto n = (-1, 0)
                    if sx != ox or sy != oy:
                        changed[l] = True
                    r_s[l, 6], r_s[l, 7] = sx, sy
                    r_s[l, 0] = s0 + (sx - ox) * sm_inv
                    r_s[l, 1] = s1 + (sy - oy) * sm_inv
                if not changed[l] or it + 1 >= iterations[b]:
                    sweep[l] = False
                else:
                    any_sweep = True
            if not any_sweep:
                break
        for l in range(L):
            if not live[l]:
                continue
            b = b0 + l
            N = n_lower[b]
            U = n_upper[b]
            S = n_seg[b]
            h = dt[b]
            settle = settling[b]
            k = nstep[b]  # as at this step's start: only the lines below advance it
            na, n_isl = na_[l], n_isl_[l]
            sv[b, 0], sv[b, 1], svb[b, 0], svb[b, 1] = r_s[l, 0], r_s[l, 1], r_s[l, 2], r_s[l, 3]
            sgj[b, 0], sgj[b, 1] = r_s[l, 4], r_s[l, 5]
            hold_j[b, 0], hold_j[b, 1] = r_s[l, 6], r_s[l, 7]
            for q in range(n_isl):
                i = isl[l, q]
                lv[b, i, 0], lv[b, i, 1] = bd[l, q, V0], bd[l, q, V1]
                lvb[b, i, 0], lvb[b, i, 1] = bd[l, q, B0], bd[l, q, B1]
                gj[b, i, 0], gj[b, i, 1] = bd[l, q, G0], bd[l, q, G1]
            n_c = 0
            for a in range(na):
                for c in range(a_cnt[l, a]):
                    jn[l, a, c], jt[l, a, c] = pt[l, n_c, JN], pt[l, n_c, JT]
                    n_c += 1
            remember(b, N, U, S, na, a_j[l], a_i[l], a_cnt[l], key[l], jn[l], jt[l], c_n, c_key, c_jn, c_jt, s_n, s_key,
                     s_jn, s_jt)
            if not settle:  # settling is before t = 0: it counts no step
                nstep[b] = k + 1
            # 7. projection back onto the tracks; the static/kinetic switch
            project(b, 0 if lat[b] else N, lp, lv, lx0, sp, sv, fixed, track_y)  # (a lattice has no tracks)
            if switch_on[b] and not settle:
                switch(b, N, na, a_i[l], a_nx[l], a_ny[l], sv, lv, slips, seen, present, stuck, slid, mu, mu_s, mu_k,
                       v_stick, slip_dist, h)
            # divergence guard and the record
            if not (math.isfinite(sp[b, 0]) and math.isfinite(sp[b, 1]) and math.isfinite(sv[b, 0])
                    and math.isfinite(sv[b, 1])):
                fail[b] = NONFINITE
                fail_step[b] = k + 1
                running[l] = False
                continue
            if settle:
                continue
            if (k + 1) % rec_every == 0 and rec_at[b] < rec.shape[2]:
                record(b, rec, rec_at, sp, sv, na, a_nx[l], a_ny[l], a_cnt[l], jn[l], jt[l], h, spring, dk, dc, dv,
                        dorigin, dforce, k + 1)
            # the stops, at the run loop's samples: every rec_every steps of this call and at its end
            if local[l] % rec_every == 0 or local[l] == steps[b]:
                code = stop(b, k, sp, sv, stop_x, stuck_v, stuck_dwell, slow_since, v_unit, dt_s, off_x)
                if code != STOP_NONE:
                    stop_code[b] = code
                    running[l] = False


def groups(B: int) -> int:
    """How many groups a batch of ``B`` scenes is stepped in: a multiple of Numba's threads, each
    of at most :data:`LANES` scenes, the scenes shared out as evenly as they go (a thread left
    with fewer scenes than the others would wait for them; at most ``B``)."""
    threads = get_num_threads()
    return min(B, threads * -(-B // (threads * LANES)))


@njit(parallel=True, cache=True, error_model="numpy")
def advance(steps, rec_every, rec_at, rec, lp, lv, lvb, gj, sp, sv, svb, sgj,
            c_n, c_key, c_jn, c_jt, stuck, slid, mu, present, nstep, fail, fail_step,
            lx0, lverts, lnorms, nv_l, lm_inv, lk, lc, ldown, lup, n_lower,
            uverts, unorms, nv_u, n_upper, s_m_inv, fixed, track_y, g_x, g_y,
            spring, dk, dc, dv, dorigin, dforce, load,
            dt, iterations, slop, bias_coef, joint_bias_coef, restitution,
            mu_s, mu_k, v_stick, slip_dist, switch_on, seg_a, seg_b, seg_n, n_seg, seg_mu, s_n, s_key, s_jn, s_jt, stop_x, first,
            settling, damp, push, hold, hold_x, hold_j, hold_coef, stop_code, stuck_v, stuck_dwell,
            slow_since, v_unit, dt_s, off_x, lat, n_link, link_ab, link_p, link_kc, n_groups):
    """Advance every scene ``b`` of the batch by ``steps[b]`` steps: ``n_groups`` groups of
    consecutive scenes (:func:`groups`), in parallel over the groups."""
    B = steps.shape[0]
    for g in prange(n_groups):
        b0 = g * B // n_groups
        _step_group(b0, (g + 1) * B // n_groups - b0, steps, rec_every, rec_at, rec, lp, lv, lvb, gj, sp, sv, svb, sgj,
                    c_n, c_key, c_jn, c_jt, stuck, slid, mu, present, nstep, fail, fail_step,
                    lx0, lverts, lnorms, nv_l, lm_inv, lk, lc, ldown, lup, n_lower,
                    uverts, unorms, nv_u, n_upper, s_m_inv, fixed, track_y, g_x, g_y,
                    spring, dk, dc, dv, dorigin, dforce, load,
                    dt, iterations, slop, bias_coef, joint_bias_coef, restitution,
                    mu_s, mu_k, v_stick, slip_dist, switch_on, seg_a, seg_b, seg_n, n_seg, seg_mu, s_n, s_key, s_jn, s_jt, stop_x, first,
                    settling, damp, push, hold, hold_x, hold_j, hold_coef, stop_code, stuck_v, stuck_dwell,
                    slow_since, v_unit, dt_s, off_x, lat, n_link, link_ab, link_p, link_kc)
