"""The engine's C step loop (engine.kernel) against the Python loop it replaces.

The C loop makes the same Chipmunk calls and the same IEEE operations as
``Engine.step``'s Python loop, so two copies of one engine -- one stepped in C,
one with its kernel taken away -- must agree to the bit after every step: the
bodies, the stick/slip switch's state, the drift books and the contacts.
Without the compiled extension these tests skip, saying why; the Python loop
is then what every other test runs.
"""

import os
import subprocess
import sys

import numpy as np
import pytest

import asperity2d as a
from asperity2d.engine import Engine, kernel
from asperity2d.engine.core import TRACK_TOLERANCE
from asperity2d.engine.energy import EnergyMeter
from asperity2d.run import default_dt

pytestmark = pytest.mark.skipif(not kernel.KERNEL, reason=f"the C step loop is off here: {kernel.KERNEL_REASON}")


def _state(e: Engine):
    sw = e.switch
    ints, floats = e._native.read_arbiters()
    return (e.bodies_internal().tobytes(), sw.stuck.tolist(), sw.slid.tolist(), sw.mu.tolist(),
            sorted(sw._present), e.step_count, e.max_solver_drift, sorted(zip(ints[2::3], floats[0::6], floats[1::6])))


def _pair(scene, *, push=2e-3, dt=None):
    """Two copies of one settled engine: the first steps in C, the second in Python."""
    e = Engine(scene, default_dt(scene) if dt is None else dt, engaged=scene.slider.track == "fixed")
    e.settle(20 * scene.slowest_period(), push=push)
    c, py = e.copy(), e.copy()
    assert c._kernel is not None
    py._kernel = None
    return c, py


SCENES = {
    "fixed, regular, spring": dict(drive_damping=1e-4),
    "fixed, random, force": dict(spacing="random", seed=4, drive="force", drive_force=6e-3),
    "free, regular, force": dict(track="free", drive="force", drive_force=2e-2),
    "free, random, spring": dict(track="free", spacing="random", seed=2, drive_velocity=400.0),  # fast: it slips
    "half triangles, one mu (no switch)": dict(profile="half", mu=0.3, drive="force", drive_force=4e-3),
    "MATLAB lattice": dict(lateral_stiffness=50.0, drive="force", drive_force=6e-3),
    "40 lower / 6 upper, random": dict(lower_count=40, upper_count=6, spacing="random", seed=7),
}


#: Scenes whose tips stay stuck through the ~2,000 compared steps (the drive spring still loading
#: them): their switch is compared holding, not switching; the others must switch.
STUCK_THROUGHOUT = {"fixed, regular, spring"}


@pytest.mark.parametrize("name", list(SCENES))
def test_the_c_loop_steps_as_the_python_loop_to_the_bit(name):
    scene = a.make_scene(**SCENES[name])
    c, py = _pair(scene)
    assert _state(c) == _state(py)
    contacts = switches = 0
    stuck = c.switch.stuck
    for k in range(300):
        n = 1 + k % 13  # runs of several lengths, as the run loop's record_every makes them
        c.step(n)
        py.step(n)
        assert _state(c) == _state(py), f"differs after {c.step_count} steps"
        contacts += bool(c.arbiters_internal().pairs())
        switches += int(np.count_nonzero(c.switch.stuck != stuck))
        stuck = c.switch.stuck
    print(name, contacts, switches)
    assert contacts > 0, contacts  # the comparison covered contacts, not free flight
    if c.switch.active:
        assert switches > 0 or name in STUCK_THROUGHOUT, switches  # ... and the switch had work to do


@pytest.mark.parametrize("name", ["fixed, regular, spring", "free, regular, force", "free, random, spring"])
def test_settling_in_c_is_settling_in_python_to_the_bit(name):
    # the fixed track lowered onto the surface and pushed; the free slider dropped, then pushed
    # (force drive) or left to find the spring's preload (spring drive)
    scene = a.make_scene(**SCENES[name])
    one, two = (Engine(scene, default_dt(scene), engaged=scene.slider.track == "fixed") for _ in range(2))
    two._kernel = None
    spent = [e.settle(20 * scene.slowest_period(), push=2e-3) for e in (one, two)]
    assert spent[0] == spent[1] > 0
    assert _state(one) == _state(two)


