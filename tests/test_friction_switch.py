"""The asperity model's contact law: both step loops against its Python reference, step by step.

:class:`asperity2d.contact_laws.StaticKineticSwitch` states the rule of one contact
(``step``, ``coefficient``; a lost contact goes back to ``idle``). The engine's Python
loop calls it; the C loop (``_kernel.c``) has its own copy. Here the reference is fed,
after every single step of several scenes, the contacts and bodies that step left, and
must give each asperity's state exactly (to the bit) as either loop did, and the
coefficient pymunk holds for its shape: a check of the C loop against the law itself,
not only against the Python loop (``tests/test_engine_kernel.py``).
"""

from typing import NamedTuple

import pytest

import asperity2d as a
from asperity2d.engine import Engine, kernel
from asperity2d.contact_laws import StaticKineticSwitch
from asperity2d.run import default_dt

# Scenes whose contacts switch within the steps checked (measured, Python loop, 1500 steps: 2
# to 20 stick/slip flips each); fast drives (400 m/s) make them slip early.
SCENES = {
    "fixed, regular, spring": dict(drive_velocity=400.0),
    "fixed, random, force": dict(spacing="random", seed=4, drive="force", drive_force=6e-3),
    "free, random, spring": dict(track="free", spacing="random", seed=2, drive_velocity=400.0),
    "no slip distance, stick speed given": dict(spacing="random", seed=9, slip_distance=0.0, stick_speed=5e-4,
                                                drive_velocity=400.0),
}
STEPS = 1500

LOOPS = ["python"] + (["C"] if kernel.KERNEL else [])


class ContactState(NamedTuple):
    """One lower asperity after a step: touching, stuck, distance slid since it stuck, mu."""

    present: bool
    stuck: bool
    slid: float
    mu: float


def reference_step(law, states: list, slips: dict, _dt=None) -> list:
    """Every asperity one step on, by the law: a touching one by ``law.step`` (new or not), a
    lost contact reset to ``law.idle``, an untouched one unchanged."""
    out = []
    for i, s in enumerate(states):
        if i not in slips:
            out.append(ContactState(False, False, 0.0, law.idle) if s.present else s)
            continue
        new = not s.present
        mu, (stuck, slid) = law.step(law.initial if new else (s.stuck, s.slid), slips[i], 1.0, new)
        out.append(ContactState(True, stuck, slid, mu))
    return out


def _states(switch) -> list[ContactState]:
    stuck, slid, mu = switch.stuck.tolist(), switch.slid.tolist(), switch.mu.tolist()
    present = set(switch._present)  # after the properties above took the state back from the C loop
    return [ContactState(i in present, bool(s), d, m) for i, (s, d, m) in enumerate(zip(stuck, slid, mu))]


def _slips(engine) -> dict[int, float]:
    """Each touching lower asperity's slip speed after the last step, as the loops take it:
    the largest over the slider's tips touching it, NaN never kept (its magnitude: the sign does
    not matter to this law)."""
    rows, layout = engine.bodies_internal(), engine.layout
    svx, svy = rows.item(layout.slider_row, 2), rows.item(layout.slider_row, 3)
    out: dict[int, float] = {}
    for i, nx, ny in engine.arbiters_internal().pairs():
        if i < 0:  # the floor
            continue
        row = layout.lower_row_of[i]
        slip = abs((svx - rows.item(row, 2)) * ny - (svy - rows.item(row, 3)) * nx)
        if slip > out.get(i, -1.0):
            out[i] = slip
    return out


@pytest.mark.parametrize("loop", LOOPS)
@pytest.mark.parametrize("name", list(SCENES))
def test_each_step_of_the_switch_is_the_reference_laws_to_the_bit(name, loop):
    scene = a.make_scene(**SCENES[name])
    engine = Engine(scene, default_dt(scene), engaged=scene.slider.track == "fixed")
    engine.settle(20 * scene.slowest_period(), push=2e-3)
    if loop == "python":
        engine._kernel = None
    else:
        assert engine._kernel is not None
    law = engine.switch.law
    assert law.active and law == StaticKineticSwitch(engine.switch.mu_static, engine.switch.mu_kinetic,
                                                     engine.switch.stick_speed, engine.switch.slip_distance,
                                                     engine.switch.dt, engine.units.velocity)
    shapes = engine.layout.lower_shapes
    before = _states(engine.switch)
    flips = touching = 0
    for _ in range(STEPS):
        engine.step(1)
        expected = reference_step(law, before, _slips(engine))
        after = _states(engine.switch)
        assert after == expected, f"differs from the reference after {engine.step_count} steps"
        assert [s.friction for s in shapes] == [s.mu for s in after]  # what pymunk will use next step
        flips += sum(x.stuck != y.stuck for x, y in zip(before, after))
        touching += any(s.present for s in after)
        before = after
    # the comparison covered contacts that switched, not a slider in free flight
    assert touching > STEPS // 2 and flips > 0, (touching, flips)
