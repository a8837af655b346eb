"""The asperity scene as a picture: camera, vertical exaggeration, bodies, forces, labels.

:class:`Stage` maps one sample of a :class:`~asperity2d.result.Result` to
pixels of a scene panel and paints it on a palette image:

* the lower asperities (each its own polygon, :meth:`~asperity2d.scene.LowerSurface.outlines`)
  on their vertical spring tracks, green while they touch the slider; the
  ground band (the engine's guard floor, the bottom of the tracks) hatched
  every half pitch, so a moving camera shows as moving ground;
* the slider's bar and tips, tinted by the stick/slip state (dark bar and
  amber tips while it sticks, red while it slips), and the drive spring from
  its front to the drive block (the spring's rest length is zero in the
  model: it is drawn with one pitch added, so its stretch ``drive_x - x`` shows);
* the contact force on the slider as arrows on the touching lower tips: the
  recorded total (``-friction_force``, ``normal_force``) shared among the
  touching asperities in proportion to the load on each one's track spring
  (``k * max(-dy, 0)``; equal shares when none is compressed), so the arrows
  sum to the measured force; one px-per-newton scale for the whole run (the
  largest force on one tip about 40 px long), with a key;
* a header (time in engineering units, STICK / SLIP, "×N slow", frame
  counter) and a footer (scale bar, "vertical ×N", the arrow key).

Camera: ``"follow"`` (default) keeps the slider and the drive block in a
window as wide as the widest the run needs (and at least the slider plus six
pitches of surface), and moves only when one of them
would leave it (a lazy camera: the ground stands still while the slider
sticks); ``"whole"`` shows the whole surface and the drive's travel at once.
One horizontal scale for the whole animation. Vertical exaggeration
(``exaggeration=None``: automatic) stretches heights by a whole factor N when
the lower asperities are shallow (height under a fifth of the base) and
there is room, labelled "vertical ×N"; forces keep their true direction.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np

from .._format import si
from ..errors import SceneError
from . import raster

CAMERAS = ("follow", "whole")
HEADER, CAPTION, FOOTER, GROUND = 24, 16, 22, 16  # px: time row, caption, scale bar row, ground band
MIN_HEIGHT = 190  # px: the least a scene panel takes (spare room goes to the ground band)
ARROW_PX = 40.0  # px for the largest (99th percentile) force on one tip over the frames


def slip_mask(result) -> np.ndarray:
    """Boolean per sample: the slider is inside a slip (``t_slip < t <= t_end`` of an event)."""
    from .timeline import slip_intervals

    t = np.asarray(result.t, dtype=float)
    mask = np.zeros(t.shape, dtype=bool)
    for a, b in slip_intervals(result):
        mask |= (t > a) & (t <= b)
    return mask


def force_shares(result, k: int) -> np.ndarray:
    """Share of the total contact force carried by each lower asperity at sample ``k`` (sums to
    1 over the touching ones, 0 elsewhere): by the load on its track spring, ``k_i * max(-dy_i, 0)``."""
    touching = np.asarray(result.lower_contact[:, k], dtype=bool)
    if not touching.any():
        return np.zeros(touching.shape)
    stiffness = np.asarray(result.scene.lower.stiffness, dtype=float)
    load = np.where(touching, stiffness * np.maximum(-np.asarray(result.lower_dy[:, k], float), 0.0), 0.0)
    total = load.sum()
    if total > 0:
        return load / total
    return touching / touching.sum()


def tip_force_scale(result, samples) -> float:
    """The 99th percentile over ``samples`` (with contact) of the largest force on one tip (N):
    the arrows' scale, so the longest arrows are about :data:`ARROW_PX` long."""
    samples = np.asarray(samples, dtype=np.int64)
    force = np.hypot(np.asarray(result.friction_force, float), np.asarray(result.normal_force, float))
    stiffness = np.asarray(result.scene.lower.stiffness, dtype=float)[:, None]
    largest = []
    for chunk in np.array_split(samples, max(1, len(samples) // 2000)):  # bounded memory
        touching = np.asarray(result.lower_contact[:, chunk], dtype=bool)
        count = touching.sum(axis=0)
        load = np.where(touching, stiffness * np.maximum(-np.asarray(result.lower_dy[:, chunk], float), 0.0), 0.0)
        total = load.sum(axis=0)
        with np.errstate(invalid="ignore", divide="ignore"):
            share = np.where(total > 0, load.max(axis=0) / total, 1.0 / np.maximum(count, 1))
        largest.append((share * force[chunk])[count > 0])
    values = np.concatenate(largest) if largest else np.array([])
    return float(np.percentile(values, 99)) if values.size else 0.0


def rest_record(scene) -> SimpleNamespace:
    """A one-sample record of ``scene`` at rest where a run starts: a fixed-track slider left of the
    surface, its tips ``interference`` into it; a free slider over the first valley, its deepest
    tip on the lower tips' rest height. Drive spring unstretched, no forces, no contact."""
    lower, slider = scene.lower, scene.slider
    tips = lower.tips()
    apex = slider.tips()
    left_lower = float(np.ravel(lower.runs()[0])[0])
    right_upper = float(np.ravel(slider.runs()[1])[-1])
    if slider.track == "fixed":
        x0 = tips[0] - left_lower - right_upper - apex[-1] - 0.1 * scene.base
        y0 = lower.top - slider.interference + slider.depth
    else:
        x0 = (0.5 * (tips[0] + tips[1]) if len(tips) > 1 else tips[0]) - apex[0]
        y0 = lower.top + slider.depth
    n = lower.count
    one = np.array
    from ..scene import SpringDrive

    drive_x = x0 if isinstance(scene.drive, SpringDrive) else np.nan
    return SimpleNamespace(
        scene=scene, t=one([0.0]), x=one([x0]), y=one([y0]), v=one([0.0]), vy=one([0.0]),
        drive_x=one([drive_x]), drive_force=one([0.0]), normal_force=one([0.0]),
        friction_force=one([0.0]), tangential_force=one([0.0]), contact_count=one([0]),
        lower_dx=np.zeros((n, 1)), lower_dy=np.zeros((n, 1)), lower_contact=np.zeros((n, 1), bool))


class Stage:
    """World (m) to pixels for a scene panel ``width`` px wide and at most ``height`` px tall
    (:attr:`height`: what it takes), and the painter.

    ``px = (X - left[k]) * scale``, ``py = base_py - (Y - y_ref) * scale * exaggeration``.
    ``frames``: the sample indices the animation shows (the lazy camera moves
    frame by frame); default every sample.
    """

    def __init__(self, result, *, width: int, height: int, camera: str = "follow",
                 exaggeration: float | None = None, frames=None, arrows: bool = True):
        if camera not in CAMERAS:
            raise SceneError(f"`camera` must be one of {', '.join(map(repr, CAMERAS))}, got {camera!r}")
        if hasattr(result, "require_lower"):  # a Result (the notebook's scene drawing is not one)
            result.require_lower("drawing the scene")
        scene = result.scene
        self.result, self.width, self.max_height, self.camera = result, int(width), int(height), camera
        self.arrows = arrows
        lower, slider = scene.lower, scene.slider
        self.lower_polys = np.array([np.asarray(v, float) for v in lower.outlines()], dtype=object)
        self.uniform_lower = len({len(v) for v in self.lower_polys}) == 1
        if self.uniform_lower:
            self.lower_polys = np.stack([np.asarray(v, float) for v in lower.outlines()])
        self.upper_polys = [np.asarray(v, float) for v in slider.outlines()]
        shapes = lower.shape_set()
        self.levels = np.array(shapes.levels, dtype=float)
        self.summits = np.array(shapes.summits, dtype=float)
        self.heights = np.array(shapes.heights, dtype=float)
        self.lower_x = lower.tips()
        self.upper_x = slider.tips()
        self.substrate = [np.asarray(line, float) for line in lower.substrate or ()]
        self.base, self.pitch = scene.base, lower.spacing.mean_pitch
        left_runs, right_runs = (np.ravel(r) for r in slider.runs())
        self.rear = float(self.upper_x[0] - left_runs[0])
        self.front = float(self.upper_x[-1] + right_runs[-1])
        self.floor = lower.floor
        x = np.asarray(result.x, dtype=float)
        self.x, self.y = x, np.asarray(result.y, dtype=float)
        drive_x = np.asarray(result.drive_x, dtype=float)
        self.has_drive = bool(np.isfinite(drive_x).any())
        self.drive_end = drive_x + self.front + self.pitch if self.has_drive else None
        self.frames = np.arange(len(x)) if frames is None else np.asarray(frames, dtype=np.int64)
        self.slipping = slip_mask(result) if self.has_drive else np.zeros(len(x), dtype=bool)
        self._horizontal()
        self._vertical(exaggeration)
        big = tip_force_scale(result, self.frames)
        self.newton_px = ARROW_PX / big if big > 0 else 0.0

    # -- camera ---------------------------------------------------------------------------------
    def _needed(self):
        """Left and right world x (m) each sample needs in view."""
        margin = 0.6 * self.pitch
        left = self.x + self.rear - margin
        right = self.x + self.front + margin
        if self.has_drive:
            right = np.fmax(right, self.drive_end + 0.8 * self.pitch)
        return left, right

    def _horizontal(self):
        left, right = self._needed()
        surface = (float(self.lower_x[0] - self.pitch), float(self.lower_x[-1] + self.pitch))
        if self.camera == "whole":
            lo = min(surface[0], float(np.min(left)))
            hi = max(surface[1], float(np.max(right)))
            self.scale = self.width / (hi - lo)
            self.lefts = np.full(len(self.x), lo)
            return
        # as wide as the run needs, and at least the slider and six pitches of surface around it
        span = max(float(np.max(right - left)), self.front - self.rear + 6.0 * self.pitch)
        self.scale = self.width / span
        # lazy camera, frame by frame: keep the previous centre unless that loses something
        centres = np.empty(len(self.frames))
        c = 0.5 * (left[self.frames[0]] + right[self.frames[0]])
        for j, k in enumerate(self.frames):
            lo, hi = right[k] - 0.5 * span, left[k] + 0.5 * span
            c = min(max(c, lo), hi)
            centres[j] = c
        self.lefts = np.full(len(self.x), np.nan)
        self.lefts[self.frames] = centres - 0.5 * span
        missing = np.isnan(self.lefts)
        if missing.any():  # samples between frames: the nearest earlier frame's camera
            idx = np.where(~missing, np.arange(len(self.lefts)), 0)
            np.maximum.accumulate(idx, out=idx)
            self.lefts = self.lefts[idx]

    def _vertical(self, exaggeration):
        top_world = float(np.nanmax(self.y))  # the slider's datum; its bar is drawn in px above
        bottom_world = self.floor  # the bottom of the tracks (the ground's top)
        self.bar_px = max(8.0, min(0.3 * self.base * self.scale, 18.0))
        fixed = HEADER + CAPTION + 10 + self.bar_px + GROUND + FOOTER
        room = self.max_height - fixed  # px for the heights at most
        extent = max(top_world - bottom_world, 1e-300)
        fit = room / (extent * self.scale)
        if exaggeration is None:
            shallow = float(np.median(self.heights)) < 0.2 * self.base
            exaggeration = float(min(max(1, math.floor(fit)), 50)) if shallow and fit >= 2 else 1.0
        elif not (isinstance(exaggeration, (int, float)) and not isinstance(exaggeration, bool)
                  and math.isfinite(exaggeration) and exaggeration >= 1):
            raise SceneError(f"`exaggeration` must be a number >= 1, got {exaggeration!r}")
        self.exaggeration = float(exaggeration)
        self.vscale = self.scale * self.exaggeration
        used = extent * self.vscale
        # the panel is as tall as its contents need (the meters get the rest), within bounds
        self.height = int(min(self.max_height, max(MIN_HEIGHT, math.ceil(fixed + used))))
        spare = max(0.0, self.height - fixed - used)
        self.y_ref = top_world
        self.top_py = HEADER + CAPTION + 10 + self.bar_px + 0.35 * spare
        self.ground_py = self.top_py + (top_world - bottom_world) * self.vscale

    def to_px(self, X, Y, k: int):
        """Pixel coordinates of world points (m) at sample ``k``."""
        return ((np.asarray(X, dtype=float) - self.lefts[k]) * self.scale,
                self.top_py - (np.asarray(Y, dtype=float) - self.y_ref) * self.vscale)

    # -- what is drawn where ---------------------------------------------------------------------
    def shapes(self, k: int, *, slow: float = 1.0, counter: str = "") -> dict:
        """Pixel-space shapes of sample ``k`` (what :meth:`paint` draws, and the benchmark's
        matplotlib side): polylines, polygons with their colour names, boxes, arrows, header text."""
        r = self.result
        left = self.lefts[k]
        x, y = float(self.x[k]), float(self.y[k])
        W, H = self.width, self.height
        view = (left - self.base, left + W / self.scale + self.base)
        g = float(self.ground_py)
        step = 0.5 * self.pitch
        first = math.floor(view[0] / step)
        hx = (np.arange(first, first + int((view[1] - view[0]) / step) + 2) * step - left) * self.scale
        hatch = [((float(px), g + 2), (float(px) - 6, g + 10)) for px in hx] if g < H else []
        substrate = []
        for line in self.substrate:
            if line[-1, 0] < view[0] or line[0, 0] > view[1]:
                continue
            X, Y = self.to_px(line[:, 0], line[:, 1], k)
            substrate.append(list(zip(X.tolist(), Y.tolist())))
        dx, dy = r.lower_dx[:, k], r.lower_dy[:, k]
        cx = self.lower_x + dx
        visible = np.flatnonzero((cx > view[0] - self.base) & (cx < view[1] + self.base))
        touching = np.asarray(r.lower_contact[:, k], dtype=bool)
        amp = max(2.0, min(0.12 * self.base * self.scale, 5.0))
        tracks, lower, tips = [], [], {}
        px, base_py = self.to_px(cx[visible], dy[visible] + self.levels[visible], k)
        tx, ty = self.to_px(cx[visible], dy[visible] + self.summits[visible], k)
        for j, i in enumerate(visible):
            tracks.append(raster.zigzag(float(px[j]), g, float(px[j]), float(base_py[j]), coils=4, amplitude=amp))
            poly = self.lower_polys[i]
            X, Y = self.to_px(cx[i] + poly[:, 0], dy[i] + poly[:, 1], k)
            lower.append((list(zip(X.tolist(), Y.tolist())), "touching" if touching[i] else "lower"))
            tips[int(i)] = (float(tx[j]), float(ty[j]))
        slipping = bool(self.slipping[k])
        upper = []
        for c, poly in zip(self.upper_x, self.upper_polys):
            X, Y = self.to_px(x + c + poly[:, 0], y + poly[:, 1], k)
            upper.append(list(zip(X.tolist(), Y.tolist())))
        bx0, by1 = self.to_px(x + self.rear, y, k)
        bx1 = float(self.to_px(x + self.front, y, k)[0])
        out = {"ground": (0.0, g, float(W), float(H)), "hatch": hatch, "substrate": substrate,
               "tracks": tracks, "lower": lower, "tips": tips, "upper": upper,
               "upper_colour": "tips_slip" if slipping else "tips_stick",
               "bar": (float(bx0), float(by1) - self.bar_px, bx1, float(by1)),
               "bar_colour": "slider_slip" if slipping else "slider_stick",
               "spring": [], "drive": None, "arrows": []}
        if self.has_drive:
            sy = float(by1) - 0.5 * self.bar_px
            end = float(self.to_px(self.drive_end[k], 0.0, k)[0])
            out["spring"] = raster.zigzag(bx1, sy, end, sy, coils=8, amplitude=max(3.0, 0.3 * self.bar_px))
            half = 0.6 * self.bar_px
            out["drive"] = (end, sy - half, end + 1.2 * half, sy + half)
        if self.arrows and self.newton_px > 0 and touching.any():
            shares = force_shares(r, k)
            fx, fy = -float(r.friction_force[k]) * self.newton_px, float(r.normal_force[k]) * self.newton_px
            out["arrows"] = [(a, b, a + fx * shares[i], b - fy * shares[i])
                             for i, (a, b) in tips.items() if shares[i] > 0]
        out["time"] = f"t = {si(r.t[k], 's', 4)}"
        out["state"] = ("SLIP" if slipping else "STICK") if self.has_drive else ""
        out["slow"] = f"×{slow:g} slow" if slow > 1 else ""
        out["counter"] = counter
        return out

    # -- painting ---------------------------------------------------------------------------------
    def caption(self) -> str:
        """One short line saying what the scene is (under the time row)."""
        scene = self.result.scene
        lower, slider, drive = scene.lower, scene.slider, scene.drive
        track = "on a fixed track" if slider.track == "fixed" else f"free under {si(slider.normal_load, 'N', trim=True)}"
        text = (f"{lower.count} lower asperities on spring tracks · slider with {slider.count} "
                f"tip{'s' if slider.count != 1 else ''} {track} · ")
        if self.has_drive:
            text += f"pulled by a {si(drive.stiffness, 'N/m', trim=True)} spring, far end at {si(drive.velocity, 'm/s', trim=True)}"
        else:
            text += f"pushed by {si(drive.force, 'N', trim=True)}"
        return text

    def paint_static(self, img) -> None:
        """What never changes: the caption, the footer (scale bar, "vertical ×N", the force arrows' key)."""
        from PIL import ImageDraw

        I, W, H = raster.INDEX, self.width, self.height
        d = ImageDraw.Draw(img)
        raster.draw_text(img, (8, HEADER), self.caption(), colour="grey", size=11)
        d.rectangle((0, H - FOOTER, W, H), fill=I["white"])
        extra = f"   vertical ×{self.exaggeration:g}" if self.exaggeration > 1 else ""
        raster.scale_bar(img, 10, H - FOOTER / 2, px_per_unit=self.scale, unit="m", target_px=80,
                         label_extra=extra)
        if self.arrows and self.newton_px > 0:
            force = raster.nice_length(30.0 / self.newton_px)
            x1, y = W - 10, H - FOOTER / 2
            raster.arrow(d, x1 - force * self.newton_px, y, x1, y, fill=I["arrow"], width=2)
            raster.draw_text(img, (x1 - force * self.newton_px - 6, y),
                             f"contact force on the slider {si(force, 'N', 1)}", colour="arrow", size=11,
                             anchor="rm")

    def paint(self, img, shapes: dict) -> None:
        """Draw ``shapes`` (from :meth:`shapes`) on ``img``, a copy of the static panel."""
        from PIL import ImageDraw

        I, W = raster.INDEX, self.width
        d = ImageDraw.Draw(img)
        ground = shapes["ground"]
        if ground[1] < self.height - FOOTER - 1:  # (a tall scene's ground may be below the panel)
            d.rectangle((ground[0], ground[1], ground[2], self.height - FOOTER - 1), fill=I["ground"])
            for a, b in shapes["hatch"]:
                d.line([a, b], fill=I["hatch"])
            d.line([(0, ground[1]), (W, ground[1])], fill=I["outline"])
        for line in shapes["substrate"]:
            d.line(line, fill=I["substrate"], width=2)
        for pts in shapes["tracks"]:
            d.line(pts, fill=I["track"])
        for pts, colour in shapes["lower"]:
            d.polygon(pts, fill=I[colour], outline=I["outline"])
        for pts in shapes["upper"]:
            d.polygon(pts, fill=I[shapes["upper_colour"]], outline=I["outline"])
        d.rectangle(shapes["bar"], fill=I[shapes["bar_colour"]], outline=I["outline"])
        if shapes["drive"] is not None:
            d.line(shapes["spring"], fill=I["spring"], width=2)
            x0, y0, x1, y1 = shapes["drive"]
            d.rectangle(shapes["drive"], fill=I["drive"], outline=I["outline"])
            d.line([(x1, 0.5 * (y0 + y1)), (x1 + 10, 0.5 * (y0 + y1))], fill=I["drive"], width=2)
        for a in shapes["arrows"]:
            raster.arrow(d, *a, fill=I["arrow"], width=2)
        d.rectangle((0, 0, W, HEADER - 1), fill=I["white"])
        box = raster.draw_text(img, (8, 4), shapes["time"], size=14, bold=True)
        x = max(box[2] + 14, 150)
        if shapes["state"]:
            word = shapes["state"]
            fg, bg = ("white", "slip_bg") if word == "SLIP" else ("stick_fg", "stick_bg")
            w = raster.text_size(word, 13, True)[0]
            d.rectangle((x, 3, x + w + 12, HEADER - 3), fill=I[bg])
            raster.draw_text(img, (x + 6, HEADER // 2), word, colour=fg, bg=bg, size=13, bold=True, anchor="lm")
            x += w + 24
        if shapes["slow"]:
            raster.draw_text(img, (x, 5), shapes["slow"], colour="spring", size=13, bold=True)
        if shapes["counter"]:
            raster.draw_text(img, (W - 8, 5), shapes["counter"], colour="grey", size=11, anchor="ra")
        if shapes.get("note"):  # why this frame jumps more than a pitch (over the caption)
            raster.draw_text(img, (8, HEADER), shapes["note"], colour="slider_slip", size=11, bold=True, box=True)


__all__ = ["CAMERAS", "Stage", "force_shares", "rest_record", "slip_mask"]
