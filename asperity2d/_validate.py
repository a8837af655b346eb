"""Parameter checks that raise :class:`SceneError` naming the parameter."""

from __future__ import annotations

import math
from numbers import Integral, Real
from typing import Iterable

import numpy as np

from .errors import SceneError


def _is_real(value) -> bool:
    return isinstance(value, Real) and not isinstance(value, bool)


def check_finite(name: str, value) -> float:
    if not _is_real(value) or not math.isfinite(value):
        raise SceneError(f"`{name}` must be a finite number, got {value!r}")
    return float(value)


def check_positive(name: str, value) -> float:
    value = check_finite(name, value)
    if value <= 0:
        raise SceneError(f"`{name}` must be > 0, got {value!r}")
    return value


def check_nonnegative(name: str, value) -> float:
    value = check_finite(name, value)
    if value < 0:
        raise SceneError(f"`{name}` must be >= 0, got {value!r}")
    return value


def check_int(name: str, value, *, minimum: int | None = None) -> int:
    if not isinstance(value, Integral) or isinstance(value, bool):
        raise SceneError(f"`{name}` must be an integer, got {value!r}")
    if minimum is not None and value < minimum:
        raise SceneError(f"`{name}` must be >= {minimum}, got {value!r}")
    return int(value)


def check_choice(name: str, value, choices: Iterable[str]) -> str:
    choices = tuple(choices)
    if value not in choices:
        raise SceneError(f"`{name}` must be one of {', '.join(map(repr, choices))}, got {value!r}")
    return value


def per_item(name: str, value, count: int, *, allow_zero: bool) -> tuple[float, ...]:
    """A scalar or a length-``count`` sequence of finite numbers, as a tuple.

    Values must be > 0, or >= 0 when ``allow_zero``.
    """
    check = check_nonnegative if allow_zero else check_positive
    if _is_real(value):
        return (check(name, value),) * count
    try:
        items = list(np.asarray(value, dtype=float).ravel()) if not isinstance(value, str) else None
    except (TypeError, ValueError):
        items = None
    if items is None:
        raise SceneError(f"`{name}` must be a number or a sequence of {count} numbers, got {value!r}")
    if len(items) != count:
        raise SceneError(f"`{name}` must have {count} entries (one per asperity), got {len(items)}")
    return tuple(check(f"{name}[{i}]", float(v)) for i, v in enumerate(items))
