"""Animations with meters: GIF (Pillow) and MP4 (imageio's ffmpeg) from one frame painter.

A frame is the scene (:class:`~asperity2d.renderers.stage.Stage` for an
asperity run, :class:`~asperity2d.renderers.belt_stage.ChainStage` for a belt
chain) above synchronised meters (:mod:`.meters`), each a trace that grows with
the frame and a cursor at "now". Frame times come from the motion
(:func:`~asperity2d.renderers.timeline.schedule`): slips play in slow motion,
each such frame marked "×N slow", slower still where the slider moves fast, so
that no frame moves it more than about half a pitch (the tips are seen to
climb the flanks; a frame that must jump further says why);
``timing="uniform"`` spaces them evenly.

Speed: every frame is a palette image with one fixed palette
(:mod:`.raster`), so nothing is quantised; what never changes (meter frames,
ticks, titles) is drawn once, and the traces grow on a persistent layer by
the pixel columns the cursor passed since the last frame, so a frame costs a
copy, the scene, the cursors and a few strings. The GIF is written by
Pillow's own writer (each frame only its changed rectangle; unchanged pixels
inside it transparent), the MP4 by imageio's ffmpeg plugin (the optional
``video`` extra).
"""

from __future__ import annotations

import io
import os
import tempfile
from pathlib import Path

import numpy as np

from .._io import atomic_write
from ..errors import SceneError
from . import raster
from .meters import MeterPanel, asperity_meters, chain_meters
from .timeline import TIMINGS, schedule, slip_intervals

#: Animation formats by extension, and the imageio plugin that encodes each (GIF: Pillow itself).
FORMATS = {".gif": "pillow", ".mp4": "FFMPEG"}


def is_chain(result) -> bool:
    """True for a belt-chain result (:class:`~asperity2d.belt.result.BeltResult`)."""
    from ..belt.result import BeltResult

    return isinstance(result, BeltResult)


