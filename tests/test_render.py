"""Animation and plot renderers: frame counts, sizes, dispatch by extension, atomic files."""

import dataclasses
import sys

import numpy as np
import pytest
from PIL import Image, ImageFont, ImageSequence

import asperity2d as a
from asperity2d.analysis import synthetic_stick_slip
from asperity2d.experiments.compare import Comparison
from asperity2d.renderers import render
from asperity2d.renderers.animate import (Layout, draw_frame, frame_indices, frame_shapes,
                                       render_animation)
from asperity2d.renderers.plots import plot_comparison, plot_force_displacement, plot_run

MAGIC = {".gif": b"GIF89a", ".png": b"\x89PNG", ".pdf": b"%PDF"}


@pytest.fixture(scope="module")
def run():
    return a.simulate(a.make_scene(lower_count=4, upper_count=2))


def leftovers(directory):
    return [p.name for p in directory.iterdir() if p.name.endswith(".tmp")]


@pytest.mark.parametrize("frames", [1, 7, 33])
def test_gif_has_exactly_the_frames_asked(run, tmp_path, frames):
    path = render_animation(run, tmp_path / "run.gif", frames=frames, width=200, height=100)
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
    path = render_animation(few, tmp_path / "few.gif", frames=12, width=160, height=80)
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


def test_gif_frames_are_the_pillow_drawings_unchanged(run, tmp_path):
    """imageio encodes the palette frames exactly as Pillow drew them (no re-quantisation)."""
    path = render_animation(run, tmp_path / "run.gif", frames=5, width=160, height=80)
    layout, font = Layout(run, width=160, height=80), ImageFont.load_default()
    drawn = [draw_frame(frame_shapes(layout, int(k), frame=i, frames=5), width=160, height=80,
                        font=font) for i, k in enumerate(frame_indices(run, 5))]
    with Image.open(path) as im:
        decoded = [np.asarray(f.convert("RGB")) for f in ImageSequence.Iterator(im)]
    assert len(decoded) == 5
    for picture, frame in zip(drawn, decoded):
        np.testing.assert_array_equal(np.asarray(picture.convert("RGB")), frame)


def test_mp4_has_the_frames_and_size_asked(run, tmp_path):
    """The optional video extra: H.264 through imageio's ffmpeg plugin, written atomically."""
    pytest.importorskip("imageio_ffmpeg")
    import imageio.v3 as iio

    path = render(run, tmp_path / "run.mp4", frames=9, width=160, height=80, fps=10)
    frames = list(iio.imiter(path, plugin="FFMPEG"))
    assert len(frames) == 9 and frames[0].shape == (80, 160, 3)
    assert leftovers(tmp_path) == [] and sorted(p.name for p in tmp_path.iterdir()) == ["run.mp4"]
    with pytest.raises(a.SceneError, match="`width` must be even"):
        render(run, tmp_path / "odd.mp4", frames=2, width=161, height=80)


def test_mp4_without_the_video_extra_is_a_scene_error(run, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "imageio_ffmpeg", None)  # import now raises ImportError
    with pytest.raises(a.SceneError, match=r"asperity2d\[video\]"):
        render(run, tmp_path / "run.mp4", frames=2, width=160, height=80)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("name", ["out.avi", "out", "out.GIFX"])
def test_bad_extension_is_a_scene_error(run, tmp_path, name):
    with pytest.raises(a.SceneError, match="`path`"):
        render(run, tmp_path / name)
    assert list(tmp_path.iterdir()) == []


def test_bad_gif_options(run, tmp_path):
    with pytest.raises(a.SceneError, match="`frames`"):
        render_animation(run, tmp_path / "x.gif", frames=0)
    with pytest.raises(a.SceneError, match="`fps`"):
        render_animation(run, tmp_path / "x.gif", fps=0)
    with pytest.raises(a.SceneError, match="`view_width`"):
        render_animation(run, tmp_path / "x.gif", view_width=-1.0)


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
