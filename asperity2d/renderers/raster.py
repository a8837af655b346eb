"""Drawing on palette images: one fixed palette, readable text, springs, dampers, arrows.

Every animation frame is a palette ("P") image drawn with ``PIL.ImageDraw``
against the one fixed :data:`PALETTE` below, so the GIF needs no per-frame
quantisation and the MP4 maps indices to RGB with one table look-up. Shapes
are drawn crisp (no antialiasing: the palette cannot blend); **text** is
antialiased all the same: each string is rasterised in grey levels (DejaVu
Sans, shipped with matplotlib, found without importing it; Pillow's own
scalable font otherwise) and its levels mapped onto a ramp of palette entries
between the text's colour and its background (:data:`TEXT_PAIRS`).
"""

from __future__ import annotations

import functools
import importlib.util
import math
import os

import numpy as np

#: Named colours (RGB). Physical bodies first, then meters, then text.
COLOURS = {
    "white": (255, 255, 255), "black": (0, 0, 0), "outline": (45, 45, 50), "grey": (120, 120, 125),
    "light": (232, 232, 236), "faint": (246, 246, 248), "panel": (250, 250, 252),
    "lower": (122, 150, 190), "touching": (46, 150, 120), "track": (120, 120, 130),
    "ground": (214, 210, 200), "hatch": (160, 150, 135), "substrate": (90, 80, 70),
    "slider_stick": (70, 80, 100), "tips_stick": (236, 170, 70),
    "slider_slip": (200, 45, 45), "tips_slip": (246, 120, 90),
    "spring": (150, 30, 30), "drive": (150, 30, 30), "arrow": (180, 30, 160),
    "stick_bg": (215, 230, 250), "stick_fg": (25, 70, 140), "slip_bg": (210, 40, 40),
    "slip_band": (255, 228, 224), "cursor": (20, 20, 20),
    "belt": (95, 95, 100), "belt_mark": (235, 235, 235), "wall": (110, 100, 90),
    "mass_stick": (70, 120, 200), "mass_fast": (215, 60, 45), "mass_slow": (240, 160, 40),
    "damper": (70, 70, 80),
    # meter traces (a colour-blind-safe set: Okabe & Ito), cycled for chains
    "c0": (0, 114, 178), "c1": (213, 94, 0), "c2": (0, 158, 115), "c3": (204, 121, 167),
    "c4": (86, 180, 233), "c5": (230, 159, 0), "c6": (120, 120, 120), "c7": (150, 60, 40),
}
TRACE_COLOURS = ("c0", "c1", "c2", "c3", "c4", "c5", "c6", "c7")
#: (text colour, background) pairs that get an antialiasing ramp.
TEXT_PAIRS = [("black", "white"), ("grey", "white"), ("black", "panel"), ("grey", "panel"),
              ("white", "slip_bg"), ("stick_fg", "stick_bg"), ("arrow", "white"),
              ("spring", "white"), ("slider_slip", "white"), ("white", "mass_stick"),
              ("white", "mass_fast"), ("white", "mass_slow")] + [(c, "panel") for c in TRACE_COLOURS]
LEVELS = 6  # palette entries per ramp (the last is the text colour itself)


def _build():
    names = list(COLOURS)
    entries = [COLOURS[n] for n in names]
    index = {n: i for i, n in enumerate(names)}
    ramps = {}
    for fg, bg in TEXT_PAIRS:
        f, b = np.array(COLOURS[fg], float), np.array(COLOURS[bg], float)
        start = len(entries)
        for level in range(1, LEVELS + 1):
            a = level / LEVELS
            entries.append(tuple(int(round(v)) for v in (1 - a) * b + a * f))
        ramps[fg, bg] = start
    if len(entries) > 256:  # pragma: no cover - a programming error, caught by the tests
        raise RuntimeError(f"palette has {len(entries)} entries")
    entries += [(0, 0, 0)] * (256 - len(entries))
    return index, ramps, entries


INDEX, RAMPS, PALETTE = _build()
PALETTE_BYTES = bytes(c for rgb in PALETTE for c in rgb)
RGB = np.array(PALETTE, dtype=np.uint8)  # index -> RGB table (MP4 frames, tests)


def new(width: int, height: int, fill: str = "white"):
    """A palette image of ``width`` x ``height`` px filled with colour ``fill``."""
    from PIL import Image

    img = Image.new("P", (int(width), int(height)), INDEX[fill])
    img.putpalette(PALETTE_BYTES)
    return img


@functools.lru_cache(maxsize=None)
def font_path(bold: bool = False) -> str | None:
    """DejaVu Sans from matplotlib's bundled fonts (found without importing matplotlib), or None."""
    spec = importlib.util.find_spec("matplotlib")
    for root in (spec.submodule_search_locations or []) if spec else []:
        path = os.path.join(root, "mpl-data", "fonts", "ttf",
                            "DejaVuSans-Bold.ttf" if bold else "DejaVuSans.ttf")
        if os.path.exists(path):
            return path
    return None


