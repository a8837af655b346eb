"""Atomic file writing: nothing a user saved is ever left half-written."""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path
from typing import Callable, IO


def atomic_write(path: str | os.PathLike, write: Callable[[IO[bytes]], None]) -> Path:
    """Call ``write(fileobj)`` on a temporary file beside ``path``, then rename it.

    The rename is atomic on POSIX and Windows, so readers see either the old
    file or the complete new one. The temporary file is removed on error.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600; give the usual permissions
        with os.fdopen(fd, "wb") as fh:
            write(fh)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise
    return path


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def atomic_write_text(path: str | os.PathLike, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    return atomic_write(path, lambda fh: fh.write(text.encode("utf-8")))


def save_npz(path: str | os.PathLike, arrays: dict, meta: dict) -> Path:
    """Write ``arrays`` plus a JSON ``metadata`` entry as one compressed ``.npz``, atomically."""
    import io
    import json

    import numpy as np

    from .errors import SceneError

    path = Path(path)
    if path.suffix != ".npz":
        raise SceneError(f"`path` must end in .npz, got {str(path)!r}")
    payload = {name: np.asarray(value) for name, value in arrays.items()}
    payload["metadata"] = np.array(json.dumps(meta, sort_keys=True))

    def write(fh):
        buf = io.BytesIO()
        np.savez_compressed(buf, **payload)
        fh.write(buf.getvalue())

    return atomic_write(path, write)


def load_npz(path: str | os.PathLike, names, *, kind: str) -> tuple[dict, dict]:
    """Read the arrays ``names`` and the JSON metadata of a :func:`save_npz` file.

    A missing, unreadable or foreign file raises ``SceneError`` naming ``path``
    (``kind`` says what was expected, e.g. "an asperity2d result file").
    """
    import json

    import numpy as np

    from .errors import SceneError

    path = Path(path)
    if not path.exists():
        raise SceneError(f"`path` does not exist: {str(path)!r}")
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {name: data[name] for name in names}
            meta = json.loads(str(data["metadata"]))
    except (OSError, KeyError, ValueError) as exc:
        raise SceneError(f"`path` is not {kind}: {str(path)!r} ({exc})") from None
    return arrays, meta
