"""Animated GIF, drawing and encoding: Pillow + imageio against a well-built matplotlib loop.

Both sides draw the very same pixel-space shapes
(:func:`asperity2d.renderers.animate.frame_shapes` of one real run), the same
number of frames at the same size, and both encode a GIF with the same
imageio writer (its Pillow plugin):

* **Pillow** (what ``render(result, "run.gif")`` does): ``ImageDraw`` on
  palette images (:func:`~asperity2d.renderers.animate.draw_frame`), then
  :func:`~asperity2d.renderers.animate.encode` (palette frames as drawn).
* **matplotlib**, done as a user who cares about speed would: the figure and
  its artists are built once (a ``PolyCollection`` per surface, a
  ``LineCollection`` for the tracks, rectangles, a line and texts, with
  Pillow's line widths and without antialiasing, so the frames have the same
  few colours as Pillow's); each
  frame only updates the artists' data and is blitted (background restored,
  animated artists drawn, RGBA buffer read). A plain ``canvas.draw()`` per
  frame is timed too and the faster of the two is the baseline. The RGB
  frames go to ``imageio.v3.imwrite(..., ".gif")``, which lets Pillow
  quantise them: what a matplotlib user's GIF costs.

For reference the Pillow frames are also saved by Pillow's own GIF writer
(what ``render`` did before imageio), to show what the imageio layer costs.

CPU time (``time.process_time``), the sides interleaved in each repeat,
medians over the repeats. Target: Pillow + imageio >= 20x faster in total.
``main`` prints the table and writes it into ``benchmarks/results.json``
under ``gif`` (other keys kept).

Run: ``python benchmarks/bench_gif.py [--quick] [--no-save]``.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

import asperity2d as a  # noqa: E402
from asperity2d._io import atomic_write_text  # noqa: E402
from asperity2d.renderers import animate  # noqa: E402

FPS = 20.0
TARGET = 20.0
PX = 72.0 / 100.0  # points per pixel at the figure's 100 dpi: Pillow's 1-px lines are 0.72 pt


def _rgb(index):
    return tuple(c / 255.0 for c in animate.PALETTE[index])


class MatplotlibFrames:
    """Draw :func:`frame_shapes` output on one Agg figure built once; artists updated per frame."""

    def __init__(self, width: int, height: int, *, ground, blit: bool):
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.collections import LineCollection, PolyCollection
        from matplotlib.figure import Figure
        from matplotlib.lines import Line2D
        from matplotlib.patches import Rectangle

        self.width, self.height, self.blit = width, height, blit
        self.fig = Figure(figsize=(width / 100.0, height / 100.0), dpi=100)
        self.fig.patch.set_facecolor(_rgb(animate.BACKGROUND))
        self.canvas = FigureCanvasAgg(self.fig)
        ax = self.ax = self.fig.add_axes((0, 0, 1, 1))
        ax.set_axis_off()
        ax.set_xlim(0, width)
        ax.set_ylim(height, 0)
        x0, y0, x1, y1 = ground  # static: the layout keeps one scale and floor
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, color=_rgb(animate.GROUND),
                               antialiased=False))
        outline = _rgb(animate.OUTLINE)
        self.tracks = LineCollection([], colors=[outline], linewidths=PX, antialiased=False)
        self.lower = PolyCollection([], facecolors=[_rgb(animate.LOWER)], edgecolors=[outline],
                                    linewidths=PX, antialiased=False)
        self.upper = PolyCollection([], facecolors=[_rgb(animate.UPPER)], edgecolors=[outline],
                                    linewidths=PX, antialiased=False)
        self.bar = Rectangle((0, 0), 1, 1, facecolor=_rgb(animate.BAR), edgecolor=outline,
                             lw=PX, antialiased=False)
        self.spring = Line2D([], [], color=_rgb(animate.SPRING), lw=2 * PX, antialiased=False)
        self.drive = Rectangle((0, 0), 1, 1, facecolor=_rgb(animate.SPRING), edgecolor=outline,
                               lw=PX, antialiased=False)
        self.band = Rectangle((0, 0), width, animate.TEXT_HEIGHT,
                              color=_rgb(animate.BACKGROUND), antialiased=False)
        self.text = ax.text(4, 3, "", va="top", fontsize=7, antialiased=False)
        self.counter = ax.text(width - 4, 3, "", va="top", ha="right", fontsize=7,
                               antialiased=False)
        for artist in (self.tracks, self.lower, self.upper):
            ax.add_collection(artist)
        for artist in (self.bar, self.drive, self.band):
            ax.add_patch(artist)
        ax.add_line(self.spring)
        self.animated = (self.tracks, self.lower, self.upper, self.bar, self.spring, self.drive,
                         self.band, self.text, self.counter)
        self.background = None
        if blit:
            for artist in self.animated:
                artist.set_animated(True)
            self.canvas.draw()
            self.background = self.canvas.copy_from_bbox(self.fig.bbox)

    def draw(self, shapes: dict) -> np.ndarray:
        """RGB frame (height x width x 3, uint8) of ``shapes``."""
        self.tracks.set_segments(shapes["tracks"])
        self.lower.set_verts(shapes["lower"])
        self.upper.set_verts(shapes["upper"])
        x0, y0, x1, y1 = animate._ordered(shapes["bar"])
        self.bar.set_bounds(x0, y0, x1 - x0, y1 - y0)
        has_spring = bool(shapes["spring"])
        self.spring.set_visible(has_spring)
        self.drive.set_visible(has_spring)
        if has_spring:
            self.spring.set_data(*zip(*shapes["spring"]))
            x0, y0, x1, y1 = animate._ordered(shapes["drive"])
            self.drive.set_bounds(x0, y0, x1 - x0, y1 - y0)
        self.text.set_text(shapes["text"])
        self.counter.set_text(shapes["counter"])
        if self.blit:
            self.canvas.restore_region(self.background)
            for artist in self.animated:
                self.ax.draw_artist(artist)
        else:
            self.canvas.draw()
        return np.asarray(self.canvas.buffer_rgba())[..., :3].copy()


def _pillow(shapes, width, height, font):
    t0 = time.process_time()
    pictures = [animate.draw_frame(s, width=width, height=height, font=font) for s in shapes]
    t1 = time.process_time()
    data = animate.encode(pictures, suffix=".gif", fps=FPS)
    return t1 - t0, time.process_time() - t1, len(data)


def _pillow_direct(shapes, width, height, font):
    """The same frames saved by Pillow's own GIF writer (what ``render`` did before imageio)."""
    import io

    pictures = [animate.draw_frame(s, width=width, height=height, font=font) for s in shapes]
    t0 = time.process_time()
    buffer = io.BytesIO()
    pictures[0].save(buffer, format="GIF", save_all=True, append_images=pictures[1:],
                     duration=int(round(1000 / FPS)), loop=0)
    return 0.0, time.process_time() - t0, len(buffer.getvalue())


