"""Regimes of a belt chain: steady sliding, stick-slip, quasi-harmonic oscillation (or stuck).

A run is judged on its second half (after the start-up transient):

* ``stick-slip``: some mass spends more than ``stick_fraction`` of the window stuck, and slips too;
* ``stuck``: every frictional mass is stuck throughout the window;
* ``quasi-harmonic``: no stick, but the velocities still oscillate by more than
  ``osc_tol`` times the belt speed (peak to peak);
* ``steady sliding``: no stick and the oscillation has died out.

For a single mass with a Stribeck law the linearised steady sliding at belt
speed V has the effective damping c + N·μ'(V) (μ' the slope of the friction
curve, s/m): steady sliding is unstable where it is negative. ``regime_map``
draws that boundary.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import SceneError
from .solver import simulate_chain

REGIMES = ("steady sliding", "stick-slip", "quasi-harmonic", "stuck")
AXES = ("v_belt", "k", "c", "m", "mu")


def classify(result, *, stick_fraction: float = 1e-3, osc_tol: float = 1e-3) -> str:
    """The regime (one of ``REGIMES``) of ``result`` over the second half of the run.

    Parameters
    ----------
    result : BeltResult
        A chain run of :func:`simulate_chain`.
    stick_fraction : float, optional
        A mass sticking for more than this fraction of the window is stick-slip (default 1e-3).
    osc_tol : float, optional
        Below this relative oscillation amplitude the sliding is steady (default 1e-3).

    Returns
    -------
    str
        ``"steady sliding"``, ``"stick-slip"``, ``"quasi-harmonic"`` or ``"stuck"``.

    See Also
    --------
    classify_contact : the same for a chain with a normal contact.
    regime_map : the regime over a grid of two parameters.

    Examples
    --------
    >>> from asperity2d import belt
    >>> r = belt.simulate_chain([1.0], [100.0, 0.0], [0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...                         v_belt=0.1, x0=[0.0], v0=[0.1], t_end=2.0)
    >>> belt.classify(r)
    'stick-slip'
    """
    t = result.t
    t_half = 0.5 * t[-1]
    window = t >= t_half
    span = t[-1] - t_half
    stuck_time = []
    for per in result.stick_intervals:
        stuck_time.append(sum(max(0.0, min(b, t[-1]) - max(a, t_half)) for a, b in per))
    stuck_time = np.array(stuck_time)
    if np.all(stuck_time >= span * (1 - 1e-9)):
        return "stuck"
    if np.any(stuck_time > stick_fraction * span):
        return "stick-slip"
    V = result.chain.belt_velocity(t[window]) if result.chain is not None else np.zeros(window.sum())
    swing = np.ptp(result.v[:, window] - V[None, :], axis=1)
    scale = max(np.max(np.abs(V)), 1e-12)
    return "quasi-harmonic" if np.max(swing) > osc_tol * scale else "steady sliding"


@dataclass(frozen=True)
class RegimeMap:
    """Regime labels over a grid: ``labels[i][j]`` for ``x_values[i]``, ``y_values[j]``.

    ``boundary`` is (x, y) arrays of the Stribeck linear stability boundary, or None.
    """

    x_name: str
    x_values: tuple
    y_name: str
    y_values: tuple
    labels: tuple
    boundary: tuple | None = None

    def to_dict(self) -> dict:
        return {
            "x_name": self.x_name, "x_values": list(self.x_values), "y_name": self.y_name,
            "y_values": list(self.y_values), "labels": [list(r) for r in self.labels],
            "counts": {name: sum(row.count(name) for row in self.labels) for name in REGIMES},
        }


def _apply(kwargs, name, value):
    kw = dict(kwargs)
    if name == "v_belt":
        kw["v_belt"] = float(value)
    elif name == "k":
        kw["springs"] = [float(value) if s != 0 else 0.0 for s in kw["springs"]]
    elif name == "c":
        kw["dampers"] = [float(value)] * len(kw["dampers"])
    elif name == "m":
        kw["masses"] = [float(value)] * len(kw["masses"])
    elif name == "mu":
        kw["mu_s"] = kw["mu_k"] = float(value)
    return kw


def regime_map(base: dict, x_name: str, x_values, y_name: str, y_values, *, progress=None) -> RegimeMap:
    """Run ``simulate_chain(**base)`` over the grid of two parameters from ``AXES`` and classify each run.

    ``k`` sets every non-zero spring, ``c`` every damper, ``m`` every mass, ``mu`` both coefficients.

    Parameters
    ----------
    base : dict
        Keyword arguments of :func:`simulate_chain` for every run.
    x_name, y_name : str
        The two parameters varied, from ``AXES`` (``"v_belt"``, ``"k"``, ``"c"``, ``"m"``, ``"mu"``).
    x_values, y_values : sequence of float
        Their values (SI: m/s, N/m, N s/m, kg, 1).
    progress : bool, optional
        Show a progress bar.

    Returns
    -------
    RegimeMap
        ``labels[j][i]`` is the regime at ``(x_values[i], y_values[j])``.

    See Also
    --------
    classify : the regime of one run.

    Examples
    --------
    One mass on a belt: stick-slip at a slow belt without damping, quasi-harmonic otherwise.

    >>> from asperity2d import belt
    >>> base = dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...             v_belt=0.1, x0=[0.0], v0=[0.1], t_end=2.0)
    >>> belt.regime_map(base, "v_belt", [0.1, 1.0], "c", [0.0, 5.0]).labels
    (('stick-slip', 'quasi-harmonic'), ('quasi-harmonic', 'quasi-harmonic'))
    """
    for name in (x_name, y_name):
        if name not in AXES:
            raise SceneError(f"`axis` must be one of {', '.join(AXES)}, got {name!r}")
    labels = []
    for xv in x_values:
        row = []
        for yv in y_values:
            kw = _apply(_apply(base, x_name, xv), y_name, yv)
            row.append(classify(simulate_chain(**kw)))
            if progress is not None:
                progress()
        labels.append(tuple(row))
    boundary = None
    law = base.get("friction")
    if law is not None and hasattr(law, "slope") and x_name == "v_belt" and y_name in ("c", "k"):
        boundary = stribeck_boundary(law, base, x_values, y_name, y_values)
    return RegimeMap(x_name, tuple(map(float, x_values)), y_name, tuple(map(float, y_values)), tuple(labels),
                     boundary)


def stribeck_boundary(law, base, v_values, y_name, y_values):
    """Where c + N·μ'(V) = 0 (single-mass linearisation; N from the first mass)."""
    normal = (base.get("normal_load") or [base["masses"][0] * base.get("g", 9.81)])[0]
    v = np.linspace(min(v_values), max(v_values), 400)
    c_crit = -normal * law.slope(v)
    if y_name == "c":
        return (v, c_crit)
    c = sum(base["dampers"][:2]) if len(base["masses"]) == 1 else base["dampers"][0]
    sign = np.sign(c_crit - c)
    cross = np.flatnonzero(np.diff(sign) != 0)
    if cross.size == 0:
        return None
    vx = v[cross[0]]
    return (np.array([vx, vx]), np.array([min(y_values), max(y_values)]))


