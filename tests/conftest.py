"""Fixtures shared by several test modules."""

import signal

import pytest


def pytest_configure(config):
    """Take SIGINT as a terminal's foreground command does, whatever this run inherited.

    The Ctrl-C tests (``test_cli_terminal``, ``test_sweep_engine``) and the servers' stops send
    SIGINT to commands this process starts, as a terminal sends it to its foreground command. A
    test run started in the background of a non-interactive shell (``pytest &``, ``nohup``)
    inherits SIGINT ignored, and a child inherits that through ``exec``: its commands would never
    see the signal (four such tests failed so). A handler, unlike an ignored signal, is reset to
    the default across ``exec``, so Python's own handler here gives every child the default.
    """
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})


@pytest.fixture(scope="session")
def stick_slip_run():
    """A spring-driven run with 4 stick-slip events (8 lower / 3 upper asperities, slips of 1-25 ns,
    7,120 samples; 2.5 s): the pictures', the player's and the browser tests' run."""
    import asperity2d as a

    return a.simulate(a.make_scene(lower_count=8, upper_count=3))
