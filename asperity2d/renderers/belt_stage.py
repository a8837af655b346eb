"""A belt chain as a picture: masses on the moving belt, springs, dampers, walls, friction arrows.

:class:`ChainStage` is the belt-chain counterpart of
:class:`~asperity2d.renderers.stage.Stage` (same ``shapes`` / ``paint`` /
``paint_static`` interface, used by the same animation and player code).

What is drawn (the multi-DOF belt thesis' figure 1): two walls; between them the n masses as
blocks standing on the belt, joined wall-mass-...-mass-wall by the n + 1
springs (zig-zags, upper half) and dampers (dash-pots, lower half; a link
with zero stiffness and damping is not drawn); the belt as a band whose
marks move at the belt's displacement, so it is seen moving; each mass
coloured by its state (blue: stuck on the belt; red: slipping faster than
the belt; orange: slower) with its friction force as an arrow under it (one
px-per-newton scale, with a key). The masses' rest positions are evenly
spaced (the chain's spring lengths are not part of the model); their
displacements are drawn to scale, with a scale bar.
"""

from __future__ import annotations

import numpy as np

from .._format import si
from . import raster
from .stage import FOOTER, HEADER

STATE_COLOURS = {0: "mass_stick", 1: "mass_fast", -1: "mass_slow"}
STATE_WORDS = {0: "STICK", 1: "SLIP", -1: "SLIP"}
STATE_KEY = (("mass_stick", "stuck on the belt"), ("mass_fast", "slipping, faster"), ("mass_slow", "slower"))


def _links(result):
    """Springs (N/m) and dampers (N s/m) of the n + 1 links."""
    if result.chain is not None:
        return np.asarray(result.chain.k, float), np.asarray(result.chain.c, float)
    chain = result.meta.get("chain", {})
    n = result.n
    return (np.asarray(chain.get("springs", [1.0] * (n + 1)), float),
            np.asarray(chain.get("dampers", [0.0] * (n + 1)), float))


