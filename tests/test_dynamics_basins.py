"""Basin maps: classification against the 1-DOF closed form, the resumable store, the CLI.

Cost: about 5 s (a 4 x 3 grid and a 2 x 2 grid of 50 s 1-DOF runs, in-process; two CLI calls).
"""

import json

import numpy as np
import pytest

from asperity2d import SceneError
from asperity2d.belt import simulate_chain
from asperity2d.cli import main
from asperity2d.dynamics.basins import LABELS, chain_basins, classify_chain, with_initial

M, K, G, V = 1.0, 10.0, 9.81, 0.1
OMEGA = np.sqrt(K / M)
# no damping, static > kinetic friction: a stick-slip limit cycle around a family of pure-slip orbits
CHAIN = dict(masses=[M], springs=[K, 0.0], dampers=[0.0, 0.0], mu_s=0.3, mu_k=0.2, v_belt=V, x0=[0.0],
             v0=[0.0], t_end=50.0, n_samples=2501)
X_K = 0.2 * M * G / K  # centre of the slip oscillation (m)


def expected_label(x0, v0):
    """Closed form: slipping orbits are circles about (x_k, 0) in (x, v/ω); one whose top speed
    sqrt(ω²(x0 - x_k)² + v0²) stays below V never sticks (pure slip, for ever: no damping);
    any other reaches the belt speed and is captured by the stick-slip cycle."""
    top = np.hypot(OMEGA * (x0 - X_K), v0)
    return "pure slip" if top < V else "stick-slip"


XS = np.linspace(X_K - 0.06, X_K + 0.06, 4)
VS = np.array([-0.3, -0.05, 0.06])


def test_classes_follow_the_closed_form(tmp_path):
    bm = chain_basins(CHAIN, x=("x1", XS), y=("v1", VS), store=tmp_path / "runs", workers=1, progress=False)
    assert bm.failed == 0
    for i, x0 in enumerate(XS):
        for j, v0 in enumerate(VS):
            top = np.hypot(OMEGA * (x0 - X_K), v0)
            if abs(top - V) < 0.01:  # too close to the boundary to expect a clean answer in 50 s
                continue
            assert LABELS[int(bm.values["label"][i, j])] == expected_label(x0, v0), (x0, v0)
    stick = bm.values["label"] == 2
    assert stick.any() and (bm.values["label"] == 1).any()
    assert np.all(bm.values["multiplicity"][stick] == 1)
    assert bm.to_dict()["counts"]["failed"] == 0


def test_store_resumes_only_missing_runs(tmp_path):
    store = tmp_path / "runs"
    first = chain_basins(CHAIN, x=("x1", XS[:2]), y=("v1", VS[:2]), store=store, workers=1, progress=False)
    files = sorted((store / "runs").glob("*.json"))
    assert len(files) == 4
    files[0].unlink()
    stamps = {f.name: f.stat().st_mtime_ns for f in files[1:]}
    again = chain_basins(CHAIN, x=("x1", XS[:2]), y=("v1", VS[:2]), store=store, workers=1, progress=False)
    assert {f.name: f.stat().st_mtime_ns for f in files[1:]} == stamps  # untouched
    assert files[0].exists()
    for key in ("label", "period", "last_stick"):
        assert np.array_equal(first.values[key], again.values[key], equal_nan=True)


def test_classify_rest_and_at_rest_on_a_still_surface():
    damped = simulate_chain([M], [K, 0.0], [1.0, 0.0], mu_s=0.2, v_belt=V, x0=[X_K + 0.01], v0=[0.0],
                            t_end=200.0)
    assert LABELS[int(classify_chain(damped)["label"])] == "rest"  # steady sliding
    still = simulate_chain([M], [K, 0.0], [0.0, 0.0], mu_s=0.2, v_belt=0.0, x0=[0.5], v0=[0.0], t_end=20.0)
    assert LABELS[int(classify_chain(still)["label"])] == "rest"  # Coulomb decay, then stuck


def test_with_initial_sets_one_coordinate():
    chain = with_initial({**CHAIN, "masses": [1, 1], "x0": [0, 0], "v0": [0, 0]}, "v2", 0.3)
    assert chain["v0"] == [0.0, 0.3] and chain["x0"] == [0, 0]


@pytest.mark.parametrize("axis, match", [(("z1", [0.0]), "`x`"), (("x2", [0.0]), "out of range"),
                                         (("x1", []), "`x` values")])
def test_bad_axes_name_the_parameter(axis, match):
    with pytest.raises(SceneError, match=match):
        chain_basins(CHAIN, x=axis, y=("v1", [0.0]), progress=False)


