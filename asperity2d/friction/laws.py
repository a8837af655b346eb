"""Friction laws shared by the belt chains and by fits to measured data.

Every law is a small frozen dataclass, validated on construction, with

* ``curve(v)`` -- the steady-state friction force per unit normal load
  (dimensionless, an odd function of the sliding velocity ``v`` in m/s,
  positive when it resists motion in +x);
* ``force(v_rel, normal)`` -- the friction force on the body (N) for a
  relative velocity ``v_rel = v_body - v_surface`` (m/s) and a normal load
  (N): ``-normal * curve(v_rel)``; set-valued laws return 0 at ``v_rel == 0``
  (the static force is then decided by the caller's stick logic);
* ``static_coefficient`` -- the largest force/normal the contact holds while
  stuck (the stick limit used by the event-driven belt solver);
* ``params`` / ``from_params(vector)`` / ``param_names`` -- the flat parameter
  vector used by ``scipy.optimize.least_squares`` fits.

State-variable laws (:class:`Dahl`, :class:`LuGre`) carry a bristle
deflection ``z`` (m) with ``state_derivative(z, v_rel)`` and
``state_force(z, v_rel, normal)``; they are continuous through zero velocity
and their steady state reproduces :class:`Coulomb` / :class:`Stribeck`.
Stiffness-like parameters are per unit normal load: ``sigma0`` in 1/m,
``sigma1`` and ``sigma2`` in s/m.
"""

from __future__ import annotations

from dataclasses import astuple, dataclass, fields

import numpy as np

from .._inputs import check_real, show
from ..contact_laws import LawEntry, register_law
from ..errors import SceneError

__all__ = ["Coulomb", "StaticKinetic", "CoulombViscous", "Stribeck", "Dahl", "LuGre", "FrictionLaw"]


def _check(name: str, value, *, positive: bool = False) -> None:
    """Raise SceneError unless ``value`` is a finite real number >= 0 (or > 0) within the chains'
    magnitude window: the rules of :func:`asperity2d._inputs.check_real` (the belt package's
    ``__init__`` resolves its names lazily, so importing its validator here makes no cycle)."""
    check_real(name, value, positive=positive, nonneg=not positive)


class FrictionLaw:
    """Common behaviour; subclasses are frozen dataclasses of floats.

    See Also
    --------
    asperity2d.friction.Coulomb : the laws.
    asperity2d.friction.StaticKinetic
    asperity2d.friction.CoulombViscous
    asperity2d.friction.Stribeck
    asperity2d.friction.Dahl
    asperity2d.friction.LuGre
    asperity2d.belt.simulate_chain : ``friction=`` takes any of them.

    Examples
    --------
    >>> from asperity2d.friction import Coulomb, FrictionLaw
    >>> isinstance(Coulomb(mu=0.3), FrictionLaw)
    True
    >>> Coulomb(mu=0.3).to_dict()
    {'law': 'Coulomb', 'mu': 0.3}
    """

    #: True when the slip force is piecewise constant (exact closed-form solver applies).
    piecewise_constant = False
    #: True for laws with an internal state (Dahl, LuGre).
    has_state = False

    @property
    def param_names(self) -> tuple[str, ...]:
        return tuple(f.name for f in fields(self))

    @property
    def params(self) -> np.ndarray:
        """The parameters as a float vector, in ``param_names`` order."""
        return np.asarray(astuple(self), dtype=float)

    @classmethod
    def from_params(cls, vector) -> "FrictionLaw":
        """Build the law from a parameter vector (``param_names`` order)."""
        values = [float(p) for p in np.asarray(vector, dtype=float).ravel()]
        if len(values) != len(fields(cls)):
            raise SceneError(f"`vector` must have {len(fields(cls))} entries for {cls.__name__}, got {len(values)}")
        return cls(*values)

    def to_dict(self) -> dict:
        return {"law": type(self).__name__, **dict(zip(self.param_names, self.params.tolist()))}

    def curve(self, v):
        """Steady-state friction force / normal load at sliding velocity ``v`` (m/s)."""
        raise NotImplementedError

    def force(self, v_rel, normal):
        """Friction force on the body (N) at relative velocity ``v_rel`` (m/s)."""
        return -np.asarray(normal, dtype=float) * self.curve(v_rel)

    @property
    def static_coefficient(self) -> float:
        raise NotImplementedError

    @property
    def kinetic_coefficient(self) -> float:
        """Force / normal load of the slip phase (piecewise-constant laws)."""
        return self.static_coefficient


