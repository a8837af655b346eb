"""The batched engine's end of a step (Numba): the projection back onto the tracks, the
static/kinetic switch with its hold rule, and the run loop's stops.

Part of :mod:`asperity2d.engine` (used by :mod:`.batched_kernel`, only where Numba is installed),
as the pymunk path does them after each step (:mod:`.core`, :mod:`.contacts`,
:mod:`asperity2d.stops`). Everything is in the engine's internal units.
"""

from __future__ import annotations

from numba import njit

#: Why a scene's call ended before its steps were done (``stop_code``): 0 it ran them all;
#: its slider passed the surface, stuck, or (a free slider) ran off its far end.
STOP_NONE, STOP_PASSED, STOP_STUCK, STOP_OFF = 0, 1, 2, 3


@njit(cache=True, error_model="numpy")
def project(b, N, lp, lv, lx0, sp, sv, fixed, track_y):
    """Scene ``b``'s bodies back onto their tracks when one drifted more than ``1e-9`` bases."""
    drift = 0.0
    for i in range(N):
        drift = max(drift, abs(lp[b, i, 0] - lx0[b, i]))
    if fixed[b]:
        drift = max(drift, abs(sp[b, 1] - track_y[b]))
    if drift > 1e-9:
        for i in range(N):
            lp[b, i, 0] = lx0[b, i]
            lv[b, i, 0] = 0.0
        if fixed[b]:
            sp[b, 1] = track_y[b]
            sv[b, 1] = 0.0


@njit(cache=True, error_model="numpy")
def switch(b, N, na, a_i, a_nx, a_ny, sv, lv, slips, seen, present, stuck, slid, mu, mu_s, mu_k, v_stick,
           slip_dist, h):
    """Scene ``b``'s static/kinetic switch (:class:`asperity2d.contact_laws.StaticKineticSwitch`):
    per lower asperity the largest slip over this step's ``na`` contacts (``a_i``, normal ``a_nx``,
    ``a_ny``), then its coefficient by the hold rule."""
    for i in range(N):
        slips[i] = -1.0
        seen[i] = False
    for a in range(na):
        i = a_i[a]
        if i >= N:  # a static segment keeps its coefficient
            continue
        n_x, n_y = a_nx[a], a_ny[a]
        s = abs((sv[b, 0] - lv[b, i, 0]) * n_y - (sv[b, 1] - lv[b, i, 1]) * n_x)
        if s > slips[i]:
            slips[i] = s
        seen[i] = True
    for i in range(N):
        if not seen[i]:
            if present[b, i]:
                stuck[b, i], slid[b, i], mu[b, i] = False, 0.0, mu_k[b]
            present[b, i] = False
            continue
        s = slips[i]
        if not present[b, i]:
            st, sd = s < v_stick[b], 0.0
        elif stuck[b, i]:
            if s > v_stick[b]:
                sd = slid[b, i] + s * h
                st = not (sd > slip_dist[b])
            else:
                st, sd = True, 0.0
        elif s < v_stick[b]:
            st, sd = True, 0.0
        else:
            st, sd = False, slid[b, i]
        stuck[b, i], slid[b, i] = st, sd
        mu[b, i] = mu_s[b] if st else mu_k[b]
        present[b, i] = True


@njit(cache=True, error_model="numpy")
def stop(b, k, sp, sv, stop_x, stuck_v, stuck_dwell, slow_since, v_unit, dt_s, off_x):
    """The run loop's stops for scene ``b`` after its step ``k + 1``: the stop code
    (:data:`STOP_NONE` to go on)."""
    if sp[b, 0] > stop_x[b]:  # Passed
        return STOP_PASSED
    if stuck_v[b] > 0.0:  # Stuck: |v| under stuck_v (m/s) for stuck_dwell (s)
        t = (k + 1) * dt_s[b]
        if abs(sv[b, 0] * v_unit[b]) >= stuck_v[b]:
            slow_since[b] = -1.0
        else:
            if slow_since[b] < 0.0:
                slow_since[b] = t
            if t - slow_since[b] >= stuck_dwell[b]:
                return STOP_STUCK
    if sp[b, 0] > off_x[b]:  # a free slider past the far end of the surface
        return STOP_OFF
    return STOP_NONE
