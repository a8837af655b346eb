"""The batched engine's contact geometry and record (Numba): Chipmunk's support edges and contact
points, the slider's tips against the static segments, the contacts kept for the next step's
warm start, one sample of a scene.

Part of :mod:`asperity2d.engine` (used by :mod:`.batched_kernel`, only where Numba is installed).
Everything is in the engine's internal units.
"""

from __future__ import annotations

import numpy as np
from numba import njit

#: Failure codes (per scene): 0 ok; the others name why a scene stopped.
OK, NONFINITE, OVERLAP, PAIRS = 0, 1, 2, 4
#: A contact's key, the pair of vertices it joins: a * KEY_BASE + b (more than any outline's vertices).
KEY_BASE = 1 << 16
#: Recorded columns per sample (the Result's slider columns but t and drive_x, which the
#: Python side makes from the step count).
N_REC = 9  # x, vx, y, vy, drive force, fx, fy, f_tangential, contact count

DBL_MAX = 1.7976931348623157e308


@njit(inline="always")
def clamp01(t):
    return 0.0 if t < 0.0 else (1.0 if t > 1.0 else t)


@njit(cache=True)
def placed(verts, nv, px, py, wx, wy):
    """The first ``nv`` vertices of an outline, ``verts``, moved by (px, py) into ``wx`` and ``wy``;
    their bounding box (left, right, bottom, top)."""
    left, right, bottom, top = np.inf, -np.inf, np.inf, -np.inf
    for q in range(nv):
        wx[q] = verts[q, 0] + px
        wy[q] = verts[q, 1] + py
        left, right = min(left, wx[q]), max(right, wx[q])
        bottom, top = min(bottom, wy[q]), max(top, wy[q])
    return left, right, bottom, top


@njit(cache=True)
def penetration(norms_b, nb, norms_a, na, bx, by, ax, ay):
    """The separating-axis test of two placed convex outlines, B (``nb`` vertices ``bx``, ``by``,
    outward normals ``norms_b``) and A: the minimum penetration over the Minkowski difference's
    edge normals m (B's outward normals and A's negated), h(m) = max_B m.b - min_A m.a, as
    ``(depth, m_x, m_y)``; a negative depth: separated."""
    best, mx, my = np.inf, 0.0, 0.0
    for side in range(2):
        for e in range(nb if side == 0 else na):
            if side == 0:
                ex, ey = norms_b[e, 0], norms_b[e, 1]
            else:
                ex, ey = -norms_a[e, 0], -norms_a[e, 1]
            hb, ha = -np.inf, np.inf
            for q in range(nb):
                hb = max(hb, bx[q] * ex + by[q] * ey)
            for q in range(na):
                ha = min(ha, ax[q] * ex + ay[q] * ey)
            depth = hb - ha
            if depth < best:
                best, mx, my = depth, ex, ey
    return best, mx, my


@njit(cache=True)
def support_edge(vx, vy, nxs, nys, px, py, n_x, n_y, nv):
    """Chipmunk's SupportEdgeForPoly for a convex polygon of ``nv`` vertices translated by
    (px, py): the edge's two vertex indices (a, b)."""
    best, i1 = -np.inf, 0
    for i in range(nv):
        d = (vx[i] + px) * n_x + (vy[i] + py) * n_y
        if d > best:
            best, i1 = d, i
    i0 = (i1 - 1 + nv) % nv
    i2 = (i1 + 1) % nv
    if n_x * nxs[i1] + n_y * nys[i1] > n_x * nxs[i2] + n_y * nys[i2]:
        return i0, i1
    return i1, i2