def test_the_c_loop_puts_drifted_bodies_back_as_the_python_loop_does():
    # A hard start: the fixed track's slider driven at 30 x the default force from the run-up
    # makes the groove joints drift past TRACK_TOLERANCE, so the write-back path runs.
    scene = a.make_scene(drive="force", drive_force=0.3, lower_count=8, upper_count=3)
    e = Engine(scene, default_dt(scene))
    c, py = e.copy(), e.copy()
    py._kernel = None
    for _ in range(200):
        c.step(7)
        py.step(7)
        assert _state(c) == _state(py)
    assert c.max_solver_drift > TRACK_TOLERANCE


def test_the_switch_state_moves_between_the_loops_whenever_a_meter_comes_and_goes():
    scene = a.make_scene(spacing="random", seed=11)
    c, py = _pair(scene)
    for k in range(12):
        if k % 4 == 1:  # an energy meter's hooks send the steps through Python ...
            meter = EnergyMeter(c)
            meter_py = EnergyMeter(py)
        c.step(50)
        py.step(50)
        assert _state(c) == _state(py)
        if k % 4 == 2:  # ... and the C loop takes over again once it is gone
            meter.detach()
            meter_py.detach()
        c.set_drive_velocity(c.drive.v * c.units.velocity * (1.5 if k % 2 else 0.7))
        py.set_drive_velocity(py.drive.v * py.units.velocity * (1.5 if k % 2 else 0.7))
    # a copy made while the C loop holds the switch's state starts from that state
    c2 = c.copy()
    py2 = py.copy()
    py2._kernel = None
    c2.step(100)
    py2.step(100)
    assert _state(c2) == _state(py2)


def test_whole_runs_and_a_critical_force_are_the_same_with_the_c_loop_off():
    code = ("import asperity2d as a, hashlib, numpy as np\n"
            "s = a.make_scene(spacing='random', seed=5, lower_count=10, upper_count=3)\n"
            "r = a.simulate(s, duration=s.base / s.drive.velocity, progress=False)\n"
            "h = hashlib.sha256(b''.join(np.ascontiguousarray(getattr(r, k)).tobytes() for k in\n"
            "    ('t', 'x', 'y', 'v', 'drive_force', 'friction_force', 'normal_force', 'lower_dy')))\n"
            "f = a.critical_force_bracket(a.make_scene(drive='force', lower_count=6, upper_count=2))\n"
            "from asperity2d.engine import kernel\n"
            "print(kernel.KERNEL, h.hexdigest(), repr(f))\n")
    out = {}
    for flag in ("1", "0"):
        env = {**os.environ, kernel.SWITCH: flag}
        proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True)
        used, digest, bracket = proc.stdout.strip().split(" ", 2)
        out[flag] = (used, digest, bracket)
    assert out["1"][0] == "True" and out["0"][0] == "False"  # each run took the loop it was meant to
    assert out["1"][1:] == out["0"][1:]


def test_the_switch_names_why_the_c_loop_is_off():
    code = "from asperity2d.engine import kernel; print(kernel.KERNEL, kernel.KERNEL_REASON)"
    env = {**os.environ, kernel.SWITCH: "0"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True)
    assert out.stdout.strip() == f"False {kernel.SWITCH}=0"


def test_a_finished_copy_is_freed_at_once_not_at_the_next_cycle_collection():
    # an engine and its C loop form no reference cycle: a critical force's forks (and their
    # pymunk spaces) go as soon as each run ends, not whenever the cycle collector next runs
    import gc
    import weakref

    scene = a.make_scene(lower_count=6, upper_count=2)
    copy = Engine(scene, default_dt(scene)).copy()
    copy.step(10)
    assert copy._kernel is not None
    space = weakref.ref(copy.layout.space)
    gc.disable()
    try:
        del copy
        assert space() is None
    finally:
        gc.enable()
