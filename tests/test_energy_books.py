"""Energy books of the asperity engine close: every channel metered (asperity2d/engine/energy.py).

Undamped, frictionless runs on both set-ups (free slider under a normal load;
Ooten's fixed-height track) with both drives. Small scenes (3 lower, 1
upper asperity) at 2.5 x the default drive speed keep the default run fast:
the module costs about 7 s of CPU.
"""

import functools
import math

import numpy as np
import pytest

import asperity2d as a

SMALL = {"lower_count": 3, "upper_count": 1, "mu": 0.0, "damping_ratio": 0.0}
SETUPS = {"free": {"track": "free"}, "fixed": {"track": "fixed", "interference": 0.125e-6}}
DRIVES = {"spring": {"drive": "spring", "drive_velocity": 50.0},
          # above both critical forces, so the slider crosses the surface
          "force": {"drive": "force", "drive_force": 0.02}}
NUMERICAL = ("constraint_work", "position_correction", "projection", "integrator")


def energy_of(**params) -> tuple[dict, a.Result]:
    return _energy_of(tuple(sorted(params.items())))


@functools.lru_cache(maxsize=None)  # the tests share runs
def _energy_of(params: tuple) -> tuple[dict, a.Result]:
    result = a.simulate(a.make_scene(**{**SMALL, **dict(params)}), energy=True)
    return result.meta["energy"], result


@pytest.fixture(scope="module", params=[(s, d) for s in SETUPS for d in DRIVES],
                ids=lambda p: "-".join(p))
def books(request):
    setup, drive = request.param
    report, result = energy_of(**SETUPS[setup], **DRIVES[drive])
    assert result.status == "passed"
    return setup, drive, report


def test_books_close_to_a_millionth_of_the_drive_work(books):
    _, _, e = books
    work = e["drive_work_J"]
    assert work > 0
    # Every flow is metered, so drive work = stored change + removed holds to what the
    # accounting leaves out (the hanging track springs' geometric nonlinearity, ~1e-13
    # measured); 1e-6 is far inside the 1 % the issue asks for.
    assert e["residual_fraction"] <= 1e-6
    removed = e["dissipated_J"] + e["numerical_J"]
    assert e["stored_energy_change_J"] + removed == pytest.approx(work, rel=1e-6)
    # The unmetered impulses are the groove joints': their sizes agree with the joints'
    # own impulse reports to rounding (1e-12 measured; 1e-9 leaves room for the sums).
    assert e["unmatched_impulse_fraction"] <= 1e-9
    # mu = 0 and no dampers: those channels must stay empty (nothing leaks into them)
    assert abs(e["friction_work_J"]) <= 1e-9 * work
    assert abs(e["damper_work_J"]) <= 1e-9 * work
    assert all(math.isfinite(e[f"{k}_J"]) for k in NUMERICAL)
    # inelastic contacts (restitution 0) lose energy at every impact, never gain it
    assert e["normal_work_J"] > 0


def test_the_numerical_share_is_what_the_books_check(books):
    """The books close by construction; the numerical channels' share of the drive work is the
    check (``checks["energy_numerical"]``): their absolute values summed, so channels of opposite
    sign cannot cancel in it."""
    _, _, e = books
    share = sum(abs(e[f"{k}_J"]) for k in NUMERICAL) / max(e["drive_work_J"], e["dissipated_J"] + e["numerical_J"])
    assert e["numerical_fraction"] == pytest.approx(share, rel=1e-12)
    assert share >= abs(e["numerical_J"]) / e["drive_work_J"] * (1 - 1e-12)


def test_a_run_whose_numerical_share_is_above_the_tolerance_is_flagged():
    """The validation page's scene: 1.3 % of the drive work at the default step passes; at 2.5 x
    it (the coarsest step allowed, unsafe_dt not needed) 3.6 % is flagged: the result is
    unsuccessful and says why."""
    from asperity2d.run import NUMERICAL_ENERGY_TOLERANCE, default_dt

    e, fine = energy_of(**SETUPS["free"], **DRIVES["spring"])
    assert fine.checks["energy_numerical"]["passed"] and fine.success
    assert fine.checks["energy_numerical"]["worst"] == e["numerical_fraction"]
    scene = a.make_scene(**SMALL, **SETUPS["free"], **DRIVES["spring"])
    coarse = a.simulate(scene, dt=2.5 * default_dt(scene), energy=True)
    check = coarse.checks["energy_numerical"]
    assert not check["passed"] and check["worst"] > NUMERICAL_ENERGY_TOLERANCE
    assert not coarse.success and "the numerical method took" in coarse.meta["message"]