#: regimes of a chain with a normal contact (``simulate_chain(..., normal=...)``), judged on the
#: second half of the run like :func:`classify`
CONTACT_REGIMES = ("steady sliding", "quasi-harmonic", "flutter", "stick-slip", "separation", "separation + stick",
                   "stuck")


def classify_contact(result, *, stick_fraction: float = 1e-3, osc_tol: float = 1e-3, grow_tol: float = 0.05) -> str:
    """The regime (one of ``CONTACT_REGIMES``) of a contact-chain run over its second half.

    Parameters
    ----------
    result : ContactResult
        A run of a chain with a normal contact (``simulate_chain(..., normal=...)``).
    stick_fraction : float
        Fraction of the window a mass must stick for to count as sticking, as in :func:`classify`.
    osc_tol : float
        Velocity swing, as a fraction of the belt speed, below which sliding is steady, as in
        :func:`classify`.
    grow_tol : float
        Relative growth of the oscillation over the window above which it is growing (flutter),
        and relative decay beyond which it is dying out.

    Returns
    -------
    str
        One of ``CONTACT_REGIMES`` (rules below).

    See Also
    --------
    classify : the regime of a chain without a normal contact.

    Examples
    --------
    >>> from asperity2d import belt
    >>> r = belt.simulate_chain([1.0], [100.0, 0.0], [0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...                         v_belt=0.1, x0=[0.0], v0=[0.1], t_end=2.0,
    ...                         normal=belt.NormalContact(stiffness=1e4))
    >>> belt.classify_contact(r)
    'stick-slip'

    * ``separation``: some contact opens in the window (bouncing), and no mass sticks for more
      than ``stick_fraction`` of it; ``separation + stick`` when one also does;
    * ``stick-slip``: a mass sticks (more than ``stick_fraction``), no contact opens;
    * ``stuck``: every frictional mass stuck throughout;
    * otherwise every mass slides in contact, and the velocity swing over the last quarter of the
      run, against the one over the third quarter, decides: grown by more than ``grow_tol``,
      ``flutter`` (an unstable steady sliding that has not met stick or separation yet); shrunk by
      more than ``grow_tol``, or below ``osc_tol`` of the belt speed, ``steady sliding``; in
      between ``quasi-harmonic`` (a neutral oscillation: undamped chains). A growth or decay rate
      is resolved when it changes the swing by more than ``grow_tol`` over a quarter of the run.
    """
    t = result.t
    t_half = 0.5 * (t[0] + t[-1])
    span = t[-1] - t_half
    overlap = [sum(max(0.0, min(b, t[-1]) - max(a, t_half)) for a, b in per) for per in result.stick_intervals]
    opened = any(b > t_half and a < t[-1] for per in result.separation_intervals for a, b in per)
    stuck = np.array(overlap) > stick_fraction * span
    if opened:
        return "separation + stick" if stuck.any() else "separation"
    if np.all(np.array(overlap) >= span * (1 - 1e-9)):
        return "stuck"
    if stuck.any():
        return "stick-slip"
    V = float(result.chain.v_belt)
    q3 = (t >= t_half) & (t < t_half + 0.5 * span)
    q4 = t >= t_half + 0.5 * span
    swing3, swing4 = (float(np.max(np.ptp(result.v[:, q], axis=1))) for q in (q3, q4))
    if swing4 <= osc_tol * max(abs(V), 1e-12) or swing4 < (1 - grow_tol) * swing3:
        return "steady sliding"
    return "flutter" if swing4 > (1 + grow_tol) * swing3 else "quasi-harmonic"