def test_cli_writes_map_and_summary(tmp_path, capsys):
    toml = tmp_path / "chain.toml"
    toml.write_text("masses = [1.0]\nsprings = [10.0, 0.0]\ndampers = [0.0, 0.0]\nmu_s = 0.3\nmu_k = 0.2\n"
                    "v_belt = 0.1\nx0 = [0.0]\nv0 = [0.0]\nt_end = 40.0\n")
    out = tmp_path / "map.png"
    code = main(["belt", "basins", "--chain-file", str(toml), "--x", "x1", "--x-range", "0.1,0.3",
                 "--y", "v1", "--y-range=-0.3,0.0", "--grid", "2", "-o", str(out), "--workers", "1", "--json"])
    assert code == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["shape"] == [2, 2] and sum(summary["counts"].values()) == 4
    assert out.read_bytes()[:4] == b"\x89PNG"
    assert json.loads(out.with_suffix(".json").read_text()) == summary
    assert (tmp_path / "map.runs" / "manifest.json").exists()


def test_cli_bad_input_is_one_line(tmp_path, capsys):
    code = main(["belt", "basins", "--preset", "table2-3dof", "--x-range", "1,0", "-o", str(tmp_path / "m.png")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "`x-range`" in err[0]


def sawtooth_run(stick_samples):
    """A synthetic spring-driven run (asperity2d.analysis.synthetic_stick_slip) whose drive force is an exact
    sawtooth: it rises through each stick and drops in each slip, cycle after cycle."""
    from asperity2d.analysis import synthetic_stick_slip

    result, truth = synthetic_stick_slip(n_events=24, samples_per_stick=stick_samples, samples_per_slip=20)
    force = np.empty_like(result.t)
    starts = np.concatenate([[0], truth["end_index"]])
    for a, s, b in zip(starts[:-1], truth["slip_index"], truth["end_index"]):
        force[a:s + 1] = np.linspace(1.0, 2.0, s + 1 - a)  # N: stick ramp
        force[s + 1:b] = np.linspace(2.0, 1.0, b - s + 1)[1:-1]  # slip drop
    force[starts[-1]:] = 1.0
    result.drive_force = result.friction_force = force
    return result, truth


def test_asperity_classifier_finds_the_period_of_a_regular_sawtooth():
    from asperity2d.dynamics.asperity_basins import classify_asperity

    result, truth = sawtooth_run((120, 120))
    out = classify_asperity(result)
    dt = result.t[1] - result.t[0]
    assert LABELS[int(out["label"])] == "stick-slip" and out["multiplicity"] == 1
    assert out["period"] == pytest.approx(140 * dt, rel=1e-9)  # 120 stick + 20 slip samples
    irregular, _ = sawtooth_run((60, 200))  # random stick lengths: no repeat
    assert LABELS[int(classify_asperity(irregular)["label"])] == "irregular"


def test_asperity_scan_refuses_its_own_axes():
    from asperity2d.dynamics.asperity_basins import asperity_basins

    with pytest.raises(SceneError, match="`drive_preload`"):
        asperity_basins({"drive_preload": 0.1}, [0.0], progress=False)
    with pytest.raises(SceneError, match="`drive`"):
        asperity_basins({"drive": "force"}, [0.0], progress=False)


def test_shifting_the_lower_surface_changes_nothing():
    # why the asperity scan varies the drive preload: the builder places the slider relative to the first
    # lower asperity, so the spacing offset translates the whole run (x by the offset, forces unchanged)
    import dataclasses

    import asperity2d as a

    scene = a.make_scene(track="fixed", lower_count=5, upper_count=2)
    spacing = dataclasses.replace(scene.lower.spacing, offset=0.37e-6)
    shifted = dataclasses.replace(scene, lower=dataclasses.replace(scene.lower, spacing=spacing))
    r1, r2 = a.simulate(scene, 3e-7), a.simulate(shifted, 3e-7)
    assert np.allclose(r2.x - r1.x, 0.37e-6, rtol=0, atol=1e-15)  # 1e-9 of the base: round-off of the shift
    assert np.allclose(r2.drive_force, r1.drive_force, rtol=0, atol=1e-12 * np.abs(r1.drive_force).max())


def test_cpu_limit_bounds_a_run():
    from asperity2d import SimulationError
    from asperity2d.dynamics.basins import cpu_limit

    with pytest.raises(SimulationError, match="CPU"):
        with cpu_limit(0.2):
            while True:  # a stalled solver: never returns on its own
                sum(range(1000))
    with cpu_limit(5.0):  # a run within its budget is untouched, and the timer is cleared afterwards
        total = sum(range(1000))
    assert total == 499500
