"""Parameter checks that raise :class:`SceneError` naming the parameter: the package's one set of
rules and messages (scenes, runs, belt chains, friction laws and the command line's argument types).

The rules:

* a number is real -- ``int``, ``float``, ``Fraction``, ``Decimal``, NumPy reals -- never
  ``bool``, ``str`` or ``complex``; a sequence is a list, tuple or 1-D array of such numbers;
* it is finite after conversion to ``float`` (``10**400`` and ``1e400`` are refused, not
  overflowed); values come back as plain ``float`` / ``int`` (JSON- and pymunk-safe);
* where a model forms products of its parameters (the belt chains: k·x·x, m·v·v, mu·m·g,
  k/m), :func:`check_real` also holds every quantity to the magnitude window: at most
  :data:`HUGE`, and one that must be positive at least :data:`TINY`, so that a product of
  three such numbers, or a quotient by a positive one, cannot overflow a double.

Messages name the parameter in backticks, as the user wrote it: "`mass` must be > 0, got -1.0".
Formatting a value for a message never raises (:func:`show`). NumPy is not imported here (the
command line's argument types use these checks before anything heavy is loaded).
"""

from __future__ import annotations

import math
import sys
from decimal import Decimal
from numbers import Integral, Real
from typing import Iterable

from .errors import SceneError

#: Largest count of asperities (per surface) or of anything else counted.
MAX_COUNT = 100_000
#: Default budget of runs one command or study starts (``max_runs`` / ``--max-runs`` raise it).
MAX_RUNS = 100_000
#: Most seeds a study or comparison holds (its seed list is kept in memory).
MAX_SEEDS = 1_000_000
#: The magnitude window of :func:`check_real`: smallest and largest magnitude of a non-zero number.
TINY, HUGE = 1e-100, 1e100


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


def _is_bool(value) -> bool:
    if isinstance(value, bool):
        return True
    np = sys.modules.get("numpy")  # a NumPy bool exists only once NumPy is loaded
    return np is not None and isinstance(value, np.bool_)


def is_real(value) -> bool:
    """True for real numbers (int, float, Fraction, Decimal, NumPy scalars), False for bool and
    the rest."""
    return isinstance(value, (Real, Decimal)) and not _is_bool(value)


def check_finite(name: str, value, *, where: str = "") -> float:
    """``value`` as a finite float (``where``, e.g. " at index 3", follows the name)."""
    if not is_real(value):
        raise SceneError(f"`{name}` must be a real number{where}, got {show(value)}")
    try:
        out = float(value)
    except (OverflowError, TypeError, ValueError):
        out = math.inf
    if not math.isfinite(out):
        raise SceneError(f"`{name}` must be a finite number{where}, got {show(value)}")
    return out


def check_positive(name: str, value) -> float:
    out = check_finite(name, value)
    if out <= 0:
        raise SceneError(f"`{name}` must be > 0, got {show(value)}")
    return out


#: The smallest relative tolerance a float can meet: four units in the last place (a double
#: resolves relative differences of 2.2e-16; a bracket cannot be narrower than its two ends).
MIN_TOLERANCE = 4 * 2.0 ** -52


def check_tolerance(name: str, value) -> float:
    """``value`` as a relative tolerance: finite, below 1 and at least :data:`MIN_TOLERANCE`
    (one below it could never be met: a bisection would run until its budget, silently)."""
    out = check_positive(name, value)
    if out >= 1:
        raise SceneError(f"`{name}` must be < 1, got {show(value)}")
    if out < MIN_TOLERANCE:
        raise SceneError(f"`{name}` must be >= {MIN_TOLERANCE:.2g}, got {show(value)}: a float resolves "
                         "relative differences of 2.2e-16, so a tolerance below that can never be met")
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


def _window(name: str, out: float, raw, where: str, positive: bool, nonneg: bool) -> float:
    if positive and out <= 0:
        raise SceneError(f"`{name}` must be > 0{where}, got {show(raw)}")
    if nonneg and out < 0:
        raise SceneError(f"`{name}` must be >= 0{where}, got {show(raw)}")
    if abs(out) > HUGE:
        raise SceneError(f"`{name}` must be of magnitude at most {HUGE:g}{where}, got {show(raw)}")
    if positive and out < TINY:
        raise SceneError(f"`{name}` must be at least {TINY:g}{where}, got {show(raw)}")
    return out


def check_real(name: str, value, *, positive: bool = False, nonneg: bool = False) -> float:
    """A finite float within the magnitude window (``positive``: > 0; ``nonneg``: >= 0)."""
    return _window(name, check_finite(name, value), value, "", positive, nonneg)


