"""GIF frame drawing: Pillow ImageDraw against matplotlib, same frames, same size.

Both back ends draw the very same pixel-space shapes
(:func:`asperity2d.render.gif.frame_shapes` of one real run) into an image of
the same size: Pillow with ``ImageDraw`` on a palette image
(:func:`asperity2d.render.gif.draw_frame`), matplotlib by redrawing one Agg
figure per frame (patches, lines, text, ``canvas.draw()``, RGBA buffer). The
two are timed side by side in each repeat; the table gives medians over the
repeats. Target: Pillow at least 20x faster.

Run: ``python benchmarks/bench_gif.py [--quick]``.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import asperity2d as a
from asperity2d.render.gif import PALETTE, Layout, draw_frame, frame_indices, frame_shapes


def _rgb(index):
    return tuple(c / 255.0 for c in PALETTE[index])


class MatplotlibFrames:
    """Draw :func:`frame_shapes` output with matplotlib on one reused Agg figure."""

    def __init__(self, width: int, height: int):
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        self.width, self.height = width, height
        self.fig = Figure(figsize=(width / 100.0, height / 100.0), dpi=100)
        self.canvas = FigureCanvasAgg(self.fig)
        self.ax = self.fig.add_axes((0, 0, 1, 1))

    def draw(self, shapes: dict) -> np.ndarray:
        from matplotlib.patches import Polygon, Rectangle

        from asperity2d.render import gif

        ax = self.ax
        ax.cla()
        ax.set_axis_off()
        ax.set_xlim(0, self.width)
        ax.set_ylim(self.height, 0)
        x0, y0, x1, y1 = shapes["ground"]
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, color=_rgb(gif.GROUND)))
        for pts in shapes["tracks"]:
            ax.plot(*zip(*pts), color=_rgb(gif.OUTLINE), lw=0.7)
        for key, color in (("lower", gif.LOWER), ("upper", gif.UPPER)):
            for pts in shapes[key]:
                ax.add_patch(Polygon(pts, closed=True, facecolor=_rgb(color),
                                     edgecolor=_rgb(gif.OUTLINE), lw=0.7))
        x0, y0, x1, y1 = gif._ordered(shapes["bar"])
        ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, facecolor=_rgb(gif.BAR),
                               edgecolor=_rgb(gif.OUTLINE)))
        if shapes["spring"]:
            ax.plot(*zip(*shapes["spring"]), color=_rgb(gif.SPRING), lw=1.5)
            x0, y0, x1, y1 = gif._ordered(shapes["drive"])
            ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, color=_rgb(gif.SPRING)))
        ax.text(4, 3, shapes["text"], va="top", fontsize=7)
        ax.text(self.width - 4, 3, shapes["counter"], va="top", ha="right", fontsize=7)
        self.canvas.draw()
        return np.asarray(self.canvas.buffer_rgba()).copy()


def run(quick: bool = False) -> dict:
    """Time both back ends; return medians (s per frame, frames per second) and the speed-up."""
    from PIL import ImageFont

    if quick:
        scene, frames, repeats = a.make_scene(lower_count=6, upper_count=2), 20, 3
    else:
        scene, frames, repeats = a.make_scene(lower_count=10, upper_count=4), 60, 5
    width, height = 640, 320
    result = a.simulate(scene)
    layout = Layout(result, width=width, height=height)
    shapes = [frame_shapes(layout, int(k), frame=i, frames=frames)
              for i, k in enumerate(frame_indices(result, frames))]
    font = ImageFont.load_default()
    mpl = MatplotlibFrames(width, height)
    draw_frame(shapes[0], width=width, height=height, font=font)  # warm up both
    mpl.draw(shapes[0])
    pillow_times, mpl_times = [], []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for s in shapes:
            draw_frame(s, width=width, height=height, font=font).tobytes()
        pillow_times.append((time.perf_counter() - t0) / frames)
        t0 = time.perf_counter()
        for s in shapes:
            mpl.draw(s)
        mpl_times.append((time.perf_counter() - t0) / frames)
    pil, plt_ = statistics.median(pillow_times), statistics.median(mpl_times)
    return {"width": width, "height": height, "frames": frames, "repeats": repeats,
            "pillow_s_per_frame": pil, "matplotlib_s_per_frame": plt_,
            "pillow_fps": 1.0 / pil, "matplotlib_fps": 1.0 / plt_, "speedup": plt_ / pil}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer frames and repeats")
    out = run(quick=parser.parse_args(argv).quick)
    print(f"GIF frame drawing, {out['width']}x{out['height']} px, {out['frames']} frames, "
          f"median of {out['repeats']} repeats")
    print(f"{'back end':<12}{'ms/frame':>10}{'frames/s':>10}")
    for name in ("pillow", "matplotlib"):
        print(f"{name:<12}{1e3 * out[name + '_s_per_frame']:>10.3f}{out[name + '_fps']:>10.1f}")
    print(f"speed-up: {out['speedup']:.1f}x (target >= 20x)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
