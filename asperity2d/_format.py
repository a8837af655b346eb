"""Numbers as people read them: SI prefixes chosen from the value (``si(0.0345, "N")`` -> "34.5 mN").

One place for engineering-unit text, so a GIF's meters, the HTML player, a
scene's ``repr`` and printed summaries say the same thing the same way. The
prefix is the power of 1000 that puts the mantissa in [1, 1000); ``kg`` is
prefixed as grams (2.88e-16 kg -> "0.288 pg" would be odd: "288 fg").
Plain ``math`` only: the command line imports this without NumPy.
"""

from __future__ import annotations

import math

#: Engineering exponents (powers of ten, multiples of 3) and their prefixes.
PREFIXES = {-18: "a", -15: "f", -12: "p", -9: "n", -6: "µ", -3: "m", 0: "", 3: "k", 6: "M", 9: "G",
            12: "T"}
_LOW, _HIGH = min(PREFIXES), max(PREFIXES)


def _base(unit: str) -> tuple[str, int]:
    """``(unit to prefix, exponent already in it)``: kg is prefixed as g (10^3 g)."""
    return ("g", 3) if unit == "kg" else (unit, 0)


def exponent(value: float) -> int:
    """The engineering exponent (a multiple of 3 in PREFIXES' range) for ``value``; 0 for 0/NaN/inf."""
    if not math.isfinite(value) or value == 0:
        return 0
    e = 3 * math.floor(math.log10(abs(value)) / 3)
    return max(_LOW, min(_HIGH, e))


def prefixed(scale: float, unit: str) -> tuple[float, str]:
    """``(factor, label)`` to show numbers of magnitude ``scale`` in ``unit``: divide by ``factor``.

    ``prefixed(0.0345, "N") == (1e-3, "mN")``; ``prefixed(3e-7, "m") == (1e-6, "µm")``.
    An axis uses it with its largest value, so its tick labels share one unit.
    """
    base, shift = _base(unit)
    e = exponent(scale * 10.0**shift)
    return 10.0 ** (e - shift), PREFIXES[e] + base


def si(value: float, unit: str = "", digits: int = 3, *, trim: bool = False) -> str:
    """``value`` (in ``unit``, SI) with ``digits`` significant digits and an SI prefix.

    ``si(0.03452, "N") == "34.5 mN"``, ``si(1.25e-6, "m") == "1.25 µm"``,
    ``si(999.96e-6, "N") == "1.00 mN"``, ``si(0, "s") == "0 s"``, ``si(2e4, "m/s") == "20.0 km/s"``;
    ``trim=True`` drops trailing zeros (``si(1e-6, "m", trim=True) == "1 µm"``).
    Non-finite values print as ``nan`` / ``inf`` with the unit.
    """
    if isinstance(digits, bool) or not isinstance(digits, int) or digits < 1:
        raise ValueError(f"`digits` must be an integer >= 1, got {digits!r}")
    sep = " " if unit else ""
    value = float(value)
    if not math.isfinite(value):
        return f"{value}{sep}{unit}"
    if value == 0:
        return f"0{sep}{unit}"
    base, shift = _base(unit)
    scaled = value * 10.0**shift
    e = exponent(scaled)
    mantissa = scaled / 10.0**e
    decimals = max(0, digits - 1 - math.floor(math.log10(abs(mantissa))))
    text = f"{mantissa:.{decimals}f}"
    if abs(float(text)) >= 1000 and e < _HIGH:  # 999.96 -> "1000": one prefix up
        e += 3
        mantissa = scaled / 10.0**e
        text = f"{mantissa:.{max(0, digits - 1)}f}"
    if trim and "." in text:
        text = text.rstrip("0").rstrip(".")
    return f"{text}{sep}{PREFIXES[e]}{base}"


def number(value: float, digits: int = 3) -> str:
    """A plain number, ``digits`` significant, no exponent for everyday magnitudes (tick labels)."""
    value = float(value)
    if value == 0 or not math.isfinite(value):
        return "0" if value == 0 else str(value)
    decimals = max(0, digits - 1 - math.floor(math.log10(abs(value))))
    return f"{value:.{decimals}f}"


__all__ = ["PREFIXES", "exponent", "number", "prefixed", "si"]
