"""Files in and out: atomic writes, and reads that fail with one clear error.

Nothing a user saved is ever left half-written (:func:`atomic_write`), and a
file that cannot be used -- missing, a directory, unreadable, not UTF-8, not
TOML, a damaged or foreign ``.npz`` -- raises :class:`FileError` (a
``SceneError``) that names the argument, the problem and the file, never an
exception from deep inside zipfile or NumPy. The command line renames the
argument to what the user typed (:func:`argument`), e.g. ``--save``.
"""

from __future__ import annotations

import contextlib
import math
import os
import stat
import tempfile
from decimal import Decimal
from numbers import Integral, Real
from pathlib import Path
from typing import IO, Callable, Iterator

from .errors import SceneError


class FileError(SceneError):
    """A file argument that cannot be used.

    ``arg`` names the argument (``path``, or on the command line ``--save``,
    ``result``, ...), ``path`` the file, ``problem`` what is wrong with it and
    ``detail`` the underlying reason, if any.
    """

    def __init__(self, arg: str, path, problem: str, detail: str | None = None):
        self.arg, self.path, self.problem, self.detail = arg, str(path), problem, detail
        super().__init__(f"`{arg}` {problem}: {self.path!r}" + (f" ({detail})" if detail else ""))

    def renamed(self, arg: str) -> "FileError":
        """The same error, naming the argument ``arg``."""
        return FileError(arg, self.path, self.problem, self.detail)


@contextlib.contextmanager
def argument(arg: str) -> Iterator[None]:
    """Re-raise a :class:`FileError` from the block as one about argument ``arg``."""
    try:
        yield
    except FileError as exc:
        raise exc.renamed(arg) from None


@contextlib.contextmanager
def writing(arg: str, path) -> Iterator[None]:
    """Turn an ``OSError`` while writing ``path`` (disk full, permissions) into a FileError."""
    try:
        yield
    except OSError as exc:
        raise FileError(arg, path, "could not be written", exc.strerror or str(exc)) from None


# -- reading -----------------------------------------------------------------
def input_path(arg: str, path, *, directory: bool = False) -> Path:
    """``path`` as a Path if it exists and is a readable file (or a directory, with ``directory``)."""
    path = Path(path)
    try:
        mode = path.stat().st_mode
    except (FileNotFoundError, NotADirectoryError):
        raise FileError(arg, path, "does not exist") from None
    except OSError as exc:
        raise FileError(arg, path, "cannot be read", exc.strerror) from None
    if directory and not stat.S_ISDIR(mode):
        raise FileError(arg, path, "is not a directory")
    if not directory and stat.S_ISDIR(mode):
        raise FileError(arg, path, "is a directory")
    if not os.access(path, os.R_OK | (os.X_OK if directory else 0)):
        raise FileError(arg, path, "is not readable", "permission denied")
    return path


def read_bytes(arg: str, path) -> bytes:
    """The contents of file ``path``."""
    path = input_path(arg, path)
    try:
        return path.read_bytes()
    except OSError as exc:
        raise FileError(arg, path, "cannot be read", exc.strerror or str(exc)) from None


def read_text(arg: str, path) -> str:
    """The contents of file ``path``, which must be UTF-8 text."""
    data = read_bytes(arg, path)
    try:
        # utf-8-sig: a byte-order mark (some Windows editors write one) is not part of the text
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise FileError(arg, path, "is not UTF-8 text",
                        f"byte {data[exc.start]:#04x} at position {exc.start}") from None


