"""Reading measured profiles: two-column text traces, and instrument files through SurfaceTopography.

The file's extension picks the reader (like the renderers):

* ``.csv``, ``.txt``, ``.dat``, ``.tsv``, ``.xy``: two numeric columns x, z in
  the ``unit`` the caller states, separated by commas, semicolons, tabs or
  spaces. Blank lines and comment lines (``#``, ``%``, ``//``) are skipped; a
  comment ``# unit: um`` is checked against ``unit``, or states it when the
  caller gives none (a file with neither is refused); one column-header line
  (e.g. ``x,z``) before the first number is skipped. Anything else that is not
  two finite numbers is a :class:`~asperity2d.SceneError` naming the file and
  its line.
* any other extension: instrument formats (Digital Surf ``.sur``, ISO 25178
  ``.x3p``, Bruker ``.spm``/``.di``, Zygo ``.datx``, Mitutoyo, Keyence ``.vk``,
  Gwyddion ``.gwy``, netCDF ``.nc`` and some 40 more) read with the optional
  SurfaceTopography package (``pip install "asperity2d[profiles]"``). The
  file's own unit is used (``unit`` only if it has none); a 2-D map needs
  ``line``, the index of the scan line (along the first axis) to take.
"""

from __future__ import annotations

import io
import os
import re
from pathlib import Path

import numpy as np

from .._inputs import check_choice, check_int
from ..errors import SceneError
from .profile import SurfaceProfile

#: Length units accepted for ``unit`` and their size in metres.
UNITS = {"m": 1.0, "mm": 1e-3, "um": 1e-6, "µm": 1e-6, "nm": 1e-9}
TEXT_SUFFIXES = (".csv", ".txt", ".dat", ".tsv", ".xy")
_SPLIT = re.compile(r"[,;\s]+")
_UNIT_COMMENT = re.compile(r"^(?:#|%|//)\s*unit\s*[:=]\s*(\S+)\s*$", re.IGNORECASE)
_COMMENTS = ("#", "%", "//")
_TO_SPACE = str.maketrans(",;\t", "   ")


def read_profile(path: str | os.PathLike, *, unit: str | None = None, line: int | None = None,
                 name: str | None = None) -> SurfaceProfile:
    """Read a measured height trace from ``path`` into a :class:`SurfaceProfile` (SI).

    Parameters
    ----------
    path : str or os.PathLike
        A text file of two columns (x, z), or an instrument file (with the ``profiles`` extra).
    unit : {"m", "mm", "um", "µm", "nm"}
        Unit of both columns of a text file (required there unless the file
        states it in a ``# unit: ...`` comment), or of an instrument file
        that does not record one.
    line : int, optional
        Scan line to take from a 2-D instrument map.
    name : str, optional
        Profile name (default: the file name).

    Returns
    -------
    SurfaceProfile
        Heights and positions in m.

    Raises
    ------
    FileError
        A missing or unreadable file, or a unit that is not given (naming ``path``).

    See Also
    --------
    asperity2d.make_scene : ``lower_surface="trace.txt", surface_unit="um"`` reads it for a scene.

    Examples
    --------
    >>> from pathlib import Path
    >>> import asperity2d.surface as surface
    >>> _ = Path("trace.txt").write_text("# unit: um\\n0 0.0\\n1 0.2\\n2 0.05\\n3 0.3\\n4 0.0\\n")
    >>> profile = surface.read_profile("trace.txt")
    >>> print(f"{profile.x[-1]:.3g} m long, highest point {profile.z.max():.3g} m")
    4e-06 m long, highest point 3e-07 m
    """
    if not isinstance(path, (str, os.PathLike)):
        raise SceneError(f"`path` must be a file name (str or path), got {type(path).__name__}"
                         + ("; to read bytes, write them to a file first" if isinstance(path, (bytes, bytearray)) else ""))
    path = Path(path)
    if unit is not None:
        check_choice("unit", unit, UNITS)
    if not path.is_file():
        raise SceneError(f"`path` is not a file: {str(path)!r}")
    if path.suffix.lower() in TEXT_SUFFIXES:
        x, z, comments, unit = _read_text(path, unit)
        meta = {"source": str(path), "unit": unit, "comments": comments}
    else:
        x, z, meta = _read_instrument(path, unit, line)
    return SurfaceProfile(x, z, name=path.name if name is None else name, metadata=meta)


