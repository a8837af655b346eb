"""Animations of a run: frames drawn with Pillow, encoded by imageio (GIF; MP4 optional).

Drawing is split in two so the benchmark can draw the very same frames with
matplotlib: :func:`frame_shapes` turns one sample of a
:class:`~asperity2d.result.Result` into pixel-space shapes, and
:func:`draw_frame` paints them on a palette image with ``PIL.ImageDraw``.
:func:`encode` hands the frames to imageio: ``.gif`` through its Pillow
plugin (the palette images as they are, no re-quantisation), ``.mp4`` (H.264)
through its ffmpeg plugin, which needs the optional extra
``pip install "asperity2d[video]"`` (imageio-ffmpeg, with its own ffmpeg).

What is drawn (seed 000, figures 5–8): the lower asperities (each with its own
shape, :meth:`~asperity2d.scene.LowerSurface.outlines`) on their vertical
spring tracks, standing on a ground band whose top is the engine's guard floor
(the bottom of the tracks, ``-travel_down``), the slider's bar and its downward
asperities, the drive spring as a zig-zag from the slider's front to the
moving drive block, and an overlay with the time, the drive force and the
frame number. The view keeps one scale for the whole animation and follows the
slider. The drive spring's rest length is zero in the model; it is drawn from
the slider's front with one pitch added, so its stretch (drive_x - x) shows.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np

from .._io import atomic_write
from ..errors import SceneError

#: Palette indices (RGB below): background, outline, lower, upper, bar, ground, spring, text.
BACKGROUND, OUTLINE, LOWER, UPPER, BAR, GROUND, SPRING, TEXT = range(8)
PALETTE = [(255, 255, 255), (40, 40, 40), (90, 130, 190), (230, 140, 50),
           (70, 70, 80), (200, 200, 200), (170, 30, 30), (0, 0, 0)]
PALETTE_BYTES = bytes(c for rgb in PALETTE for c in rgb)
TEXT_HEIGHT = 18  # px reserved at the top for the overlay


def zigzag(x0: float, x1: float, y: float, *, coils: int = 8, amplitude: float = 5.0,
           vertical: bool = False) -> list[tuple[float, float]]:
    """Points of a zig-zag spring from ``x0`` to ``x1`` at ``y`` (pixels).

    ``vertical=True`` swaps the axes (a spring from y = x0 to y = x1 at x = y).
    """
    n = 2 * coils
    s = np.linspace(x0, x1, n + 3)
    off = np.zeros(n + 3)
    off[2:-2:2], off[3:-2:2] = amplitude, -amplitude
    pts = np.column_stack([s, y + off])
    if vertical:
        pts = pts[:, ::-1]
    return [tuple(p) for p in pts.tolist()]


class Layout:
    """Fixed scale and vertical placement for a whole animation, following the slider.

    ``view_width`` (m) defaults to the slider's span plus four lower pitches.
    World (m) to pixels: ``px = (X - left) * scale``, ``py = ground - Y * scale``.
    """

    def __init__(self, result, *, width: int, height: int, view_width: float | None = None):
        scene = result.scene
        self.result, self.width, self.height = result, width, height
        # each asperity's own polygon (m, relative to its tip's x and the rest datum)
        self.lower_polys = [np.asarray(v) for v in scene.lower.outlines()]
        self.upper_polys = [np.asarray(v) for v in scene.slider.outlines()]
        self.lower_levels = np.array(scene.lower.shape_set().levels)
        self.substrate = [np.asarray(line) for line in scene.lower.substrate or ()]
        self.lower_centers = scene.lower.tips()
        self.upper_centers = scene.slider.tips()
        self.base, h = scene.base, scene.lower.top
        self.pitch = scene.lower.spacing.mean_pitch
        self.upper_front = self.upper_centers[-1] + float(np.ravel(scene.slider.runs()[1])[-1])
        span = self.upper_front - self.upper_centers[0] + float(np.ravel(scene.slider.runs()[0])[0])
        if view_width is None:
            view_width = span + 4.0 * self.pitch
        if not view_width > 0:
            raise SceneError(f"`view_width` must be > 0, got {view_width!r}")
        self.view_width = float(view_width)
        self.bar = 0.3 * self.base
        # The engine's guard floor (it stops sinking upper tips) is at the bottom of
        # the lower tracks; the track springs are drawn standing on it.
        self.track_floor = scene.lower.floor
        y_top = float(np.nanmax(result.y)) + self.bar
        y_bot = self.track_floor - 0.3 * h
        usable = height - TEXT_HEIGHT - 6
        self.scale = min(width / self.view_width, usable / max(y_top - y_bot, 1e-300))
        self.ground = TEXT_HEIGHT + 3 + (usable + (y_top + y_bot) * self.scale) / 2.0
        self.half_span = 0.5 * self.upper_centers[-1]

    def left(self, x: float) -> float:
        """World x (m) at the left edge when the slider's reference point is at ``x``."""
        return x + self.half_span - 0.5 * self.width / self.scale

    def to_px(self, X, Y, left):
        return (np.asarray(X) - left) * self.scale, self.ground - np.asarray(Y) * self.scale