class Movie:
    """The frames of an animation of ``result`` (see :func:`render_animation` for the options).

    ``frame(j)`` returns frame ``j`` as a palette image; frames must be asked
    for in order (the traces grow on a persistent layer), or the layer is
    redrawn. ``drawn`` holds what the last frame drew where (px), for tests.
    """

    def __init__(self, result, *, frames: int = 120, width: int = 720, height: int = 480,
                 timing: str = "events", camera: str = "follow", exaggeration: float | None = None,
                 arrows: bool = True, meters: bool = True):
        if len(result.t) == 0:
            raise SceneError("`result` has no samples to draw")
        if timing not in TIMINGS:
            raise SceneError(f"`timing` must be one of {', '.join(map(repr, TIMINGS))}, got {timing!r}")
        self.result, self.width, self.height = result, width, height
        self.chain = is_chain(result)
        slips = slip_intervals(result)
        if self.chain:
            self.schedule = schedule(result.t, slips, frames, timing=timing)
        else:  # slower where the slider moves fast: no frame moves it more than about half a pitch
            self.schedule = schedule(result.t, slips, frames, timing=timing, x=result.x,
                                     pitch=result.scene.lower.spacing.mean_pitch)
        if self.chain:
            from .belt_stage import ChainStage

            self.stage = ChainStage(result, width=width, height=int(0.4 * height) if meters else height)
            specs, cols = chain_meters(result), 1
        else:
            from .stage import Stage

            self.stage = Stage(result, width=width, height=int(0.5 * height) if meters else height,
                               camera=camera, exaggeration=exaggeration, frames=self.schedule.index,
                               arrows=arrows)
            specs, cols = asperity_meters(result), 2
        self.scene_height = self.stage.height
        if not meters:
            specs = []
        rows = max(1, -(-len(specs) // cols))
        top, gap = self.scene_height + 2, 2
        cell_w = (width - gap * (cols - 1)) / cols
        cell_h = (height - top - gap * (rows - 1)) / rows
        if specs and (cell_h < 56 or cell_w < 200):
            raise SceneError(f"`height` {height} px and `width` {width} px leave no room for the meters "
                             "(at least 480 x 320 px), or pass meters=False")
        self.meters = [MeterPanel(m, (c * (cell_w + gap), top + r * (cell_h + gap),
                                      c * (cell_w + gap) + cell_w - 1, top + r * (cell_h + gap) + cell_h - 1),
                                  result.t, slips=() if self.chain else slips, font_size=11)
                       for i, m in enumerate(specs) for r, c in [divmod(i, cols)]]
        self._static()
        self.drawn: dict = {}

    def _static(self):
        from PIL import ImageDraw

        self.layer = raster.new(self.width, self.height, "light")
        ImageDraw.Draw(self.layer).line([(0, self.scene_height), (self.width, self.scene_height)],
                                        fill=raster.INDEX["grey"])
        for meter in self.meters:
            meter.draw_static(self.layer)
        self.scene_bg = raster.new(self.width, self.scene_height, "white")
        self.stage.paint_static(self.scene_bg)
        self._last = -1

    def __len__(self) -> int:
        return len(self.schedule)

    def frame(self, j: int):
        """Frame ``j`` (palette image)."""
        k = int(self.schedule.index[j])
        t = float(self.result.t[k])
        if j <= self._last:
            self._static()
        for meter in self.meters:
            meter.advance(self.layer, t)
        img = self.layer.copy()
        scene = self.scene_bg.copy()
        jumps = self.schedule.jumps
        note = (f"moved {jumps[j]:.1f} pitches since the last frame: {self.schedule.coarse_reason}"
                if jumps is not None and jumps[j] > 1.0 else "")
        self.drawn = self.stage.shapes(k, slow=float(self.schedule.slow[j]),
                                       counter=f"frame {j + 1}/{len(self)}")
        if not self.chain:
            self.drawn["note"] = note
        self.stage.paint(scene, self.drawn)
        img.paste(scene, (0, 0))
        for meter in self.meters:
            meter.draw_now(img, k)
        self._last = j
        return img

    def frames(self):
        """Every frame in order (a generator)."""
        for j in range(len(self)):
            yield self.frame(j)


def render_animation(result, path: str | os.PathLike, *, frames: int = 120, width: int = 720,
                     height: int = 480, fps: float = 20.0, timing: str = "events", camera: str = "follow",
                     exaggeration: float | None = None, arrows: bool = True, meters: bool = True) -> Path:
    """Write an animation of ``result`` (a Result or a BeltResult) to ``path`` atomically.

    The extension picks the format: ``.gif``, or ``.mp4`` (H.264; needs
    ``pip install "asperity2d[video]"``).

    Parameters
    ----------
    frames : int
        Number of frames; the file holds exactly this many (each carries its
        number, so a GIF writer merges none).
    width, height : int
        Frame size (px); even for ``.mp4`` (H.264's 4:2:0 chroma). The scene
        takes the top ~45 %, the meters the rest.
    fps : float
        Playback rate (frames per second; GIF delays are whole centiseconds).
    timing : {"events", "uniform"}
        Frame times: slow motion through slips (default, each slowed frame
        marked "×N slow"), or evenly spaced.
    camera : {"follow", "whole"}
        Keep the slider, its contacts and the drive block in view (default),
        or show the whole surface (asperity runs; a chain is always whole).
    exaggeration : float, optional
        Vertical exaggeration (>= 1); default automatic for shallow surfaces.
    arrows : bool
        Draw the contact forces as arrows on the touching tips (asperity runs).
    meters : bool
        Draw the meters below the scene (default); without them the scene
        takes the whole frame (small sizes, down to 240 x 160 px).
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in FORMATS:
        raise SceneError(f"`path` must end in one of {', '.join(FORMATS)}, got {str(path)!r}")
    frames = _check_int("frames", frames, 1)
    width, height = _check_int("width", width, 240), _check_int("height", height, 160)
    if not (isinstance(fps, (int, float)) and not isinstance(fps, bool) and 0 < fps <= 100):
        raise SceneError(f"`fps` must be in (0, 100], got {fps!r}")
    if suffix == ".mp4":
        _check_video(width, height)
    movie = Movie(result, frames=frames, width=width, height=height, timing=timing, camera=camera,
                  exaggeration=exaggeration, arrows=arrows, meters=bool(meters))
    data = encode(movie.frames(), suffix=suffix, fps=float(fps))
    return atomic_write(path, lambda fh: fh.write(data))


def encode(pictures, *, suffix: str, fps: float) -> bytes:
    """Encode palette images (all with :data:`raster.PALETTE`) as a ``.gif`` or ``.mp4`` file's bytes.

    GIF: Pillow's writer, looping, each frame shown 1/fps s rounded to whole
    centiseconds (at least 20 ms: browsers slow shorter delays down to 100 ms).
    The palette is the frames' own, so nothing is quantised; ``optimize``
    lets Pillow code the unchanged pixels of each frame's changed rectangle
    as transparent (smaller files). MP4: the frames are mapped to RGB and
    streamed to ffmpeg (libx264, yuv420p) at ``fps``; ffmpeg needs a real
    file, so it writes into a temporary directory whose file is read back
    (the caller writes the bytes atomically).
    """
    if suffix == ".gif":
        delay = max(20, int(round(1000.0 / fps / 10.0)) * 10)  # ms, whole centiseconds
        frames = iter(pictures)
        first = next(frames, None)
        if first is None:
            raise SceneError("`frames` must be >= 1, got 0")
        buffer = io.BytesIO()
        first.save(buffer, format="GIF", save_all=True, append_images=frames, duration=delay, loop=0,
                   optimize=True)
        return buffer.getvalue()
    if suffix not in FORMATS:
        raise SceneError(f"`suffix` must be one of {', '.join(FORMATS)}, got {suffix!r}")
    _require_ffmpeg()
    import imageio.v3 as iio

    with tempfile.TemporaryDirectory(prefix="asperity2d-video-") as tmp:
        scratch = Path(tmp) / f"animation{suffix}"
        # A generator: frames stream to ffmpeg one at a time, never all in memory.
        iio.imwrite(scratch, (raster.RGB[np.asarray(picture)] for picture in pictures),
                    plugin=FORMATS[suffix], is_batch=True, fps=fps, codec="libx264",
                    pixelformat="yuv420p", macro_block_size=2, ffmpeg_log_level="error")
        return scratch.read_bytes()


def _check_video(width: int, height: int) -> None:
    for name, value in (("width", width), ("height", height)):
        if value % 2:
            raise SceneError(f"`{name}` must be even for .mp4 (H.264 4:2:0 chroma), got {value}")
    _require_ffmpeg()


def _require_ffmpeg() -> None:
    try:
        import imageio_ffmpeg  # noqa: F401  (the ffmpeg binary imageio's FFMPEG plugin runs)
    except ImportError:
        raise SceneError("`path`: writing .mp4 needs the optional video extra: "
                         "pip install \"asperity2d[video]\" (imageio-ffmpeg)") from None


def _check_int(name: str, value, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise SceneError(f"`{name}` must be an integer >= {minimum}, got {value!r}")
    return int(value)


__all__ = ["FORMATS", "Movie", "encode", "is_chain", "render_animation"]