def _read_text(path: Path, unit: str | None):
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneError(f"`path` cannot be read as text: {str(path)!r} ({exc})") from None
    numbers, rows, comments = [], [], []
    for number, raw in enumerate(text.splitlines(), start=1):
        s = raw.strip()
        if not s:
            continue
        if s.startswith(_COMMENTS):
            comments.append(s)
            declared = _UNIT_COMMENT.match(s)
            if declared and unit is None:
                unit = declared.group(1)
                if unit not in UNITS:
                    raise SceneError(f"`unit`: {path.name} line {number} states {unit!r}; "
                                     f"the reader knows {', '.join(UNITS)}")
            elif declared and UNITS.get(declared.group(1)) != UNITS[unit]:
                raise SceneError(f"`unit` is {unit!r} but {path.name} line {number} says "
                                 f"{declared.group(1)!r}")
            continue
        numbers.append(number)
        rows.append(s)
    if unit is None:
        raise SceneError(f"`unit` is required for a text profile ({', '.join(UNITS)}): {path.name} "
                         "states none (a comment line '# unit: um' would)")
    if rows and _fields(rows[0]) is None:  # one column-header line such as "x,z"
        del numbers[0], rows[0]
    if len(rows) < 3:
        raise SceneError(f"`path` {path.name} holds {len(rows)} data lines; a profile needs at least 3")
    # Fast path: NumPy parses all rows at once; on any problem the rows are
    # checked one by one so the error names the line.
    try:
        values = np.loadtxt(io.StringIO("\n".join(rows).translate(_TO_SPACE)), dtype=float, ndmin=2)
    except ValueError:
        values = None
    if values is None or values.shape[1] != 2 or not np.all(np.isfinite(values)):
        _raise_at_first_bad_row(path, numbers, rows)
    steps = np.diff(values[:, 0])
    if not np.all(steps > 0):
        i = int(np.argmax(steps <= 0)) + 1
        raise SceneError(f"`path` {path.name} line {numbers[i]}: x must increase, got "
                         f"{values[i, 0]!r} after {values[i - 1, 0]!r}")
    scale = UNITS[unit]
    return values[:, 0] * scale, values[:, 1] * scale, comments, unit


def _fields(row: str) -> list[float] | None:
    try:
        return [float(f) for f in _SPLIT.split(row)]
    except ValueError:
        return None


def _raise_at_first_bad_row(path: Path, numbers, rows):
    for number, row in zip(numbers, rows):
        values = _fields(row)
        if values is None or len(values) != 2 or not all(np.isfinite(values)):
            raise SceneError(f"`path` {path.name} line {number}: expected two finite numbers "
                             f"(x, z), got {row!r}")
    raise SceneError(f"`path` {path.name}: could not be read as two columns of numbers")


def _read_instrument(path: Path, unit: str | None, line: int | None):
    try:
        from SurfaceTopography import open_topography
    except ImportError:
        raise SceneError(f"`path` {path.name}: {path.suffix or 'extension-less'} files are read with "
                         "SurfaceTopography: pip install \"asperity2d[profiles]\" (text profiles "
                         f"{', '.join(TEXT_SUFFIXES)} need nothing)") from None
    try:
        reader = open_topography(str(path))
        channel = reader.default_channel
        kwargs = {} if channel.unit is not None else {"unit": _require_unit(unit, path, reader)}
        topography = reader.topography(**kwargs).to_unit("m")
    except SceneError:
        raise
    except Exception as exc:  # the library raises many kinds; the user needs one clear line
        raise SceneError(f"`path` {path.name} could not be read by SurfaceTopography: "
                         f"{type(exc).__name__}: {exc}") from None
    if topography.dim == 1:
        if line is not None:
            raise SceneError(f"`line` applies to 2-D maps; {path.name} is a line scan")
        x, z = topography.positions_and_heights()
    else:
        if line is None:
            raise SceneError(f"`line` is required: {path.name} is a 2-D map of "
                             f"{topography.nb_grid_pts} points; give the scan line index")
        rows = topography.nb_grid_pts[1]
        line = check_int("line", line, minimum=0)
        if line >= rows:
            raise SceneError(f"`line` must be < {rows} for {path.name}, got {line}")
        x = topography.positions()[0][:, line]
        z = topography.heights()[:, line]
    meta = {"source": str(path), "format": reader.format(), "unit": "m",
            "file_unit": str(channel.unit or unit), "line": line}
    return np.asarray(x, dtype=float), np.asarray(z, dtype=float), meta


def _require_unit(unit, path: Path, reader) -> str:
    if unit is None:
        raise SceneError(f"`unit` is required: {path.name} (read as format {reader.format()!r}) "
                         "does not record its length unit")
    return "um" if unit == "µm" else unit
