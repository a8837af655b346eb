"""Checks for every ``simulate_chain`` parameter: one :class:`SceneError` naming the parameter.

The rules, in the order they are applied:

* a number is real -- ``int``, ``float``, ``Fraction``, ``Decimal``, NumPy reals -- never
  ``bool``, ``str`` or ``complex``; a sequence is a list, tuple or 1-D array of such numbers;
* it is finite after conversion to ``float`` (``10**400`` and ``1e400`` are refused, not
  overflowed);
* every quantity, dimensional (kg, N/m, N·s/m, m, m/s, s, N, m/s²) or not, is of magnitude
  at most 1e100, and one that must be positive (masses, ``t_end``, tolerances) at least
  1e-100: a product of three such numbers, or a quotient by a positive one, cannot overflow
  a double, which is what the solver forms (k·x·x, m·v·v, mu·m·g, k/m);
* ranges: masses > 0; springs, dampers, coefficients, loads >= 0; ``mu_k <= mu_s``;
* the chain's derived scales (``ChainSpec.rate_bound``, ``velocity_scale``,
  ``length_scale``, force and energy scales) are finite and below 1e150 -- the jointly
  absurd combinations that pass the per-parameter window;
* budgets (overridable): ``max_steps`` bounds the work of a run, counted as scan steps of
  the exact solver (``t_end`` over 1/16 of the fastest period) or right-hand-side
  evaluations of an integrator; at most ``MAX_MASSES`` masses; at most ``MAX_VALUES``
  sampled values (masses x samples).

Formatting a value for a message never raises (:func:`show`).
"""

from __future__ import annotations

import math
from decimal import Decimal
from numbers import Integral, Real

import numpy as np

from .._validate import show  # noqa: F401 -- one message formatter for the package (check.show)
from ..errors import SceneError

#: smallest and largest magnitude of any non-zero number given to a chain
TINY, HUGE = 1e-100, 1e100
#: largest derived scale (rate, speed, length, force, energy) of a chain
SCALE_LIMIT = 1e150
#: the dense eigendecomposition of an all-slipping chain costs O(n³): minutes beyond this
MAX_MASSES = 2000
#: masses x output samples (each result holds ~8 such arrays of doubles)
MAX_VALUES = 20_000_000


def _as_float(name: str, value, where: str = "") -> float:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (Real, Decimal)):
        raise SceneError(f"`{name}` must be a real number{where}, got {show(value)}")
    try:
        out = float(value)
    except (OverflowError, ValueError, TypeError):
        out = math.inf
    if not math.isfinite(out):
        raise SceneError(f"`{name}` must be finite{where}, got {show(value)}")
    return out


def _range(name: str, out: float, raw, where: str, positive: bool, nonneg: bool) -> float:
    if positive and out <= 0:
        raise SceneError(f"`{name}` must be > 0{where}, got {show(raw)}")
    if nonneg and out < 0:
        raise SceneError(f"`{name}` must be >= 0{where}, got {show(raw)}")
    if abs(out) > HUGE:
        raise SceneError(f"`{name}` must be of magnitude at most {HUGE:g}{where}, got {show(raw)}")
    if positive and out < TINY:
        raise SceneError(f"`{name}` must be at least {TINY:g}{where}, got {show(raw)}")
    return out


def real(name: str, value, *, positive: bool = False, nonneg: bool = False) -> float:
    """A real, finite number within the magnitude window, as ``float``."""
    return _range(name, _as_float(name, value), value, "", positive, nonneg)


