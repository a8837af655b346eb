"""The batched engine's lattice links (Numba): Ooten's MATLAB lattice, whose peaks are joined to
their neighbours and the two walls by horizontal spring-dampers.

Part of :mod:`asperity2d.engine` (used by :mod:`.batched_kernel`, only where Numba is installed).
Each link is Chipmunk's ``cpDampedSpring`` (``cpDampedSpring.c``) as the pymunk adapter builds it
(:mod:`asperity2d.engine.space`'s lattice: between body centres, a wall's end a point of the
static body one mean pitch outside the end peak); its sweep, ``applyImpulse``, runs in the
kernel's island sweeps. Everything is in the engine's internal units.
"""

from __future__ import annotations

import math

from numba import njit

#: A link's per-lane fields (``lf[lane, link, field]``): its direction, mass ``1 / k``, exact
#: damping coefficient ``1 - exp(-c dt k)``, the damping's target velocity and the accumulated
#: impulse ``jAcc`` (the damping's impulse is taken through it, as Chipmunk clamps it to the
#: link's maximum force, which is unbounded here: ``(jAcc + j) - jAcc``, not always ``j``).
LNX, LNY, LNM, LVC, LTG, LJA = range(6)
N_LINK = 6


@njit(cache=True, error_model="numpy")
def links_prestep(b, l, h, lp, lv, lm_inv, n_link, link_ab, link_p, link_kc, lf):
    """Scene ``b``'s links' ``preStep`` in the space's order: each link's direction, mass and
    damping coefficient into lane ``l``'s rows of ``lf``, and its spring force
    ``(rest - length) k`` as an impulse ``f dt`` on its two bodies.

    A link joins bodies ``link_ab[b, e]`` (-1: the static body); each end is where Chipmunk
    puts it, the body's position plus its anchor ``link_p[b, e]`` (zero at a body's centre, a
    point of the static body at a wall); ``link_kc[b, e]`` is its rest length, stiffness and
    damping."""
    for e in range(n_link[b]):
        ia, ib = link_ab[b, e, 0], link_ab[b, e, 1]
        ax = (lp[b, ia, 0] if ia >= 0 else 0.0) + link_p[b, e, 0]
        ay = (lp[b, ia, 1] if ia >= 0 else 0.0) + link_p[b, e, 1]
        bx = (lp[b, ib, 0] if ib >= 0 else 0.0) + link_p[b, e, 2]
        by = (lp[b, ib, 1] if ib >= 0 else 0.0) + link_p[b, e, 3]
        dx, dy = bx - ax, by - ay
        dist = math.sqrt(dx * dx + dy * dy)
        inv = 1.0 / dist if dist != 0.0 else 0.0  # 1 / (dist ? dist : INFINITY)
        n_x, n_y = dx * inv, dy * inv
        ma = lm_inv[b, ia] if ia >= 0 else 0.0
        mb = lm_inv[b, ib] if ib >= 0 else 0.0
        k = ma + mb  # k_scalar: the bodies cannot rotate
        lf[l, e, LNX], lf[l, e, LNY] = n_x, n_y
        lf[l, e, LNM] = 1.0 / k
        lf[l, e, LVC] = 1.0 - math.exp(-link_kc[b, e, 2] * h * k)
        lf[l, e, LTG] = 0.0
        j = (link_kc[b, e, 0] - dist) * link_kc[b, e, 1] * h
        lf[l, e, LJA] = j
        jx, jy = n_x * j, n_y * j
        if ia >= 0:  # apply_impulses: -j on a, then j on b
            lv[b, ia, 0] = lv[b, ia, 0] + (-jx) * ma
            lv[b, ia, 1] = lv[b, ia, 1] + (-jy) * ma
        if ib >= 0:
            lv[b, ib, 0] = lv[b, ib, 0] + jx * mb
            lv[b, ib, 1] = lv[b, ib, 1] + jy * mb


@njit(cache=True, error_model="numpy")
def links_sweep(n, lq, lf, bd, mi, v0, v1):
    """One sweep of a lane's ``n`` links in order (``applyImpulse``: each link's damping towards
    its target, the impulse taken through ``jAcc``) on the lane's island rows ``bd``, whose
    columns ``mi``, ``v0``, ``v1`` hold a body's inverse mass and velocity (the static body's
    row: zeros); ``lq``: each link's two rows. Whether any target or impulse changed."""
    changed = False
    for e in range(n):
        qa, qb = lq[e, 0], lq[e, 1]
        n_x, n_y = lf[e, LNX], lf[e, LNY]
        vrn = (bd[qb, v0] - bd[qa, v0]) * n_x + (bd[qb, v1] - bd[qa, v1]) * n_y
        v_damp = (lf[e, LTG] - vrn) * lf[e, LVC]
        target = vrn + v_damp
        if v_damp != 0.0 or target != lf[e, LTG]:
            changed = True
        lf[e, LTG] = target
        j_acc = lf[e, LJA]
        j = (j_acc + v_damp * lf[e, LNM]) - j_acc
        lf[e, LJA] = j_acc + j
        jx, jy = n_x * j, n_y * j
        bd[qa, v0] += (-jx) * bd[qa, mi]  # apply_impulses: -j on a, then j on b
        bd[qa, v1] += (-jy) * bd[qa, mi]
        bd[qb, v0] += jx * bd[qb, mi]
        bd[qb, v1] += jy * bd[qb, mi]
    return changed
