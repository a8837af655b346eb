"""A wall-clock limit for a block of a test (the CLI budget tests and the CLI fuzzer)."""

from __future__ import annotations

import signal
from contextlib import contextmanager


class TooLong(AssertionError):
    """The block ran past its wall-clock limit."""


@contextmanager
def within(seconds: float):
    """Raise TooLong if the block runs longer than ``seconds`` of wall-clock time (SIGALRM)."""
    def alarm(signum, frame):
        raise TooLong(f"still running after {seconds} s: past any budget")

    old = signal.signal(signal.SIGALRM, alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