def check_vector(name: str, value, length: int | None = None, *, positive: bool = False,
                 nonneg: bool = False, as_array: bool = False):
    """A non-empty 1-D sequence of real numbers, each checked as :func:`check_real`, as a tuple
    of floats (``length`` entries if given), or with ``as_array`` as a new float64 array of the
    same numbers (long sample times: no round trip through a tuple)."""
    np = sys.modules.get("numpy")
    if np is not None and isinstance(value, np.ndarray):
        if value.ndim != 1 or value.dtype.kind not in "iuf":
            raise SceneError(f"`{name}` must be a 1-D sequence of real numbers, got an array of "
                             f"shape {value.shape} and dtype {value.dtype}")
        if value.dtype.kind == "f" and value.size and (length is None or value.size == length):
            arr = value.astype(float)  # fast path for long arrays (sample times): no Python loop
            if _plain_ok(arr, positive, nonneg):
                return arr if as_array else tuple(arr.tolist())
        items = value.tolist()
    elif isinstance(value, (list, tuple)):
        items = list(value)
    else:
        raise SceneError(f"`{name}` must be a list of numbers, got {show(value)}")
    if not items:
        raise SceneError(f"`{name}` must not be empty")
    if length is not None and len(items) != length:
        raise SceneError(f"`{name}` must have {length} entries, got {len(items)}")
    if set(map(type, items)) <= {float, int} and all(abs(v) <= HUGE for v in items):  # plain numbers
        if len(items) <= 16 and not as_array:
            # a few (a chain's masses and springs): :func:`_plain_ok`'s tests in Python, cheaper than
            # NumPy's calls at this size (abs(v) <= HUGE above is also the finiteness test)
            out = tuple(map(float, items))
            if all((not positive or v >= TINY) and (not nonneg or v >= 0) for v in out):
                return out
        else:  # fast path for long plain lists (sample times)
            import numpy as np

            arr = np.array(items, dtype=float)
            if _plain_ok(arr, positive, nonneg):
                return arr if as_array else tuple(arr.tolist())
    out = tuple(_window(name, check_finite(name, v, where=f" at index {i}"), v, f" at index {i}",
                        positive, nonneg) for i, v in enumerate(items))
    if as_array:
        import numpy as np

        return np.fromiter(out, dtype=float, count=len(out))
    return out


def _plain_ok(arr, positive: bool, nonneg: bool) -> bool:
    """True when every entry passes :func:`_window` (else the slow path names the culprit)."""
    import numpy as np

    ok = np.isfinite(arr).all() and (np.abs(arr) <= HUGE).all()
    if positive:
        ok = ok and (arr >= TINY).all()
    if nonneg:
        ok = ok and (arr >= 0).all()
    return bool(ok)


def check_int(name: str, value, *, minimum: int | None = None, maximum: int | None = MAX_COUNT) -> int:
    """An ``int`` (not bool) within [minimum, maximum] (None: unbounded on that side)."""
    if not isinstance(value, Integral) or _is_bool(value):
        raise SceneError(f"`{name}` must be an integer, got {show(value)}")
    if minimum is not None and value < minimum:
        raise SceneError(f"`{name}` must be >= {minimum}, got {show(value)}")
    if maximum is not None and value > maximum:
        raise SceneError(f"`{name}` must be <= {maximum:,}, got {show(value)}")
    return int(value)


def check_choice(name: str, value, choices: Iterable[str]) -> str:
    choices = tuple(choices)
    if not isinstance(value, str) or value not in choices:
        raise SceneError(f"`{name}` must be one of {', '.join(map(repr, choices))}, got {show(value)}")
    return value


#: Longest free text a parameter holds (a name, a label): a few lines of words, not a file.
MAX_TEXT = 1000


def check_text(name: str, value, *, maximum: int = MAX_TEXT) -> str:
    """A string of at most ``maximum`` characters (default :data:`MAX_TEXT`): every input is
    bounded, text as numbers are (a name of 200 MB would be copied into every record)."""
    if not isinstance(value, str):
        raise SceneError(f"`{name}` must be a string, got {show(value)}")
    if len(value) > maximum:
        raise SceneError(f"`{name}` must be at most {maximum:,} characters, got {len(value):,}")
    return value


def check_flag(name: str, value) -> bool:
    """``True`` or ``False`` (a NumPy bool too), as ``bool``."""
    if not _is_bool(value):
        raise SceneError(f"`{name}` must be True or False, got {show(value)}")
    return bool(value)


def per_item(name: str, value, count: int, *, allow_zero: bool) -> tuple[float, ...]:
    """A scalar or a length-``count`` sequence of finite numbers, as a tuple of floats.

    Values must be > 0, or >= 0 when ``allow_zero``.
    """
    import numpy as np

    check = check_nonnegative if allow_zero else check_positive
    if is_real(value):
        return (check(name, value),) * count
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__len__"):
        raise SceneError(f"`{name}` must be a number or a sequence of {count} numbers, got {show(value)}")
    items = list(np.ravel(np.asarray(value, dtype=object)))
    if len(items) != count:
        raise SceneError(f"`{name}` must have {count} entries (one per asperity), got {len(items)}")
    return tuple(check(f"{name}[{i}]", v) for i, v in enumerate(items))


def check_runs(runs: int, max_runs: int | None, why: str, *, name: str = "max_runs") -> None:
    """Refuse (SceneError naming ``name``) work of ``runs`` runs over ``max_runs`` (default
    :data:`MAX_RUNS`); ``why`` says where the count comes from. Every command and study that
    starts many runs checks this before it starts any."""
    limit = MAX_RUNS if max_runs is None else check_int(name, max_runs, minimum=1, maximum=None)
    if runs > limit:
        raise SceneError(f"{why}: {runs:,} runs, over `{name}` = {limit:,}; ask for fewer, or raise "
                         f"`{name}`")


def count_seeds(name: str, seeds) -> int:
    """How many seeds ``seeds`` holds, refusing (SceneError naming ``name``) more than
    :data:`MAX_SEEDS` before any list of them is made (``range(10**12)`` would not fit in memory)."""
    try:
        count = len(seeds)
    except OverflowError:
        count = math.inf
    except TypeError:
        return -1  # an iterator: counted as it is read
    if count > MAX_SEEDS:
        raise SceneError(f"`{name}` holds {f'{count:,}' if math.isfinite(count) else 'over 2**63'} seeds, over "
                         f"the {MAX_SEEDS:,} a study or comparison can hold; use fewer seeds")
    return count
