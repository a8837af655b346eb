"""A run's record streamed to disk as it is taken, and read back lazily (``simulate(...,
record_to=path)``, ``asperity2d.load(path)``).

A streamed record is a directory: one ``.npy`` file per array of the :class:`~asperity2d.result.Result`
(``t.npy`` ... ``contact_count.npy`` of shape (T,); ``lower_dx.npy``, ``lower_dy.npy``,
``lower_contact.npy`` of shape (T, N), read back as (N, T) views) and a JSON manifest,
``record.json``, holding the format tag, the scene, the run's metadata and how many samples are
committed. Plain ``.npy`` keeps the dependencies light and every array readable by
``numpy.load`` alone; :func:`load` maps the files (``mmap_mode="r"``), so a record far larger
than memory loads at once and is read only where it is used.

The run writes a block of samples at a time (:class:`Writer`, the sink of
:class:`asperity2d.engine.recorder.Recorder`): it appends the block to every file, syncs them,
rewrites each file's header with its new length, and only then replaces the manifest
(atomically) with the new count. So whatever moment the run is killed at, the manifest names a
prefix that is fully on disk: :func:`load` returns those samples, with status ``"interrupted"``
(``success`` False) and a message saying so, and ignores anything written after them. A
directory that is not such a record, or whose files hold fewer samples than its manifest says,
is refused with one :class:`~asperity2d._io.FileError`.
"""

from __future__ import annotations

import json
import os
import struct
from pathlib import Path

import numpy as np

from ._io import FileError, atomic_write_text, input_path, output_dir, writing
from .errors import SceneError
from .result import LOWER_SERIES, SERIES, Result
from .scene import Scene

#: The manifest's format tag.
FORMAT = "asperity2d.record/1"
MANIFEST = "record.json"
#: Every .npy header is padded to this many bytes, so it can be rewritten in place as the file grows.
HEADER_BYTES = 256
_DTYPES = {**{name: np.dtype("<f8") for name in SERIES + ("lower_dx", "lower_dy")},
           "lower_contact": np.dtype("|b1")}
#: Status of a record whose run did not finish writing it.
INTERRUPTED = "interrupted"


def _header(dtype: np.dtype, shape: tuple[int, ...]) -> bytes:
    """A version 1.0 ``.npy`` header of exactly :data:`HEADER_BYTES` bytes."""
    text = repr({"descr": np.lib.format.dtype_to_descr(dtype), "fortran_order": False,
                 "shape": tuple(shape)})
    body = text.encode("latin1")
    pad = HEADER_BYTES - 10 - len(body) - 1
    if pad < 0:  # pragma: no cover - a shape of ~200 digits
        raise SceneError(f"a record of shape {shape} does not fit a {HEADER_BYTES}-byte header")
    return b"\x93NUMPY\x01\x00" + struct.pack("<H", HEADER_BYTES - 10) + body + b" " * pad + b"\n"


def is_record(path) -> bool:
    """True if ``path`` is a directory holding a streamed record's manifest."""
    path = Path(path)
    return path.is_dir() and (path / MANIFEST).is_file()


class Writer:
    """Streams a run's record into directory ``path`` (created; a previous record there is
    replaced, anything else refused). ``n_lower`` lower asperities, whose arrays are written
    only with ``lower``; ``meta`` the run's settings, kept in the manifest from the start (an
    interrupted record still says its step and units). The sink of
    :class:`~asperity2d.engine.recorder.Recorder`."""

    def __init__(self, path, *, scene: Scene, lower: bool = True, meta: dict | None = None):
        path = output_dir("record_to", path)
        if path.exists():
            if not path.is_dir():
                raise FileError("record_to", path, "exists and is not a directory")
            foreign = [p.name for p in path.iterdir()
                       if p.name != MANIFEST and not (p.suffix == ".npy" and p.stem in _DTYPES)]
            if foreign or (any(path.iterdir()) and not is_record(path)):
                raise FileError("record_to", path, "exists and is not a streamed record",
                                f"it holds {', '.join(sorted(foreign)[:3]) or 'no manifest'}; "
                                "give a new directory")
        self.path = path
        self.scene = scene
        self.lower = bool(lower)
        self.n_lower = scene.lower.count if lower else 0
        self.samples = 0
        with writing("record_to", path):
            path.mkdir(parents=True, exist_ok=True)
            for stale in path.glob("*.npy"):
                stale.unlink()
            (path / MANIFEST).unlink(missing_ok=True)
            self._files = {}
            for name, dtype in _DTYPES.items():
                fh = open(path / f"{name}.npy", "w+b")
                fh.write(_header(dtype, self._shape(name, 0)))
                self._files[name] = fh
        self._meta: dict = dict(meta or {})
        self._commit(complete=False)

    def _shape(self, name: str, samples: int) -> tuple[int, ...]:
        return (samples, self.n_lower) if name in LOWER_SERIES else (samples,)

    def write(self, cols: np.ndarray, dx: np.ndarray, dy: np.ndarray, contact: np.ndarray) -> None:
        """Append ``m`` samples: ``cols`` (11, m) in :data:`~asperity2d.result.SERIES` order and
        the lower asperities' (N, m) arrays (ignored without ``lower``); then commit them."""
        m = cols.shape[1]
        if not m:
            return
        blocks = {name: cols[j] for j, name in enumerate(SERIES)}
        if self.lower:
            blocks.update(lower_dx=dx.T, lower_dy=dy.T, lower_contact=contact.T)
        with writing("record_to", self.path):
            for name, fh in self._files.items():
                if name in blocks:
                    fh.seek(0, os.SEEK_END)
                    fh.write(np.ascontiguousarray(blocks[name], dtype=_DTYPES[name]).data)
            self.samples += m
            self._sync()
            self._commit(complete=False)

    def _sync(self) -> None:
        """Data on disk first, then each header with the new length (in place)."""
        for fh in self._files.values():
            fh.flush()
            os.fsync(fh.fileno())
        for name, fh in self._files.items():
            fh.seek(0)
            fh.write(_header(_DTYPES[name], self._shape(name, self.samples)))
            fh.flush()

    def _commit(self, *, complete: bool) -> None:
        manifest = {"format": FORMAT, "complete": complete, "samples": self.samples,
                    "lower": self.lower, "n_lower": self.n_lower,
                    "scene": self.scene.to_dict(), "meta": self._meta}
        with writing("record_to", self.path):
            atomic_write_text(self.path / MANIFEST, json.dumps(manifest, sort_keys=True) + "\n")

    def finish(self, meta: dict) -> None:
        """Mark the record complete with the run's metadata ``meta`` (its status and message);
        samples written after this (a run advanced again) make it incomplete until the next call."""
        self._meta = {**self._meta, **meta}
        self._commit(complete=True)

    def abort(self, reason: str, meta: dict | None = None) -> None:
        """Keep what is written, marked as not finished because of ``reason`` (the run raised)."""
        self._meta = {**self._meta, **(meta or {}), "status": INTERRUPTED,
                      "message": f"the run stopped after {self.samples} samples: {reason}"}
        self._commit(complete=False)

    def close(self) -> None:
        for fh in self._files.values():
            fh.close()
        self._files = {}


