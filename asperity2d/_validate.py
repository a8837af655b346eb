"""Parameter checks that raise :class:`SceneError` naming the parameter.

Every check converts before it compares, so nothing downstream sees a string,
a bool, a complex number, an int too large for a float or a NaN; values come
back as plain ``float`` / ``int`` (JSON- and pymunk-safe). Formatting an
error message never raises: values are shown through :func:`show`.
"""

from __future__ import annotations

import math
from numbers import Integral, Real
from typing import Iterable

import numpy as np

from .errors import SceneError

#: Largest count of asperities (per surface) or of anything else counted.
MAX_COUNT = 100_000


def show(value, limit: int = 60) -> str:
    """``repr(value)`` shortened to ``limit`` characters for error messages; never raises (an
    integer too long for ``repr``, a hostile ``__repr__``)."""
    try:
        if isinstance(value, Integral) and not isinstance(value, bool) and abs(int(value)).bit_length() > 200:
            return f"an integer of {abs(int(value)).bit_length()} bits"
        text = repr(value)
    except Exception:  # noqa: BLE001 -- a message must never fail to format
        text = f"<{type(value).__name__} object>"
    return text if len(text) <= limit else text[: limit - 3] + "..."


def is_real(value) -> bool:
    """True for real numbers (int, float, Fraction, NumPy scalars), False for bool and the rest."""
    return isinstance(value, Real) and not isinstance(value, (bool, np.bool_))


def check_finite(name: str, value) -> float:
    """``value`` as a finite float."""
    if not is_real(value):
        raise SceneError(f"`{name}` must be a real number, got {show(value)}")
    try:
        out = float(value)
    except (OverflowError, TypeError, ValueError):
        raise SceneError(f"`{name}` is too large to be a finite number, got {show(value)}") from None
    if not math.isfinite(out):
        raise SceneError(f"`{name}` must be a finite number, got {show(value)}")
    return out


def check_positive(name: str, value) -> float:
    out = check_finite(name, value)
    if out <= 0:
        raise SceneError(f"`{name}` must be > 0, got {show(value)}")
    return out


def check_nonnegative(name: str, value) -> float:
    out = check_finite(name, value)
    if out < 0:
        raise SceneError(f"`{name}` must be >= 0, got {show(value)}")
    return out


def check_range(name: str, value, low: float, high: float, *, unit: str = "") -> float:
    """``value`` as a float in the closed interval [low, high]."""
    out = check_finite(name, value)
    if not low <= out <= high:
        raise SceneError(f"`{name}` must be in [{low:g}, {high:g}]{unit}, got {show(value)}")
    return out


def check_int(name: str, value, *, minimum: int | None = None, maximum: int | None = MAX_COUNT) -> int:
    if not isinstance(value, Integral) or isinstance(value, (bool, np.bool_)):
        raise SceneError(f"`{name}` must be an integer, got {show(value)}")
    if minimum is not None and value < minimum:
        raise SceneError(f"`{name}` must be >= {minimum}, got {show(value)}")
    if maximum is not None and value > maximum:
        raise SceneError(f"`{name}` must be <= {maximum}, got {show(value)}")
    return int(value)


def check_choice(name: str, value, choices: Iterable[str]) -> str:
    choices = tuple(choices)
    if not isinstance(value, str) or value not in choices:
        raise SceneError(f"`{name}` must be one of {', '.join(map(repr, choices))}, got {show(value)}")
    return value


def check_text(name: str, value) -> str:
    if not isinstance(value, str):
        raise SceneError(f"`{name}` must be a string, got {show(value)}")
    return value


def per_item(name: str, value, count: int, *, allow_zero: bool) -> tuple[float, ...]:
    """A scalar or a length-``count`` sequence of finite numbers, as a tuple of floats.

    Values must be > 0, or >= 0 when ``allow_zero``.
    """
    check = check_nonnegative if allow_zero else check_positive
    if is_real(value):
        return (check(name, value),) * count
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__len__"):
        raise SceneError(f"`{name}` must be a number or a sequence of {count} numbers, got {show(value)}")
    items = list(np.ravel(np.asarray(value, dtype=object)))
    if len(items) != count:
        raise SceneError(f"`{name}` must have {count} entries (one per asperity), got {len(items)}")
    return tuple(check(f"{name}[{i}]", v) for i, v in enumerate(items))
