"""Fixtures shared by several test modules."""

import pytest


@pytest.fixture(scope="session")
def stick_slip_run():
    """A spring-driven run with 4 stick-slip events (8 lower / 3 upper asperities, slips of 1-25 ns,
    7,120 samples; 2.5 s): the pictures', the player's and the browser tests' run."""
    import asperity2d as a

    return a.simulate(a.make_scene(lower_count=8, upper_count=3))