def law_from_dict(record: dict) -> FrictionLaw:
    """Inverse of ``FrictionLaw.to_dict``.

    Parameters
    ----------
    record : dict
        A law's ``to_dict()``: its class name under ``"law"`` and its parameters.

    Returns
    -------
    FrictionLaw

    Raises
    ------
    SceneError
        An unknown law or bad parameters.

    See Also
    --------
    asperity2d.friction.FrictionLaw : ``to_dict``.

    Examples
    --------
    >>> from asperity2d.friction import Stribeck, law_from_dict
    >>> law = Stribeck(mu_s=0.4, mu_k=0.3, v_s=0.01)
    >>> law_from_dict(law.to_dict()) == law
    True
    """
    laws = {c.__name__: c for c in (Coulomb, StaticKinetic, CoulombViscous, Stribeck, Dahl, LuGre)}
    if not isinstance(record, dict):
        raise SceneError(f"`friction` must be a table with a `law` entry, got {show(record)}")
    record = dict(record)
    name = record.pop("law", None)
    cls = laws.get(name) if isinstance(name, str) else None
    if cls is None:
        raise SceneError(f"`friction` law must be one of {', '.join(laws)}, got {show(name)}")
    try:
        return cls(**record)
    except TypeError as exc:  # a missing or unknown parameter of the law
        raise SceneError(f"`friction` parameters do not fit {cls.__name__}: {exc}") from None


@dataclass(frozen=True)
class Coulomb(FrictionLaw):
    """Coulomb friction: abs(F) = mu·N while sliding, at most mu·N while stuck (mu dimensionless).

    Parameters
    ----------
    mu : float
        The friction coefficient, >= 0.

    See Also
    --------
    asperity2d.friction.StaticKinetic : a higher coefficient while stuck.

    Examples
    --------
    >>> from asperity2d.friction import Coulomb
    >>> law = Coulomb(mu=0.3)
    >>> float(law.force(0.1, 10.0))  # sliding at +0.1 m/s under 10 N: friction opposes the motion
    -3.0
    """

    mu: float
    piecewise_constant = True

    def __post_init__(self):
        _check("mu", self.mu)

    def curve(self, v):
        return self.mu * np.sign(v)

    @property
    def static_coefficient(self) -> float:
        return float(self.mu)


@dataclass(frozen=True)
class StaticKinetic(FrictionLaw):
    """Static limit mu_s·N while stuck, kinetic mu_k·N while sliding (mu_s >= mu_k >= 0).

    Parameters
    ----------
    mu_s, mu_k : float
        Static and kinetic coefficients, mu_s >= mu_k >= 0.

    Raises
    ------
    SceneError
        mu_k > mu_s, or a negative coefficient.

    See Also
    --------
    asperity2d.friction.Coulomb, asperity2d.friction.Stribeck
    asperity2d.belt.simulate_chain : ``mu_s=``, ``mu_k=`` build this law.

    Examples
    --------
    >>> from asperity2d.friction import StaticKinetic
    >>> law = StaticKinetic(mu_s=0.4, mu_k=0.3)
    >>> law.static_coefficient, law.kinetic_coefficient
    (0.4, 0.3)
    >>> StaticKinetic(mu_s=0.3, mu_k=0.4)
    Traceback (most recent call last):
    ...
    asperity2d.errors.SceneError: `mu_k` must be <= `mu_s` (0.3), got 0.4
    """

    mu_s: float
    mu_k: float
    piecewise_constant = True

    def __post_init__(self):
        _check("mu_s", self.mu_s)
        _check("mu_k", self.mu_k)
        if self.mu_k > self.mu_s:
            raise SceneError(f"`mu_k` must be <= `mu_s` ({show(self.mu_s)}), got {show(self.mu_k)}")

    def curve(self, v):
        return self.mu_k * np.sign(v)

    @property
    def static_coefficient(self) -> float:
        return float(self.mu_s)

    @property
    def kinetic_coefficient(self) -> float:
        return float(self.mu_k)


