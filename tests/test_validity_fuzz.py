"""A physical-validity fuzzer (issue 27): no returned run is physically impossible.

Hypothesis draws valid but extreme scenes -- every physical parameter log-uniform over six
decades about Ooten's value (loads, forces, preloads, masses, stiffnesses, pitches), either
track, every profile and spacing, now and then an ``unsafe_dt`` step of up to three periods and
an energy meter -- and runs each for at most a few thousand steps. Each example must either
raise ``SceneError`` / ``SimulationError`` with one line of message, or return a result that,
checked independently from its recorded arrays, has

* every series finite (the drive's far end aside: NaN for a constant force);
* no slider step, while it is over the surface, longer than the feature it could collide with
  (:func:`asperity2d.engine.run_checks._features`), sample by sample and between samples;
* no free slider's tip below the guard floor by more than the tolerance;
* energy books (when metered) closing to 1e-6 of the drive work (README; measured 1e-14 -
  1e-13 on ordinary scenes);
* every check passed, or a WARNING in its message and ``success`` False.

Default run: 200 examples (derandomized, ~20 s; 400 measured 19 s of CPU); ``-m slow``: 1,000.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import asperity2d as a
from asperity2d.engine.run_checks import FLOOR_TOLERANCE, STEP_FRACTION, _features
from asperity2d.run import default_dt
from asperity2d.units import Units

#: the energy books' tolerance (README: "tests hold it to 1e-6")
BOOKS = 1e-6
SCALED = ("normal_load", "drive_force", "drive_velocity", "drive_stiffness", "slider_mass", "mass", "stiffness")


@st.composite
def runs(draw):
    kw = {"lower_count": draw(st.integers(1, 6)), "upper_count": draw(st.integers(1, 3)),
          "track": draw(st.sampled_from(["fixed", "free"])),
          "drive": draw(st.sampled_from(["spring", "force"])),
          "profile": draw(st.sampled_from(["full", "full", "half", "flat"])),
          "spacing": draw(st.sampled_from(["regular", "random", "random-upper"])),
          "seed": draw(st.integers(0, 50))}
    from asperity2d.builders import DEFAULTS as defaults
    for name in draw(st.lists(st.sampled_from(SCALED), unique=True, max_size=4)):
        kw[name] = defaults[name] * 10.0 ** draw(st.floats(-3.0, 3.0))
    if draw(st.booleans()):
        kw["drive_preload"] = draw(st.sampled_from([-1.0, 1.0])) * 10.0 ** draw(st.floats(-6.0, 3.0))
    if draw(st.booleans()):
        kw["pitch"] = 1e-6 * draw(st.floats(1.0, 3.0))
    if draw(st.integers(0, 3)) == 0:
        kw["mu_static"] = draw(st.floats(0.0, 1.5))
    if draw(st.integers(0, 3)) == 0:
        kw["restitution"] = draw(st.floats(0.0, 1.0))
    if draw(st.integers(0, 4)) == 0:
        kw["gravity"] = 10.0 ** draw(st.floats(0.0, 15.0))
    run = {"dt_periods": draw(st.one_of(st.none(), st.none(), st.floats(0.05, 3.0))),
           "steps": draw(st.integers(50, 1500)), "energy": draw(st.integers(0, 3)) == 0}
    return kw, run


def _check(kw, run):
    try:
        scene = a.make_scene(**kw)
        period = scene.shortest_period()
        dt = None if run["dt_periods"] is None else run["dt_periods"] * period
        step = default_dt(scene) if dt is None else dt
        result = a.simulate(scene, duration=run["steps"] * step, dt=dt, unsafe_dt=dt is not None,
                            energy=run["energy"], max_steps=20_000, progress=False)
    except (a.SceneError, a.SimulationError) as exc:
        message = str(exc)
        assert message and "\n" not in message
        return
    # finite series
    for name in ("t", "x", "v", "y", "vy", "drive_force", "normal_force", "friction_force", "lower_dx", "lower_dy"):
        assert np.all(np.isfinite(getattr(result, name))), name
    units = Units.for_scene(scene)
    L = units.length
    fx, fy = _features(scene, units)
    lower_x = scene.lower.tips()
    reach = 2.0 * max(np.max(scene.lower.shape_set().bases), np.max(scene.slider.shape_set().bases))
    front = float(scene.slider.tips()[-1])
    over = (result.x + front >= lower_x[0] - reach) & (result.x <= lower_x[-1] + reach)
    dt = result.dt
    steps = np.diff(result.t) / dt
    # every step, sampled and between samples (mean displacement per step), over the surface
    sampled = np.abs(result.v) * dt
    mean = np.abs(np.diff(result.x)) / np.maximum(steps, 1)
    assert np.all(sampled[over] <= STEP_FRACTION * fx * L * (1 + 1e-9)), "a step longer than the window"
    both = over[1:] & over[:-1]
    assert np.all(mean[both] <= STEP_FRACTION * fx * L * (1 + 1e-9)), "steps between samples too long"
    if scene.slider.track == "free":
        tips = result.y - float(np.max(scene.slider.summits()))
        assert np.min(tips) >= scene.lower.floor - FLOOR_TOLERANCE * L, "a tip below the floor"
        assert np.all((np.abs(result.vy) * dt)[over] <= STEP_FRACTION * fy * L * (1 + 1e-9))
    if run["energy"]:
        assert result.meta["energy"]["residual_fraction"] <= BOOKS, result.meta["energy"]
        assert result.checks["energy_books"]["passed"]
    failed = [name for name, c in result.checks.items() if not c["passed"]]
    assert result.success == (not failed and result.status != "time limit")
    if failed:
        assert "WARNING" in result.message


FUZZ = dict(deadline=None, derandomize=True, database=None,
            suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


@settings(max_examples=200, **FUZZ)
@given(case=runs())
def test_no_returned_run_is_physically_impossible(case):
    _check(*case)


@pytest.mark.slow
@settings(max_examples=1000, **FUZZ)
@given(case=runs())
def test_no_returned_run_is_physically_impossible_thorough(case):
    _check(*case)
