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

    Parameters
    ----------
    value : float
        The value, in ``unit`` (SI, unprefixed).
    unit : str
        The unit's symbol (``"N"``, ``"m/s"``); "" for a plain number.
    digits : int
        Significant digits.
    trim : bool
        Drop trailing zeros.

    Returns
    -------
    str
        The value with its prefixed unit.

    Examples
    --------
    >>> from asperity2d.scripting import si
    >>> si(0.03452, "N"), si(1.25e-6, "m"), si(2.88e-16, "kg")
    ('34.5 mN', '1.25 µm', '288 fg')
    >>> si(1e-6, "m", trim=True)
    '1 µm'
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
    # round to `digits` significant digits first: 9.99987 is "10.00", not "10.000"
    mantissa = float(f"{scaled / 10.0**e:.{digits - 1}e}")
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


#: Key suffixes of summaries and claim numbers, and the SI unit each says its value is in
#: (``critical_force_N`` is in N, ``stuck_fraction`` a fraction shown in percent).
UNIT_SUFFIXES = (("_N_per_m", "N/m"), ("_m_per_s", "m/s"), ("_per_s", "1/s"), ("_Hz", "Hz"),
                 ("_deg", "°"), ("_kg", "kg"), ("_J", "J"), ("_N", "N"), ("_m", "m"), ("_s", "s"),
                 ("_fraction", "%"))


#: Keys whose unit no suffix says: :func:`asperity2d.analysis.event_statistics`' (JSON names kept).
NAMED_UNITS = {"force_drop_mean": "N", "force_drop_std": "N", "slip_distance_mean": "m",
               "stick_duration_mean": "s", "stick_duration_std": "s", "interval_mean": "s"}


def split_unit(key: str) -> tuple[str, str | None]:
    """``("critical force", "N")`` from ``"critical_force_N"``: the plain name and the unit its
    suffix names (None without one)."""
    key = str(key)
    if key in NAMED_UNITS:
        return key.replace("_", " "), NAMED_UNITS[key]
    for suffix, unit in UNIT_SUFFIXES:
        if key.endswith(suffix) and len(key) > len(suffix):
            name = key[: -len(suffix)] + (" fraction" if unit == "%" else "")
            return name.replace("_", " "), unit
    return key.replace("_", " "), None


def value(x, unit: str | None = None, digits: int = 4) -> str:
    """One value for text output: SI prefixes for a float with a unit, ``digits`` significant
    digits for a plain float, percent for a fraction, yes / no, "n/a" for None and NaN."""
    if x is None:
        return "n/a"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, int):
        return str(x)
    if isinstance(x, float):
        if not math.isfinite(x):
            return "n/a" if math.isnan(x) else str(x)
        if unit == "%":
            return f"{number(100 * x, digits - 1)} %" if x else "0 %"
        if unit:
            return si(x, unit, digits)
        if x.is_integer() and abs(x) < 1e6:  # a count stored as a float
            return str(int(x))
        return number(x, digits) if 1e-3 <= abs(x) < 1e6 or x == 0 else f"{x:.{digits - 1}e}"
    return str(x)


def lines(summary: dict, *, indent: str = "", digits: int = 4) -> list[str]:
    """``summary`` as "name: value" lines in engineering units (units from the keys' suffixes,
    :func:`split_unit`); nested dicts indented below their name, lists inline."""
    out = []
    for key, x in summary.items():
        name, unit = split_unit(key)
        if isinstance(x, dict):
            out.append(f"{indent}{name}:")
            out += lines(x, indent=indent + "  ", digits=digits)
        elif isinstance(x, (list, tuple)):
            shown = ", ".join(value(v, unit, digits) if not isinstance(v, (list, tuple, dict)) else str(v)
                              for v in x[:8])
            out.append(f"{indent}{name}: {shown}{', ...' if len(x) > 8 else ''}")
        else:
            out.append(f"{indent}{name}: {value(x, unit, digits)}")
    return out


__all__ = ["NAMED_UNITS", "PREFIXES", "UNIT_SUFFIXES", "exponent", "lines", "number", "prefixed", "si", "split_unit", "value"]
