"""Largest Lyapunov exponent: from a measured series, or from two nearby belt-chain runs.

**From a series** (:func:`lyapunov_series`): Rosenstein, Collins & De Luca
(1993). The series is delay-embedded in ``emb_dim`` dimensions with delay
``lag`` samples; every embedded point is paired with its nearest neighbour
at least ``min_tsep`` samples away in time; the mean logarithm of the pairs'
distance after k steps grows as λ·k·dt, and λ is the slope of a least-squares
line over k = 0..``trajectory_len``. With the optional ``nolds`` package
(``pip install 'asperity2d[chaos]'``) its ``lyap_r`` does this (with the
deterministic least-squares fit); without it, the same algorithm here
(``method="rosenstein"``) is used. Defaults follow nolds: ``lag`` where the
autocorrelation first falls below 1 - 1/e, ``min_tsep`` one mean period
(1 / the power-weighted mean frequency). The estimate is only as good as the
embedding: check it against ``emb_dim`` and ``trajectory_len``.

**From the equations** (:func:`chain_lyapunov`), for belt chains, Benettin et
al. (1980): a reference run and a run started ``d0`` away (in a random,
seeded direction) are both advanced ``interval`` s with the exact solver;
their separation d is measured, log(d/d0) accumulated, and the perturbed
state put back at distance d0 along the separation, ``steps`` times.
λ = Σ log(d/d0) / (steps·interval) in 1/s. Distances are measured in scaled
coordinates (positions over ``length``, velocities over ``speed``) so both
count. The first ``discard`` intervals are left out while the perturbation
turns into the most unstable direction. A limit cycle or a torus gives 0
(a shift along the orbit neither grows nor decays), steady sliding the
largest real part of its eigenvalues, chaos a positive value. A step whose
perturbation is erased entirely (d = 0, every perturbed direction stuck)
counts as log(machine epsilon) and is reported in ``collapsed_steps``: the
value is then an upper bound.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SceneError
from .signals import check_series, resample

METHODS = ("auto", "nolds", "rosenstein")


@dataclass(frozen=True)
class Lyapunov:
    """A largest-Lyapunov-exponent estimate: ``value`` (1/s), ``method`` and its settings.

    See Also
    --------
    asperity2d.dynamics.chain_lyapunov, asperity2d.dynamics.lyapunov_series : compute one.

    Examples
    --------
    >>> from asperity2d import belt, dynamics
    >>> chain = dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...             v_belt=0.1, x0=[0.0], v0=[0.1], t_end=20.0)
    >>> result = belt.simulate_chain(**chain)  # one mass, stick-slip on the belt
    >>> estimate = dynamics.chain_lyapunov(chain, steps=50)
    >>> estimate.method, abs(estimate.value) < 0.05  # a stable cycle: about 0
    ('benettin', True)
    """

    value: float
    method: str
    settings: dict

    def to_dict(self) -> dict:
        return {"value_per_s": self.value, "method": self.method, **self.settings}


def have_nolds() -> bool:
    try:
        import nolds  # noqa: F401
    except Exception:  # nolds 0.6.3 fails at import on Python < 3.12 (importlib.resources)
        return False
    return True


def lyapunov_series(t, y, *, emb_dim: int = 6, lag: int | None = None, min_tsep: int | None = None,
                    trajectory_len: int = 20, method: str = "auto", dt: float | None = None) -> Lyapunov:
    """Largest Lyapunov exponent (1/s) of ``y(t)`` (Rosenstein; see the module docstring).

    ``t`` may be non-uniform: the series is resampled at ``dt`` (default the
    median spacing) first. For a map, pass ``t = arange(len(y))``: the value
    is then per iteration.

    Parameters
    ----------
    t, y : array_like
        Times (s) and the series.
    emb_dim : int, default 6
        Embedding dimension.
    lag : int, optional
        Embedding lag (samples).
    min_tsep : int, optional
        Smallest time separation of neighbours (samples).
    trajectory_len : int, default 20
        Samples over which divergence is fitted.
    method : {"auto", "nolds", "rosenstein"}, default "auto"
        nolds when installed (the ``chaos`` extra), else the package's own Rosenstein.
    dt : float, optional
        Resampling step (s).

    Returns
    -------
    Lyapunov

    See Also
    --------
    asperity2d.dynamics.chain_lyapunov : exact, for belt chains.

    Examples
    --------
    >>> import numpy as np
    >>> from asperity2d import dynamics
    >>> x = np.empty(3000)
    >>> x[0] = 0.3
    >>> for i in range(1, 3000):
    ...     x[i] = 4 * x[i - 1] * (1 - x[i - 1])
    >>> estimate = dynamics.lyapunov_series(np.arange(3000.0), x, emb_dim=2, lag=1, min_tsep=10,
    ...                                     trajectory_len=6, method="rosenstein")
    >>> round(estimate.value, 2)  # the logistic map at r = 4: ln 2 = 0.69 per iteration
    0.69
    """
    t, y = check_series(t, y, minimum=32)
    if method not in METHODS:
        raise SceneError(f"`method` must be one of {', '.join(METHODS)}, got {method!r}")
    for name, val, low in (("emb_dim", emb_dim, 1), ("trajectory_len", trajectory_len, 2)):
        if isinstance(val, bool) or not isinstance(val, (int, np.integer)) or val < low:
            raise SceneError(f"`{name}` must be an integer >= {low}, got {val!r}")
    tu, yu = resample(t, y, dt=dt)
    step = float(tu[1] - tu[0])
    if lag is None:
        lag = _lag(yu)
    if min_tsep is None:
        min_tsep = _mean_period(yu)
    for name, val in (("lag", lag), ("min_tsep", min_tsep)):
        if isinstance(val, bool) or not isinstance(val, (int, np.integer)) or val < (1 if name == "lag" else 0):
            raise SceneError(f"`{name}` must be a positive integer, got {val!r}")
    points = yu.size - (emb_dim - 1) * lag
    if points - trajectory_len <= 2 * min_tsep + 2:
        raise SceneError(f"`y` is too short ({yu.size} samples) for emb_dim={emb_dim}, lag={lag}, "
                         f"min_tsep={min_tsep}, trajectory_len={trajectory_len}")
    settings = {"emb_dim": int(emb_dim), "lag": int(lag), "min_tsep": int(min_tsep),
                "trajectory_len": int(trajectory_len), "dt": step}
    use_nolds = method == "nolds" or (method == "auto" and have_nolds())
    if method == "nolds" and not have_nolds():
        raise SceneError("`method` 'nolds' needs the nolds package (pip install 'asperity2d[chaos]')")
    if use_nolds:
        import nolds

        value = nolds.lyap_r(yu, emb_dim=emb_dim, lag=lag, min_tsep=min_tsep, tau=step,
                             trajectory_len=trajectory_len, fit="poly")
        return Lyapunov(float(value), "nolds.lyap_r", settings)
    return Lyapunov(_rosenstein(yu, emb_dim, lag, min_tsep, trajectory_len) / step, "rosenstein", settings)


def _lag(y) -> int:
    """First lag where the autocorrelation drops below 1 - 1/e (at least 1)."""
    z = y - y.mean()
    n = z.size
    spec = np.fft.rfft(z, 2 * n)
    acf = np.fft.irfft(spec * np.conj(spec))[:n]
    if acf[0] <= 0:
        return 1
    below = np.flatnonzero(acf / acf[0] < 1 - 1 / np.e)
    return int(max(1, below[0])) if below.size else 1


def _mean_period(y) -> int:
    """1 / power-weighted mean frequency, in samples."""
    power = np.abs(np.fft.rfft(y - y.mean())) ** 2
    freq = np.fft.rfftfreq(y.size)
    if power[1:].sum() <= 0:
        return 0
    mean_f = float((freq[1:] * power[1:]).sum() / power[1:].sum())
    return int(np.ceil(1 / mean_f))


def _rosenstein(y, emb_dim, lag, min_tsep, trajectory_len) -> float:
    """Per-sample exponent: slope of the mean log divergence of nearest neighbours."""
    M = y.size - (emb_dim - 1) * lag
    X = np.stack([y[i * lag:i * lag + M] for i in range(emb_dim)], axis=1)
    usable = M - trajectory_len
    idx = np.arange(usable)
    nearest = np.empty(usable, dtype=int)
    Y = X[:usable]
    norms = np.sum(Y**2, axis=1)
    for start in range(0, usable, 1024):  # blocks of squared distances |a|² + |b|² - 2 a·b (a BLAS product)
        block = idx[start:start + 1024]
        d = norms[block, None] + norms[None, :] - 2.0 * (Y[block] @ Y.T)
        d[np.abs(block[:, None] - idx[None, :]) <= min_tsep] = np.inf
        nearest[start:start + 1024] = np.argmin(d, axis=1)
    curve = []
    for k in range(trajectory_len + 1):
        dist = np.linalg.norm(X[idx + k] - X[nearest + k], axis=1)
        dist = dist[dist > 0]
        curve.append(np.mean(np.log(dist)) if dist.size else -np.inf)
    curve = np.array(curve)
    ok = np.isfinite(curve)
    if ok.sum() < 2:
        raise SceneError("every nearest-neighbour pair coincides: the series repeats exactly (exponent -inf)")
    return float(np.polyfit(np.arange(curve.size)[ok], curve[ok], 1)[0])


def chain_lyapunov(chain: dict, *, steps: int = 200, interval: float = 1.0, d0: float = 1e-8,
                   discard: int | None = None, length: float | None = None, speed: float | None = None,
                   seed: int = 0) -> Lyapunov:
    """Largest Lyapunov exponent (1/s) of a belt chain by Benettin's method (module docstring).

    ``chain`` holds ``simulate_chain``'s keyword arguments; the run starts
    from its ``x0``, ``v0`` (its ``t_end`` is ignored). ``discard``
    defaults to a tenth of ``steps``; ``speed`` (m/s) to the solver's
    velocity scale and ``length`` (m) to ``speed`` over the highest natural
    frequency.

    Parameters
    ----------
    chain : dict
        ``simulate_chain`` keyword arguments.
    steps : int, default 200
        Renormalisation steps.
    interval : float, default 1.0
        Time between renormalisations (s).
    d0 : float, default 1e-8
        Initial separation, relative to the chain's length scale.
    discard : int, optional
        Steps left out of the average (default a tenth).
    length, speed : float, optional
        Scales of positions (m) and velocities (m/s) in the distance.
    seed : int, default 0
        The direction of the first perturbation.

    Returns
    -------
    Lyapunov
        1/s.

    See Also
    --------
    asperity2d.dynamics.lyapunov_series : from a measured series.

    Examples
    --------
    >>> from asperity2d import belt, dynamics
    >>> chain = dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...             v_belt=0.1, x0=[0.0], v0=[0.1], t_end=20.0)
    >>> result = belt.simulate_chain(**chain)  # one mass, stick-slip on the belt
    >>> estimate = dynamics.chain_lyapunov(chain, steps=50)
    >>> abs(estimate.value) < 0.05  # a stable limit cycle: about zero
    True
    """
    from .floquet import flow_map

    if callable(chain.get("v_belt")):
        raise SceneError("`v_belt` must be constant for chain_lyapunov (the flow must be autonomous)")
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 2:
        raise SceneError(f"`steps` must be an integer >= 2, got {steps!r}")
    if not np.isfinite(interval) or interval <= 0:
        raise SceneError(f"`interval` must be > 0, got {interval!r}")
    if not np.isfinite(d0) or not 0 < d0 < 1e-2:
        raise SceneError(f"`d0` must be in (0, 0.01), got {d0!r}")
    discard = steps // 10 if discard is None else discard
    if isinstance(discard, bool) or not isinstance(discard, (int, np.integer)) or not 0 <= discard < steps:
        raise SceneError(f"`discard` must be an integer in [0, steps), got {discard!r}")
    speed, length = _scales(chain, speed, length)
    n = len(chain["masses"])
    scale = np.concatenate([np.full(n, length), np.full(n, speed)])
    rng = np.random.default_rng(seed)
    s = np.concatenate([np.asarray(chain["x0"], float), np.asarray(chain["v0"], float)])
    u = rng.standard_normal(2 * n)
    p = s + d0 * scale * u / np.linalg.norm(u)
    total, collapsed = 0.0, 0
    for k in range(steps):
        s1, p1 = flow_map(chain, s, interval), flow_map(chain, p, interval)
        sep = (p1 - s1) / scale
        d = float(np.linalg.norm(sep))
        if d == 0.0:  # the perturbation was erased (a stick phase): restart it in a fresh direction
            collapsed += 1
            u = rng.standard_normal(2 * n)
            sep, d = u / np.linalg.norm(u) * d0, d0 * np.finfo(float).eps
        if k >= discard:
            total += np.log(d / d0)
        p = s1 + d0 * scale * sep / np.linalg.norm(sep)
        s = s1
    value = total / ((steps - discard) * interval)
    return Lyapunov(float(value), "benettin", {"steps": int(steps), "interval_s": float(interval), "d0": d0,
                                               "discard": int(discard), "length_m": length, "speed_m_s": speed,
                                               "seed": int(seed), "collapsed_steps": collapsed})


def _scales(chain, speed, length):
    m = np.asarray(chain["masses"], float)
    k = np.asarray(chain["springs"], float)
    omega = float(np.sqrt(np.max(k[:-1] + k[1:]) / np.min(m))) if np.any(k > 0) else 1.0
    if speed is None:
        mu = chain.get("mu_s") or 0.0
        g = chain.get("g", 9.81)
        speed = max(abs(float(chain["v_belt"])), float(np.max(np.abs(chain["v0"]))), mu * g / omega, 1e-12)
    if length is None:
        length = speed / omega
    for name, val in (("speed", speed), ("length", length)):
        if not np.isfinite(val) or val <= 0:
            raise SceneError(f"`{name}` must be > 0, got {val!r}")
    return float(speed), float(length)