@functools.lru_cache(maxsize=None)
def font(size: int, bold: bool = False):
    """A TrueType font of ``size`` px: DejaVu Sans, else Pillow's scalable default."""
    from PIL import ImageFont

    path = font_path(bold)
    if path is not None:
        return ImageFont.truetype(path, size)
    return ImageFont.load_default(size=size)  # Pillow >= 10.1: scalable


@functools.lru_cache(maxsize=None)
def _luts(pair):
    """Grey level -> palette index on the (fg, bg) ramp, and -> binary mask (0 below half a level)."""
    start = RAMPS[pair]
    levels = np.minimum(LEVELS, (np.arange(256) * LEVELS / 255 + 0.5).astype(int))
    colour = np.where(levels > 0, start + levels - 1, 0).astype(np.uint8)
    mask = np.where(levels > 0, 255, 0).astype(np.uint8)
    return colour, mask


@functools.lru_cache(maxsize=4096)
def _glyph(char: str, size: int, bold: bool):
    """One character's grey bitmap, its offset from the pen on the baseline, and its advance (px)."""
    from PIL import Image, ImageDraw

    f = font(size, bold)
    x0, y0, x1, y1 = f.getbbox(char, anchor="ls")
    advance = f.getlength(char)
    if x1 <= x0 or y1 <= y0:
        return np.zeros((0, 0), np.uint8), 0, 0, advance
    grey = Image.new("L", (x1 - x0, y1 - y0), 0)
    ImageDraw.Draw(grey).text((-x0, -y0), char, fill=255, font=f, anchor="ls")
    return np.asarray(grey), x0, y0, advance


def text_size(text: str, size: int, bold: bool = False) -> tuple[int, int]:
    """Width and height (px) the string takes (its advance; from the font's ascent to its descent)."""
    ascent, descent = font(size, bold).getmetrics()
    return int(math.ceil(sum(_glyph(c, size, bold)[3] for c in text))), ascent + descent


def draw_text(img, xy, text: str, *, colour: str = "black", bg: str = "white", size: int = 12,
              anchor: str = "la", bold: bool = False, box: bool = False):
    """Antialiased ``text`` on palette image ``img`` at ``xy`` (px).

    ``anchor`` as in Pillow: horizontal ``l``/``m``/``r`` (left, middle,
    right of the advance), vertical ``a``/``t`` (ascender), ``m`` (middle),
    ``s`` (baseline), ``d`` (descender). Glyphs are rasterised once per
    (character, size, weight) and placed on the baseline at their advances
    (no kerning: a GIF's labels are short); their grey levels are mapped onto
    the (``colour``, ``bg``) ramp. ``box`` fills the text's rectangle with
    ``bg`` first (a label over a drawing). Returns its box (x0, y0, x1, y1).
    """
    from PIL import Image, ImageDraw

    ascent, descent = font(size, bold).getmetrics()
    glyphs = [_glyph(c, size, bold) for c in text]
    width = sum(g[3] for g in glyphs)
    h, v = anchor[0], anchor[1]
    pen_x = xy[0] - {"l": 0.0, "m": 0.5 * width, "r": width}[h]
    base_y = xy[1] + {"a": ascent, "t": ascent, "m": 0.5 * (ascent - descent), "s": 0.0,
                      "d": -descent}[v]
    left, top = int(math.floor(pen_x)), int(round(base_y - ascent))
    right, bottom = int(math.ceil(pen_x + width)), int(round(base_y + descent))
    if box:
        ImageDraw.Draw(img).rectangle((left - 2, top - 1, right + 1, bottom), fill=INDEX[bg])
    placed, x = [], pen_x
    for grey, gx, gy, advance in glyphs:
        if grey.size:
            placed.append((grey, int(round(x)) + gx, int(round(base_y)) + gy))
        x += advance
    if not placed:
        return (left, top, right, bottom)
    x0 = min(p[1] for p in placed)
    y0 = min(p[2] for p in placed)
    x1 = max(p[1] + p[0].shape[1] for p in placed)
    y1 = max(p[2] + p[0].shape[0] for p in placed)
    canvas = np.zeros((y1 - y0, x1 - x0), np.uint8)
    for grey, gx, gy in placed:
        region = canvas[gy - y0:gy - y0 + grey.shape[0], gx - x0:gx - x0 + grey.shape[1]]
        np.maximum(region, grey, out=region)
    lut, mask_lut = _luts((colour, bg))
    ink = Image.frombytes("P", (x1 - x0, y1 - y0), lut[canvas].tobytes())
    mask = Image.frombytes("L", (x1 - x0, y1 - y0), mask_lut[canvas].tobytes())
    img.paste(ink, (x0, y0), mask)
    return (min(left, x0), min(top, y0), max(right, x1), max(bottom, y1))


