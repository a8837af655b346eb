"""Seed 000 Table 1 steel scene: overlap, constraint drift, quasi-static convergence."""

import importlib.util
import json
from pathlib import Path

import pytest

import asperity2d as a
from asperity2d import quasistatic as qs

ROOT = Path(__file__).resolve().parent.parent


def _script():
    spec = importlib.util.spec_from_file_location("steel_table1", ROOT / "scenes" / "steel_table1.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_steel_scene_geometry_is_table1_with_consistent_height():
    scene = _script().build_scene()
    assert scene.base == 1e-6 and scene.lower.mass[0] == 2.88e-16 and scene.lower.stiffness[0] == 37_200.0
    assert scene.lower.profile.height == pytest.approx(0.5e-6)  # 45 deg on a 1 um base, not 1.5 um


def test_steel_run_converges_without_overlap_or_drift(capsys, tmp_path):
    code = _script().main(["--quick", "--json", "--no-gif", "-o", str(tmp_path)])
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("peak_force_N", "slip_distance_m", "max_overlap_fraction", "max_track_drift_fraction",
                "acceleration_factor", "converged"):
        assert key in out
    assert out["fast"]["status"] == "passed" and out["slow"]["status"] == "passed"
    assert out["max_overlap_fraction"] <= 0.02
    assert out["max_track_drift_fraction"] <= 1e-6
    # halving the acceleration changes the headline numbers by less than the tolerance
    assert out["converged"] is True
    assert out["peak_force_change"] < qs.TOLERANCE and out["slip_distance_change"] < qs.TOLERANCE
    # the wedge law bounds the breakaway: L tan(45 deg + atan mu_s) with mu_s = 0.3
    assert out["peak_force_N"] == pytest.approx(4e-3 * 1.3 / 0.7, rel=0.03)
    assert (tmp_path / "figure17.png").stat().st_size > 1000


def test_acceleration_rejects_a_constant_force_drive():
    with pytest.raises(a.SceneError, match="spring drive"):
        qs.accelerated(a.make_scene(drive="force"), factor=10.0)
    with pytest.raises(a.SceneError, match="`factor`"):
        qs.accelerated(a.make_scene(), factor=0.0)
