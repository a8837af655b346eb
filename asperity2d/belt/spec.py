"""The chain of masses on a moving belt: a frozen, validated specification.

n masses ``m_i`` (kg) sit in a row on a belt moving at ``v_belt`` (m/s).
Spring ``k_j`` (N/m) and damper ``c_j`` (N·s/m), j = 0..n, join mass j-1 to
mass j, with the walls as "mass -1" and "mass n": ``springs[0]`` ties m1 to
the left wall, ``springs[n]`` ties mn to the right wall; a zero removes the
link. Positions ``x_i`` (m) are measured from the configuration in which
every spring is unstretched. Each mass presses on the belt with the normal
load ``N_i`` (N, default m_i·g) and feels friction from ``friction``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..errors import SceneError
from ..friction import Coulomb, FrictionLaw, StaticKinetic


def _vector(name, value, length=None, *, positive=False, nonneg=False) -> tuple:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise SceneError(f"`{name}` must be a sequence of numbers, got {value!r}") from None
    if arr.ndim != 1 or arr.size == 0:
        raise SceneError(f"`{name}` must be a non-empty 1-D sequence, got shape {arr.shape}")
    if length is not None and arr.size != length:
        raise SceneError(f"`{name}` must have {length} entries, got {arr.size}")
    bad = ~np.isfinite(arr)
    if bad.any():
        raise SceneError(f"`{name}` must be finite, got {arr[bad][0]!r} at index {int(np.argmax(bad))}")
    if positive and (arr <= 0).any():
        raise SceneError(f"`{name}` must be > 0, got {arr[arr <= 0][0]!r}")
    if nonneg and (arr < 0).any():
        raise SceneError(f"`{name}` must be >= 0, got {arr[arr < 0][0]!r}")
    return tuple(float(a) for a in arr)


def _scalar(name, value, *, positive=False, nonneg=False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise SceneError(f"`{name}` must be a number, got {value!r}")
    value = float(value)
    if not math.isfinite(value):
        raise SceneError(f"`{name}` must be finite, got {value!r}")
    if positive and value <= 0:
        raise SceneError(f"`{name}` must be > 0, got {value!r}")
    if nonneg and value < 0:
        raise SceneError(f"`{name}` must be >= 0, got {value!r}")
    return value


@dataclass(frozen=True)
class ChainSpec:
    """A validated belt chain (all SI). Build it through :func:`simulate_chain` or directly.

    ``v_belt`` is a constant (m/s) or a callable ``v_belt(t)`` (ramps);
    ``mu_k`` defaults to ``mu_s``; ``friction`` overrides (mu_s, mu_k) with a
    law from :mod:`asperity2d.friction`.
    """

    masses: tuple
    springs: tuple
    dampers: tuple
    mu_s: float
    mu_k: float | None
    v_belt: float | Callable[[float], float]
    x0: tuple
    v0: tuple
    t_end: float
    g: float = 9.81
    normal_load: tuple | None = None
    friction: FrictionLaw | None = None
    law: FrictionLaw = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        s = object.__setattr__
        s(self, "masses", _vector("masses", self.masses, positive=True))
        n = len(self.masses)
        s(self, "springs", _vector("springs", self.springs, n + 1, nonneg=True))
        s(self, "dampers", _vector("dampers", self.dampers, n + 1, nonneg=True))
        s(self, "x0", _vector("x0", self.x0, n))
        s(self, "v0", _vector("v0", self.v0, n))
        s(self, "t_end", _scalar("t_end", self.t_end, positive=True))
        s(self, "g", _scalar("g", self.g, nonneg=True))
        if self.normal_load is not None:
            s(self, "normal_load", _vector("normal_load", self.normal_load, n, nonneg=True))
        if callable(self.v_belt):
            probe = self.v_belt(0.0)
            _scalar("v_belt", probe)
        else:
            s(self, "v_belt", _scalar("v_belt", self.v_belt))
        if self.friction is not None:
            if not isinstance(self.friction, FrictionLaw):
                raise SceneError(f"`friction` must be a law from asperity2d.friction, got {self.friction!r}")
            s(self, "law", self.friction)
        else:
            mu_s = _scalar("mu_s", self.mu_s, nonneg=True)
            mu_k = mu_s if self.mu_k is None else _scalar("mu_k", self.mu_k, nonneg=True)
            if mu_k > mu_s:
                raise SceneError(f"`mu_s` must be >= `mu_k` ({mu_k!r}), got {mu_s!r}")
            s(self, "mu_s", mu_s)
            s(self, "mu_k", mu_k)
            s(self, "law", Coulomb(mu_s) if mu_s == mu_k else StaticKinetic(mu_s, mu_k))

    # -- derived arrays ---------------------------------------------------
    @property
    def n(self) -> int:
        return len(self.masses)

    @property
    def m(self) -> np.ndarray:
        return np.asarray(self.masses)

    @property
    def k(self) -> np.ndarray:
        return np.asarray(self.springs)

    @property
    def c(self) -> np.ndarray:
        return np.asarray(self.dampers)

    @property
    def normal(self) -> np.ndarray:
        """Normal load per mass (N)."""
        if self.normal_load is not None:
            return np.asarray(self.normal_load)
        return self.m * self.g

    @property
    def constant_belt(self) -> bool:
        return not callable(self.v_belt)

    def belt_velocity(self, t):
        """Belt speed (m/s) at time(s) ``t``."""
        if callable(self.v_belt):
            return np.vectorize(lambda s: float(self.v_belt(s)))(t) if np.ndim(t) else float(self.v_belt(t))
        return np.full(np.shape(t), self.v_belt) if np.ndim(t) else float(self.v_belt)

    def belt_acceleration(self, t) -> float:
        """dv_belt/dt (m/s²); central difference for callables, 0 for a constant belt."""
        if not callable(self.v_belt):
            return 0.0
        h = 1e-6 * max(1.0, abs(t))
        return (float(self.v_belt(t + h)) - float(self.v_belt(t - h))) / (2 * h)

    def stiffness_matrix(self) -> np.ndarray:
        """Tridiagonal K (N/m) with M·x'' + C·x' + K·x = friction."""
        return _tridiag(self.k)

    def damping_matrix(self) -> np.ndarray:
        return _tridiag(self.c)

    def to_dict(self) -> dict:
        return {
            "masses": list(self.masses),
            "springs": list(self.springs),
            "dampers": list(self.dampers),
            "friction": self.law.to_dict(),
            "v_belt": repr(self.v_belt) if callable(self.v_belt) else self.v_belt,
            "x0": list(self.x0),
            "v0": list(self.v0),
            "t_end": self.t_end,
            "g": self.g,
            "normal_load": list(self.normal) if self.normal_load is not None else None,
        }


def _tridiag(links: np.ndarray) -> np.ndarray:
    n = len(links) - 1
    out = np.diag(links[:-1] + links[1:])
    idx = np.arange(n - 1)
    out[idx, idx + 1] = -links[1:-1]
    out[idx + 1, idx] = -links[1:-1]
    return out


def link_force(links: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Force on each mass (N) from links of coefficient ``links`` (n+1,) acting on ``x`` (n, ...).

    With springs and positions it is the spring force; with dampers and
    velocities the damper force. Walls sit at 0 and never move.
    """
    x = np.asarray(x, dtype=float)
    pad = np.zeros((1,) + x.shape[1:])
    elong = np.diff(np.concatenate([pad, x, pad]), axis=0)  # (n+1, ...) link extension
    tension = links.reshape((-1,) + (1,) * (x.ndim - 1)) * elong
    return tension[1:] - tension[:-1]


def link_extension(x: np.ndarray) -> np.ndarray:
    """Extension (m) or extension rate of each of the n+1 links for positions ``x`` (n, ...)."""
    x = np.asarray(x, dtype=float)
    pad = np.zeros((1,) + x.shape[1:])
    return np.diff(np.concatenate([pad, x, pad]), axis=0)