def zigzag(x0: float, y0: float, x1: float, y1: float, *, coils: int = 6,
           amplitude: float = 4.0, lead: float = 0.12) -> list[tuple[float, float]]:
    """A zig-zag spring from (x0, y0) to (x1, y1) (px): straight leads of ``lead`` of its
    length at both ends, ``coils`` teeth of half-width ``amplitude`` between."""
    dx, dy = x1 - x0, y1 - y0
    length = math.hypot(dx, dy)
    if length == 0:
        return [(x0, y0), (x1, y1)]
    ux, uy, nx, ny = dx / length, dy / length, -dy / length, dx / length
    a, b = lead * length, (1 - lead) * length
    pts = [(x0, y0), (x0 + ux * a, y0 + uy * a)]
    n = 2 * coils
    for i in range(n):
        s = a + (b - a) * (i + 0.5) / n
        side = amplitude if i % 2 == 0 else -amplitude
        pts.append((x0 + ux * s + nx * side, y0 + uy * s + ny * side))
    pts += [(x0 + ux * b, y0 + uy * b), (x1, y1)]
    return pts


def arrow(draw, x0: float, y0: float, x1: float, y1: float, *, fill: int, width: int = 2,
          head: float = 7.0) -> None:
    """An arrow from (x0, y0) to its tip (x1, y1) (px) with a filled head; nothing if shorter than 1 px."""
    dx, dy = x1 - x0, y1 - y0
    length = math.hypot(dx, dy)
    if length < 1:
        return
    ux, uy = dx / length, dy / length
    head = min(head, 0.6 * length + 2)
    bx, by = x1 - ux * head, y1 - uy * head
    draw.line([(x0, y0), (bx, by)], fill=fill, width=width)
    half = 0.45 * head
    draw.polygon([(x1, y1), (bx - uy * half, by + ux * half), (bx + uy * half, by - ux * half)],
                 fill=fill)


def dashpot(draw, x0: float, x1: float, y: float, *, half: float, fill: int, width: int = 1) -> None:
    """A damper (piston in a cylinder) from x0 to x1 at height y (px), cylinder ``half`` px tall."""
    if x1 < x0:
        x0, x1 = x1, x0
    mid = 0.5 * (x0 + x1)
    span = x1 - x0
    cyl0, cyl1 = mid - 0.18 * span, mid + 0.12 * span
    draw.line([(x0, y), (mid, y)], fill=fill, width=width)  # rod to the piston
    draw.line([(mid, y - 0.7 * half), (mid, y + 0.7 * half)], fill=fill, width=2)  # piston
    draw.line([(cyl0, y - half), (cyl1, y - half)], fill=fill, width=width)
    draw.line([(cyl0, y + half), (cyl1, y + half)], fill=fill, width=width)
    draw.line([(cyl1, y - half), (cyl1, y + half)], fill=fill, width=width)
    draw.line([(cyl1, y), (x1, y)], fill=fill, width=width)


def nice_length(target: float) -> float:
    """The 1-2-5 x 10^n number nearest below ``target`` (> 0)."""
    if not target > 0 or not math.isfinite(target):
        return 1.0
    e = math.floor(math.log10(target))
    for m in (5.0, 2.0, 1.0):
        if m * 10.0**e <= target:
            return m * 10.0**e
    return 10.0**e  # pragma: no cover


def scale_bar(img, x: float, y: float, *, px_per_unit: float, unit: str, target_px: float = 90,
              label_extra: str = "") -> tuple[int, int, int, int]:
    """A scale bar whose left end is at (x, y) (px), of a 1-2-5 length near ``target_px``, labelled
    in engineering units of ``unit`` (``label_extra`` appended, e.g. "vertical ×5"). Returns its box."""
    from PIL import ImageDraw

    from .._format import si

    length = nice_length(target_px / px_per_unit)
    px = length * px_per_unit
    d = ImageDraw.Draw(img)
    ink = INDEX["black"]
    d.rectangle((x, y - 2, x + px, y + 2), fill=ink)
    d.line([(x, y - 5), (x, y + 5)], fill=ink)
    d.line([(x + px, y - 5), (x + px, y + 5)], fill=ink)
    label = si(length, unit, digits=1 if length / 10 ** math.floor(math.log10(length)) in (1, 2, 5) else 2)
    box = draw_text(img, (x + px + 6, y), label + label_extra, size=11, anchor="lm")
    return (int(x), int(y - 5), box[2], int(y + 5))


def font_note() -> str:
    """Which font the frames use (for reports and tests)."""
    return os.path.basename(font_path() or "Pillow default")


__all__ = ["COLOURS", "INDEX", "PALETTE", "PALETTE_BYTES", "RGB", "TRACE_COLOURS", "arrow",
           "dashpot", "draw_text", "font", "new", "nice_length", "scale_bar", "text_size", "zigzag"]
