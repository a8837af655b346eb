"""Commands that never ended, and the last tracebacks and confusing refusals (issue 27 items 5, 10, 11).

Every case runs in-process through ``main(argv)`` and must answer within seconds: one error
line naming the argument the user wrote, exit status 2, no traceback -- or, for the inputs that
are fine (a TOML file with a byte-order mark), exit 0. Each is timed out by an alarm: a command
that would run for hours fails the test instead of hanging it.
"""

from __future__ import annotations

import json
import time

import numpy as np
import pytest

import asperity2d as a
from asperity2d import SceneError
from asperity2d.cli import main
from wall_clock import within

CHAIN = ('masses = [1.0]\nsprings = [10.0, 0.0]\ndampers = [0.0, 0.0]\nmu_s = 0.3\nv_belt = 0.1\n'
         'x0 = [0.0]\nv0 = [0.0]\nt_end = 2.0\n')
BOM = "\ufeff"


def fill(argv, files):
    """``argv`` with each ``{name}`` replaced by the path of file ``name``."""
    out = []
    for word in argv:
        for name, path in files.items():
            word = word.replace("{" + name + "}", path)
        out.append(word)
    return out


def refused(capsys, argv, needle, seconds=20.0):
    with within(seconds):
        code = main(argv)
    out, err = capsys.readouterr()
    assert code == 2, (argv, out, err)
    assert "Traceback" not in err and len(err.splitlines()) == 1 and err.startswith("asperity2d: error: "), err
    assert needle in err, err
    return err


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    root = tmp_path_factory.mktemp("budgets")
    result = a.simulate(a.make_scene(lower_count=4, upper_count=2), 2e-9, progress=False)
    result.save(root / "result.npz")
    # the same file with NaN positions: no run writes one (a run that goes non-finite raises)
    data = dict(np.load(root / "result.npz"))
    data["x"] = np.full_like(data["x"], np.nan)
    np.savez(root / "nan.npz", **data)
    (root / "chain.toml").write_text(CHAIN)
    (root / "bom_chain.toml").write_text(BOM + CHAIN, encoding="utf-8")
    (root / "bom_scene.toml").write_text(BOM + "lower_count = 4\nupper_count = 2\n", encoding="utf-8")
    (root / "huge_grid.toml").write_text(
        'name = "huge"\nrun = "asperity2d.studies.ooten:critical_force_run"\nseeds = 100000\n[grid]\n'
        f"lower_count = {list(range(2, 1002))}\nupper_count = {list(range(1, 1001))}\n")
    (root / "huge_seeds.toml").write_text(
        'name = "seeds"\nrun = "asperity2d.studies.ooten:critical_force_run"\nseeds = 1000000000000\n')
    return {p.name: str(p) for p in root.iterdir()} | {"root": str(root)}


# -- item 5: commands that never ended are refused up front ---------------------------------------
def test_a_basin_map_of_ten_billion_runs_is_refused(capsys, files):
    err = refused(capsys, ["belt", "basins", "--preset", "table2-3dof", "--grid", "100000", "--t-end", "1",
                           "-o", f"{files['root']}/b.png"], "`--max-runs`", seconds=10)
    assert "10,000,000,000 runs" in err


def test_a_sweep_of_1e11_runs_and_a_trillion_seeds_are_refused(capsys, files):
    store = f"{files['root']}/store"
    err = refused(capsys, ["sweep", "run", files["huge_grid.toml"], "--store", store], "`--max-runs`", seconds=10)
    assert "1,000 x 1,000 grid point(s) x 100,000 seeds" in err
    refused(capsys, ["sweep", "run", files["huge_seeds.toml"], "--store", store], "`seeds` holds 1,000,000,000,000",
            seconds=10)


def test_compare_with_1e20_seeds_is_refused(capsys):
    refused(capsys, ["compare", "--seeds", "100000000000000000000"], "`--max-runs`", seconds=10)


def test_the_run_budget_can_be_raised(capsys, files):
    # the same refusal names the option, and the option lifts it (here to a refusal of another kind)
    refused(capsys, ["compare", "--seeds", "200000", "--variants", "regular"], "`--max-runs` = 100,000")
    refused(capsys, ["compare", "--seeds", "3", "--variants", "regular", "--max-runs", "2"], "3 runs")