def _matplotlib(shapes, drawer):
    import imageio.v3 as iio

    t0 = time.process_time()
    frames = [drawer.draw(s) for s in shapes]
    t1 = time.process_time()
    data = iio.imwrite("<bytes>", frames, extension=".gif", plugin="pillow",
                       duration=int(round(1000 / FPS)), loop=0)
    return t1 - t0, time.process_time() - t1, len(data)


def run(quick: bool = False) -> dict:
    """Time both sides; medians of the per-frame draw, encode and total CPU times and ratios."""
    from PIL import ImageFont

    if quick:
        scene, frames, repeats = a.make_scene(lower_count=6, upper_count=2), 20, 3
    else:
        scene, frames, repeats = a.make_scene(lower_count=10, upper_count=4), 60, 5
    width, height = 640, 320
    result = a.simulate(scene)
    layout = animate.Layout(result, width=width, height=height)
    shapes = [animate.frame_shapes(layout, int(k), frame=i, frames=frames)
              for i, k in enumerate(animate.frame_indices(result, frames))]
    font = ImageFont.load_default()
    drawers = {"blit": MatplotlibFrames(width, height, ground=shapes[0]["ground"], blit=True),
               "draw": MatplotlibFrames(width, height, ground=shapes[0]["ground"], blit=False)}
    _pillow(shapes[:2], width, height, font)  # warm up every path (fonts, imageio plugins)
    for drawer in drawers.values():
        _matplotlib(shapes[:2], drawer)
    times = {name: {"draw": [], "encode": []} for name in ("pillow", "blit", "draw", "direct")}
    sizes = {}
    for _ in range(repeats):  # interleaved
        for name in times:
            if name == "pillow":
                draw, encode, size = _pillow(shapes, width, height, font)
            elif name == "direct":
                draw, encode, size = _pillow_direct(shapes, width, height, font)
            else:
                draw, encode, size = _matplotlib(shapes, drawers[name])
            times[name]["draw"].append(draw / frames)
            times[name]["encode"].append(encode / frames)
            sizes[name] = size
    med = {name: {part: statistics.median(v) for part, v in parts.items()}
           for name, parts in times.items()}
    for name in med:
        med[name]["total"] = statistics.median(
            np.add(times[name]["draw"], times[name]["encode"]) )
    best = min(("blit", "draw"), key=lambda n: med[n]["total"])
    pil, mpl = med["pillow"], med[best]
    return {"width": width, "height": height, "frames": frames, "repeats": repeats,
            "timer": "process_time", "matplotlib_method": best,
            "pillow_s_per_frame": pil["total"], "matplotlib_s_per_frame": mpl["total"],
            "pillow_draw_s_per_frame": pil["draw"], "pillow_encode_s_per_frame": pil["encode"],
            "matplotlib_draw_s_per_frame": mpl["draw"],
            "matplotlib_encode_s_per_frame": mpl["encode"],
            "matplotlib_full_draw_s_per_frame": med["draw"]["total"],
            "matplotlib_blit_s_per_frame": med["blit"]["total"],
            "pillow_direct_encode_s_per_frame": med["direct"]["encode"],
            "pillow_fps": 1.0 / pil["total"], "matplotlib_fps": 1.0 / mpl["total"],
            "speedup": mpl["total"] / pil["total"], "draw_speedup": mpl["draw"] / pil["draw"],
            "gif_bytes": {"pillow": sizes["pillow"], "matplotlib": sizes[best],
                          "pillow_direct": sizes["direct"]}}


