"""The run file format: one finished run as checksummed JSON.

A run file is ``{"format", "payload", "checksum"}``: ``payload`` holds the
run's inputs (run path, params, seed), its status, quantities or error text
and traceback, and its wall time; ``checksum`` is ``"sha256:"`` + the hex
SHA-256 of the canonical JSON of ``payload``. :func:`decode_run` trusts a file
only if it parses, its checksum matches, and its payload hashes to the key it
is filed under, so a half-written, edited or misplaced file is never data.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field
from datetime import datetime, timezone
from typing import Any, Mapping

from ..errors import SceneError
from .study import RunSpec, canonical_json, run_key

FORMAT = "asperity2d-sweep/1"
STATUSES = ("done", "failed")


class CorruptRunWarning(UserWarning):
    """A run file could not be trusted; the run will be executed again.

    See Also
    --------
    asperity2d.sweep.ResultStore, asperity2d.sweep.run_study

    Examples
    --------
    >>> from asperity2d import sweep
    >>> issubclass(sweep.CorruptRunWarning, UserWarning)
    True
    """


class CorruptRunError(ValueError):
    """Raised by :func:`decode_run`; the message says what is wrong."""


def now() -> str:
    """Current UTC time, ISO 8601 to the second."""
    return datetime.now(timezone.utc).isoformat(timespec="seconds")


@dataclass(frozen=True, kw_only=True)
class RunRecord:
    """One finished run as stored: inputs, status, outputs and timing.

    ``quantities`` maps name -> float for done runs (empty when failed);
    ``error``/``traceback`` hold the exception text of failed runs;
    ``wall_time`` is the time spent in the run function (s).

    See Also
    --------
    asperity2d.sweep.ResultStore

    Examples
    --------
    >>> from asperity2d import sweep
    >>> study = sweep.Study(name='spacing', run='asperity2d.studies.ooten:critical_force_run',
    ...                     grid={'spacing': ('regular', 'random')}, seeds=(0,),
    ...                     fixed={'lower_count': 4, 'upper_count': 2}, quantities=('critical_force_N',))
    >>> session = sweep.run_study(study, store='spacing', workers=1, progress=False)
    >>> store = sweep.ResultStore('spacing')
    >>> record = store.read_run(session.executed[0])
    >>> record.status, {k: round(v, 5) for k, v in record.quantities.items()}
    ('done', {'critical_force_N': 0.00761})
    """

    key: str
    run: str
    params: Mapping[str, Any]
    seed: int
    status: str
    quantities: Mapping[str, float] = field(default_factory=dict)
    error: str | None = None
    traceback: str | None = None
    wall_time: float = float("nan")
    finished: str = ""

    def __post_init__(self) -> None:
        if self.status not in STATUSES:
            raise SceneError(f"`status` must be one of {STATUSES}, got {self.status!r}")

    @classmethod
    def from_outcome(cls, spec: RunSpec, run: str, outcome) -> "RunRecord":
        """Record for ``spec`` from the engine's :class:`~.engine.Outcome` of
        ``execute_run`` (its value: the quantities of a done run)."""
        return cls(
            key=spec.key,
            run=run,
            params=dict(spec.params),
            seed=spec.seed,
            status=outcome.status,
            quantities=dict(outcome.value) if outcome.ok else {},
            error=outcome.error,
            traceback=outcome.traceback,
            wall_time=float(outcome.wall_time),
            finished=now(),
        )

    def to_payload(self) -> dict[str, Any]:
        return {
            "key": self.key,
            "run": self.run,
            "params": dict(self.params),
            "seed": self.seed,
            "status": self.status,
            "quantities": dict(self.quantities),
            "error": self.error,
            "traceback": self.traceback,
            "wall_time": self.wall_time,
            "finished": self.finished,
        }


def checksum(payload: Mapping[str, Any]) -> str:
    """``"sha256:<hex>"`` of the canonical JSON of ``payload``."""
    return "sha256:" + hashlib.sha256(canonical_json(payload).encode("utf-8")).hexdigest()


def encode_run(record: RunRecord) -> str:
    """The text of a run file for ``record``."""
    payload = record.to_payload()
    document = {"format": FORMAT, "payload": payload, "checksum": checksum(payload)}
    return json.dumps(document, indent=1) + "\n"


def decode_run(text: str, key: str) -> RunRecord:
    """Parse and verify a run file filed under ``key``; CorruptRunError if untrustworthy."""
    try:
        document = json.loads(text)
        payload = document["payload"]
        if document.get("format") != FORMAT:
            raise CorruptRunError(f"unknown format {document.get('format')!r}")
        if document.get("checksum") != checksum(payload):
            raise CorruptRunError("checksum mismatch")
        if payload["key"] != key or run_key(payload["run"], payload["params"], payload["seed"]) != key:
            raise CorruptRunError("contents do not match the file's key")
        return RunRecord(**payload)
    except CorruptRunError:
        raise
    except (json.JSONDecodeError, KeyError, TypeError, ValueError, AttributeError) as exc:
        raise CorruptRunError(f"malformed: {type(exc).__name__}: {exc}") from None
