"""Small deterministic run functions for the sweep tests (importable by dotted path)."""

from __future__ import annotations

import time

import numpy as np


def noisy_run(*, amplitude: float, offset: float = 0.0, seed: int) -> dict[str, float]:
    """Deterministic given (params, seed): statistics of seeded normal samples."""
    rng = np.random.default_rng(seed)
    x = amplitude * rng.normal(size=256) + offset
    return {"mean": float(x.mean()), "peak": float(np.abs(x).max())}


def slow_run(*, amplitude: float, seed: int, delay: float = 0.1) -> dict[str, float]:
    """``noisy_run`` after sleeping ``delay`` seconds (for kill / resume tests)."""
    time.sleep(delay)
    return noisy_run(amplitude=amplitude, seed=seed)


def flaky_run(*, amplitude: float, seed: int, label: str = "") -> dict[str, float]:
    """Raises for negative amplitudes, else ``noisy_run`` (``label`` is ignored)."""
    if amplitude < 0:
        raise ValueError(f"amplitude must be >= 0, got {amplitude}")
    return noisy_run(amplitude=amplitude, seed=seed)


def wrong_type_run(*, seed: int):
    """Returns something that is not a mapping of quantities."""
    return [seed]


def pid_run(*, seed: int) -> dict[str, float]:
    """The id of the process that executed the run."""
    import os

    return {"pid": float(os.getpid())}


def subprocess_env() -> dict[str, str]:
    """Environment in which child processes import asperity2d and these fixtures."""
    import os
    from pathlib import Path

    import asperity2d.sweep

    root = Path(asperity2d.sweep.__file__).resolve().parents[2]
    tests = Path(__file__).resolve().parent
    parts = [str(root), str(tests)] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    return {**os.environ, "PYTHONPATH": os.pathsep.join(parts)}


def pid_call(x: int) -> int:
    """The id of the process that ran the call."""
    import os

    return os.getpid()


def engine_call(x: int) -> int:
    """x², except: 3 raises ValueError, 5 kills its worker process (never call 5 in-process)."""
    import os

    if x == 3:
        raise ValueError("three is refused")
    if x == 5:
        os._exit(7)
    return x * x


class Unpicklable(Exception):
    """An exception that cannot travel back from a worker (it holds a lock)."""

    def __init__(self):
        import threading

        super().__init__("holds a lock")
        self.lock = threading.Lock()


def unpicklable_failure(x: int) -> int:
    raise Unpicklable()
