"""Ooten's thesis Table 1 steel scene: overlap, constraint drift, and the quasi-static convergence ladder.

Default run: the ladder's arithmetic against a closed form (~0 s), the
script's quick ladder (free slider, x8000 / x4000 / x2000, 6 lower
asperities: ~6 s CPU), argument checks.
"""

import importlib.util
import json
import math
from pathlib import Path

import numpy as np
import pytest

import asperity2d as a
from asperity2d.experiments import quasistatic as qs

ROOT = Path(__file__).resolve().parent.parent


def _script():
    spec = importlib.util.spec_from_file_location("steel_table1", ROOT / "scenes" / "steel_table1.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_steel_scene_geometry_is_table1_with_consistent_height():
    mod = _script()
    for setup in ("free", "fixed"):
        scene = mod.build_scene(setup=setup)
        assert scene.base == 1e-6 and scene.lower.mass[0] == 2.88e-16 and scene.lower.stiffness[0] == 37_200.0
        assert scene.lower.profile.height == pytest.approx(0.5e-6)  # 45 deg on a 1 um base, not 1.5 um
        assert scene.slider.track == setup


def _ladder(values: dict, factors=(4000.0, 2000.0, 1000.0, 500.0), tolerance=0.02):
    rungs = tuple({name: values.get(name, lambda f: 1.0)(f) for name in qs.QUANTITIES} for f in factors)
    return qs.Ladder(factors=factors, rungs=rungs, tolerance=tolerance, production=factors[1])


def test_ladder_richardson_recovers_a_power_law_exactly():
    # Q(f) = Q0 + C f^p: the observed order is p and the extrapolated limit Q0 (to rounding)
    for p in (1.0, 2.0, 0.5):
        ladder = _ladder({"slip_duration_s": lambda f, p=p: 3.0 + 1e-4 * f ** p})
        r = ladder.richardson("slip_duration_s")
        assert r["order"] == pytest.approx(p, rel=1e-9)
        assert r["limit"] == pytest.approx(3.0, rel=1e-9)
        errors = ladder.errors("slip_duration_s")
        assert errors[-1] == 0.0 and np.all(np.diff(errors) < 0)  # shrinking with the speed-up


def test_ladder_judges_convergence_by_error_and_by_shrinking_changes():
    # first order, 0.4 % change per halving at x2000: converged at x2000
    good = _ladder({"stick_force_N": lambda f: 1.0 + 2e-6 * f})
    assert good.converged_at("stick_force_N", 2000.0) and good.converged
    # within tolerance but changes that grow down the ladder (not the quasi-static limit): not converged
    drifting = _ladder({"stick_force_N": lambda f: 1.0 + 0.001 * math.log2(8000.0 / f) ** 2})
    assert drifting.errors("stick_force_N")[1] < 0.02
    assert not drifting.converged_at("stick_force_N", 2000.0) and not drifting.converged
    # an undefined value (a rung with too few events) breaks convergence at and above its rung
    missing = _ladder({"energy_per_cycle_J": lambda f: math.nan if f == 2000.0 else 1.0})
    assert not missing.converged and missing.converged_from("energy_per_cycle_J") == 1000.0


def test_steel_quick_ladder_converges_as_the_speed_up_shrinks(capsys, tmp_path):
    code = _script().main(["--quick", "--json", "--no-gif", "-o", str(tmp_path)])
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    free = out["setups"]["free"]
    assert free["factors"] == [8000.0, 4000.0, 2000.0] and free["production_factor"] == 4000.0
    assert all(r["status"] == "passed" and r["events"] >= 2 for r in free["rungs"])  # >= 2 whole cycles
    assert free["max_overlap_fraction"] <= 0.02 and free["max_track_drift_fraction"] <= 1e-6
    q = free["quantities"]
    for name, entry in q.items():
        v = np.array(entry["values"])
        assert np.all(np.isfinite(v)), name  # every quantity measured at every rung
        # the reported errors are the values' relative differences from the slowest rung
        assert entry["error_vs_slowest"] == pytest.approx(list(np.abs(v - v[-1]) / abs(v[-1])))
        # quasi-static limit approached: the faster the drive, the larger the error
        assert entry["error_vs_slowest"][0] > entry["error_vs_slowest"][1], name
    # halving the speed-up from x4000 moves the loading-set quantities by well under 2 %
    for name in ("stick_force_N", "first_breakaway_N", "slip_distance_m"):
        assert q[name]["converged_at_production"], name
    # `converged` means exactly: every quantity converged at the production factor
    assert free["converged"] == all(e["converged_at_production"] for e in q.values())
    assert out["converged"] == free["converged"]
    # the wedge law bounds the breakaway: L tan(45 deg + atan mu_s) with mu_s = 0.3, L = 4 mN
    assert q["stick_force_N"]["values"][-1] == pytest.approx(4e-3 * 1.3 / 0.7, rel=0.03)
    assert (tmp_path / "figure17_free.png").stat().st_size > 1000


def test_acceleration_and_ladder_reject_bad_arguments():
    with pytest.raises(a.SceneError, match="spring drive"):
        qs.accelerated(a.make_scene(drive="force"), factor=10.0)
    with pytest.raises(a.SceneError, match="`factor`"):
        qs.accelerated(a.make_scene(), factor=0.0)
    with pytest.raises(a.SceneError, match="`factors`"):
        qs.convergence_ladder(a.make_scene(), factors=(4000.0, 3000.0, 1000.0))
    with pytest.raises(a.SceneError, match="`production`"):
        qs.convergence_ladder(a.make_scene(), factors=(4000.0, 2000.0, 1000.0), production=1000.0)
