"""Scenes as TOML files in the model layer: a whole scene written by ``Scene.to_toml`` reads back
equal, and ``asperity2d run`` on it reproduces the scene's run bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

import asperity2d as a
from asperity2d.cli import main
from asperity2d.run import default_duration
from asperity2d.scene import Scene
from asperity2d.scene_io import read_scene

TINY = {"lower_count": 4, "upper_count": 2}


@pytest.mark.parametrize("kwargs", [
    {"spacing": "random", "seed": 11},
    {"drive": "force", "track": "free", "profile": "half", "seed": 2},
], ids=["random spring", "free slider under a force"])
def test_a_scene_written_as_toml_reads_back_equal(tmp_path, kwargs):
    scene = a.make_scene(**TINY, **kwargs)
    path = scene.to_toml(tmp_path / "scene.toml", run={"duration": 1e-6})
    assert Scene.from_toml(path) == scene
    again, run = read_scene(path)
    assert again == scene and run == {"duration": 1e-6}


def test_asperity2d_run_of_a_saved_scene_reproduces_its_run_to_the_bit(tmp_path, capsys):
    scene = a.make_scene(**TINY, spacing="random", seed=3)
    duration = 0.2 * default_duration(scene)  # ~2000 steps: enough contacts to switch stick/slip
    direct = a.simulate(scene, duration, progress=False)
    path = scene.to_toml(tmp_path / "scene.toml", run={"duration": duration})
    assert main(["run", str(path), "--save", str(tmp_path / "run.npz"), "--json"]) == 0
    capsys.readouterr()
    again = a.load(tmp_path / "run.npz")
    assert again.scene == scene
    assert len(direct.t) > 1000
    for name in ("t", "x", "v", "y", "vy", "drive_x", "drive_force", "normal_force", "friction_force",
                 "tangential_force", "contact_count", "lower_dx", "lower_dy", "lower_contact"):
        np.testing.assert_array_equal(getattr(again, name), getattr(direct, name), err_msg=name)


def test_a_file_that_is_not_a_scene_is_refused_naming_what_is_wrong(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('format = "asperity2d.scene/1"\n[spec]\ntype = "Slider"\n')
    with pytest.raises(a.SceneError, match="`spec`"):
        Scene.from_toml(bad)
    bad.write_text('format = "something/1"\n')
    with pytest.raises(a.SceneError, match="not a scene file"):
        Scene.from_toml(bad)
    bad.write_text('format = "asperity2d.scene/1"\nextra = 1\n[spec]\ntype = "Scene"\n')
    with pytest.raises(a.SceneError, match="`extra`"):
        read_scene(bad)