def read_toml(arg: str, path) -> dict:
    """The TOML document in file ``path``, as a dict."""
    import tomllib

    text = read_text(arg, path)
    deep = deep_key(text)
    if deep is not None:  # before parsing: tomllib takes quadratic time over a dotted key's parts
        raise FileError(arg, path, "is nested too deeply",
                        f"`{deep}` nests tables more than {MAX_TOML_DEPTH} levels deep; no scene, chain or "
                        "study needs more than a few")
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise FileError(arg, path, "is not valid TOML", str(exc)) from None
    except RecursionError:  # tomllib parses nested arrays and tables recursively
        raise FileError(arg, path, "is nested too deeply", "arrays or inline tables nested "
                        "thousands deep; no scene or chain needs more than a few levels") from None
    deep = too_deep(data)
    if deep is not None:  # dotted keys nest without recursing in the parser, but not in a message
        raise FileError(arg, path, "is nested too deeply",
                        f"`{deep}` nests tables more than {MAX_TOML_DEPTH} levels deep; no scene, chain or "
                        "study needs more than a few") from None
    return data


#: Deepest nesting of tables and arrays a TOML input may have (a scene uses 2 or 3 levels).
MAX_TOML_DEPTH = 32


_PART = r"""(?:[A-Za-z0-9_-]+|"[^"\n]*"|'[^'\n]*')"""
_DEEP_KEY = None


def deep_key(text: str) -> str | None:
    """The first dotted key or table header of TOML ``text`` with more than
    :data:`MAX_TOML_DEPTH` parts (shortened), or None: found on the text, in linear time, before
    a parser spends quadratic time on it."""
    global _DEEP_KEY
    import re

    if text.count(".") <= MAX_TOML_DEPTH:
        return None
    if _DEEP_KEY is None:
        _DEEP_KEY = re.compile(rf"^[ \t]*\[{{0,2}}[ \t]*({_PART}(?:[ \t]*\.[ \t]*{_PART}){{{MAX_TOML_DEPTH},}})"
                               rf"[ \t]*(?:\]{{0,2}}[ \t]*$|=)", re.MULTILINE)
    match = _DEEP_KEY.search(text)
    if match is None:
        return None
    parts = re.findall(_PART, match.group(1))
    return f"{'.'.join(parts[:4])}...({len(parts)} levels)"


def too_deep(data) -> str | None:
    """The first key path (shortened) deeper than :data:`MAX_TOML_DEPTH`, or None; iterative, so
    a document 10,000 levels deep is walked without recursion."""
    stack = [(data, ())]
    while stack:
        value, where = stack.pop()
        if len(where) > MAX_TOML_DEPTH:
            shown = ".".join(map(str, where[:4]))
            return f"{shown}...({len(where)}+ levels)"
        if isinstance(value, dict):
            stack.extend((v, (*where, k)) for k, v in value.items())
        elif isinstance(value, list):
            stack.extend((v, (*where, i)) for i, v in enumerate(value))
    return None


def toml_text(tables: dict, *, header: str = "") -> str:
    """A TOML document of ``tables``: top-level scalars first, then one ``[table]`` per dict
    value (nested dicts and lists inline). Floats are written with ``repr`` (the shortest text
    that reads back to the same bits; ``inf``/``nan`` as TOML spells them), so a document
    read back with ``tomllib`` gives the same numbers. TOML has no null: a ``None`` raises
    ``ValueError`` naming its key (leave such keys out)."""
    lines = [f"# {line}" for line in header.splitlines()]
    plain = {k: v for k, v in tables.items() if not isinstance(v, dict)}
    lines += [f"{_toml_key(k)} = {_toml_value(v, k)}" for k, v in plain.items()]
    for name, table in tables.items():
        if isinstance(table, dict):
            lines += ["", f"[{_toml_key(name)}]"]
            lines += [f"{_toml_key(k)} = {_toml_value(v, f'{name}.{k}')}" for k, v in table.items()]
    return "\n".join(lines) + "\n"


def _toml_key(key) -> str:
    import json
    import re

    key = str(key)
    return key if re.fullmatch(r"[A-Za-z0-9_-]+", key) else json.dumps(key)


def _toml_value(value, where: str) -> str:
    import json

    if value is None:
        raise ValueError(f"`{where}` is None, which TOML cannot hold")
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, Integral):
        return str(int(value))
    if isinstance(value, Real):
        x = float(value)
        return ("nan" if math.isnan(x) else "inf" if x > 0 else "-inf") if not math.isfinite(x) else repr(x)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)  # JSON's string escapes are TOML's
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_toml_key(k)} = {_toml_value(v, f'{where}.{k}')}" for k, v in value.items()) + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v, f"{where}[{i}]") for i, v in enumerate(value)) + "]"
    raise ValueError(f"`{where}` is a {type(value).__name__}, which TOML cannot hold")