def load(path) -> Result:
    """A streamed record as a :class:`~asperity2d.result.Result` whose arrays are read-only
    memory maps of its files (nothing is read until used).

    A record whose run did not finish (killed, or it raised) loads as the prefix its manifest
    committed, with ``status == "interrupted"`` and a message saying how far it got. A
    directory that is not a record, a damaged manifest, or files shorter than the manifest
    says raise :class:`~asperity2d._io.FileError` naming ``path``.
    """
    return read(path)


def read(path, *, start: int = 0) -> Result:
    """:func:`load`, from sample ``start`` on (:meth:`asperity2d.run.Run.result`)."""
    kind = "a streamed asperity2d record"
    path = input_path("path", path, directory=True)
    if not (path / MANIFEST).is_file():
        raise FileError("path", path, f"is not {kind}", f"it has no {MANIFEST}")
    try:
        manifest = json.loads((path / MANIFEST).read_text(encoding="utf-8"))
        if not isinstance(manifest, dict) or manifest.get("format") != FORMAT:
            raise ValueError(f"its format is {manifest.get('format') if isinstance(manifest, dict) else None!r}, "
                             f"expected {FORMAT!r}")
        samples, n_lower, lower = int(manifest["samples"]), int(manifest["n_lower"]), bool(manifest["lower"])
        complete, meta = bool(manifest["complete"]), dict(manifest["meta"])
        scene = Scene.from_dict(manifest["scene"])
        if samples < 0 or n_lower != (scene.lower.count if lower else 0):
            raise ValueError(f"{samples} samples of {n_lower} lower asperities for a scene of "
                             f"{scene.lower.count}")
    except FileError:
        raise
    except Exception as exc:  # noqa: BLE001 - any malformed manifest; the file is not ours to trust
        raise FileError("path", path, f"is not {kind}", f"its {MANIFEST} is invalid: {exc}") from None
    arrays = {}
    for name, dtype in _DTYPES.items():
        file = path / f"{name}.npy"
        tail = (n_lower,) if name in LOWER_SERIES else ()
        try:
            mapped = np.load(file, mmap_mode="r", allow_pickle=False) if samples else None
        except Exception as exc:  # noqa: BLE001 - missing, truncated or foreign file
            raise FileError("path", path, "is a damaged record",
                            f"{file.name}: {type(exc).__name__}: {exc}") from None
        if mapped is None or start >= samples:
            data = np.empty((0, *tail), dtype=dtype)
        elif mapped.dtype != dtype or mapped.shape[1:] != tail or mapped.shape[0] < samples:
            raise FileError("path", path, "is a damaged record",
                            f"{file.name} holds {mapped.shape} {mapped.dtype}, the manifest says "
                            f"{samples} samples of {tail} {dtype}")
        else:
            data = mapped[start:samples]
        arrays[name] = data.T if name in LOWER_SERIES else data
    if not lower:  # the lower asperities were not recorded: no samples
        for name in LOWER_SERIES:
            arrays[name] = np.empty((scene.lower.count, 0), dtype=_DTYPES[name])
    if not complete and meta.get("status") != INTERRUPTED:  # killed: nobody marked it
        meta["status"] = INTERRUPTED
        meta["message"] = (f"the run stopped after {samples} samples before it finished (killed?); "
                           "these are the samples it had written")
    meta["record_to"] = str(path)
    return Result(**arrays, scene=scene, meta=meta)
