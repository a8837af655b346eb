"""Hoffmann's minimal model of the mode-coupling instability, and its closed forms.

Hoffmann, Fischer, Allgaier & Gaul (2002), "A minimal model for studying
properties of the mode-coupling type instability in friction induced
oscillations": a point mass m (kg) on a belt moving at V (m/s), with a
tangential coordinate x and a normal one y (the gap, up from the belt), held to
the frame by two springs k1, k2 (N/m) whose axes make angles alpha1, alpha2 with
the belt direction, pressed on the belt by a preload F (N) through a contact
stiffness k_c (N/m). Here it is one mass of :func:`~.solver.simulate_chain` with
``normal=NormalContact(contact_stiffness=k_c, preload=F, inclined=((k1, alpha1),
(k2, alpha2)))`` and no chain springs; the defaults are a brake-pad-like set
(0.1 kg, MN/m stiffnesses, 1 kN preload) that squeals at about 1.56 kHz.

**Equations of motion.** With the inclined springs' stiffness
K_s = [[K11, kappa], [kappa, K22]], K11 = Σ k_a·cos²alpha_a, kappa = Σ k_a·cos alpha_a·sin alpha_a,
K22 = Σ k_a·sin²alpha_a (+ k_n), and in contact N = k_c·(-y), sliding in direction s
(s = sign(v - V); s = -1 when the belt drags the mass), F_friction = -s·mu·N:

    m·x'' + c_x·x' + K11·x + (kappa - s·mu·k_c)·y = 0
    m·y'' + c_y·y' + kappa·x + (K22 + k_c)·y      = -F

so the stiffness of steady sliding is K_eff = [[K11, kappa - s·mu·k_c], [kappa, K22']]
with K22' = K22 + k_c: not symmetric unless mu = 0. The equilibrium is
K_eff·(x*, y*) = (0, -F), with the contact force N* = k_c·K11·F / det K_eff.

**Characteristic polynomial** (undamped; Lambda = lambda²):

    m²·Lambda² + m·(K11 + K22')·Lambda + det K_eff = 0,
    det K_eff = K11·K22' - kappa·(kappa - s·mu·k_c).

Its discriminant Delta(mu) = (K11 - K22')² + 4·kappa·(kappa - s·mu·k_c) is linear in mu.
For Delta > 0 (and det > 0) both Lambda are real and negative: two neutral modes.
At Delta = 0 they coalesce, at omega_c² = (K11 + K22')/(2m); for Delta < 0 they are
a complex pair and one lambda = ±sqrt(Lambda) has a positive real part: flutter.

    mu_crit = [(K11 - K22')² + 4·kappa²] / (4·s·kappa·k_c)        (needs s·kappa > 0)

(s·kappa < 0 instead lowers det K_eff: a real root crosses zero -- divergence, the
sprag-slip of a rigid strut.) Above mu_crit, Lambda = [-(K11 + K22') ± i·sqrt(-Delta)]/(2m)
and the growth rate is Re sqrt(Lambda) = sqrt((|Lambda| + Re Lambda)/2).

**Damping** proportional to the mass, c_x = c_y = eta·m: det(m·lambda² + eta·m·lambda + K_eff)
= 0 gives lambda² + eta·lambda = Lambda (the undamped roots), so
lambda = [-eta ± sqrt(eta² + 4·Lambda)]/2. A root crosses the imaginary axis,
lambda = i·omega, where Lambda = -omega² + i·eta·omega: Re Lambda = -(K11 + K22')/(2m)
= -omega² and |Im Lambda| = sqrt(-Delta)/(2m) = eta·omega, i.e. Delta = -2·m·eta²·(K11 + K22'):

    mu_crit(eta) = [(K11 - K22')² + 4·kappa² + 2·m·eta²·(K11 + K22')] / (4·s·kappa·k_c)

(mass-proportional damping raises the threshold; other damping distributions can
lower it -- Hoffmann & Gaul 2003 -- which this closed form does not cover).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import SceneError
from ... import _inputs as check
from ..normal import NormalContact


@dataclass(frozen=True)
class MinimalModel:
    """Hoffmann's minimal model (SI; angles in degrees from the belt direction towards the normal).

    ``eta`` (1/s) is the mass-proportional damping rate: c_x = c_y = eta·m. ``direction``
    s = sign(v - V) of the steady sliding the closed forms describe (-1: belt faster).

    Parameters
    ----------
    mass : float, default 0.1
        The mass (kg).
    k1, k2 : float, default 9e6, 2.25e6
        The two inclined springs (N/m).
    alpha1, alpha2 : float, default 150, 30
        Their angles (degrees from the belt direction towards the normal).
    contact_stiffness : float, default 8e6
        The contact spring k_c (N/m).
    preload : float, default 1000
        The normal preload (N).
    eta : float, default 0
        Mass-proportional damping rate (1/s).
    direction : {-1, 1}, default -1
        The sliding direction s.

    See Also
    --------
    asperity2d.belt.simulate_chain, asperity2d.belt.steady_sliding

    Examples
    --------
    >>> from asperity2d import belt
    >>> model = belt.MinimalModel()
    >>> f"flutter from mu = {model.mu_crit:.4f}"
    'flutter from mu = 0.4257'
    """

    mass: float = 0.1
    k1: float = 9.0e6
    alpha1: float = 150.0
    k2: float = 2.25e6
    alpha2: float = 30.0
    contact_stiffness: float = 8.0e6
    preload: float = 1000.0
    eta: float = 0.0
    direction: int = -1

    def __post_init__(self):
        for name in ("mass", "contact_stiffness"):
            object.__setattr__(self, name, check.check_real(name, getattr(self, name), positive=True))
        for name in ("k1", "k2", "preload", "eta"):
            object.__setattr__(self, name, check.check_real(name, getattr(self, name), nonneg=True))
        for name in ("alpha1", "alpha2"):
            value = check.check_real(name, getattr(self, name))
            if not -180 <= value <= 180:
                raise SceneError(f"`{name}` must be within [-180, 180] degrees, got {check.show(value)}")
            object.__setattr__(self, name, value)
        if self.direction not in (-1, 1) or isinstance(self.direction, bool):
            raise SceneError(f"`direction` must be -1 or 1, got {check.show(self.direction)}")

    # -- the matrices ---------------------------------------------------------
    @property
    def normal(self) -> NormalContact:
        return NormalContact(damping=self.eta * self.mass, preload=self.preload,
                             contact_stiffness=self.contact_stiffness,
                             inclined=((self.k1, self.alpha1), (self.k2, self.alpha2)))

    @property
    def structure(self) -> tuple[float, float, float]:
        """(K11, kappa, K22) of the inclined springs (N/m)."""
        return self.normal.coupling()

    def k_eff(self, mu: float) -> np.ndarray:
        """The steady-sliding stiffness K_eff (2, 2, N/m) at friction coefficient ``mu``."""
        K11, kap, K22 = self.structure
        kc, s = self.contact_stiffness, self.direction
        return np.array([[K11, kap - s * mu * kc], [kap, K22 + kc]])

    def discriminant(self, mu: float) -> float:
        """Delta(mu) = (K11 - K22')² + 4·kappa·(kappa - s·mu·k_c) (N²/m²): < 0 is flutter."""
        K11, kap, K22 = self.structure
        kc, s = self.contact_stiffness, self.direction
        return (K11 - K22 - kc) ** 2 + 4 * kap * (kap - s * mu * kc)

    # -- closed forms ---------------------------------------------------------
    @property
    def mu_crit(self) -> float:
        """Undamped flutter onset (coalescence of the two modes); inf when s·kappa <= 0."""
        return self.mu_crit_damped(0.0)

    def mu_crit_damped(self, eta: float | None = None) -> float:
        """Flutter onset with mass-proportional damping rate ``eta`` (1/s; default the model's)."""
        eta = self.eta if eta is None else eta
        K11, kap, K22 = self.structure
        kc, s = self.contact_stiffness, self.direction
        if s * kap <= 0:
            return math.inf
        trace = K11 + K22 + kc
        return ((K11 - K22 - kc) ** 2 + 4 * kap * kap + 2 * self.mass * eta * eta * trace) / (4 * s * kap * kc)

    @property
    def coalescence_frequency(self) -> float:
        """omega_c = sqrt((K11 + K22')/(2m)) (rad/s), where the modes meet at mu_crit."""
        K11, _, K22 = self.structure
        return math.sqrt((K11 + K22 + self.contact_stiffness) / (2 * self.mass))

    def eigenvalues(self, mu: float) -> np.ndarray:
        """The four lambda (1/s) of steady sliding from the characteristic polynomial (with eta)."""
        K = self.k_eff(mu)
        m = self.mass
        trace, det = K[0, 0] + K[1, 1], K[0, 0] * K[1, 1] - K[0, 1] * K[1, 0]
        root = np.sqrt(complex(trace * trace - 4 * det))
        Lam = np.array([(-trace + root) / (2 * m), (-trace - root) / (2 * m)])
        out = []
        for L in Lam:
            r = np.sqrt(self.eta * self.eta + 4 * L + 0j)
            out += [(-self.eta + r) / 2, (-self.eta - r) / 2]
        return np.array(out)

    def growth_rate(self, mu: float) -> float:
        """max Re lambda (1/s) of steady sliding at ``mu``."""
        return float(np.max(self.eigenvalues(mu).real))

    def first_limit_speed(self, mu: float) -> float:
        """The belt speed V* (m/s) that decides which nonlinearity a growing flutter meets first.

        The unstable mode grows as a·w·exp(lambda·t) (w its eigenvector over (x, y, x', y')): the
        slip velocity x' - V reaches zero (stick) when a·abs(w_x') = V, the contact force
        N = N* - k_c·y reaches zero (separation) when a·k_c·abs(w_y) = N*. Below V* = N*·abs(w_x')/(k_c·abs(w_y))
        the oscillation sticks first, above it the contact opens first. NaN below mu_crit (nothing grows).
        """
        if self.growth_rate(mu) <= 0:
            return math.nan
        m, c = self.mass, self.eta * self.mass
        A = np.block([[np.zeros((2, 2)), np.eye(2)], [-self.k_eff(mu) / m, -c / m * np.eye(2)]])
        lam, W = np.linalg.eig(A)
        w = W[:, int(np.argmax(lam.real))]
        _, _, N = self.equilibrium(mu)
        return float(N * abs(w[2]) / (self.contact_stiffness * abs(w[1])))

    def equilibrium(self, mu: float) -> tuple[float, float, float]:
        """(x*, y*, N*) of steady sliding (m, m, N)."""
        x, y = np.linalg.solve(self.k_eff(mu), [0.0, -self.preload])
        return float(x), float(y), float(-self.contact_stiffness * y)

    def chain(self, *, mu: float, v_belt: float, t_end: float, kick: float = 0.0, **run) -> dict:
        """``simulate_chain`` keyword arguments: the model at ``mu`` from steady sliding, its normal velocity
        kicked by ``kick`` (m/s); ``run`` adds run settings (``n_samples``, ...)."""
        mu = check.check_real("mu", mu, nonneg=True)
        v_belt = check.check_real("v_belt", v_belt)
        if v_belt == 0 or np.sign(-v_belt) != self.direction:
            raise SceneError(f"`v_belt` must have sign {-self.direction} for sliding direction {self.direction}, "
                             f"got {check.show(v_belt)}")
        x, y, _ = self.equilibrium(mu)
        c = self.eta * self.mass
        return dict(masses=[self.mass], springs=[0.0, 0.0], dampers=[c, 0.0], mu_s=mu, mu_k=mu, v_belt=v_belt,
                    x0=[x], v0=[0.0], t_end=t_end, g=0.0, normal=self.normal, y0=[y], vy0=[kick], **run)