# -- writing -----------------------------------------------------------------
def output_path(arg: str, path, *, suffixes: tuple[str, ...] | None = None, probe: bool = True) -> Path:
    """``path`` as a Path if a file can be written there; checked before any work is done.

    Refuses a wrong extension (``suffixes``, lower case with the dot), an
    existing directory, and a parent that is a file or not writable.
    """
    if not str(path).strip():
        raise FileError(arg, path, "is empty", "give a file name")
    path = Path(path)
    if suffixes is not None and path.suffix.lower() not in suffixes:
        raise FileError(arg, path, f"must end in {', '.join(suffixes)}")
    if path.is_dir():
        raise FileError(arg, path, "is a directory")
    parent = path.parent
    while not parent.exists() and parent != parent.parent:
        parent = parent.parent  # atomic_write creates the missing directories
    if not parent.is_dir():
        raise FileError(arg, path, "cannot be created", f"{str(parent)!r} is not a directory")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise FileError(arg, path, "cannot be created", f"{str(parent)!r} is not writable")
    if probe:
        _probe_write(arg, path, parent)
    return path


def _probe_write(arg: str, path, directory: Path) -> None:
    """Create and remove a temporary file in ``directory``: the only sure test that files can be
    written there (``os.access`` says yes to root for /proc, /sys and read-only mounts)."""
    try:
        fd, tmp = tempfile.mkstemp(prefix=".asperity2d-probe-", dir=directory)
    except OSError as exc:
        raise FileError(arg, path, "cannot be created",
                        f"{str(directory)!r}: {exc.strerror or exc}") from None
    os.close(fd)
    with contextlib.suppress(OSError):
        os.unlink(tmp)


def output_dir(arg: str, path) -> Path:
    """``path`` as a Path if it is, or can be created as, a directory we can write into."""
    if not str(path).strip():
        raise FileError(arg, path, "is empty", "give a directory name")
    path = Path(path)
    existing = path
    while not existing.exists() and existing != existing.parent:
        existing = existing.parent
    if not existing.is_dir():
        if existing == path:
            raise FileError(arg, path, "is not a directory")
        raise FileError(arg, path, "cannot be created", f"{str(existing)!r} is not a directory")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise FileError(arg, path, "is not writable", f"permission denied in {str(existing)!r}")
    _probe_write(arg, path, existing)
    return path


