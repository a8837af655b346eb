"""Animated GIF with meters, drawn and encoded: asperity2d's renderer against matplotlib done well.

Both sides draw the same picture of one real run -- the scene above four
meters (drive force; contact force, friction and tangential; slider and
drive-end position; slider velocity) whose traces grow up to a cursor at
"now", with the time, the STICK/SLIP badge and the "×N slow" mark -- at the
same frames (the renderer's own event-aware schedule), the same size, and
both encode a GIF:

* **asperity2d** (what ``render(result, "run.gif")`` does):
  :class:`asperity2d.renderers.animate.Movie` draws palette images against
  one fixed palette (static parts once, the traces growing on a persistent
  layer), :func:`~asperity2d.renderers.animate.encode` hands them to
  Pillow's GIF writer (no quantisation).
* **matplotlib**, written as a speed-minded user would write a
  ``FuncAnimation`` with blitting: one Agg figure built once, the scene in
  pixel coordinates (the very same shapes, from
  :meth:`~asperity2d.renderers.stage.Stage.shapes`, as a ``PolyCollection``
  per surface, ``LineCollection`` for tracks, hatching and arrow shafts,
  rectangles, a line and texts), four axes with the meters' limits, ticks and
  titles; everything static drawn once and cached, and each frame restores
  that background, updates the animated artists' data (growing ``Line2D``
  traces, the revealed slip bands, the cursor, the value dots and read-outs,
  the header texts) and draws only them (``draw_artist``), then reads the RGBA
  buffer. Antialiasing is off, as on the palette frames. The RGB frames go to
  Pillow's GIF writer, which quantises each one (what a matplotlib GIF
  costs; ``FuncAnimation.save`` with ``PillowWriter`` does the same, but
  without blitting: it is also timed once, for reference).

CPU time (``time.process_time``), the two sides interleaved in each repeat,
medians over the repeats. Target: asperity2d >= 10x faster in total.
``main`` prints the table and writes it into ``benchmarks/results.json``
under ``gif`` (other keys kept).

Run: ``python benchmarks/bench_gif.py [--quick] [--no-save]``.
"""

from __future__ import annotations

import argparse
import io
import json
import statistics
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

import asperity2d as a  # noqa: E402
from asperity2d._format import si  # noqa: E402
from asperity2d._io import atomic_write_text  # noqa: E402
from asperity2d.renderers import animate, raster  # noqa: E402
from asperity2d.renderers.meters import ticks  # noqa: E402

FPS = 20.0
TARGET = 10.0
PX = 72.0 / 100.0  # points per pixel at the figure's 100 dpi


def _rgb(name):
    return tuple(c / 255.0 for c in raster.COLOURS[name])