@njit(cache=True)
def contact_points(e1ax, e1ay, e1bx, e1by, e2ax, e2ay, e2bx, e2by, n_x, n_y):
    """Chipmunk's ContactPoints of edge e1 (body a's) and edge e2 (body b's) along the normal n
    (from a to b): its two candidates, each ``(kept, p1x, p1y, p2x, p2y)`` in turn (ten values),
    p1 on e1 and p2 on e2, ``kept`` where they overlap along n."""
    d_e1_a = e1ax * n_y - e1ay * n_x
    d_e1_b = e1bx * n_y - e1by * n_x
    d_e2_a = e2ax * n_y - e2ay * n_x
    d_e2_b = e2bx * n_y - e2by * n_x
    e1_denom = min(1.0 / (d_e1_b - d_e1_a), DBL_MAX)
    e2_denom = min(1.0 / (d_e2_b - d_e2_a), DBL_MAX)
    t1 = clamp01((d_e2_b - d_e1_a) * e1_denom)
    t2 = clamp01((d_e1_a - d_e2_a) * e2_denom)
    ax, ay = e1ax * (1.0 - t1) + e1bx * t1, e1ay * (1.0 - t1) + e1by * t1
    bx, by = e2ax * (1.0 - t2) + e2bx * t2, e2ay * (1.0 - t2) + e2by * t2
    t1 = clamp01((d_e2_a - d_e1_a) * e1_denom)
    t2 = clamp01((d_e1_b - d_e2_a) * e2_denom)
    cx, cy = e1ax * (1.0 - t1) + e1bx * t1, e1ay * (1.0 - t1) + e1by * t1
    dx, dy = e2ax * (1.0 - t2) + e2bx * t2, e2ay * (1.0 - t2) + e2by * t2
    return ((bx - ax) * n_x + (by - ay) * n_y <= 0.0, ax, ay, bx, by,
            (dx - cx) * n_x + (dy - cy) * n_y <= 0.0, cx, cy, dx, dy)


@njit(cache=True)
def warm_start(keys, jns, jts, n, kk):
    """The previous step's impulses (jn, jt) of the contact keyed ``kk`` among a pair's ``n``
    cached ones (``keys``, ``jns``, ``jts``); (0, 0) for a new contact."""
    jn = jt = 0.0
    for o in range(n):
        if keys[o] == kk:
            jn, jt = jns[o], jts[o]
    return jn, jt


@njit(cache=True)
def remember(b, N, U, S, na, a_j, a_i, a_cnt, key, jn, jt, c_n, c_key, c_jn, c_jt, s_n, s_key, s_jn, s_jt):
    """Scene ``b``'s ``na`` contact pairs of this step (tip ``a_j``, lower asperity or ``N`` +
    segment ``a_i``, their points' keys and impulses) kept for the next step's :func:`warm_start`.
    The collision has set every other tip-asperity pair's count to 0; the segments' are reset here."""
    for j in range(U):
        for sg in range(S):
            s_n[b, j, sg] = 0
    for a in range(na):
        j, i = a_j[a], a_i[a]
        if i < N:
            c_n[b, j, i] = a_cnt[a]
            for c in range(a_cnt[a]):
                c_key[b, j, i, c] = key[a, c]
                c_jn[b, j, i, c] = jn[a, c]
                c_jt[b, j, i, c] = jt[a, c]
        else:
            s_n[b, j, i - N] = a_cnt[a]
            for c in range(a_cnt[a]):
                s_key[b, j, i - N, c] = key[a, c]
                s_jn[b, j, i - N, c] = jn[a, c]
                s_jt[b, j, i - N, c] = jt[a, c]


