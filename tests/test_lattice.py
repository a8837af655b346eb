"""Ooten's MATLAB contact model: lower peaks free in x and y, joined by horizontal springs."""

import numpy as np
import pytest

import asperity2d as a
from asperity2d.engine import Engine

K = 37_200.0


def test_lattice_small_displacement_stiffness_matches_the_spring_matrix():
    links = [K, 20_000.0, 30_000.0, 10_000.0, K]  # wall, peak-peak x3, wall
    scene = a.make_scene(lower_count=4, upper_count=1, track="fixed", lateral_stiffness=links,
                         damping_ratio=0.5, lateral_damping=1e-6)
    stiffness = scene.lower.lateral_stiffness_matrix()
    assert stiffness[0, 0] == links[0] + links[1] and stiffness[1, 0] == -links[1]
    force = 1e-4  # N, displaces a peak by ~3e-9 m = 0.3 % of a base: small
    compliance = np.zeros((4, 4))
    for j in range(4):
        engine = Engine(scene, scene.shortest_period() / 50)
        layout, u = engine.layout, engine.units  # the adapter's own test: it pokes one body
        body = layout.lower_bodies[j]
        for _ in range(20_000):  # damped to rest (~60 periods)
            body.force = (force / u.force, 0.0)
            layout.space.step(engine.dt_internal)
        dx = np.array([b.position.x for b in layout.lower_bodies]) - layout.lower_x0
        compliance[:, j] = dx * u.length / force
    measured = np.linalg.inv(compliance)
    np.testing.assert_allclose(measured, stiffness, rtol=0.01, atol=0.01 * K)


def test_contact_cases_come_from_the_rigid_body_contacts():
    """The slider tip meets the peaks one after another (Ooten's thesis Table 2), unscripted."""
    scene = a.make_scene(lower_count=3, upper_count=1, track="fixed", lateral_stiffness=K,
                         slider_mass=2.88e-16, drive_stiffness=K, drive_velocity=20.0)
    result = a.simulate(scene)
    assert result.status == "passed"
    touching = result.contact_count > 0
    # contact, no contact, contact, ...: at least three separate contact episodes
    episodes = np.count_nonzero(np.diff(touching.astype(int)) == 1) + int(touching[0])
    assert episodes >= 3
    # pushing a peak sideways loads its neighbours through the horizontal springs
    assert np.abs(result.lower_dx).max() > 1e-3 * scene.base
    assert result.meta["max_track_drift_fraction"] < 1e-6  # the slider's own x track
    with pytest.raises(a.SceneError, match="`lateral_stiffness`"):
        a.make_scene(lower_count=3, lateral_stiffness=[K, K])


def test_matlab_lattice_script_reproduces_the_seed_contact_cases(tmp_path, capsys):
    import json
    from pathlib import Path

    from asperity2d.cli.args import load_script

    script = load_script(Path(__file__).resolve().parent.parent / "scenes" / "matlab_lattice.py")
    assert script.main(["--json", "--frames", "5", "-o", str(tmp_path)]) == 0
    summary = json.loads(capsys.readouterr().out)
    # Ooten's thesis Table 2: cases 1-7 for three peaks, here from the contacts themselves
    assert summary["contact_cases"] == ["none", "peak 1", "none", "peak 2", "none", "peak 3", "none"]
    assert summary["status"] == "passed"
    assert (tmp_path / "figure17.png").stat().st_size > 0 and (tmp_path / "run.gif").stat().st_size > 0


def test_the_gershgorin_bound_without_the_dense_matrix_is_the_dense_one_to_the_bit():
    """The time step of every lattice scene comes from this bound, so it must not move by one ulp:
    random links over six decades (where (a + b) + c and a + (b + c) differ in ~1 row in 6)
    and lengths that reach every branch of NumPy's pairwise sum (under 8, 8-128, split)."""
    from asperity2d.scene import gershgorin_rows

    rng = np.random.default_rng(35)
    for n in [*range(1, 300), 511, 1000, 1029, 2050]:
        links = rng.uniform(0.1, 10.0, n + 1) * 10.0 ** rng.uniform(-3, 3, n + 1)
        dense = np.diag(links[:-1] + links[1:])
        dense -= np.diag(links[1:-1], 1) + np.diag(links[1:-1], -1)
        np.testing.assert_array_equal(gershgorin_rows(links), np.abs(dense).sum(axis=1), err_msg=f"n = {n}")
    scene = a.make_scene(lower_count=7, lateral_stiffness=list(rng.uniform(1e3, 1e5, 8)))
    dense = np.abs(scene.lower.lateral_stiffness_matrix()).sum(axis=1)
    assert scene.natural_frequencies()["lattice"] == float(np.max(np.sqrt(dense / np.asarray(scene.lower.mass))))


def test_a_lattice_of_100_000_peaks_takes_its_time_step_in_bounded_memory():
    """The dense matrix of 100,000 peaks is 74.5 GiB (a MemoryError before) and of 12,000 3.4 GB;
    the bound now needs a few arrays of n floats (measured: ~10 MB at n = 100,000)."""
    import tracemalloc

    scene = a.make_scene(lower_count=100_000, lateral_stiffness=K)
    tracemalloc.start()
    try:
        lattice = scene.natural_frequencies()["lattice"]
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 50e6  # bytes: a few floats per peak; the dense matrix would be 8e10
    # interior rows sum to 4k (equal links, exact in any order), so the bound is sqrt(4k/m)
    assert lattice == float(np.max(np.sqrt(4 * K / np.asarray(scene.lower.mass))))