class MatplotlibMovie:
    """The frames of :class:`animate.Movie`'s picture drawn by matplotlib with blitting."""

    def __init__(self, movie: animate.Movie):
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.collections import LineCollection, PolyCollection
        from matplotlib.figure import Figure
        from matplotlib.lines import Line2D
        from matplotlib.patches import Rectangle

        self.movie = movie
        W, H = movie.width, movie.height
        self.fig = Figure(figsize=(W / 100.0, H / 100.0), dpi=100)
        self.fig.patch.set_facecolor(_rgb("light"))
        self.canvas = FigureCanvasAgg(self.fig)
        stage = movie.stage
        sh = movie.scene_height
        ax = self.scene = self.fig.add_axes((0, 1 - sh / H, 1, sh / H))
        ax.set_axis_off()
        ax.set_xlim(0, W)
        ax.set_ylim(sh, 0)
        ax.add_patch(Rectangle((0, 0), W, sh, color=_rgb("white"), antialiased=False))
        first = stage.shapes(int(movie.schedule.index[0]))
        g = first["ground"][1]
        from asperity2d.renderers.stage import FOOTER
        ax.add_patch(Rectangle((0, g), W, sh - FOOTER - g, color=_rgb("ground"), antialiased=False))
        # static footer: scale bar and the arrow key, as the palette frames have them
        length = raster.nice_length(80.0 / stage.scale)
        ax.add_patch(Rectangle((10, sh - FOOTER / 2 - 2), length * stage.scale, 4, color="k", antialiased=False))
        ax.text(16 + length * stage.scale, sh - FOOTER / 2, si(length, "m", 1), va="center", fontsize=8)
        ax.text(W - 60, sh - FOOTER / 2, "contact force on the slider", va="center", ha="right", fontsize=8,
                color=_rgb("arrow"))
        ax.text(8, 24, stage.caption(), va="top", fontsize=8, color=_rgb("grey"))
        outline = _rgb("outline")
        kw = {"antialiased": False}
        self.hatch = LineCollection([], colors=[_rgb("hatch")], linewidths=PX, **kw)
        self.tracks = LineCollection([], colors=[_rgb("track")], linewidths=PX, **kw)
        self.lower = PolyCollection([], edgecolors=[outline], linewidths=PX, **kw)
        self.upper = PolyCollection([], edgecolors=[outline], linewidths=PX, **kw)
        self.arrows = LineCollection([], colors=[_rgb("arrow")], linewidths=2 * PX, **kw)
        self.heads = PolyCollection([], facecolors=[_rgb("arrow")], linewidths=0, **kw)
        self.bar = Rectangle((0, 0), 1, 1, edgecolor=outline, lw=PX, **kw)
        self.spring = Line2D([], [], color=_rgb("spring"), lw=2 * PX, **kw)
        self.drive = Rectangle((0, 0), 1, 1, facecolor=_rgb("drive"), edgecolor=outline, lw=PX, **kw)
        self.header = Rectangle((0, 0), W, 23, color=_rgb("white"), **kw)
        self.time = ax.text(8, 4, "", va="top", fontsize=10, fontweight="bold")
        self.badge = ax.text(150, 12, "", va="center", fontsize=9, fontweight="bold",
                             bbox={"boxstyle": "square,pad=0.2", "lw": 0})
        self.slow = ax.text(230, 5, "", va="top", fontsize=9, fontweight="bold", color=_rgb("spring"))
        self.counter = ax.text(W - 8, 5, "", va="top", ha="right", fontsize=8, color=_rgb("grey"))
        for artist in (self.hatch, self.tracks, self.lower, self.upper, self.arrows, self.heads):
            ax.add_collection(artist)
        for artist in (self.bar, self.drive, self.header):
            ax.add_patch(artist)
        ax.add_line(self.spring)
        self.animated = [self.hatch, self.tracks, self.lower, self.upper, self.bar, self.spring, self.drive,
                         self.arrows, self.heads, self.header, self.time, self.badge, self.slow, self.counter]
        # meters: axes on the palette frames' plot rectangles, same limits, ticks and titles
        t = np.asarray(movie.result.t, dtype=float)
        self.t = t
        self.meters = []
        for panel in movie.meters:
            px0, py0, px1, py1 = panel.plot
            m = self.fig.add_axes((px0 / W, 1 - py1 / H, (px1 - px0) / W, (py1 - py0) / H))
            m.set_xlim(panel.t0, panel.t1)
            m.set_ylim(panel.lo, panel.hi)
            values, labels = panel.value_ticks()
            m.set_yticks(values, labels, fontsize=7)
            tv, tl = ticks(panel.t0, panel.t1, factor=panel.tfactor)
            m.set_xticks(tv, tl, fontsize=7)
            m.grid(True, color=_rgb("light"), lw=PX)
            x0, y0 = panel.box[:2]
            self.fig.text(x0 / W + 0.008, 1 - (y0 + 3) / H, f"{panel.meter.title} ({panel.unit_label})",
                          va="top", fontsize=8, fontweight="bold")
            lines, dots, texts = [], [], []
            for k, tr in enumerate(panel.meter.traces):
                line, = m.plot([], [], color=_rgb(tr.colour), lw=PX, ls="--" if tr.dashed else "-",
                               antialiased=False)
                dot, = m.plot([], [], "o", ms=5, color=_rgb(tr.colour), mec="k", mew=PX)
                text = self.fig.text((x0 + 200 + 110 * k) / W, 1 - (y0 + 4) / H, "", va="top", fontsize=8,
                                     color=_rgb(tr.colour))
                lines.append(line), dots.append(dot), texts.append(text)
            cursor = m.axvline(panel.t0, color="k", lw=PX, antialiased=False)
            bands = PolyCollection([], facecolors=[_rgb("slip_band")], linewidths=0, antialiased=False)
            m.add_collection(bands)
            self.meters.append((panel, lines, dots, texts, cursor, bands))
            self.animated += [bands, *lines, cursor, *dots, *texts]
        self.slips = animate.slip_intervals(movie.result)
        for artist in self.animated:
            artist.set_animated(True)
        self.canvas.draw()
        self.background = self.canvas.copy_from_bbox(self.fig.bbox)

    def frame(self, j: int) -> np.ndarray:
        """RGB frame ``j`` (height x width x 3, uint8)."""
        movie, stage = self.movie, self.movie.stage
        k = int(movie.schedule.index[j])
        s = stage.shapes(k, slow=float(movie.schedule.slow[j]), counter=f"frame {j + 1}/{len(movie)}")
        self.hatch.set_segments(s["hatch"])
        self.tracks.set_segments(s["tracks"])
        self.lower.set_verts([p for p, _ in s["lower"]])
        self.lower.set_facecolors([_rgb(c) for _, c in s["lower"]])
        self.upper.set_verts(s["upper"])
        self.upper.set_facecolor(_rgb(s["upper_colour"]))
        x0, y0, x1, y1 = s["bar"]
        self.bar.set_bounds(x0, y0, x1 - x0, y1 - y0)
        self.bar.set_facecolor(_rgb(s["bar_colour"]))
        if s["drive"] is not None:
            self.spring.set_data(*zip(*s["spring"]))
            x0, y0, x1, y1 = s["drive"]
            self.drive.set_bounds(x0, y0, x1 - x0, y1 - y0)
        shafts, heads = [], []
        for ax0, ay0, ax1, ay1 in s["arrows"]:
            length = np.hypot(ax1 - ax0, ay1 - ay0)
            if length < 1:
                continue
            ux, uy = (ax1 - ax0) / length, (ay1 - ay0) / length
            head = min(7.0, 0.6 * length + 2)
            bx, by = ax1 - ux * head, ay1 - uy * head
            shafts.append([(ax0, ay0), (bx, by)])
            heads.append([(ax1, ay1), (bx - uy * 0.45 * head, by + ux * 0.45 * head),
                          (bx + uy * 0.45 * head, by - ux * 0.45 * head)])
        self.arrows.set_segments(shafts)
        self.heads.set_verts(heads)
        self.time.set_text(s["time"])
        self.badge.set_text(s["state"])
        slip = s["state"] == "SLIP"
        self.badge.set_color(_rgb("white" if slip else "stick_fg"))
        self.badge.get_bbox_patch().set_facecolor(_rgb("slip_bg" if slip else "stick_bg"))
        self.slow.set_text(s["slow"])
        self.counter.set_text(s["counter"])
        now = self.t[k]
        for panel, lines, dots, texts, cursor, bands in self.meters:
            for line, dot, text, tr in zip(lines, dots, texts, panel.meter.traces):
                line.set_data(self.t[:k + 1], tr.values[:k + 1])
                value = float(tr.values[k])
                dot.set_data([now], [min(max(value, panel.lo), panel.hi)])
                text.set_text(f"{tr.label} {si(value, panel.meter.unit)}")
            cursor.set_xdata([now, now])
            bands.set_verts([[(a_, panel.lo), (min(b_, now), panel.lo), (min(b_, now), panel.hi),
                              (a_, panel.hi)] for a_, b_ in self.slips if a_ < now])
        self.canvas.restore_region(self.background)
        for artist in self.animated:
            artist.axes.draw_artist(artist) if artist.axes else self.fig.draw_artist(artist)
        self.canvas.blit(self.fig.bbox)
        return np.asarray(self.canvas.buffer_rgba())[..., :3].copy()