def headline(res: dict):
    return [("GIF draw + encode: Pillow/imageio speed-up over matplotlib (blit or draw)",
             res["speedup"], f">= {TARGET:g}"),
            ("GIF drawing alone: speed-up", res["draw_speedup"], "stated"),
            ("GIF frames per second, drawn and encoded (Pillow)", res["pillow_fps"], "")]


def save(res: dict, path: Path = HERE / "results.json") -> Path:
    """Put ``res`` under ``results.gif`` (and its headline rows) in ``path``, keeping the rest."""
    data = json.loads(path.read_text()) if path.exists() else {"results": {}, "headline": []}
    data.setdefault("results", {})["gif"] = res
    rows = [r for r in data.get("headline", []) if r.get("benchmark") != "gif"]
    rows += [{"benchmark": "gif", "figure": f, "value": v, "target": t} for f, v, t in headline(res)]
    data["headline"] = rows
    return atomic_write_text(path, json.dumps(data, indent=2, default=float) + "\n")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer frames and repeats")
    parser.add_argument("--no-save", action="store_true", help="do not update results.json")
    args = parser.parse_args(argv)
    out = run(quick=args.quick)
    print(f"GIF of {out['frames']} frames, {out['width']}x{out['height']} px, drawn and encoded; "
          f"CPU time, median of {out['repeats']} interleaved repeats (ms per frame)")
    print(f"{'side':<28}{'draw':>8}{'encode':>8}{'total':>8}{'KB':>8}")
    rows = (("Pillow + imageio", "pillow", out["gif_bytes"]["pillow"]),
            (f"matplotlib ({out['matplotlib_method']}) + imageio", "matplotlib",
             out["gif_bytes"]["matplotlib"]))
    for label, key, size in rows:
        print(f"{label:<28}{1e3 * out[key + '_draw_s_per_frame']:>8.2f}"
              f"{1e3 * out[key + '_encode_s_per_frame']:>8.2f}"
              f"{1e3 * out[key + '_s_per_frame']:>8.2f}{size / 1e3:>8.0f}")
    print(f"matplotlib totals: blit {1e3 * out['matplotlib_blit_s_per_frame']:.2f}, "
          f"full canvas.draw {1e3 * out['matplotlib_full_draw_s_per_frame']:.2f} ms per frame")
    print(f"the Pillow frames saved by Pillow's own GIF writer instead of imageio: encode "
          f"{1e3 * out['pillow_direct_encode_s_per_frame']:.2f} ms per frame, "
          f"{out['gif_bytes']['pillow_direct'] / 1e3:.0f} KB")
    for label, value, target in headline(out):
        print(f"{label}: {value:.1f}" + (f" (target {target})" if target else ""))
    if not args.no_save and not args.quick:
        print(f"wrote {save(out)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