@pytest.mark.slow
def test_the_numerical_share_shrinks_with_dt_and_bounds_the_step_error():
    """The dt study the tolerance is derived from (asperity2d.run.NUMERICAL_ENERGY_TOLERANCE): on
    the validation page's scene the share falls at every halving (measured 1.31 %, 0.81 %,
    0.26 %) and each halving moves the physical books (the impact loss) by less than the share
    at the coarser step (measured 0.40 and 0.68 of it)."""
    from asperity2d.run import default_dt

    scene = a.make_scene(**SMALL, **SETUPS["free"], **DRIVES["spring"])
    books = [a.simulate(scene, dt=f * default_dt(scene), energy=True).meta["energy"] for f in (1.0, 0.5, 0.25)]
    shares = [e["numerical_fraction"] for e in books]
    assert shares[0] > shares[1] > shares[2]
    dissipated = [e["dissipated_J"] / e["drive_work_J"] for e in books]
    for coarse, fine, share in zip(dissipated, dissipated[1:], shares):
        assert abs(coarse - fine) < share


def test_the_old_meters_missing_fifth_is_the_travel_stops():
    """The free slider's load drives undamped lower asperities to the end of their tracks.

    The old meter left ~20 % of the drive work unaccounted here; it is the
    stops' inelastic impacts. Tracks too long to reach take no stop work.
    """
    stops, _ = energy_of(**SETUPS["free"], **DRIVES["spring"])
    work = stops["drive_work_J"]
    assert stops["stop_work_J"] > 0.1 * work  # 23 % measured
    # what the old meter did not meter (stops and the numerical channels) is mostly stops
    old_unmetered = stops["stop_work_J"] + stops["numerical_J"]
    assert stops["stop_work_J"] > 0.8 * old_unmetered
    far, result = energy_of(**SETUPS["free"], **DRIVES["spring"], travel_down=4e-6, travel_up=4e-6)
    assert result.status == "passed"
    assert np.abs(result.lower_dy).max() < 1e-6  # never near the 4 um ends
    assert far["stop_work_J"] == 0.0
    assert far["residual_fraction"] <= 1e-6


def test_restitution_one_removes_the_impact_loss_on_the_fixed_track():
    """Undamped read as 'no impact loss': with restitution 1 the contacts lose < 0.1 % of the
    drive work (rounding of pymunk's bounce: measured 2e-6), against most of it at 0."""
    elastic, _ = energy_of(**SETUPS["fixed"], **DRIVES["spring"], restitution=1.0)
    inelastic, _ = energy_of(**SETUPS["fixed"], **DRIVES["spring"])
    assert abs(elastic["normal_work_J"]) <= 1e-3 * elastic["drive_work_J"]
    assert inelastic["normal_work_J"] > 0.5 * inelastic["drive_work_J"]  # 94 % measured
    assert elastic["residual_fraction"] <= 1e-6
    assert elastic["unmatched_impulse_fraction"] <= 1e-9


def test_metering_does_not_change_the_run():
    """The meter reads; it must not steer (its pre_solve callback included). Restitution 1 on
    the free slider makes contacts touch again within pymunk's persistence, the case the
    callback corrects."""
    scene = a.make_scene(**{**SMALL, **SETUPS["free"], **DRIVES["spring"]}, restitution=1.0)
    plain = a.simulate(scene, duration=5e-8)
    metered = a.simulate(scene, duration=5e-8, energy=True)
    for name in ("x", "v", "y", "normal_force", "friction_force", "lower_dy"):
        assert np.array_equal(getattr(plain, name), getattr(metered, name)), name
    assert metered.meta["energy"]["unmatched_impulse_fraction"] <= 1e-9


@pytest.mark.slow
def test_numerical_channels_shrink_with_dt_and_the_stops_do_not():
    """Position correction and the integrator's term are the method's: they fall with dt
    (~linearly); the stops are the model's physics and stay (QUICK free scene, 4 lower / 2
    upper: -6 / -3 / -1 % position correction, 23-24 % stops at T/25, T/50, T/100)."""
    scene = a.make_scene(lower_count=4, upper_count=2, mu=0.0, damping_ratio=0.0, track="free")
    period = scene.shortest_period()
    coarse = a.simulate(scene, dt=period / 25, energy=True).meta["energy"]
    fine = a.simulate(scene, dt=period / 100, energy=True).meta["energy"]
    for k in ("position_correction", "integrator"):
        c = abs(coarse[f"{k}_J"]) / coarse["drive_work_J"]
        f = abs(fine[f"{k}_J"]) / fine["drive_work_J"]
        assert f < c / 2, k  # 4x finer step: at least 2x smaller
    sc, sf = (r["stop_work_J"] / r["drive_work_J"] for r in (coarse, fine))
    assert sf == pytest.approx(sc, rel=0.1)
