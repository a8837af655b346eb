"""Poincaré sections: where a trajectory crosses a plane, and its state there.

A **Poincaré section** is where a trajectory crosses a plane ``s(t) = 0`` in a
chosen direction. For belt chains the natural plane is a mass's velocity
equal to the belt speed, crossed from below: on the exact solver's output
that is the stick onset itself, sampled exactly (the solver records a sample
at every switching instant, with v = V to the last bit in a stick), so the
section times are exact. Elsewhere a crossing is located by a cubic through
the four samples around it (linear where a cubic does not bracket it), and
the other coordinates are interpolated linearly at that time.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SceneError
from .signals import belt_speed, check_series, is_belt


@dataclass(frozen=True)
class Section:
    """Crossings of a Poincaré plane: ``t`` (K,) s, ``points`` (K, d) SI, ``names`` of the d coordinates.

    See Also
    --------
    asperity2d.dynamics.chain_section : make one.
    asperity2d.dynamics.poincare_section
    asperity2d.dynamics.opening_section

    Examples
    --------
    >>> from asperity2d import belt, dynamics
    >>> chain = dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...             v_belt=0.1, x0=[0.0], v0=[0.1], t_end=20.0)
    >>> result = belt.simulate_chain(**chain)  # one mass, stick-slip on the belt
    >>> section = dynamics.chain_section(result)
    >>> section.names, section.points.shape
    (('x1', 'v1'), (29, 2))
    >>> section.t[:3].round(4)  # stick onsets (s)
    array([0.8656, 1.5349, 2.2043])
    """

    t: np.ndarray
    points: np.ndarray
    names: tuple
    description: str


def crossings(t, s, *, direction: int = 1, hysteresis: float = 0.0) -> np.ndarray:
    """Times (s) where ``s`` crosses zero upward (``direction=1``), downward (-1) or either (0).

    An upward crossing is a sample with s >= 0 after one with s < 0; a
    sample exactly at zero is the crossing time itself. With ``hysteresis``
    h > 0 (unit of s) an upward crossing counts only if s went below -h
    since the previous one (and a downward one above +h), so noise riding on
    the level does not add crossings; the times are still those where s = 0.

    Parameters
    ----------
    t, s : array_like
        Times (s) and the signal.
    direction : {1, -1, 0}, default 1
        Upward, downward or either.
    hysteresis : float, default 0.0
        Dip needed before a crossing counts (unit of ``s``).

    Returns
    -------
    numpy.ndarray
        Crossing times (s), interpolated between samples.

    See Also
    --------
    asperity2d.dynamics.poincare_section

    Examples
    --------
    >>> import numpy as np
    >>> from asperity2d import dynamics
    >>> t = np.linspace(0.0, 1.0, 1001)
    >>> dynamics.crossings(t, np.sin(2 * np.pi * 3 * t)).round(4)  # upward, after the start
    array([0.3333, 0.6667])
    """
    t, s = np.asarray(t, dtype=float), np.asarray(s, dtype=float)
    if direction not in (-1, 0, 1):
        raise SceneError(f"`direction` must be -1, 0 or 1, got {direction!r}")
    if not np.isfinite(hysteresis) or hysteresis < 0:
        raise SceneError(f"`hysteresis` must be >= 0, got {hysteresis!r}")
    sg = np.sign(s)
    found = []
    for sense in ((1, -1) if direction == 0 else (direction,)):
        hits = np.flatnonzero((sense * sg[:-1] < 0) & (sense * sg[1:] >= 0)) + 1
        if hysteresis > 0:
            armed = np.flatnonzero(sense * s < -hysteresis)
            keep, last = [], -1
            for k in hits:
                i = np.searchsorted(armed, last, side="right")  # first arming sample after the last crossing
                if i < armed.size and armed[i] < k:
                    keep.append(k)
                    last = k
            hits = np.array(keep, dtype=int)
        found.append(hits)
    return np.array([_root(t, s, k) for k in np.sort(np.concatenate(found))])


def _root(t, s, k) -> float:
    """Zero of s between samples k-1 and k: exact sample, cubic through k-2..k+1, or linear."""
    if s[k] == 0:
        return float(t[k])
    a, b = t[k - 1], t[k]
    linear = a + (b - a) * s[k - 1] / (s[k - 1] - s[k])
    if k < 2 or k + 1 >= t.size or b <= a:
        return float(linear)
    tt, ss = t[k - 2:k + 2], s[k - 2:k + 2]
    if np.any(np.diff(tt) <= 0) or np.any(ss == 0):
        return float(linear)
    u = (tt - a) / (b - a)
    roots = np.roots(np.polyfit(u, ss, 3))
    real = roots[np.abs(roots.imag) < 1e-9].real
    real = real[(real >= 0) & (real <= 1)]
    if real.size != 1:
        return float(linear)
    return float(a + real[0] * (b - a))


def poincare_section(t, states, *, plane: int = 0, level: float = 0.0, direction: int = 1,
                     names=None) -> Section:
    """Crossings of ``states[plane] = level`` by the trajectory ``states`` (d, T) sampled at ``t``.

    Parameters
    ----------
    t : array_like
        Times (s), (T,).
    states : array_like
        The trajectory, (d, T).
    plane : int, default 0
        The coordinate that defines the plane.
    level : float, default 0.0
        Its value on the plane.
    direction : {1, -1, 0}, default 1
        Upward, downward or either.
    names : sequence of str, optional
        Names of the d coordinates.

    Returns
    -------
    Section

    See Also
    --------
    asperity2d.dynamics.chain_section : exact, for belt runs.
    asperity2d.dynamics.crossings

    Examples
    --------
    >>> import numpy as np
    >>> from asperity2d import dynamics
    >>> t = np.linspace(0.0, 2.0, 2001)
    >>> states = np.vstack([np.sin(2 * np.pi * t), np.cos(2 * np.pi * t)])
    >>> section = dynamics.poincare_section(t, states, plane=0, level=0.5)
    >>> section.t.round(4), section.points.round(3)
    (array([0.0833, 1.0833]), array([[0.5  , 0.866],
           [0.5  , 0.866]]))
    """
    states = np.atleast_2d(np.asarray(states, dtype=float))
    t, _ = check_series(t, states[0], minimum=2)
    if states.shape[1] != t.size:
        raise SceneError(f"`states` must have {t.size} columns (one per time), got shape {states.shape}")
    if not 0 <= plane < states.shape[0]:
        raise SceneError(f"`plane` must be a row index 0..{states.shape[0] - 1}, got {plane!r}")
    names = tuple(names) if names is not None else tuple(f"y{i}" for i in range(states.shape[0]))
    times = crossings(t, states[plane] - level, direction=direction)
    points = np.array([np.interp(times, t, row) for row in states]).T.reshape(times.size, states.shape[0])
    points[:, plane] = level
    return Section(times, points, names, f"{names[plane]} = {level:g} ({_dir(direction)})")


def chain_section(result, *, mass: int = 0, direction: int = 1) -> Section:
    """Section of a belt run where mass ``mass`` (0-based) reaches the belt speed (stick onsets for +1).

    Points are the full state (x_1..x_n in m, v_1..v_n in m/s) at the crossing.

    Parameters
    ----------
    result : BeltResult
        A belt run.
    mass : int, default 0
        The mass (0-based).
    direction : {1, -1}, default 1
        Upward crossings of the belt speed (stick onsets), or downward.

    Returns
    -------
    Section

    See Also
    --------
    asperity2d.dynamics.chain_cycle : the cycle on this section.

    Examples
    --------
    >>> from asperity2d import belt, dynamics
    >>> chain = dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...             v_belt=0.1, x0=[0.0], v0=[0.1], t_end=20.0)
    >>> result = belt.simulate_chain(**chain)  # one mass, stick-slip on the belt
    >>> section = dynamics.chain_section(result)
    >>> len(section.t), section.names
    (29, ('x1', 'v1'))
    """
    if not is_belt(result):
        raise SceneError("`result` must be a belt-chain result (BeltResult)")
    if isinstance(mass, bool) or not isinstance(mass, (int, np.integer)) or not 0 <= mass < result.n:
        raise SceneError(f"`mass` must be an index 0..{result.n - 1}, got {mass!r}")
    t = result.t
    slip = result.v[mass] - belt_speed(result, t)
    times = crossings(t, slip, direction=direction)
    states = np.vstack([result.x, result.v])
    idx = np.searchsorted(t, times)
    exact = (idx < t.size) & (t[np.minimum(idx, t.size - 1)] == times)
    points = np.array([np.interp(times, t, row) for row in states]).T.reshape(times.size, states.shape[0])
    # a crossing on a sample (the stick onset) takes that sample itself, not an interpolation
    points[exact] = states[:, idx[exact]].T
    names = tuple(f"x{i + 1}" for i in range(result.n)) + tuple(f"v{i + 1}" for i in range(result.n))
    return Section(times, points, names, f"v{mass + 1} = belt speed ({_dir(direction)})")


def opening_section(result, *, mass: int = 0) -> Section:
    """Section of a contact-chain run (``ContactResult``) where mass ``mass`` (0-based) loses contact.

    The openings are switching instants, sampled exactly (the solver records a sample at each, the
    first one of the flight): points are the full state (x_1..x_n, y_1..y_n in m, v_1..v_n,
    vy_1..vy_n in m/s) there, to rounding.

    Parameters
    ----------
    result : ContactResult
        A run with a normal degree of freedom (``simulate_chain(..., normal=...)``).
    mass : int, default 0
        The mass (0-based).

    Returns
    -------
    Section

    See Also
    --------
    asperity2d.dynamics.chain_section

    Examples
    --------
    >>> from asperity2d import belt, dynamics
    >>> contact = belt.simulate_chain([1.0], [100.0, 0.0], [0.0, 0.0], mu_s=0.4, mu_k=0.3, v_belt=0.1,
    ...                                x0=[0.0], v0=[0.1], t_end=2.0,
    ...                                normal=belt.NormalContact(stiffness=1e4, contact_stiffness=1e5))
    >>> len(dynamics.opening_section(contact).t)  # this mass never leaves the belt
    0
    """
    if not hasattr(result, "separation_intervals"):
        raise SceneError("`result` must be a contact-chain result (simulate_chain with `normal`)")
    if isinstance(mass, bool) or not isinstance(mass, (int, np.integer)) or not 0 <= mass < result.n:
        raise SceneError(f"`mass` must be an index 0..{result.n - 1}, got {mass!r}")
    times = np.array([a for a, _ in result.separation_intervals[mass] if a > result.t[0]])
    idx = np.searchsorted(result.t, times, side="right") - 1  # the last sample at the opening: after it
    states = np.vstack([result.x, result.y, result.v, result.vy])
    n = result.n
    names = tuple(f"{c}{i + 1}" for c in ("x", "y", "v", "vy") for i in range(n))
    return Section(times, states[:, idx].T.reshape(times.size, 4 * n), names, f"contact {mass + 1} opens")


def _dir(direction):
    return {1: "upward", -1: "downward", 0: "both ways"}[direction]