def frame_indices(result, frames: int) -> np.ndarray:
    """Sample index shown in each of ``frames`` frames, evenly spaced in time."""
    t = np.asarray(result.t, dtype=float)
    wanted = np.linspace(t[0], t[-1], frames)
    return np.clip(np.searchsorted(t, wanted), 0, len(t) - 1)


def frame_shapes(layout: Layout, k: int, *, frame: int = 0, frames: int = 1) -> dict:
    """Pixel-space shapes of sample ``k``: polygons, spring polylines, rectangles, text."""
    r, L = layout.result, layout
    x, y = float(r.x[k]), float(r.y[k])
    left = L.left(x)
    margin = L.base + L.pitch
    cx = L.lower_centers + r.lower_dx[:, k]
    visible = np.flatnonzero((cx > left - margin) & (cx < left + L.width / L.scale + margin))
    lower, tracks = [], []
    floor_py = L.to_px(0.0, L.track_floor, left)[1]
    for i in visible:
        poly = L.lower_polys[i]
        X, Y = L.to_px(cx[i] + poly[:, 0], r.lower_dy[i, k] + poly[:, 1], left)
        lower.append(list(zip(X.tolist(), Y.tolist())))
        px, base_py = L.to_px(cx[i], r.lower_dy[i, k] + L.lower_levels[i], left)
        tracks.append(zigzag(float(floor_py), float(base_py), float(px), coils=4,
                             amplitude=max(2.0, 0.12 * L.base * L.scale), vertical=True))
    upper = []
    for c, poly in zip(L.upper_centers, L.upper_polys):
        X, Y = L.to_px(x + c + poly[:, 0], y + poly[:, 1], left)
        upper.append(list(zip(X.tolist(), Y.tolist())))
    front = x + L.upper_front
    bx0, by0 = L.to_px(x - 0.5 * L.base, y + L.bar, left)
    bx1, by1 = L.to_px(front, y, left)
    substrate = []
    for line in L.substrate:
        X, Y = L.to_px(line[:, 0], line[:, 1], left)
        substrate.append(list(zip(X.tolist(), Y.tolist())))
    shapes = {"lower": lower, "tracks": tracks, "upper": upper, "substrate": substrate,
              "bar": (float(bx0), float(by0), float(bx1), float(by1)),
              "ground": (0.0, float(floor_py), float(L.width), float(L.height)),
              "spring": [], "drive": None}
    drive_x = float(r.drive_x[k])
    if np.isfinite(drive_x):
        end = front + L.pitch + (drive_x - x)
        (sx0, sx1), sy = L.to_px([front, end], y + 0.5 * L.bar, left)[0], float(
            L.to_px(0.0, y + 0.5 * L.bar, left)[1])
        shapes["spring"] = zigzag(float(sx0), float(sx1), sy, coils=8,
                                  amplitude=max(2.0, 0.25 * L.bar * L.scale))
        half = max(3.0, 0.5 * L.bar * L.scale)
        shapes["drive"] = (float(sx1), sy - half, float(sx1) + 2 * half, sy + half)
    shapes["text"] = f"t = {r.t[k]:.4e} s   drive force = {r.drive_force[k]:.4e} N"
    shapes["counter"] = f"{frame + 1}/{frames}"
    return shapes


def draw_frame(shapes: dict, *, width: int, height: int, font=None):
    """Paint ``shapes`` on a new palette ("P") image of ``width`` x ``height`` px."""
    from PIL import Image, ImageDraw, ImageFont

    img = Image.new("P", (width, height), BACKGROUND)
    img.putpalette([c for rgb in PALETTE for c in rgb])
    d = ImageDraw.Draw(img)
    d.rectangle(shapes["ground"], fill=GROUND)
    for pts in shapes["tracks"]:
        d.line(pts, fill=OUTLINE, width=1)
    for pts in shapes.get("substrate", ()):
        d.line(pts, fill=OUTLINE, width=2)
    for pts in shapes["lower"]:
        d.polygon(pts, fill=LOWER, outline=OUTLINE)
    for pts in shapes["upper"]:
        d.polygon(pts, fill=UPPER, outline=OUTLINE)
    d.rectangle(_ordered(shapes["bar"]), fill=BAR, outline=OUTLINE)
    if shapes["spring"]:
        d.line(shapes["spring"], fill=SPRING, width=2)
        d.rectangle(_ordered(shapes["drive"]), fill=SPRING, outline=OUTLINE)
    font = font or ImageFont.load_default()
    d.rectangle((0, 0, width, TEXT_HEIGHT), fill=BACKGROUND)
    d.text((4, 3), shapes["text"], fill=TEXT, font=font)
    d.text((width - 4, 3), shapes["counter"], fill=TEXT, font=font, anchor="ra")
    return img


