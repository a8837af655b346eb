"""Floquet (monodromy) multipliers of belt-chain limit cycles, stick/slip switching included.

The monodromy matrix of a periodic orbit of period T through the point s is
M = ∂Φ_T/∂s, the Jacobian of the time-T flow map of the *exact* non-smooth
solver (:func:`asperity2d.belt.simulate_chain`), taken by central finite
differences. The switching (stick onsets, breakaways, reversals) is inside
Φ_T, so the saltation at every switch is in M without being written out. The
eigenvalues of M are the Floquet multipliers: one equals 1 (a shift along the
orbit comes back as itself) and the others are the multipliers of any
Poincaré map of the orbit; the cycle is stable if they all lie inside the
unit circle.

**Stick phases give zero multipliers.** While a mass is stuck its velocity
is the belt's, whatever it was: a stick onset erases the velocity
perturbation of that mass, so M loses rank once per mass that sticks during
the cycle, and a one-mass stick-slip cycle has multipliers {1, 0}: every
neighbouring orbit lands on the cycle after one stick (superstable). Those
zeros are exact, not round-off, and are counted in ``Floquet.zero``.

**Stuck masses at the base point.** A stuck mass moves with the belt; a
velocity kick off the belt speed is not a small change of its state when
mu_k·N < |F| < mu_s·N (the kick breaks it loose for good), so the flow map
is not differentiable in that direction. The base point is therefore taken
where the fewest masses are stuck, and the velocity columns of the masses
stuck there are set to zero (their velocity is the belt's): each such mass
adds a zero multiplier by construction, like a stick onset does.

**Step choice.** The state is perturbed by ``step`` times a per-coordinate
scale (the largest peak-to-peak of the positions, resp. velocities, over the
cycle). The exact solver locates switches to ~1e-15 relative, so the
round-off error of a difference quotient is ~1e-15/step and the truncation
error ~step²: the default 1e-6 balances them near 1e-9. The step must also
stay far above the solver's switching tolerance (1e-9 of its velocity scale)
and far below the distance to any grazing switch, or a perturbed orbit takes
another sequence of modes and the quotient is meaningless. The check is
built in: M is computed again with ``step/10`` and ``convergence`` is the
largest change of a multiplier; a large value flags a step that crossed a
mode change (or a grazing orbit, where M does not exist).

The base point s is chosen on the cycle at the middle of the longest
interval free of switches, so Φ_T is smooth there.

**Chains with a normal degree of freedom** (``chain["normal"]``, a
:class:`~asperity2d.belt.normal.NormalContact`): the state is (x, y, v, vy),
4n coordinates, and the openings, closings and impacts are inside Φ_T like the
switches. A rigid contact that is closed at the base point holds y = vy = 0:
those columns are zero (two zero multipliers per such mass, like a stuck
mass's velocity). A compliant contact's gap is free: a separation limit cycle
of the minimal model has four multipliers.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SceneError
from .cycles import chain_cycle

ZERO = 1e-8  # |multiplier| below max(ZERO, 10 x the step-convergence error) counts as a zero


@dataclass(frozen=True)
class Floquet:
    """Multipliers of a belt-chain limit cycle.

    ``multipliers`` (complex, by decreasing modulus, the trivial one
    included); ``trivial`` (the one nearest 1); ``period`` (s) and
    ``multiplicity`` of the cycle; ``t_point`` (s) and ``state`` (x_1..x_n m,
    v_1..v_n m/s) of the base point; ``closure`` (abs(Φ_T(s) - s) over the state
    scale: how exactly s lies on the cycle); ``step``; ``convergence``
    (largest multiplier change from ``step`` to ``step/10``); ``zero``
    (multipliers below max(1e-8, 10·convergence): stick-phase collapses); ``stuck_masses``
    (0-based masses that stick during the cycle); ``stable`` (every
    non-trivial multiplier inside the unit circle); ``matrix`` (M).

    See Also
    --------
    asperity2d.dynamics.floquet : computes one.

    Examples
    --------
    >>> from asperity2d import belt, dynamics
    >>> chain = dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...             v_belt=0.1, x0=[0.0], v0=[0.1], t_end=20.0)
    >>> result = belt.simulate_chain(**chain)  # one mass, stick-slip on the belt
    >>> f = dynamics.floquet(chain)
    >>> [float(round(abs(m), 6)) for m in f.multipliers]  # the trivial 1; sticking collapses the other
    [1.0, 0.0]
    """

    multipliers: np.ndarray
    trivial: complex
    period: float
    multiplicity: int
    t_point: float
    state: np.ndarray
    closure: float
    step: float
    convergence: float
    zero: int
    stuck_masses: tuple
    stable: bool
    matrix: np.ndarray

    def to_dict(self) -> dict:
        return {
            "multipliers": [[float(m.real), float(m.imag)] for m in self.multipliers],
            "moduli": [float(abs(m)) for m in self.multipliers],
            "trivial": [float(self.trivial.real), float(self.trivial.imag)],
            "period_s": self.period, "multiplicity": self.multiplicity, "t_point_s": self.t_point,
            "state": self.state.tolist(), "closure": self.closure, "step": self.step,
            "convergence": self.convergence, "zero": self.zero, "stuck_masses": list(self.stuck_masses),
            "stable": self.stable,
        }


def flow_map(chain: dict, state, duration: float) -> np.ndarray:
    """Φ_duration(state): the exact solver's state (x..., v...) after ``duration`` s from ``state``.

    ``chain`` holds the keyword arguments of ``simulate_chain`` (its
    ``x0``, ``v0``, ``t_end`` and sampling are replaced). The belt speed must
    be constant: the flow map of an autonomous chain does not depend on the
    start time.

    Parameters
    ----------
    chain : dict
        ``simulate_chain`` keyword arguments.
    state : array_like
        (x_1..x_n in m, v_1..v_n in m/s).
    duration : float
        Time (s).

    Returns
    -------
    numpy.ndarray
        The state after ``duration``.

    See Also
    --------
    asperity2d.dynamics.monodromy

    Examples
    --------
    >>> from asperity2d import belt, dynamics
    >>> chain = dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...             v_belt=0.1, x0=[0.0], v0=[0.1], t_end=20.0)
    >>> result = belt.simulate_chain(**chain)  # one mass, stick-slip on the belt
    >>> dynamics.flow_map(chain, [0.0, 0.1], 0.3924)  # carried by the belt until it slips at x = 0.03924 m
    array([0.0392, 0.1   ])
    """
    from ..belt import simulate_chain

    state = np.asarray(state, dtype=float)
    kw = {k: v for k, v in chain.items() if k not in ("n_samples", "t_eval", "include_events")}
    if chain.get("normal") is not None:  # (x, y, v, vy): the normal degree of freedom
        n = state.size // 4
        kw.update(x0=state[:n].tolist(), y0=state[n:2 * n].tolist(), v0=state[2 * n:3 * n].tolist(),
                  vy0=state[3 * n:].tolist(), t_end=float(duration))
        r = simulate_chain(**kw, n_samples=2, include_events=False)
        return np.concatenate([r.x[:, -1], r.y[:, -1], r.v[:, -1], r.vy[:, -1]])
    n = state.size // 2
    kw.update(x0=state[:n].tolist(), v0=state[n:].tolist(), t_end=float(duration))
    r = simulate_chain(**kw, n_samples=2, include_events=False)
    return np.concatenate([r.x[:, -1], r.v[:, -1]])


def monodromy(chain: dict, state, period: float, *, step: float = 1e-6, scale=None,
              coordinates=None) -> np.ndarray:
    """∂Φ_period/∂state by central differences (see the module docstring for ``step``).

    ``scale`` (2n,) sets the size of each coordinate's perturbation
    (``step * scale``); default: 1 for every coordinate. Only the columns in
    ``coordinates`` (indices, default all) are differenced; the others are
    zero (used for the velocities of stuck masses).

    Parameters
    ----------
    chain : dict
        ``simulate_chain`` keyword arguments.
    state : array_like
        A point of the cycle (x..., v...).
    period : float
        The cycle's period (s).
    step : float, default 1e-6
        Relative perturbation.
    scale : array_like, optional
        Size of each coordinate's perturbation.
    coordinates : sequence of int, optional
        The columns differenced.

    Returns
    -------
    numpy.ndarray
        (2n, 2n).

    See Also
    --------
    asperity2d.dynamics.floquet

    Examples
    --------
    >>> from asperity2d import belt, dynamics
    >>> chain = dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...             v_belt=0.1, x0=[0.0], v0=[0.1], t_end=20.0)
    >>> result = belt.simulate_chain(**chain)  # one mass, stick-slip on the belt
    >>> cycle = dynamics.chain_cycle(result)
    >>> section = dynamics.chain_section(result)
    >>> M = dynamics.monodromy(chain, section.points[-1], cycle.period)
    >>> M.shape
    (2, 2)
    """
    if callable(chain.get("v_belt")):
        raise SceneError("`v_belt` must be constant for a monodromy matrix (the flow must be autonomous)")
    if not np.isfinite(period) or period <= 0:
        raise SceneError(f"`period` must be > 0, got {period!r}")
    if not np.isfinite(step) or not 0 < step < 1:
        raise SceneError(f"`step` must be in (0, 1), got {step!r}")
    state = np.asarray(state, dtype=float)
    scale = np.ones(state.size) if scale is None else np.asarray(scale, dtype=float)
    M = np.zeros((state.size, state.size))
    for j in (range(state.size) if coordinates is None else coordinates):
        h = step * scale[j]
        e = np.zeros(state.size)
        e[j] = h
        M[:, j] = (flow_map(chain, state + e, period) - flow_map(chain, state - e, period)) / (2 * h)
    return M


def floquet(chain: dict, *, mass: int | None = None, step: float = 1e-6, rtol: float = 1e-6) -> Floquet:
    """Floquet multipliers of the limit cycle that ``simulate_chain(**chain)`` settles on.

    The run must reach the cycle within ``chain["t_end"]`` (found with
    :func:`~asperity2d.dynamics.chain_cycle`, ``mass`` and ``rtol``
    passed on); otherwise a SceneError says so.

    Parameters
    ----------
    chain : dict
        ``simulate_chain`` keyword arguments; ``t_end`` long enough to reach the cycle.
    mass : int, optional
        As for :func:`chain_cycle`.
    step : float, default 1e-6
        Relative size of the finite-difference perturbations.
    rtol : float, default 1e-6
        As for :func:`chain_cycle`.

    Returns
    -------
    Floquet

    Raises
    ------
    SceneError
        The run reaches no cycle.

    See Also
    --------
    asperity2d.dynamics.monodromy, asperity2d.dynamics.flow_map

    Examples
    --------
    >>> from asperity2d import belt, dynamics
    >>> chain = dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...             v_belt=0.1, x0=[0.0], v0=[0.1], t_end=20.0)
    >>> result = belt.simulate_chain(**chain)  # one mass, stick-slip on the belt
    >>> f = dynamics.floquet(chain)
    >>> round(f.period, 4), [float(round(abs(m), 6)) for m in f.multipliers]
    (0.6694, [1.0, 0.0])
    """
    from ..belt import simulate_chain

    result = simulate_chain(**{**chain, "include_events": True})
    cycle = chain_cycle(result, mass=mass, rtol=rtol)
    if not cycle.periodic:
        raise SceneError(f"no limit cycle to analyse: {cycle.message}")
    T = cycle.period
    t = result.t
    t_point = _base_time(result, T)
    k = int(np.argmin(np.abs(t - t_point)))
    t_point = float(t[k])
    last = t >= t[-1] - T
    n = result.n
    px = max(float(np.max(np.ptp(result.x[:, last], axis=1))), 1e-300)
    pv = max(float(np.max(np.ptp(result.v[:, last], axis=1))), abs(float(result.chain.v_belt)), 1e-300)
    held = np.flatnonzero(result.state[:, k] == 0)  # stuck at the base point: v_i = V is not free
    if chain.get("normal") is None:
        state = np.concatenate([result.x[:, k], result.v[:, k]])
        scale = np.concatenate([np.full(n, px), np.full(n, pv)])
        free = np.setdiff1d(np.arange(2 * n), n + held)
    else:
        state = np.concatenate([result.x[:, k], result.y[:, k], result.v[:, k], result.vy[:, k]])
        py = max(float(np.max(np.ptp(result.y[:, last], axis=1))), 1e-300)
        pvy = max(float(np.max(np.ptp(result.vy[:, last], axis=1))), 1e-300)
        scale = np.concatenate([np.full(n, px), np.full(n, py), np.full(n, pv), np.full(n, pvy)])
        fixed = list(2 * n + held)
        if result.contact.normal.rigid:  # a closed rigid contact holds y = vy = 0
            closed = np.flatnonzero(result.state[:, k] != 2)
            fixed += list(n + closed) + list(3 * n + closed)
        free = np.setdiff1d(np.arange(4 * n), fixed)
    closure = float(np.max(np.abs(flow_map(chain, state, T) - state) / scale))
    M = monodromy(chain, state, T, step=step, scale=scale, coordinates=free)
    M_fine = monodromy(chain, state, T, step=step / 10, scale=scale, coordinates=free)
    mu = _sorted_eig(M)
    convergence = float(np.max(np.abs(mu - _sorted_eig(M_fine))))
    trivial_i = int(np.argmin(np.abs(mu - 1)))
    others = np.delete(mu, trivial_i)
    stuck = tuple(i for i, per in enumerate(result.stick_intervals)
                  if any(b > t[-1] - T and a < t[-1] for a, b in per))
    return Floquet(multipliers=mu, trivial=complex(mu[trivial_i]), period=T, multiplicity=cycle.multiplicity,
                   t_point=t_point, state=state, closure=closure, step=step, convergence=convergence,
                   zero=int(np.sum(np.abs(mu) < max(ZERO, 10 * convergence))), stuck_masses=stuck,
                   stable=bool(np.all(np.abs(others) < 1)), matrix=M)


def _sorted_eig(M) -> np.ndarray:
    """Eigenvalues by decreasing modulus (ties by angle), so two computations pair up."""
    mu = np.linalg.eigvals(M)
    return mu[np.lexsort((np.angle(mu), -np.abs(mu)))]


def _base_time(result, period) -> float:
    """Middle of a switch-free interval of the cycle, moved into the run's last period.

    Among the intervals between consecutive switches, the one with the fewest
    stuck masses wins (the longest on a tie): a stuck mass's velocity is not
    a free coordinate (see :func:`floquet`).
    """
    t_end = float(result.t[-1])
    a = t_end - period
    times = np.array(sorted(e.t for e in result.events if a - period <= e.t <= t_end))
    if times.size < 2:
        return t_end - 0.5 * period
    gaps = np.diff(times)
    mids = times[:-1] + 0.5 * gaps
    idx = np.minimum(np.searchsorted(result.t, mids), result.t.size - 1)
    stuck = np.sum(result.state[:, idx] == 0, axis=0)
    i = int(np.lexsort((-gaps, stuck))[0])
    mid = float(mids[i])
    return mid + period if mid < a else mid