class ChainStage:
    """Pixel geometry and painter of a belt chain's scene panel (``width`` x ``height`` px)."""

    def __init__(self, result, *, width: int, height: int):
        self.result, self.width, self.height = result, int(width), int(height)
        self.n = result.n
        self.x = np.asarray(result.x, dtype=float)
        self.state = np.asarray(result.state)
        self.friction = np.asarray(result.friction_force, dtype=float)
        self.k, self.c = _links(result)
        W, H = self.width, self.height
        self.wall = 16.0  # px: each wall's inner face from the panel's edge
        self.pitch = (W - 2 * self.wall) / (self.n + 1)  # px between rest positions
        self.rest = self.wall + self.pitch * np.arange(1, self.n + 1)
        self.box_w = min(0.42 * self.pitch, 90.0)
        reach = float(np.max(np.abs(self.x))) if self.x.size else 0.0
        # the largest displacement is 0.28 of the spacing, so blocks never overlap
        self.scale = 0.28 * self.pitch / reach if reach > 0 else 1.0  # px per m
        self.belt_top = H - FOOTER - 34.0
        self.box_h = min(0.42 * (self.belt_top - HEADER - 14), 70.0)
        self.box_top = self.belt_top - self.box_h
        t = np.asarray(result.t, dtype=float)
        self.t = t
        if result.chain is not None:
            V = np.asarray(result.chain.belt_velocity(t), dtype=float) * np.ones_like(t)
            self.belt_v = V
            self.belt_s = np.concatenate(([0.0], np.cumsum(0.5 * (V[1:] + V[:-1]) * np.diff(t))))
        else:
            self.belt_v, self.belt_s = None, np.zeros_like(t)
        big = float(np.percentile(np.abs(self.friction), 99)) if self.friction.size else 0.0
        self.newton_px = 0.3 * self.pitch / big if big > 0 else 0.0

    def centre(self, k: int) -> np.ndarray:
        """Pixel x of each mass's centre at sample ``k``."""
        return self.rest + self.x[:, k] * self.scale

    def shapes(self, k: int, *, slow: float = 1.0, counter: str = "") -> dict:
        W = self.width
        cx = self.centre(k)
        half = 0.5 * self.box_w
        boxes = [((float(c - half), self.box_top, float(c + half), self.belt_top - 1),
                  STATE_COLOURS.get(int(s), "mass_stick")) for c, s in zip(cx, self.state[:, k])]
        anchors = [(self.wall, None)] + [(float(c), None) for c in cx] + [(W - self.wall, None)]
        springs, dampers = [], []
        ys, yd = self.box_top + 0.3 * self.box_h, self.box_top + 0.72 * self.box_h
        for j in range(self.n + 1):
            a = anchors[j][0] + (half if j > 0 else 0.0)
            b = anchors[j + 1][0] - (half if j < self.n else 0.0)
            if self.k[j] > 0:
                y = ys if self.c[j] > 0 else 0.5 * (ys + yd)
                springs.append(raster.zigzag(a, y, b, y, coils=6, amplitude=min(6.0, 0.12 * self.box_h)))
            if self.c[j] > 0:
                dampers.append((a, b, yd))
        spacing = 24.0
        offset = (self.belt_s[k] * self.scale) % spacing
        marks = [float(m) for m in np.arange(offset - spacing, W + spacing, spacing)]
        arrows = []
        if self.newton_px > 0:
            y = self.belt_top + 9
            for c, f in zip(cx, self.friction[:, k]):
                arrows.append((float(c), y, float(c + f * self.newton_px), y))
        belt = ""
        if self.belt_v is not None:
            belt = f"belt {si(self.belt_v[k], 'm/s')}"
        return {"boxes": boxes, "springs": springs, "dampers": dampers, "marks": marks, "arrows": arrows,
                "labels": [f"m{i + 1}" for i in range(self.n)],
                "states": [STATE_WORDS.get(int(s), "") for s in self.state[:, k]],
                "time": f"t = {si(self.t[k], 's', 4)}", "belt": belt,
                "slow": f"×{slow:g} slow" if slow > 1 else "", "counter": counter}

    def paint_static(self, img) -> None:
        """Walls and the footer (scale bar, the arrow key)."""
        from PIL import ImageDraw

        I, W, H = raster.INDEX, self.width, self.height
        d = ImageDraw.Draw(img)
        top, bottom = self.box_top - 16, self.belt_top - 1
        for x0, x1 in ((0, self.wall), (W - self.wall, W)):
            d.rectangle((x0, top, x1, bottom), fill=I["wall"])
            for y in np.arange(top, bottom, 8):
                d.line([(x0, y + 8), (x1, y)], fill=I["light"])
        d.rectangle((0, H - FOOTER, W, H), fill=I["white"])
        bar = raster.scale_bar(img, 10, H - FOOTER / 2, px_per_unit=self.scale, unit="m", target_px=60,
                               label_extra=" displacement")
        x = bar[2] + 16
        for colour, words in STATE_KEY:
            d.rectangle((x, H - FOOTER / 2 - 5, x + 10, H - FOOTER / 2 + 5), fill=I[colour], outline=I["outline"])
            x = raster.draw_text(img, (x + 14, H - FOOTER / 2), words, size=11, anchor="lm")[2] + 10
        if self.newton_px > 0:
            force = raster.nice_length(50.0 / self.newton_px)
            x1, y = W - 10, H - FOOTER / 2
            raster.arrow(d, x1 - force * self.newton_px, y, x1, y, fill=I["arrow"], width=2)
            raster.draw_text(img, (x1 - force * self.newton_px - 6, y), f"friction {si(force, 'N', 1)}",
                             colour="arrow", size=11, anchor="rm")

    def paint(self, img, shapes: dict) -> None:
        from PIL import ImageDraw

        I, W = raster.INDEX, self.width
        d = ImageDraw.Draw(img)
        y0, y1 = self.belt_top, self.belt_top + 18
        d.rectangle((self.wall, y0, W - self.wall, y1), fill=I["belt"])
        for m in shapes["marks"]:
            if self.wall < m < W - self.wall - 8:
                d.line([(m, y0 + 4), (m + 7, y0 + 9), (m, y1 - 4)], fill=I["belt_mark"], width=2)
        for pts in shapes["springs"]:
            d.line(pts, fill=I["spring"], width=2)
        for a, b, y in shapes["dampers"]:
            raster.dashpot(d, a, b, y, half=min(7.0, 0.12 * self.box_h), fill=I["damper"], width=2)
        for (box, colour), label, word in zip(shapes["boxes"], shapes["labels"], shapes["states"]):
            d.rectangle(box, fill=I[colour], outline=I["outline"])
            raster.draw_text(img, (0.5 * (box[0] + box[2]), box[1] + 4), label, colour="white",
                             bg=colour, size=12, bold=True,
                             anchor="ma")
            raster.draw_text(img, (0.5 * (box[0] + box[2]), box[1] - 3), word, colour="black", size=11,
                             anchor="md")
        for a in shapes["arrows"]:
            raster.arrow(d, *a, fill=I["arrow"], width=3, head=8)
        d.rectangle((0, 0, W, HEADER - 1), fill=I["white"])
        box = raster.draw_text(img, (8, 4), shapes["time"], size=14, bold=True)
        x = max(box[2] + 14, 120)
        if shapes["belt"]:
            box = raster.draw_text(img, (x, 5), shapes["belt"] + " →", colour="black", size=13)
            x = box[2] + 14
        if shapes["slow"]:
            raster.draw_text(img, (x, 5), shapes["slow"], colour="spring", size=13, bold=True)
        if shapes["counter"]:
            raster.draw_text(img, (W - 8, 5), shapes["counter"], colour="grey", size=11, anchor="ra")


__all__ = ["ChainStage", "STATE_COLOURS"]
