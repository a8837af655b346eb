"""Animation and plot renderers: frame counts, sizes, dispatch by extension, atomic files.

What the frames show (bodies where the arrays put them, meters, slow motion) is tested in
test_pictures.py; the HTML player in test_player.py and, in a browser, test_player_browser.py.
"""

import dataclasses
import sys

import numpy as np
import pytest
from PIL import Image, ImageSequence

import asperity2d as a
from asperity2d.analysis import synthetic_stick_slip
from asperity2d.experiments.compare import Comparison
from asperity2d.renderers import render
from asperity2d.renderers.animate import Movie, render_animation
from asperity2d.renderers.plots import plot_comparison, plot_force_displacement, plot_run

MAGIC = {".gif": b"GIF89a", ".png": b"\x89PNG", ".pdf": b"%PDF"}
SMALL = {"width": 480, "height": 320}  # the least that holds the meters


@pytest.fixture(scope="module")
def run():
    return a.simulate(a.make_scene(lower_count=4, upper_count=2))


def leftovers(directory):
    return [p.name for p in directory.iterdir() if p.name.endswith(".tmp")]


@pytest.mark.parametrize("frames", [1, 7, 33])
def test_gif_has_exactly_the_frames_asked(run, tmp_path, frames):
    path = render_animation(run, tmp_path / "run.gif", frames=frames, **SMALL)
    with Image.open(path) as im:
        assert im.n_frames == frames
        assert im.size == (480, 320)
    assert 0 < path.stat().st_size < 5e6
    assert leftovers(tmp_path) == []


def test_gif_defaults_size_and_frame_count(run, tmp_path):
    path = render(run, tmp_path / "default.gif")
    with Image.open(path) as im:
        assert im.n_frames == 120 and im.size == (720, 480)
        assert im.info["duration"] == 50  # 20 fps
    assert 1e3 < path.stat().st_size < 2e6


def test_gif_frames_exact_even_with_fewer_samples_than_frames(tmp_path):
    result, _ = synthetic_stick_slip(n_events=1)
    few = dataclasses.replace(result, **{n: getattr(result, n)[:5] for n in (
        "t", "x", "v", "y", "drive_x", "drive_force")},
        lower_dx=result.lower_dx[:, :5], lower_dy=result.lower_dy[:, :5],
        lower_contact=result.lower_contact[:, :5])
    path = render_animation(few, tmp_path / "few.gif", frames=12, **SMALL)
    with Image.open(path) as im:
        assert im.n_frames == 12  # identical pictures would be merged by the GIF writer


def test_small_frames_without_meters(run, tmp_path):
    path = render_animation(run, tmp_path / "small.gif", frames=3, width=240, height=160, meters=False)
    with Image.open(path) as im:
        assert im.size == (240, 160) and im.n_frames == 3
    with pytest.raises(a.SceneError, match="meters=False"):
        render_animation(run, tmp_path / "x.gif", frames=3, width=240, height=160)


@pytest.mark.parametrize("suffix", [".gif", ".html", ".png", ".svg", ".pdf"])
def test_renderer_chosen_by_extension(run, tmp_path, suffix):
    opts = {".gif": {"frames": 3, **SMALL}, ".html": {}}.get(suffix, {"dpi": 40})
    path = render(run, tmp_path / f"out{suffix}", **opts)
    head = path.read_bytes()[:200]
    if suffix == ".svg":
        assert b"<svg" in head
    elif suffix == ".html":
        assert head.startswith(b"<!DOCTYPE html>")
    else:
        assert head.startswith(MAGIC[suffix])


def test_render_a_saved_result_without_resimulating(run, tmp_path):
    saved = run.save(tmp_path / "run.npz")
    path = render(saved, tmp_path / "again.gif", frames=4, **SMALL)
    with Image.open(path) as im:
        assert im.n_frames == 4


def test_gif_frames_are_the_palette_drawings_unchanged(run, tmp_path):
    """The GIF holds the palette frames exactly as drawn (no re-quantisation, none merged)."""
    path = render_animation(run, tmp_path / "run.gif", frames=5, **SMALL)
    movie = Movie(run, frames=5, **SMALL)
    drawn = [np.asarray(f.convert("RGB")) for f in movie.frames()]
    with Image.open(path) as im:
        decoded = [np.asarray(f.convert("RGB")) for f in ImageSequence.Iterator(im)]
    assert len(decoded) == 5
    for picture, frame in zip(drawn, decoded):
        np.testing.assert_array_equal(picture, frame)


def test_mp4_has_the_frames_and_size_asked(run, tmp_path):
    """The optional video extra: H.264 through imageio's ffmpeg plugin, written atomically."""
    pytest.importorskip("imageio_ffmpeg")
    import imageio.v3 as iio

    path = render(run, tmp_path / "run.mp4", frames=9, fps=10, **SMALL)
    frames = list(iio.imiter(path, plugin="FFMPEG"))
    assert len(frames) == 9 and frames[0].shape == (320, 480, 3)
    assert leftovers(tmp_path) == [] and sorted(p.name for p in tmp_path.iterdir()) == ["run.mp4"]
    with pytest.raises(a.SceneError, match="`width` must be even"):
        render(run, tmp_path / "odd.mp4", frames=2, width=481, height=320)


def test_mp4_without_the_video_extra_is_a_scene_error(run, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "imageio_ffmpeg", None)  # import now raises ImportError
    with pytest.raises(a.SceneError, match=r"asperity2d\[video\]"):
        render(run, tmp_path / "run.mp4", frames=2, **SMALL)
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
    for name, value in (("camera", "orbit"), ("timing", "random"), ("exaggeration", 0.5),
                        ("width", 100), ("height", 10)):
        with pytest.raises(a.SceneError, match=f"`{name}`"):
            render_animation(run, tmp_path / "x.gif", frames=2, **{**SMALL, name: value})
    assert list(tmp_path.iterdir()) == []


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


def test_a_comparison_is_plotted_in_its_measures_unit(tmp_path, monkeypatch):
    from asperity2d.renderers import plots

    shown = []
    monkeypatch.setattr(plots, "save", lambda fig, path, dpi: shown.append(" ".join(fig.axes[0].get_ylabel().split()))
                        or path)  # the label may be wrapped
    travel = Comparison(values={"regular": (2e-5, 2e-5), "random": (1.9e-5, 2.1e-5)}, seeds=(0, 1),
                        measure="travel_distance")
    force = Comparison(values={"regular": (2e-3, 2e-3)}, seeds=(0, 1), measure="critical")
    plots.plot_comparison(travel, tmp_path / "t.png")
    plots.plot_comparison(force, tmp_path / "f.png")
    assert shown == ["travel under a constant force (µm)", "critical force from rest (step load) (mN)"]
