"""The results store: one directory per study, one checksummed JSON file per run.

Layout::

    DIR/manifest.json      the study, versions, created time, one entry per session
    DIR/runs/<key>.json    one finished run (done or failed), written atomically

Run files are checksummed (see :mod:`.record`). A file that does not parse,
fails its checksum, or whose contents do not hash to its file name is
*corrupt*: it is never read as data, a :class:`CorruptRunWarning` names it,
and the run counts as pending so the next session runs it again.

Tables (structured array, CSV) cover the runs of the study recorded in the
manifest, in study order; files left over from an earlier grid ("orphans")
are kept but not reported.
"""

from __future__ import annotations

import csv
import io
import json
import platform
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .._io import atomic_write_text
from .._version import distribution_version
from ..errors import SceneError
from .record import (FORMAT, CorruptRunError, CorruptRunWarning, RunRecord, decode_run,
                     encode_run, now)
from .study import KEY_LENGTH, Study


def versions() -> dict[str, str]:
    """Versions recorded in the manifest: asperity2d, numpy, pymunk, Python."""
    return {
        "asperity2d": distribution_version("asperity2d"),
        "numpy": np.__version__,
        "pymunk": distribution_version("pymunk"),
        "python": platform.python_version(),
    }


@dataclass(frozen=True)
class StoreStatus:
    """Counts over the study's runs; ``corrupt`` runs are also counted as pending.

    See Also
    --------
    asperity2d.sweep.ResultStore.status

    Examples
    --------
    >>> from asperity2d import sweep
    >>> study = sweep.Study(name='spacing', run='asperity2d.studies.ooten:critical_force_run',
    ...                     grid={'spacing': ('regular', 'random')}, seeds=(0,),
    ...                     fixed={'lower_count': 4, 'upper_count': 2}, quantities=('critical_force_N',))
    >>> session = sweep.run_study(study, store='spacing', workers=1, progress=False)
    >>> sweep.ResultStore('spacing').status()
    StoreStatus(total=2, done=2, failed=0, pending=0, corrupt=0, orphaned=0)
    """

    total: int
    done: int
    failed: int
    pending: int
    corrupt: int
    orphaned: int

    def to_dict(self) -> dict[str, int]:
        return dict(self.__dict__)


