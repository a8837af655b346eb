"""Progress display for a running study: a tqdm bar with done / failed counts."""

from __future__ import annotations

import sys

from tqdm import tqdm


class Progress:
    """A progress bar over all runs of a study (already finished ones count).

    The bar shows runs finished out of the total, the rate of this session
    (runs/s, from tqdm) and ``done=``/``failed=`` counts. ``enabled=False``
    shows nothing but still counts.
    """

    def __init__(self, *, total: int, done: int = 0, failed: int = 0, label: str = "",
                 enabled: bool = True):
        self.done = done
        self.failed = failed
        self._bar = tqdm(
            total=total,
            initial=done + failed,
            desc=label or None,
            unit="run",
            disable=not enabled,
            file=sys.stderr,
            dynamic_ncols=True,
        )
        self._bar.set_postfix(done=self.done, failed=self.failed, refresh=False)

    def update(self, status: str) -> None:
        """Count one finished run with ``status`` ("done" or "failed")."""
        if status == "done":
            self.done += 1
        else:
            self.failed += 1
        self._bar.set_postfix(done=self.done, failed=self.failed, refresh=False)
        self._bar.update(1)

    def close(self) -> None:
        self._bar.close()

    def __enter__(self) -> "Progress":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