def _gif_of_rgb(frames) -> bytes:
    """What a matplotlib user's GIF costs: RGB frames to Pillow's writer, which quantises each."""
    from PIL import Image

    pictures = [Image.fromarray(f) for f in frames]
    buffer = io.BytesIO()
    pictures[0].save(buffer, format="GIF", save_all=True, append_images=pictures[1:],
                     duration=int(round(1000 / FPS)), loop=0)
    return buffer.getvalue()


def _ours(result, frames, size):
    t0 = time.process_time()
    movie = animate.Movie(result, frames=frames, width=size[0], height=size[1])
    pictures = list(movie.frames())
    t1 = time.process_time()
    data = animate.encode(pictures, suffix=".gif", fps=FPS)
    return t1 - t0, time.process_time() - t1, len(data)


def _matplotlib(result, frames, size):
    t0 = time.process_time()
    mpl = MatplotlibMovie(animate.Movie(result, frames=frames, width=size[0], height=size[1]))
    pictures = [mpl.frame(j) for j in range(frames)]
    t1 = time.process_time()
    data = _gif_of_rgb(pictures)
    return t1 - t0, time.process_time() - t1, len(data), pictures


def _funcanimation_save(result, frames, size) -> float:
    """CPU s per frame of ``FuncAnimation(..., blit=True).save(..., PillowWriter)`` of the same picture."""
    import tempfile

    from matplotlib.animation import FuncAnimation, PillowWriter

    mpl = MatplotlibMovie(animate.Movie(result, frames=frames, width=size[0], height=size[1]))
    for artist in mpl.animated:
        artist.set_animated(False)

    def update(j):
        mpl.frame(j)
        return mpl.animated

    anim = FuncAnimation(mpl.fig, update, frames=frames, blit=True, repeat=False)
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.process_time()
        anim.save(Path(tmp) / "anim.gif", writer=PillowWriter(fps=FPS))
        return (time.process_time() - t0) / frames