class ResultStore:
    """A study's results directory (see the module docstring for the layout).

    Parameters
    ----------
    path : str or pathlib.Path
        The study's results directory.

    See Also
    --------
    asperity2d.sweep.run_study : fills it.
    asperity2d.sweep.summarize : reads it.

    Examples
    --------
    >>> from asperity2d import sweep
    >>> study = sweep.Study(name='spacing', run='asperity2d.studies.ooten:critical_force_run',
    ...                     grid={'spacing': ('regular', 'random')}, seeds=(0,),
    ...                     fixed={'lower_count': 4, 'upper_count': 2}, quantities=('critical_force_N',))
    >>> session = sweep.run_study(study, store='spacing', workers=1, progress=False)
    >>> store = sweep.ResultStore('spacing')
    >>> store.status()
    StoreStatus(total=2, done=2, failed=0, pending=0, corrupt=0, orphaned=0)
    """

    def __init__(self, path: str | Path):
        self.path = Path(path)

    @property
    def manifest_path(self) -> Path:
        return self.path / "manifest.json"

    @property
    def runs_dir(self) -> Path:
        return self.path / "runs"

    def run_path(self, key: str) -> Path:
        return self.runs_dir / f"{key}.json"

    # -- manifest ----------------------------------------------------------
    def read_manifest(self) -> dict[str, Any]:
        """The manifest; SceneError if ``path`` is not a sweep store."""
        if not self.manifest_path.is_file():
            raise SceneError(f"`store` is not a sweep store (no manifest.json): {str(self.path)!r}")
        try:
            manifest = json.loads(self.manifest_path.read_text("utf-8"))
        except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
            raise SceneError(f"`store` manifest is unreadable: {str(self.manifest_path)!r} ({exc})") from None
        if not isinstance(manifest, dict) or manifest.get("format") != FORMAT:
            raise SceneError(f"`store` manifest is not format {FORMAT}: {str(self.manifest_path)!r}")
        if not isinstance(manifest.get("study"), dict) or not isinstance(manifest.get("sessions", []), list):
            raise SceneError(f"`store` manifest has no valid study record: {str(self.manifest_path)!r}")
        return manifest

    def study(self) -> Study:
        """The study recorded in the manifest (the latest one run here)."""
        return Study.from_dict(self.read_manifest()["study"])

    def check_study(self, study: Study) -> None:
        """SceneError unless the store is new or already holds a study of this name.

        A store holds one study by name; its grid, seeds and parameters may change
        between sessions (only the affected runs are re-run).
        """
        if self.path.exists() and not self.path.is_dir():
            raise SceneError(f"`store` exists and is not a directory: {str(self.path)!r}")
        if self.manifest_path.exists():
            old_name = self.read_manifest()["study"]["name"]
            if old_name != study.name:
                raise SceneError(
                    f"`store` {str(self.path)!r} holds study {old_name!r}, not {study.name!r}"
                )

    def begin_session(self, study: Study, *, executor: str) -> None:
        """Create the store or update its manifest for a new session of ``study``."""
        self.check_study(study)
        if self.manifest_path.exists():
            manifest = self.read_manifest()
        else:
            manifest = {"format": FORMAT, "created": now(), "versions": versions(), "sessions": []}
        manifest["study"] = study.to_dict()
        manifest["sessions"].append({"started": now(), "executor": executor, "versions": versions()})
        self.runs_dir.mkdir(parents=True, exist_ok=True)
        atomic_write_text(self.manifest_path, json.dumps(manifest, indent=2, sort_keys=True) + "\n")

    # -- run files ---------------------------------------------------------
    def write_run(self, record: RunRecord) -> Path:
        """Write one finished run atomically (temporary file, then rename)."""
        return atomic_write_text(self.run_path(record.key), encode_run(record))

    def read_run(self, key: str) -> RunRecord | None:
        """The stored run ``key``, or None if missing or corrupt (corrupt: also warns)."""
        path = self.run_path(key)
        try:
            text = path.read_text("utf-8")
        except FileNotFoundError:
            return None
        except (OSError, UnicodeDecodeError) as exc:
            return self._corrupt(path, f"unreadable ({exc})")
        try:
            return decode_run(text, key)
        except CorruptRunError as exc:
            return self._corrupt(path, str(exc))

    @staticmethod
    def _corrupt(path: Path, why: str) -> None:
        warnings.warn(
            f"sweep run file {str(path)!r} is corrupt or half-written ({why}); "
            "it is ignored and the run will be executed again",
            CorruptRunWarning,
            stacklevel=3,
        )
        return None

    def stored_keys(self) -> set[str]:
        """Keys of every run file present (valid or not)."""
        if not self.runs_dir.is_dir():
            return set()
        return {p.stem for p in self.runs_dir.glob("*.json")}

    def records(self, study: Study | None = None) -> dict[str, RunRecord]:
        """Valid finished runs of ``study`` (default: the manifest's), by key."""
        study = study or self.study()
        out = {}
        present = self.stored_keys()
        for spec in study.runs():
            if spec.key in present:
                record = self.read_run(spec.key)
                if record is not None:
                    out[spec.key] = record
        return out

    def status(self, study: Study | None = None) -> StoreStatus:
        """Counts of done, failed, pending (incl. corrupt) and orphaned runs."""
        study = study or self.study()
        specs = study.runs()
        present = self.stored_keys()
        records = self.records(study)
        keys = {s.key for s in specs}
        done = sum(r.status == "done" for r in records.values())
        failed = len(records) - done
        return StoreStatus(
            total=len(specs),
            done=done,
            failed=failed,
            pending=len(specs) - len(records),
            corrupt=len((present & keys) - set(records)),
            orphaned=len(present - keys),
        )

    # -- tables ------------------------------------------------------------
    def table(self, study: Study | None = None) -> np.ndarray:
        """Finished runs as a NumPy structured array, in study order.

        Fields: ``key``, one per grid parameter, ``seed``, ``status``, one per
        quantity (float, NaN where a run did not produce it) and ``wall_time`` (s).
        """
        study = study or self.study()
        records = self.records(study)
        rows = [(spec, records[spec.key]) for spec in study.runs() if spec.key in records]
        names = quantity_names(study, records.values())
        dtype = [("key", f"U{KEY_LENGTH}")]
        for param, values in study.grid.items():
            dtype.append((param, _dtype_for(values)))
        dtype += [("seed", "i8"), ("status", "U6")]
        dtype += [(q, "f8") for q in names] + [("wall_time", "f8")]
        table = np.zeros(len(rows), dtype=dtype)
        for i, (spec, rec) in enumerate(rows):
            row = [spec.key] + [spec.params[p] for p in study.grid] + [spec.seed, rec.status]
            row += [rec.quantities.get(q, np.nan) for q in names] + [rec.wall_time]
            table[i] = tuple(_table_value(v) for v in row)
        return table

    def export_csv(self, path: str | Path, study: Study | None = None) -> Path:
        """Write :meth:`table` as CSV (floats with full precision) atomically."""
        table = self.table(study)
        buf = io.StringIO()
        writer = csv.writer(buf, lineterminator="\n")
        writer.writerow(table.dtype.names)
        for row in table.tolist():
            writer.writerow([repr(v) if isinstance(v, float) else v for v in row])
        return atomic_write_text(path, buf.getvalue())


def quantity_names(study: Study, records) -> list[str]:
    """The study's declared quantities, else the sorted union returned by done runs."""
    if study.quantities is not None:
        return list(study.quantities)
    return sorted({q for r in records if r.status == "done" for q in r.quantities})


def _dtype_for(values) -> str:
    if all(isinstance(v, bool) for v in values):
        return "?"
    if all(isinstance(v, int) and not isinstance(v, bool) for v in values):
        return "i8"
    if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
        return "f8"
    return f"U{max(len(str(v)) for v in values)}"


def _table_value(value: Any) -> Any:
    return "None" if value is None else value
