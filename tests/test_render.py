"""GIF and plot renderers: frame counts, sizes, dispatch by extension, atomic files."""

import dataclasses

import numpy as np
import pytest
from PIL import Image

import asperity2d as a
from asperity2d.analysis import synthetic_stick_slip
from asperity2d.compare import Comparison
from asperity2d.render import render
from asperity2d.render.gif import Layout, frame_shapes, render_gif
from asperity2d.render.plots import plot_comparison, plot_force_displacement, plot_run

MAGIC = {".gif": b"GIF89a", ".png": b"\x89PNG", ".pdf": b"%PDF"}


@pytest.fixture(scope="module")
def run():
    return a.simulate(a.make_scene(lower_count=4, upper_count=2))


def leftovers(directory):
    return [p.name for p in directory.iterdir() if p.name.endswith(".tmp")]


@pytest.mark.parametrize("frames", [1, 7, 33])
def test_gif_has_exactly_the_frames_asked(run, tmp_path, frames):
    path = render_gif(run, tmp_path / "run.gif", frames=frames, width=200, height=100)
    with Image.open(path) as im:
        assert im.n_frames == frames
        assert im.size == (200, 100)
    assert 0 < path.stat().st_size < 5e6
    assert leftovers(tmp_path) == []


def test_gif_defaults_size_and_frame_count(run, tmp_path):
    path = render(run, tmp_path / "default.gif")
    with Image.open(path) as im:
        assert im.n_frames == 120 and im.size == (640, 320)
        assert im.info["duration"] == 50  # 20 fps
    assert 1e3 < path.stat().st_size < 5e6


def test_gif_frames_exact_even_with_fewer_samples_than_frames(tmp_path):
    result, _ = synthetic_stick_slip(n_events=1)
    few = dataclasses.replace(result, **{n: getattr(result, n)[:5] for n in (
        "t", "x", "v", "y", "drive_x", "drive_force")},
        lower_dx=result.lower_dx[:, :5], lower_dy=result.lower_dy[:, :5],
        lower_contact=result.lower_contact[:, :5])
    path = render_gif(few, tmp_path / "few.gif", frames=12, width=160, height=80)
    with Image.open(path) as im:
        assert im.n_frames == 12  # identical pictures would be merged by the GIF writer


def test_view_follows_the_slider(run):
    layout = Layout(run, width=400, height=200)
    centres = []
    for k in (0, len(run.t) // 2, len(run.t) - 1):
        x0, _, x1, _ = frame_shapes(layout, k)["bar"]
        centres.append(0.5 * (x0 + x1))
    assert run.x[-1] - run.x[0] > layout.view_width / 2  # the slider really travelled
    np.testing.assert_allclose(centres, centres[0], atol=1.0)
    assert abs(centres[0] - 200) < 0.1 * 400


@pytest.mark.parametrize("suffix", [".gif", ".png", ".svg", ".pdf"])
def test_renderer_chosen_by_extension(run, tmp_path, suffix):
    opts = {"frames": 3, "width": 120, "height": 64} if suffix == ".gif" else {"dpi": 40}
    path = render(run, tmp_path / f"out{suffix}", **opts)
    head = path.read_bytes()[:200]
    if suffix == ".svg":
        assert b"<svg" in head
    else:
        assert head.startswith(MAGIC[suffix])


def test_render_a_saved_result_without_resimulating(run, tmp_path):
    saved = run.save(tmp_path / "run.npz")
    path = render(saved, tmp_path / "again.gif", frames=4, width=120, height=64)
    with Image.open(path) as im:
        assert im.n_frames == 4


@pytest.mark.parametrize("name", ["out.mp4", "out", "out.GIFX"])
def test_bad_extension_is_a_scene_error(run, tmp_path, name):
    with pytest.raises(a.SceneError, match="`path`"):
        render(run, tmp_path / name)
    assert list(tmp_path.iterdir()) == []


def test_bad_gif_options(run, tmp_path):
    with pytest.raises(a.SceneError, match="`frames`"):
        render_gif(run, tmp_path / "x.gif", frames=0)
    with pytest.raises(a.SceneError, match="`fps`"):
        render_gif(run, tmp_path / "x.gif", fps=0)
    with pytest.raises(a.SceneError, match="`view_width`"):
        render_gif(run, tmp_path / "x.gif", view_width=-1.0)


def test_plots_write_files(run, tmp_path):
    assert plot_run(run, tmp_path / "run.png", dpi=40).read_bytes().startswith(MAGIC[".png"])
    fd = plot_force_displacement(run, tmp_path / "fd.pdf")
    assert fd.read_bytes().startswith(MAGIC[".pdf"])
    forced = a.simulate(a.make_scene(drive="force", drive_force=0.017, lower_count=3,
                                     upper_count=1))
    assert b"<svg" in plot_run(forced, tmp_path / "forced.svg").read_bytes()[:300]
    comparison = Comparison(values={"regular": (1.0, 2.0, 3.0), "random": (1.5, float("nan"), 0.5)},
                            seeds=(0, 1, 2), measure="breakaway_force")
    cmp_path = plot_comparison(comparison, tmp_path / "cmp.png", reference=2.0, dpi=40)
    assert cmp_path.read_bytes().startswith(MAGIC[".png"])
    with pytest.raises(a.SceneError, match="`path`"):
        plot_run(run, tmp_path / "run.jpg")
    assert leftovers(tmp_path) == []