def _ordered(box):
    x0, y0, x1, y1 = box
    return (min(x0, x1), min(y0, y1), max(x0, x1), max(y0, y1))


#: Animation formats by extension, and the imageio plugin that encodes each.
FORMATS = {".gif": "pillow", ".mp4": "FFMPEG"}


def render_animation(result, path: str | os.PathLike, *, frames: int = 120, width: int = 640,
                     height: int = 320, fps: float = 20.0,
                     view_width: float | None = None) -> Path:
    """Write an animation of ``result`` to ``path`` (atomically) and return the path.

    The extension picks the format: ``.gif``, or ``.mp4`` (H.264; needs
    ``pip install "asperity2d[video]"``).

    Parameters
    ----------
    frames : int
        Number of frames, evenly spaced in simulated time; the file holds
        exactly this many (each frame carries its number, so a GIF writer
        merges none).
    width, height : int
        Frame size (px); even for ``.mp4`` (H.264's 4:2:0 chroma).
    fps : float
        Playback rate (frames per second; GIF delays are whole centiseconds).
    view_width : float, optional
        Width of the window (m); default: slider span plus four pitches.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in FORMATS:
        raise SceneError(f"`path` must end in one of {', '.join(FORMATS)}, got {str(path)!r}")
    frames = _check_int("frames", frames, 1)
    width, height = _check_int("width", width, 64), _check_int("height", height, 48)
    if not (isinstance(fps, (int, float)) and not isinstance(fps, bool) and 0 < fps <= 100):
        raise SceneError(f"`fps` must be in (0, 100], got {fps!r}")
    if suffix == ".mp4":
        _check_video(width, height)
    if len(result.t) == 0:
        raise SceneError("`result` has no samples to draw")
    from PIL import ImageFont

    layout = Layout(result, width=width, height=height, view_width=view_width)
    font = ImageFont.load_default()
    pictures = (draw_frame(frame_shapes(layout, int(k), frame=i, frames=frames),
                           width=width, height=height, font=font)
                for i, k in enumerate(frame_indices(result, frames)))
    data = encode(pictures, suffix=suffix, fps=float(fps))
    return atomic_write(path, lambda fh: fh.write(data))


def encode(pictures, *, suffix: str, fps: float) -> bytes:
    """Encode palette images (from :func:`draw_frame`) as a ``.gif`` or ``.mp4`` file's bytes.

    GIF: imageio's Pillow plugin writes the palette frames with
    :data:`PALETTE`, looping, each frame shown 1/fps s rounded to whole
    centiseconds (at least 10 ms). MP4: the frames are mapped to RGB and
    streamed to ffmpeg (libx264, yuv420p) at ``fps``; ffmpeg needs a real
    file, so it writes into a temporary directory whose file is then read
    back (the caller writes the bytes atomically).
    """
    import imageio.v3 as iio

    if suffix == ".gif":
        delay = max(10, int(round(1000.0 / fps / 10.0)) * 10)  # ms, whole centiseconds
        indices = [np.asarray(picture) for picture in pictures]
        # `optimize` must be given with an explicit palette: Pillow then keeps
        # coding unchanged pixels of a frame as transparent (31 % smaller files).
        return iio.imwrite("<bytes>", indices, extension=".gif", plugin="pillow", mode="P",
                           palette=PALETTE_BYTES, optimize=True, duration=delay, loop=0)
    if suffix not in FORMATS:
        raise SceneError(f"`suffix` must be one of {', '.join(FORMATS)}, got {suffix!r}")
    _require_ffmpeg()
    rgb = np.asarray(PALETTE, dtype=np.uint8)
    with tempfile.TemporaryDirectory(prefix="asperity2d-video-") as tmp:
        scratch = Path(tmp) / f"animation{suffix}"
        # A generator: frames stream to ffmpeg one at a time, never all in memory.
        iio.imwrite(scratch, (rgb[np.asarray(picture)] for picture in pictures),
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