@njit(cache=True)
def static_pairs(b, j, N, S, nu, uvx, uvy, ul, ur, ub, ut, spx, spy, uverts, unorms, seg_a, seg_b, seg_n, seg_mu,
                 s_n, s_key, s_jn, s_jt, na, max_pairs, a_j, a_i, a_nx, a_ny, a_cnt, a_first, a_u, r1x, r1y,
                 r2x, r2y, key, jn, jt, fail):
    """Tip ``j`` (its world vertices ``uvx``, ``uvy`` and bounding box) of scene ``b`` against the
    scene's ``S`` static segments (the floor, a profile's valleys): each touching pair appended to
    the step's pairs from ``na`` on, warm-started from ``s_*``; returns the new ``na``.

    Chipmunk's pair is (a = the segment, b = the tip), its normal n from the segment to the tip
    (``SegmentToPoly``: the minimum-penetration axis, then ``ContactPoints`` of the segment's
    support edge and the tip's); the pair is kept here as every other (a = the slider, b = the
    segment's static body at the origin, numbered ``N + segment``), its normal -n (exact: a
    negation). The segment's two ends share one hash, so a contact is keyed by the tip's vertex.
    """
    for sg in range(S):
        sax, say = seg_a[b, sg, 0], seg_a[b, sg, 1]
        sbx, sby = seg_b[b, sg, 0], seg_b[b, sg, 1]
        if not (ul <= max(sax, sbx) and min(sax, sbx) <= ur and ub <= max(say, sby) and min(say, sby) <= ut):
            s_n[b, j, sg] = 0
            continue
        tnx, tny = seg_n[b, sg, 0], seg_n[b, sg, 1]
        # minimum penetration over the segment's two faces and the tip's negated normals
        best, mx, my = np.inf, 0.0, 0.0
        for e in range(2 + nu):
            if e == 0:
                ex, ey = tnx, tny
            elif e == 1:
                ex, ey = -tnx, -tny
            else:
                ex, ey = -unorms[b, j, e - 2, 0], -unorms[b, j, e - 2, 1]
            hb = max(sax * ex + say * ey, sbx * ex + sby * ey)
            ha = np.inf
            for q in range(nu):
                ha = min(ha, uvx[q] * ex + uvy[q] * ey)
            depth = hb - ha
            if depth < best:
                best, mx, my = depth, ex, ey
        if best < 0.0:  # separated
            s_n[b, j, sg] = 0
            continue
        # ContactPoints(SupportEdgeForSegment(seg, n), SupportEdgeForPoly(tip, -n))
        if tnx * mx + tny * my > 0.0:
            e1ax, e1ay, e1bx, e1by = sax, say, sbx, sby
        else:
            e1ax, e1ay, e1bx, e1by = sbx, sby, sax, say
        a0, a1 = support_edge(uverts[b, j, :, 0], uverts[b, j, :, 1], unorms[b, j, :, 0],
                               unorms[b, j, :, 1], spx, spy, -mx, -my, nu)
        e2ax, e2ay, e2bx, e2by = uvx[a0], uvy[a0], uvx[a1], uvy[a1]
        if na >= max_pairs:
            fail[b] = PAIRS
            break
        q = contact_points(e1ax, e1ay, e1bx, e1by, e2ax, e2ay, e2bx, e2by, mx, my)
        cnt = 0
        for w in range(2):
            kept, p1x, p1y, p2x, p2y = q[:5] if w == 0 else q[5:]
            if not kept:
                continue
            kk = a1 if w == 0 else a0  # the segment's ends share one hash: the tip's vertex keys it
            r1x[na, cnt], r1y[na, cnt] = p2x - spx, p2y - spy
            r2x[na, cnt], r2y[na, cnt] = p1x, p1y
            key[na, cnt] = kk
            jn[na, cnt], jt[na, cnt] = warm_start(s_key[b, j, sg], s_jn[b, j, sg], s_jt[b, j, sg], s_n[b, j, sg], kk)
            cnt += 1
        if cnt == 0:
            s_n[b, j, sg] = 0
            continue
        a_first[na] = s_n[b, j, sg] == 0
        a_j[na], a_i[na], a_nx[na], a_ny[na], a_cnt[na] = j, N + sg, -mx, -my, cnt
        a_u[na] = seg_mu[b]
        na += 1
    return na


@njit(cache=True)
def record(b, rec, rec_at, sp, sv, na, a_nx, a_ny, a_cnt, jn, jt, h, spring, dk, dc, dv, dorigin,
            dforce, step):
    """One sample of scene ``b``: the slider's state, the drive force, the contact forces."""
    x, vx = sp[b, 0], sv[b, 0]
    if spring[b]:
        f_drive = dk[b] * ((dorigin[b] + dv[b] * step * h) - x) + dc[b] * (dv[b] - vx)
    else:
        f_drive = dforce[b]
    fx = fy = ft = 0.0
    deepest = 0.0
    count = 0
    for a in range(na):
        n_x, n_y = a_nx[a], a_ny[a]
        for c in range(a_cnt[a]):
            # the impulse on the slider (body a of the pair): -(n jn + perp(n) jt)
            jx = -(n_x * jn[a, c] - n_y * jt[a, c])
            jy = -(n_x * jt[a, c] + n_y * jn[a, c])
            fx += jx
            fy += jy
            jnn = jx * n_x + jy * n_y
            ty = -n_x if n_y >= 0 else n_x
            ft += (jx - jnn * n_x) * abs(n_y) + (jy - jnn * n_y) * ty
        count += 1
    r = rec_at[b]
    rec[b, 0, r] = x
    rec[b, 1, r] = vx
    rec[b, 2, r] = sp[b, 1]
    rec[b, 3, r] = sv[b, 1]
    rec[b, 4, r] = f_drive
    rec[b, 5, r] = fx / h
    rec[b, 6, r] = fy / h
    rec[b, 7, r] = -ft / h
    rec[b, 8, r] = count
    rec_at[b] = r + 1