def atomic_write(path: str | os.PathLike, write: Callable[[IO[bytes]], None]) -> Path:
    """Call ``write(fileobj)`` on a temporary file beside ``path``, then rename it.

    The rename is atomic on POSIX and Windows, so readers see either the old
    file or the complete new one. The temporary file is removed on error.
    A directory at ``path``, or a file where a parent directory should be,
    raises :class:`FileError` before anything is written.
    """
    path = output_path("path", path, probe=False)  # the temporary file below is the probe
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    except OSError as exc:
        raise FileError("path", path, "cannot be created", exc.strerror or str(exc)) from None
    try:
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600; give the usual permissions
        with os.fdopen(fd, "wb") as fh:
            write(fh)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        if isinstance(exc, OSError):  # a full disk, a quota, a device error: nothing was written
            raise FileError("path", path, "could not be written",
                            f"{exc.strerror or exc}; the file was left as it was") from None
        raise
    return path


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def atomic_write_text(path: str | os.PathLike, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    return atomic_write(path, lambda fh: fh.write(text.encode("utf-8")))


# -- .npz: arrays plus JSON metadata -------------------------------------------
def save_npz(path: str | os.PathLike, arrays: dict, meta: dict, *, format: str | None = None) -> Path:
    """Write ``arrays`` plus a JSON ``metadata`` entry as one compressed ``.npz``, atomically.

    ``format`` (e.g. ``"asperity2d.result/2"``) is stored as the metadata's ``format`` tag, which
    :func:`check_format` reads back."""
    if format is not None:
        meta = {**meta, "format": format}
    import io
    import json

    import numpy as np

    path = output_path("path", path, suffixes=(".npz",))
    payload = {name: np.asarray(value) for name, value in arrays.items()}
    # metadata keeps NaN as NaN (Python's JSON extension) so a saved run loads back unchanged
    payload["metadata"] = np.array(json.dumps(meta, sort_keys=True))

    def write(fh):
        buf = io.BytesIO()
        np.savez_compressed(buf, **payload)
        fh.write(buf.getvalue())

    return atomic_write(path, write)


#: A zip archive (what an .npz is) starts with a local file header, or is an empty archive.
_ZIP_SIGNATURES = (b"PK\x03\x04", b"PK\x05\x06")


#: The most a saved ``.npz`` may inflate to (bytes, the sum of its members' uncompressed sizes in
#: the zip headers), checked before anything is inflated: a result that fits in memory is far
#: smaller, and one that does not is streamed to a directory instead (``record_to=``).
MAX_INFLATED_BYTES = 2**30


def save_mat(path: str | os.PathLike, arrays: dict) -> Path:
    """Write ``arrays`` (name -> array or string) to a MATLAB ``.mat`` (v5) file, atomically.

    A boolean array is written as MATLAB ``logical`` (SciPy sets the logical flag on a uint8 matrix),
    so ``load`` in MATLAB gives ``logical``; :func:`load_mat` gives it back as ``bool``."""
    from scipy.io import savemat

    return atomic_write(path, lambda fh: savemat(fh, arrays))


def load_mat(path: str | os.PathLike, *, kind: str = "a MATLAB .mat file") -> dict:
    """Read a ``.mat`` file: name -> array, with MATLAB ``logical`` arrays back as ``bool``.

    ``scipy.io.loadmat`` reads a logical matrix as ``uint8`` (it ignores the flag on reading); here
    the variables ``scipy.io.whosmat`` lists as ``logical`` are converted back (their values are 0
    and 1). SciPy's own keys (``__header__``, ...) are dropped. A file that cannot be read raises
    :class:`FileError` naming ``path``."""
    import numpy as np
    from scipy.io import loadmat, whosmat

    source = input_path("path", path)
    try:
        logical = {name for name, _shape, cls in whosmat(source) if cls == "logical"}
        data = loadmat(source)
    except Exception as exc:  # scipy raises ValueError, TypeError, OSError, ... on a damaged file
        raise FileError("path", source, f"is not {kind}", f"{type(exc).__name__}: {exc}") from None
    out = {}
    for name, value in data.items():
        if name.startswith("__"):
            continue
        out[name] = value.astype(bool) if name in logical else value
    return out


def _check_inflated_size(path, kind: str) -> None:
    """Refuse an archive whose zip headers promise more than :data:`MAX_INFLATED_BYTES` (a
    1.5 MB file can hold 1.5 GB of zeros). Reading the headers inflates nothing; a member whose
    data turn out longer than its header says fails its CRC check when read."""
    import zipfile

    try:
        with zipfile.ZipFile(path) as archive:
            members = archive.infolist()
    except (zipfile.BadZipFile, OSError, ValueError, EOFError) as exc:
        raise FileError("path", path, f"is damaged or not {kind}", f"{type(exc).__name__}: {exc}") from None
    total = sum(member.file_size for member in members)
    if total > MAX_INFLATED_BYTES:
        raise FileError("path", path, f"is too large to load as {kind}",
                        f"its arrays inflate to {total / 2**20:.0f} MiB, more than the limit of "
                        f"{MAX_INFLATED_BYTES / 2**20:.0f} MiB (asperity2d._io.MAX_INFLATED_BYTES)")


def load_npz(path: str | os.PathLike, names, *, kind: str,
             meta_keys: tuple[str, ...] = ()) -> tuple[dict, dict]:
    """Read the arrays ``names`` and the JSON metadata (with ``meta_keys``) of a :func:`save_npz` file.

    A missing, empty, foreign, truncated or damaged file raises
    :class:`FileError` naming ``path`` (``kind`` says what was expected, e.g.
    "an asperity2d result file"). Damage is caught by the zip format's CRC-32
    of every member, so arrays that load are the arrays that were saved.
    """
    import json

    import numpy as np

    with open(input_path("path", path), "rb") as fh:
        head = fh.read(4)
    if not head:
        raise FileError("path", path, "is empty")
    if head not in _ZIP_SIGNATURES:
        raise FileError("path", path, "is not an .npz file", f"expected {kind}, a zip archive")
    _check_inflated_size(path, kind)
    try:
        with np.load(path, allow_pickle=False) as data:
            missing = [name for name in (*names, "metadata") if name not in data.files]
            if missing:
                raise FileError("path", path, f"is not {kind}", f"it has no {missing[0]!r} array")
            arrays = {name: data[name] for name in names}
            meta = json.loads(str(data["metadata"]))
    except FileError:
        raise
    except Exception as exc:  # noqa: BLE001 - zipfile/zlib/NumPy raise a dozen types on a damaged file
        raise FileError("path", path, f"is damaged or not {kind}",
                        f"{type(exc).__name__}: {exc}") from None
    if not isinstance(meta, dict):
        raise FileError("path", path, f"is not {kind}", "its metadata is not a JSON object")
    for key in meta_keys:
        if key not in meta:
            raise FileError("path", path, f"is not {kind}", f"its metadata has no {key!r}")
    return arrays, meta


# -- strict JSON: the one emitter of --json output, summary files and saved metadata ----------
def plain(value):
    """``value`` as plain JSON data: dicts (keys as strings), lists, str, int, float, bool, None.

    NumPy scalars and arrays become Python numbers and (nested) lists, tuples lists, paths
    strings; a non-finite float (NaN, an infinity: an undefined statistic, a missing value)
    becomes ``None``; other real numbers (``Fraction``, ``Decimal``) floats, and any other
    object its ``str``. Floats keep full precision (``json`` writes their shortest repr).
    """
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if value is None or isinstance(value, (str, bool, int)):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if hasattr(value, "tolist"):  # NumPy scalars and arrays (a NumPy bool becomes a bool)
        return plain(value.tolist())
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    if isinstance(value, (Real, Decimal)):
        return plain(float(value))
    return str(value)


def to_json(value, *, indent: int | None = None) -> str:
    """Strict JSON text of ``value`` (through :func:`plain`: NaN and infinities as ``null``,
    NumPy plain), keys sorted. Every ``--json`` output and every summary file (``summary.json``,
    a study's claims, a basin map's summary, a saved comparison) is written by this function."""
    import json

    return json.dumps(plain(value), indent=indent, sort_keys=True, allow_nan=False)


def print_json(value) -> None:
    """Print ``value`` as one line of strict JSON (a command's ``--json`` output)."""
    print(to_json(value))


def write_json(path: str | os.PathLike, value, *, indent: int = 2) -> Path:
    """Write ``value`` as strict JSON (:func:`to_json`) to ``path``, atomically."""
    return atomic_write_text(path, to_json(value, indent=indent) + "\n")


def check_format(path, meta: dict, tag: str, *, kind: str, untagged: bool = True) -> int:
    """Check (and remove) the ``format`` tag of a file's metadata; return its version.

    ``tag`` is ``"name/version"``, the one this release writes. A file without a tag is
    version 1 (the previous release's files) when ``untagged`` (its layout is then checked by
    the reader); any other tag -- another kind of file, a newer version -- raises
    :class:`FileError` naming ``path`` and the tag found.
    """
    found = meta.pop("format", None)
    if found is None and untagged:
        return 1
    if found != tag:
        raise FileError("path", path, f"is not {kind}", f"its format is {found!r}, expected {tag!r}")
    return int(tag.rpartition("/")[2])