@dataclass(frozen=True)
class CoulombViscous(FrictionLaw):
    """Coulomb plus viscous: F/N = mu·sign(v) + sigma2·v (sigma2 in s/m, per unit normal load).

    Parameters
    ----------
    mu : float
        The Coulomb coefficient, >= 0.
    sigma2 : float
        The viscous coefficient per unit normal load (s/m), >= 0.

    See Also
    --------
    asperity2d.friction.Coulomb, asperity2d.friction.Stribeck

    Examples
    --------
    >>> from asperity2d.friction import CoulombViscous
    >>> law = CoulombViscous(mu=0.3, sigma2=0.5)
    >>> float(law.force(0.2, 10.0))  # -(0.3 + 0.5 * 0.2) * 10 N
    -4.0
    """

    mu: float
    sigma2: float

    def __post_init__(self):
        _check("mu", self.mu)
        _check("sigma2", self.sigma2)

    def curve(self, v):
        v = np.asarray(v, dtype=float)
        return self.mu * np.sign(v) + self.sigma2 * v

    def slope(self, v):
        """d(curve)/dv for v != 0 (s/m)."""
        return np.full_like(np.asarray(v, dtype=float), self.sigma2)

    @property
    def static_coefficient(self) -> float:
        return float(self.mu)


@dataclass(frozen=True)
class Stribeck(FrictionLaw):
    """Stribeck curve: F/N = [mu_k + (mu_s - mu_k)·exp(-abs(v/v_s)^delta)]·sign(v) + sigma2·v.

    ``v_s`` (m/s) is the Stribeck velocity, ``delta`` the shape exponent,
    ``sigma2`` (s/m) the viscous term per unit normal load. The curve falls
    from mu_s at rest to mu_k: its negative slope is what destabilises steady
    sliding (see :meth:`slope`).

    Parameters
    ----------
    mu_s, mu_k : float
        Coefficients at rest and at high speed, mu_s >= mu_k >= 0.
    v_s : float
        Stribeck velocity (m/s), > 0.
    delta : float, default 2.0
        Shape exponent, > 0.
    sigma2 : float, default 0.0
        Viscous term per unit normal load (s/m), >= 0.

    See Also
    --------
    asperity2d.friction.LuGre : the same steady curve with pre-sliding dynamics.

    Examples
    --------
    >>> import numpy as np
    >>> from asperity2d.friction import Stribeck
    >>> law = Stribeck(mu_s=0.4, mu_k=0.3, v_s=0.01)
    >>> np.round(law.curve(np.array([0.001, 0.01, 0.1])), 4)  # F/N falls from mu_s to mu_k
    array([0.399 , 0.3368, 0.3   ])
    >>> float(law.slope(0.01)) < 0  # the falling branch destabilises steady sliding
    True
    """

    mu_s: float
    mu_k: float
    v_s: float
    delta: float = 2.0
    sigma2: float = 0.0

    def __post_init__(self):
        _check("mu_s", self.mu_s)
        _check("mu_k", self.mu_k)
        _check("v_s", self.v_s, positive=True)
        _check("delta", self.delta, positive=True)
        _check("sigma2", self.sigma2)
        if self.mu_k > self.mu_s:
            raise SceneError(f"`mu_k` must be <= `mu_s` ({show(self.mu_s)}), got {show(self.mu_k)}")

    def g(self, v):
        """Magnitude of the Coulomb-Stribeck part, mu_k..mu_s (dimensionless)."""
        v = np.asarray(v, dtype=float)
        return self.mu_k + (self.mu_s - self.mu_k) * np.exp(-np.abs(v / self.v_s) ** self.delta)

    def curve(self, v):
        v = np.asarray(v, dtype=float)
        return self.g(v) * np.sign(v) + self.sigma2 * v

    def slope(self, v):
        """d(curve)/dv for v != 0 (s/m): the 'negative damping' of steady sliding."""
        a = np.abs(np.asarray(v, dtype=float)) / self.v_s
        dg = -(self.mu_s - self.mu_k) * self.delta * a ** (self.delta - 1) * np.exp(-(a**self.delta)) / self.v_s
        return dg + self.sigma2

    @property
    def static_coefficient(self) -> float:
        return float(self.mu_s)