def vector(name: str, value, length: int | None = None, *, positive=False, nonneg=False) -> tuple:
    """A non-empty 1-D sequence of real numbers (each checked as :func:`real`), as a tuple of floats."""
    if isinstance(value, np.ndarray):
        if value.ndim != 1 or value.dtype.kind not in "iuf":
            raise SceneError(f"`{name}` must be a 1-D sequence of real numbers, got an array of "
                             f"shape {value.shape} and dtype {value.dtype}")
        items = value.tolist()
    elif isinstance(value, (list, tuple)):
        items = list(value)
    else:
        raise SceneError(f"`{name}` must be a list of numbers, got {show(value)}")
    if not items:
        raise SceneError(f"`{name}` must not be empty")
    if length is not None and len(items) != length:
        raise SceneError(f"`{name}` must have {length} entries, got {len(items)}")
    if set(map(type, items)) <= {float, int}:  # fast path for long plain lists (sample times)
        arr = np.array(items, dtype=float) if all(abs(v) <= HUGE for v in items) else None
        if arr is not None and _plain_ok(arr, positive, nonneg):
            return tuple(arr.tolist())
    return tuple(_range(name, _as_float(name, v, f" at index {i}"), v, f" at index {i}", positive, nonneg)
                 for i, v in enumerate(items))


def _plain_ok(arr, positive, nonneg) -> bool:
    """True when every entry passes the checks of :func:`_range` (else the slow path names the culprit)."""
    ok = np.isfinite(arr).all() and (np.abs(arr) <= HUGE).all()
    if positive:
        ok = ok and (arr >= TINY).all()
    if nonneg:
        ok = ok and (arr >= 0).all()
    return bool(ok)


def integer(name: str, value, *, minimum: int, maximum: int | None = None) -> int:
    """An ``int`` (not bool) within [minimum, maximum]."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, Integral):
        raise SceneError(f"`{name}` must be an integer, got {show(value)}")
    if value < minimum or (maximum is not None and value > maximum):
        bound = f">= {minimum}" if maximum is None else f"within [{minimum}, {maximum:,}]"
        raise SceneError(f"`{name}` must be an integer {bound}, got {show(value)}")
    return int(value)


def choice(name: str, value, choices) -> str:
    if not isinstance(value, str) or value not in choices:
        raise SceneError(f"`{name}` must be one of {', '.join(map(repr, choices))}, got {show(value)}")
    return value


def flag(name: str, value) -> bool:
    if not isinstance(value, (bool, np.bool_)):
        raise SceneError(f"`{name}` must be True or False, got {show(value)}")
    return bool(value)


def scales(spec) -> None:
    """Refuse chains whose derived scales overflow (each parameter alone being acceptable)."""
    reach = spec.length_scale + abs(spec.belt_velocity(0.0)) * spec.t_end
    force = spec.force_scale
    derived = (
        ("fastest rate (1/s)", spec.rate_bound, "`masses`, `springs` and `dampers`"),
        ("velocity scale (m/s)", spec.velocity_scale, "`v_belt`, `v0`, `mu_s`, `g` or `normal_load`, `masses`"),
        ("length scale (m)", spec.length_scale, "`x0` and the velocity scale over the fastest rate"),
        ("distance travelled (m)", reach, "`v_belt` times `t_end`"),
        ("force scale (N)", force, "`mu_s` times the normal load, or `springs` times the length scale"),
        ("energy scale (J)", spec.energy_scale,
         "the force scale times the length scale, or `masses` times the velocity scale squared"),
    )
    for what, value, source in derived:
        if not (math.isfinite(value) and value <= SCALE_LIMIT):
            raise SceneError(f"the chain's {what} is {show(value)}, beyond {SCALE_LIMIT:g}: rescale {source}")


def budget(spec, n_values: int, max_steps: int) -> int:
    """Estimated scan steps of the run; refuse it when over ``max_steps`` or the sample budget."""
    if spec.n > MAX_MASSES:
        raise SceneError(f"`masses` may hold at most {MAX_MASSES} masses, got {spec.n}")
    if n_values * spec.n > MAX_VALUES:
        raise SceneError(f"`n_samples` (or `t_eval`) asks for {n_values:,} samples of {spec.n} masses, over the "
                         f"budget of {MAX_VALUES:,} values")
    steps = spec.t_end / spec.scan_step
    if steps > max_steps:
        raise SceneError(
            f"`t_end` = {show(spec.t_end)} s is {steps:.3g} steps of 1/16 of the chain's fastest period "
            f"({2 * math.pi / spec.rate_bound:.3g} s, from `masses`, `springs`, `dampers`), over the budget "
            f"`max_steps` = {max_steps:,}; shorten `t_end` or raise `max_steps`")
    return int(math.ceil(steps))
