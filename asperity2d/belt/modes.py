"""The mode of each mass at a switching instant: stuck (0) or slipping (±1), and grazes.

A frictional mass within ``SWITCH_TOL``·v_scale of belt speed sticks if the
static force it needs, F_req = m·dV/dt - F_springs+dampers, is below the limit
mu_s·N; otherwise it slips in the direction of the net force (which covers a
reversal through belt speed). At the limit itself (within SWITCH_TOL of it)
the trend of F_req decides: moving outwards, the mass slips.

**Grazes.** :func:`.finder.find_event` ends a phase where a slipping mass
*touches* belt speed (its relative velocity has a minimum within the tolerance
of zero, located to machine precision). There the relative acceleration is
zero, so F_req equals the kinetic force -s·mu_k·N:

* mu_k·N below mu_s·N (beyond the tolerance): the mass sticks;
* mu_k·N = mu_s·N (Coulomb, mu_s = mu_k): F_req sits on the limit and moves
  outwards (the dip is a strict minimum), so the stick condition holds only at
  that instant: the mass keeps slipping and the instant is reported as a
  ``graze`` event, not as a stick interval. Its velocity is left as computed.
"""

from __future__ import annotations

import numpy as np

from .finder import SWITCH_TOL
from .spec import link_force


def resolve_modes(spec, x, v, V, a_belt, previous, v_scale, touching=(), contradicted=()):
    """New modes at a switching instant: returns (modes, v, grazing masses).

    ``x``, ``v`` (m, m/s) the state, ``V``, ``a_belt`` the belt speed and
    acceleration, ``previous`` the modes before the instant, ``touching`` the
    masses whose touch of belt speed ended the phase (a touch that keeps its
    mode is a graze; a bystander within the tolerance that keeps its mode is
    not an event), ``contradicted`` the masses whose event function left zero the wrong
    way at once in the phase just tried (their motion, below the event functions'
    resolution, contradicts the mode the forces gave: the mode is turned round instead
    of being chosen again). Masses that end stuck, or cross belt speed, get v = V exactly.
    """
    v = np.array(v, dtype=float)
    previous = np.asarray(previous, dtype=int)
    rel = v - V
    at_belt = spec.frictional & (np.abs(rel) <= SWITCH_TOL * v_scale)
    modes = np.where(rel >= 0, 1, -1)  # off belt speed (frictionless masses never stick)
    any_at = bool(np.count_nonzero(at_belt))  # (count_nonzero: cheaper than .any() on a few masses)
    v_at = np.where(at_belt, V, v) if any_at else v  # the forces as if the masses at belt speed were stuck
    f_sd = link_force(spec.k, x)
    if spec.damped:
        # (without dampers the damper force is a signed zero, which changes neither f_req =
        # m·a_belt - f_sd, a_belt never being -0.0, nor any mode decided below)
        f_sd = f_sd + link_force(spec.c, v_at)
    f_req = spec.m * a_belt - f_sd
    if any_at:
        above, below = spec.limit_band
        size = np.abs(f_req)
        outside = at_belt & (size > above)
        modes[at_belt] = 0
        if np.count_nonzero(outside):
            modes[outside] = -np.sign(f_req[outside]).astype(int)
        border = at_belt & ~outside & (size >= below)
        if np.count_nonzero(border):
            # at the static limit: compare the trend of the required force with the tentative modes
            a = (f_sd - modes * spec.kinetic_force) / spec.m
            a[modes == 0] = a_belt
            df_req = -(link_force(spec.k, v_at) + link_force(spec.c, a))
            leaving = border & ((np.sign(f_req) * df_req > 0) | ((f_req == 0) & (df_req != 0)))
            modes[leaving] = -np.sign(np.where(f_req != 0, f_req, df_req)[leaving]).astype(int)
    for i in contradicted:
        if modes[i] == previous[i]:
            modes[i] = -previous[i] if previous[i] != 0 else (-int(np.sign(f_req[i])) or 1)
    # (per mass in Python: `touching` holds a mass or two, and this runs at every switch)
    grazed = {int(i) for i in touching if at_belt[i] and previous[i] != 0 and modes[i] == previous[i]}
    grazing = np.array(sorted(grazed), dtype=np.intp)
    if any_at:
        snap = at_belt & ((modes != previous) | (modes == 0))
        v[snap] = V
    return modes, v, grazing