# -- item 10: the remaining tracebacks ---------------------------------------------------------------
@pytest.mark.parametrize("option, path, needle", [
    ("-o", "/proc/bas.png", "`--output` cannot be created"),
    ("--store", "/proc/st", "`--store`"),
])
def test_basins_check_their_outputs_before_computing(capsys, option, path, needle):
    argv = ["belt", "basins", "--preset", "table2-3dof", "--grid", "2", "--t-end", "1", option, path]
    if option == "--store":
        argv += ["-o", "/tmp/asperity2d-test-basins.png"]
    refused(capsys, argv, needle, seconds=10)


def test_compare_refuses_an_unwritable_save_before_computing(capsys):
    start = time.perf_counter()
    refused(capsys, ["compare", "--seeds", "20", "--save", "/proc/x.json"], "`--save` cannot be created", seconds=10)
    assert time.perf_counter() - start < 5  # not after twenty critical-force bisections


def test_compare_refuses_setting_what_the_variants_set(capsys):
    refused(capsys, ["compare", "--seeds", "2", "--set", "spacing=random"], "`--set spacing=...`")


@pytest.mark.parametrize("argv", [["render", "{nan.npz}", "-o", "{root}/x.png"], ["analyze", "{nan.npz}", "--json"]])
def test_a_result_with_nan_positions_is_refused_as_damaged(capsys, files, argv):
    refused(capsys, fill(argv, files), "non-finite values")


@pytest.mark.parametrize("argv", [["run", "{bom_scene.toml}", "-o", ""], ["belt", "--preset", "table2-3dof", "-o", ""],
                                  ["compare", "--load", "x.json", "-o", ""], ["render", "{result.npz}", "-o", ""],
                                  ["run", "{bom_scene.toml}", "--save", ""]])
def test_an_empty_output_name_is_refused_not_ignored(capsys, files, argv):
    refused(capsys, fill(argv, files), "is empty")


def test_toml_files_with_a_byte_order_mark_are_read(capsys, files):
    with within(60):
        assert main(["belt", files["bom_chain.toml"], "--t-end", "0.5", "--json"]) == 0
        assert json.loads(capsys.readouterr().out)["n"] == 1
        assert main(["run", files["bom_scene.toml"], "--duration", "1e-9", "--json"]) == 0
        assert json.loads(capsys.readouterr().out)["status"] == "duration"


# -- item 11: reasonable inputs with confusing refusals ------------------------------------------------
def test_earth_gravity_on_a_loaded_micro_slider_runs():
    # 9.81 m/s^2 is 7.6e-14 of the steel scene's accelerations: negligible, not an error
    scene = a.make_scene(track="free", normal_load=0.01, gravity=9.81, lower_count=4, upper_count=2)
    result = a.simulate(scene, duration=2e-9)
    plain = a.simulate(a.make_scene(track="free", normal_load=0.01, lower_count=4, upper_count=2), duration=2e-9)
    assert result.success and np.allclose(result.x, plain.x, rtol=0, atol=1e-12 * scene.base)
    # gravity as the only load of a free slider cannot press it on: refused when the scene is made
    with pytest.raises(SceneError, match="`gravity` = 9.81 m/s\\^2 is the free slider's only load.*`normal_load`"):
        a.make_scene(track="free", normal_load=0.0, gravity=9.81)


def test_a_short_run_has_a_sound(tmp_path):
    from asperity2d.renderers import render

    from asperity2d.run import default_dt

    scene = a.make_scene(lower_count=2, upper_count=1)
    short = a.simulate(scene, duration=400 * default_dt(scene))  # 41 samples (one every 10 steps)
    assert 16 <= len(short.t) < 64  # fewer than four 16-sample segments: was "`segment` must span 16 samples"
    assert render(short, tmp_path / "x.wav").exists()
    tiny = a.simulate(scene, duration=default_dt(scene))
    with pytest.raises(SceneError, match="too few to find its dominant frequency.*record a longer run"):
        render(tiny, tmp_path / "y.wav")
