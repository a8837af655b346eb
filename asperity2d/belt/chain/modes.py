"""The mode of each mass at a switching instant: stuck (0) or slipping (±1), and grazes.

A frictional mass within ``SWITCH_TOL``·v_scale of belt speed sticks if the
static force it needs, F_req = m·dV/dt - F_springs+dampers, is below the limit
mu_s·N; otherwise it slips in the direction of the net force (which covers a
reversal through belt speed). At the limit itself (within SWITCH_TOL of it)
the trend of F_req decides: moving outwards, the mass slips.

**Grazes.** :func:`.phases.finder.find_event` ends a phase where a slipping mass
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

from ..phases.finder import SWITCH_TOL


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
    # per mass in plain Python floats: a switch concerns a mass or two of a short chain, where each
    # NumPy call costs more than its arithmetic. Every operation is elementwise -- the same IEEE
    # operations on the same numbers as the array form, so the same modes to the bit
    vs = np.asarray(v, dtype=float).tolist()
    prev = np.asarray(previous, dtype=int).tolist()
    tol = SWITCH_TOL * v_scale
    rel = [vi - V for vi in vs]
    at_belt = [bool(f) and abs(r) <= tol for f, r in zip(spec.frictional.tolist(), rel)]
    modes = [1 if r >= 0 else -1 for r in rel]  # off belt speed (frictionless masses never stick)
    any_at = any(at_belt)
    # the forces as if the masses at belt speed were stuck
    v_at = [V if at else vi for at, vi in zip(at_belt, vs)] if any_at else vs
    f_sd = _link_force(spec.springs, np.asarray(x, dtype=float).tolist())
    if spec.damped:
        # (without dampers the damper force is a signed zero, which changes neither f_req =
        # m·a_belt - f_sd, a_belt never being -0.0, nor any mode decided below)
        f_sd = [f + d for f, d in zip(f_sd, _link_force(spec.dampers, v_at))]
    f_req = [m * a_belt - f for m, f in zip(spec.masses, f_sd)]
    if any_at:
        above, below = (band.tolist() for band in spec.limit_band)
        outside = [at and abs(f) > up for at, f, up in zip(at_belt, f_req, above)]
        border = [at and not out and abs(f) >= low for at, out, f, low in zip(at_belt, outside, f_req, below)]
        modes = [-_sign(f) if out else (0 if at else mode) for at, out, f, mode in zip(at_belt, outside, f_req, modes)]
        if any(border):
            # at the static limit: compare the trend of the required force with the tentative modes
            a = [a_belt if mode == 0 else (f - mode * kin) / m
                 for mode, f, kin, m in zip(modes, f_sd, spec.kinetic_force.tolist(), spec.masses)]
            df_req = [-(fk + fc) for fk, fc in zip(_link_force(spec.springs, v_at), _link_force(spec.dampers, a))]
            modes = [-_sign(f if f != 0 else d) if on and (_sign(f) * d > 0 or (f == 0 and d != 0)) else mode
                     for on, f, d, mode in zip(border, f_req, df_req, modes)]
    for i in contradicted:
        if modes[i] == prev[i]:
            modes[i] = -prev[i] if prev[i] != 0 else (-_sign(f_req[i]) or 1)
    grazed = {int(i) for i in touching if at_belt[i] and prev[i] != 0 and modes[i] == prev[i]}
    grazing = np.array(sorted(grazed), dtype=np.intp)
    if any_at:
        vs = [V if at and (mode != p or mode == 0) else vi for at, mode, p, vi in zip(at_belt, modes, prev, vs)]
    return np.array(modes), np.array(vs), grazing


def _sign(value: float) -> int:
    """-1, 0 or 1 (NumPy's ``sign`` of a finite float, as an int)."""
    return (value > 0) - (value < 0)


def _link_force(links, x) -> list:
    """:func:`~.spec.link_force` of ``links`` (n+1) on the list ``x`` (n), as a list: the same
    extensions, products and differences, one float at a time."""
    tension = [x[0] * links[0]]
    tension += [(b - a) * k for a, b, k in zip(x, x[1:], links[1:])]
    tension.append((0.0 - x[-1]) * links[-1])
    return [b - a for a, b in zip(tension, tension[1:])]
