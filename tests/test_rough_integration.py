"""A profile scene and a random-height scene through everything users run: simulate, save /
load, critical_force, compare (in worker processes), a sweep, a GIF and the command line.

The profile is four triangles written to a CSV file in micrometres (a TOML scene names it
relative to itself). Cost: about 15 s (short runs of 4-6 asperity scenes).
"""

import json

import numpy as np
import pytest

import asperity2d as a
from asperity2d.cli import main

APEX = np.array([1.0, 2.2, 3.3, 4.5])  # um
RUN = np.array([0.5, 0.45, 0.55, 0.5])  # um, both flanks
HEIGHT = np.array([0.5, 0.35, 0.45, 0.3])  # um


@pytest.fixture(scope="module")
def profile_file(tmp_path_factory):
    x = np.arange(0.0, 5.5, 0.005)
    z = np.zeros_like(x)
    for p, r, h in zip(APEX, RUN, HEIGHT):
        z = np.maximum(z, h * (1 - np.abs(x - p) / r))
    path = tmp_path_factory.mktemp("profile") / "four.csv"
    path.write_text("# unit: um\n" + "\n".join(f"{u:.4f},{v:.6f}" for u, v in zip(x, z)) + "\n")
    return path


def scene_kw(path, **kw):
    return dict(lower_surface=str(path), surface_detrend=False, upper_count=2, **kw)


def test_profile_scene_runs_saves_loads_and_renders(profile_file, tmp_path):
    """A spring-driven pass over the profile on the fixed track: only the asperities whose
    summit rises above the track's tip level are ever touched."""
    scene = a.make_scene(**scene_kw(profile_file, interference=0.12e-6))
    result = a.simulate(scene)
    assert result.status == "passed"
    level = scene.lower.top - scene.slider.interference
    touched = result.lower_contact.any(axis=1)
    np.testing.assert_array_equal(touched, scene.lower.summits() > level)  # 0.5 and 0.45 um
    assert touched.sum() == 2
    result.save(tmp_path / "run.npz")
    back = a.load(tmp_path / "run.npz")
    assert back.scene == scene and np.array_equal(back.x, result.x)
    gif = a.render(back, tmp_path / "run.gif", frames=4, width=480, height=320)
    assert gif.read_bytes()[:6] == b"GIF89a"
    assert a.render(back, tmp_path / "run.png").stat().st_size > 0
    assert np.isfinite(a.mean_stick_force(result))


def test_critical_force_of_a_profile_scene_is_bracketed(profile_file):
    """Free slider on the four triangles (flanks of 31 to 45 degrees): the critical force lies
    between the flank law L tan(theta + atan mu) of the gentlest flank with the kinetic
    coefficient (a suddenly applied force breaks static friction dynamically, README) and of
    the steepest flank with the static one."""
    scene = a.make_scene(drive="force", track="free", **scene_kw(profile_file))
    force = a.critical_force(scene)
    angles = np.arctan2(scene.lower.heights(), np.asarray(scene.lower.shapes.left_runs))
    load, c = scene.slider.normal_load, scene.contact
    lo = load * np.tan(angles.min() + np.arctan(c.mu_kinetic))
    hi = load * np.tan(angles.max() + np.arctan(c.mu_static))
    assert lo < force < hi


def test_compare_and_a_sweep_with_random_heights_and_a_profile(profile_file, tmp_path):
    comparison = a.compare(a.critical_force,
                           {"rough": {"upper_height_std": 0.08e-6}, "smooth": {}},
                           seeds=[0, 1], base=scene_kw(profile_file, track="free"),
                           progress=False, workers=2)
    rough = np.asarray(comparison.values["rough"])
    smooth = np.asarray(comparison.values["smooth"])
    assert np.all(np.isfinite(rough)) and smooth[0] == smooth[1]  # no randomness without a std
    assert rough[0] != rough[1]
    study = tmp_path / "study.toml"
    study.write_text(f'name = "rough"\nrun = "asperity2d.studies.ooten:critical_force_run"\nseeds = 1\n'
                     f'quantities = ["critical_force_N"]\n[grid]\nupper_height_std = [0.0, 0.08e-6]\n'
                     f'[fixed]\nlower_surface = "{profile_file}"\nsurface_detrend = false\n'
                     f'upper_count = 2\ntrack = "free"\n')
    assert main(["sweep", "run", str(study), "--store", str(tmp_path / "store"), "--workers", "1",
                 "--no-progress", "--json"]) == 0
    from asperity2d.sweep import ResultStore

    table = ResultStore(tmp_path / "store").table()
    assert len(table) == 2 and np.all(np.isfinite(table["critical_force_N"]))
    assert smooth[0] in table["critical_force_N"]  # the same scene, the same force


def test_command_line_runs_a_toml_scene_naming_its_profile_relatively(profile_file, tmp_path, capsys):
    folder = profile_file.parent
    toml = folder / "scene.toml"
    toml.write_text(f'[scene]\nlower_surface = "{profile_file.name}"\nsurface_detrend = false\n'
                    f'upper_count = 2\ntrack = "free"\nheight_std = 0.05e-6\n[run]\nduration = 1e-7\n')
    assert main(["run", str(toml), "--json", "--save", str(tmp_path / "r.npz"),
                 "-o", str(tmp_path / "r.gif")]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary and (tmp_path / "r.gif").stat().st_size > 0
    assert a.load(tmp_path / "r.npz").scene.lower.count == 4
    assert main(["critical", str(toml), "--json", "--rel-tol", "0.05"]) == 0
    assert json.loads(capsys.readouterr().out)["critical_force_N"] > 0
    assert main(["compare", "--measure", "critical", "--variants", "regular", "--seeds", "2",
                 "--workers", "1", "--json", "--set", f"lower_surface={profile_file}",
                 "--set", "surface_detrend=false", "--set", "upper_count=2",
                 "--set", "upper_height_std=5e-8", "--set", "track=\"free\""]) == 0
    assert json.loads(capsys.readouterr().out)["variants"]["regular"]["n"] == 2
    bad = folder / "bad.toml"
    bad.write_text('[scene]\nlower_surface = "missing.csv"\n')
    assert main(["run", str(bad)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "`lower_surface` is not a file" in err[0]