@dataclass(frozen=True)
class Dahl(FrictionLaw):
    """Dahl model: F/N = sigma0·z, dz/dt = v - sigma0·abs(v)·z/mu.

    ``sigma0`` (1/m) is the pre-sliding stiffness per unit normal load, ``mu``
    the Coulomb level reached in steady sliding (z -> mu·sign(v)/sigma0).

    Parameters
    ----------
    sigma0 : float
        Pre-sliding stiffness per unit normal load (1/m), > 0.
    mu : float
        Coulomb level of steady sliding, >= 0.

    See Also
    --------
    asperity2d.friction.LuGre, asperity2d.friction.Coulomb

    Examples
    --------
    >>> from asperity2d.friction import Dahl
    >>> law = Dahl(sigma0=1e5, mu=0.3)
    >>> law.has_state  # z, the bristle deflection, is integrated with the motion
    True
    """

    sigma0: float
    mu: float
    has_state = True

    def __post_init__(self):
        _check("sigma0", self.sigma0, positive=True)
        _check("mu", self.mu, positive=True)

    def curve(self, v):
        return self.mu * np.sign(v)

    def state_derivative(self, z, v_rel):
        return v_rel - self.sigma0 * np.abs(v_rel) * z / self.mu

    def state_force(self, z, v_rel, normal):
        """Friction force on the body (N) for bristle deflection z (m)."""
        return -np.asarray(normal, dtype=float) * self.sigma0 * z

    def steady_state(self, v):
        return self.mu * np.sign(v) / self.sigma0

    @property
    def static_coefficient(self) -> float:
        return float(self.mu)


@dataclass(frozen=True)
class LuGre(FrictionLaw):
    """LuGre model: F/N = sigma0·z + sigma1·dz/dt + sigma2·v, dz/dt = v - sigma0·abs(v)·z/g(v).

    g(v) = mu_k + (mu_s - mu_k)·exp(-(v/v_s)^2): the steady state is the
    :class:`Stribeck` curve with delta = 2. ``sigma0`` in 1/m, ``sigma1`` and
    ``sigma2`` in s/m (all per unit normal load), ``v_s`` in m/s.

    Parameters
    ----------
    sigma0 : float
        Bristle stiffness per unit normal load (1/m), > 0.
    sigma1, sigma2 : float
        Bristle damping and viscous coefficient per unit normal load (s/m), >= 0.
    mu_s, mu_k : float
        Static and kinetic levels of the steady curve, mu_s >= mu_k >= 0.
    v_s : float
        Stribeck velocity (m/s), > 0.

    See Also
    --------
    asperity2d.friction.Stribeck : its steady state.
    asperity2d.belt.simulate_chain : ``friction=LuGre(...)`` integrates it as a smooth stiff ODE.

    Examples
    --------
    >>> import numpy as np
    >>> from asperity2d.friction import LuGre
    >>> law = LuGre(sigma0=1e5, sigma1=300.0, sigma2=0.0, mu_s=0.4, mu_k=0.3, v_s=0.01)
    >>> np.round(law.curve(np.array([0.001, 0.1])), 4)  # steady state: the Stribeck curve
    array([0.399, 0.3  ])
    """

    sigma0: float
    sigma1: float
    sigma2: float
    mu_s: float
    mu_k: float
    v_s: float
    has_state = True

    def __post_init__(self):
        _check("sigma0", self.sigma0, positive=True)
        _check("sigma1", self.sigma1)
        _check("sigma2", self.sigma2)
        _check("mu_s", self.mu_s, positive=True)
        _check("mu_k", self.mu_k, positive=True)
        _check("v_s", self.v_s, positive=True)
        if self.mu_k > self.mu_s:
            raise SceneError(f"`mu_k` must be <= `mu_s` ({show(self.mu_s)}), got {show(self.mu_k)}")

    def stribeck(self) -> Stribeck:
        return Stribeck(self.mu_s, self.mu_k, self.v_s, 2.0, self.sigma2)

    def curve(self, v):
        return self.stribeck().curve(v)

    def state_derivative(self, z, v_rel):
        g = self.stribeck().g(v_rel)
        return v_rel - self.sigma0 * np.abs(v_rel) * z / g

    def state_force(self, z, v_rel, normal):
        zdot = self.state_derivative(z, v_rel)
        return -np.asarray(normal, dtype=float) * (self.sigma0 * z + self.sigma1 * zdot + self.sigma2 * v_rel)

    def steady_state(self, v):
        return self.stribeck().g(v) * np.sign(v) / self.sigma0

    @property
    def static_coefficient(self) -> float:
        return float(self.mu_s)


# -- in the registry of both models' friction laws (asperity2d.contact_laws.LAWS) -----------------
for _cls in (Coulomb, StaticKinetic, CoulombViscous, Stribeck, Dahl, LuGre):
    register_law(LawEntry(_cls.__name__, "belt", _cls, (_cls.__doc__ or "").strip().splitlines()[0]))
del _cls