def run(quick: bool = False) -> dict:
    """Time both sides; medians of the per-frame draw, encode and total CPU times and the ratio."""
    if quick:
        scene, frames, repeats = a.make_scene(lower_count=6, upper_count=2), 20, 3
    else:
        scene, frames, repeats = a.make_scene(lower_count=10, upper_count=4), 60, 5
    size = (720, 480)
    result = a.simulate(scene)
    _ours(result, 3, size)  # warm up both (fonts, glyph caches, matplotlib's text cache)
    _matplotlib(result, 3, size)
    times = {name: {"draw": [], "encode": []} for name in ("ours", "matplotlib")}
    sizes = {}
    for _ in range(repeats):  # interleaved
        draw, encode, sizes["ours"] = _ours(result, frames, size)
        times["ours"]["draw"].append(draw / frames)
        times["ours"]["encode"].append(encode / frames)
        draw, encode, sizes["matplotlib"], last = _matplotlib(result, frames, size)
        times["matplotlib"]["draw"].append(draw / frames)
        times["matplotlib"]["encode"].append(encode / frames)
    med = {name: {part: statistics.median(v) for part, v in parts.items()} for name, parts in times.items()}
    for name in med:
        med[name]["total"] = statistics.median(np.add(times[name]["draw"], times[name]["encode"]))
    ours, mpl = med["ours"], med["matplotlib"]
    import datetime
    import os

    out = {"width": size[0], "height": size[1], "frames": frames, "repeats": repeats,
           "date": datetime.date.today().isoformat(), "load_average_after": list(os.getloadavg()),
           "timer": "process_time", "scene": f"make_scene(lower_count={scene.lower.count}, "
                                               f"upper_count={scene.slider.count})",
           "ours_s_per_frame": ours["total"], "matplotlib_s_per_frame": mpl["total"],
           "ours_draw_s_per_frame": ours["draw"], "ours_encode_s_per_frame": ours["encode"],
           "matplotlib_draw_s_per_frame": mpl["draw"], "matplotlib_encode_s_per_frame": mpl["encode"],
           "ours_fps": 1.0 / ours["total"], "matplotlib_fps": 1.0 / mpl["total"],
           "speedup": mpl["total"] / ours["total"], "draw_speedup": mpl["draw"] / ours["draw"],
           "gif_bytes": dict(sizes)}
    if not quick:
        out["funcanimation_save_s_per_frame"] = _funcanimation_save(result, frames, size)
    out["_last_matplotlib_frame"] = last[len(last) // 2]
    return out


def headline(res: dict):
    return [("GIF with meters, draw + encode: asperity2d / matplotlib (blitting) speed-up", res["speedup"],
             f">= {TARGET:g}"),
            ("GIF with meters, drawing alone: speed-up", res["draw_speedup"], "stated"),
            ("GIF frames per second, drawn and encoded (asperity2d)", res["ours_fps"], "")]


def save(res: dict, path: Path = HERE / "results.json") -> Path:
    """Put ``res`` under ``results.gif`` (and its headline rows) in ``path``, keeping the rest."""
    data = json.loads(path.read_text()) if path.exists() else {"results": {}, "headline": []}
    data.setdefault("results", {})["gif"] = {k: v for k, v in res.items() if not k.startswith("_")}
    rows = [r for r in data.get("headline", []) if r.get("benchmark") != "gif"]
    rows += [{"benchmark": "gif", "figure": f, "value": v, "target": t} for f, v, t in headline(res)]
    data["headline"] = rows
    return atomic_write_text(path, json.dumps(data, indent=2, default=float) + "\n")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer frames and repeats")
    parser.add_argument("--no-save", action="store_true", help="do not update results.json")
    parser.add_argument("--frame", help="write the middle matplotlib frame to this PNG (to compare by eye)")
    args = parser.parse_args(argv)
    out = run(quick=args.quick)
    if args.frame:
        from PIL import Image

        Image.fromarray(out["_last_matplotlib_frame"]).save(args.frame)
    print(f"GIF with meters, {out['frames']} frames, {out['width']}x{out['height']} px, drawn and encoded; "
          f"CPU time, median of {out['repeats']} interleaved repeats (ms per frame)")
    print(f"{'side':<34}{'draw':>8}{'encode':>8}{'total':>8}{'KB':>8}")
    for label, key in (("asperity2d (palette, Pillow writer)", "ours"),
                       ("matplotlib (blitting) + Pillow", "matplotlib")):
        print(f"{label:<34}{1e3 * out[key + '_draw_s_per_frame']:>8.2f}"
              f"{1e3 * out[key + '_encode_s_per_frame']:>8.2f}"
              f"{1e3 * out[key + '_s_per_frame']:>8.2f}{out['gif_bytes'][key] / 1e3:>8.0f}")
    if "funcanimation_save_s_per_frame" in out:
        print(f"FuncAnimation(blit=True).save(PillowWriter) of the same picture: "
              f"{1e3 * out['funcanimation_save_s_per_frame']:.2f} ms per frame (it does not blit when saving)")
    for label, value, target in headline(out):
        print(f"{label}: {value:.1f}" + (f" (target {target})" if target else ""))
    if not args.no_save and not args.quick:
        print(f"wrote {save(out)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
