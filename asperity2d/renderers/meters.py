"""Meters, as in Working Model: small synchronised plots of a run's quantities beside the scene.

:func:`asperity_meters` and :func:`chain_meters` say *what* is metered (title,
unit, traces, the axis ranges): the GIF/MP4 frames (:class:`MeterPanel`, on
palette images) and the HTML player (which receives the same specs as JSON)
draw the very same meters. Axes are in engineering units chosen from the data
(:func:`asperity2d._format.prefixed`): ns/µs/ms, nm/µm, µN/mN, mm/s or m/s.

The value axis spans the 0.5th to 99.5th percentile of the traces (padded by
8 %, and including zero when it is near): single-sample impact spikes of the
contact force, thousands of times the drive force, would otherwise flatten
everything else; they are clipped at the plot's edge, and marked there: a red
bar along the edge where a trace is off the axis, a triangle where it left,
an arrowhead for the cursor's dot and "▲"/"▼" before the read-out.

On a GIF a trace *grows* with the frame (:meth:`MeterPanel.advance` adds the
pixel columns the cursor has passed since the last frame onto a persistent
layer, drawing each column's minimum-to-maximum so a spike shorter than a
pixel still shows); slips are shaded behind the traces as they happen, and
the cursor (a vertical line at "now") and the current values are drawn on
each frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._format import prefixed, si
from . import raster

#: Percentiles of the values the value axis spans (spikes beyond are clipped).
ROBUST = (0.5, 99.5)
PAD = 0.08


@dataclass(frozen=True)
class Trace:
    """One metered series: ``values`` (T,) in SI, drawn in ``colour`` (a raster colour name)."""

    label: str
    values: np.ndarray
    colour: str
    dashed: bool = False


@dataclass(frozen=True)
class Meter:
    """A meter: ``title``, SI ``unit``, its traces, and the value range ``limits`` (SI)."""

    title: str
    unit: str
    traces: tuple
    limits: tuple[float, float] = field(default=(0.0, 1.0))

    @property
    def scale(self) -> tuple[float, str]:
        """``(factor, unit label)`` for the axis: values are shown divided by ``factor``."""
        lo, hi = self.limits
        return prefixed(max(abs(lo), abs(hi)), self.unit)

    def to_json(self, keep=None) -> dict:
        factor, label = self.scale
        traces = []
        for tr in self.traces:
            values = np.asarray(tr.values, dtype=float)
            traces.append({"label": tr.label, "colour": "#%02x%02x%02x" % raster.COLOURS[tr.colour],
                           "dashed": tr.dashed, "values": values if keep is None else values[keep]})
        return {"title": self.title, "unit": self.unit, "factor": factor, "unit_label": label,
                "limits": list(self.limits), "ticks": ticks(*self.limits, factor=factor)[0].tolist(),
                "traces": traces}


def limits(arrays, *, include_zero: bool = True) -> tuple[float, float]:
    """Value range (SI) for a meter's axis: robust percentiles of the finite values, padded."""
    values = np.concatenate([np.ravel(np.asarray(a, dtype=float)) for a in arrays])
    values = values[np.isfinite(values)]
    if values.size == 0:
        return (-1.0, 1.0)
    lo, hi = (float(v) for v in np.percentile(values, ROBUST))
    if include_zero and (lo > 0 and lo < 0.5 * hi or hi < 0 and hi > 0.5 * lo):
        lo, hi = min(lo, 0.0), max(hi, 0.0)
    span = hi - lo
    if not span > 1e-12 * max(abs(lo), abs(hi), 1e-300):
        half = 0.5 * abs(hi) if hi != 0 else 1.0
        return (lo - half, hi + half)
    return (lo - PAD * span, hi + PAD * span)


def nice_step(span: float, count: int = 4) -> float:
    """A 1-2-2.5-5 x 10^n step giving about ``count`` ticks over ``span``."""
    raw = span / max(count, 1)
    e = math.floor(math.log10(raw))
    for m in (1.0, 2.0, 2.5, 5.0, 10.0):
        if m * 10.0**e >= raw:
            return m * 10.0**e
    return 10.0 ** (e + 1)  # pragma: no cover


def ticks(lo: float, hi: float, *, factor: float, count: int = 5) -> tuple[np.ndarray, list[str]]:
    """Tick values (SI) inside [lo, hi] at a nice step in the displayed unit, and their labels."""
    a, b = lo / factor, hi / factor
    step = nice_step(b - a, count)
    first = math.ceil(a / step - 1e-9)
    values = np.arange(first, math.floor(b / step + 1e-9) + 1) * step
    lead = math.floor(math.log10(step) + 1e-9)
    # a step of 2.5 x 10^lead needs one more decimal than 10^lead when it is below 10 (0.25, 2.5)
    decimals = max(0, -lead) + (1 if lead <= 0 and round(step / 10.0**lead, 6) == 2.5 else 0)
    labels = [f"{v:.{decimals}f}".replace("-0", "-0") if abs(v) > 1e-12 * step else "0" for v in values]
    return values * factor, labels


# -- what is metered ---------------------------------------------------------------------------
def asperity_meters(result) -> list[Meter]:
    """Drive force; contact force (the friction, its horizontal total, and the contacts'
    tangential, Coulomb, part); slider position (and the drive's far end); slider velocity."""
    drive = np.asarray(result.drive_force, float)
    friction = np.asarray(result.friction_force, float)
    tangential = np.asarray(result.tangential_force, float)
    x, v = np.asarray(result.x, float), np.asarray(result.v, float)
    forces = [Meter("drive force", "N", (Trace("drive", drive, "c1"),), limits([drive])),
              Meter("contact force on the slider", "N",
                    (Trace("friction (total)", friction, "c2"), Trace("tangential", tangential, "c3")),
                    limits([friction, tangential]))]
    position = [Trace("slider", x, "c0")]
    drive_x = np.asarray(result.drive_x, float)
    if np.isfinite(drive_x).any():
        position.append(Trace("drive end", drive_x, "c6", dashed=True))
    return forces + [Meter("position", "m", tuple(position), limits([tr.values for tr in position],
                                                                      include_zero=False)),
                     Meter("slider velocity", "m/s", (Trace("slider", v, "c4"),), limits([v]))]


def chain_meters(result) -> list[Meter]:
    """Per mass: position, velocity (with the belt's), friction force."""
    n = result.n
    colours = [raster.TRACE_COLOURS[i % len(raster.TRACE_COLOURS)] for i in range(n)]
    names = [f"m{i + 1}" for i in range(n)]
    x, v, f = (np.asarray(a, float) for a in (result.x, result.v, result.friction_force))
    vel = [Trace(nm, v[i], c) for i, (nm, c) in enumerate(zip(names, colours))]
    if result.chain is not None:
        vel.append(Trace("belt", np.asarray(result.chain.belt_velocity(result.t), float) *
                         np.ones(len(result.t)), "black", dashed=True))
    return [Meter("position", "m", tuple(Trace(nm, x[i], c) for i, (nm, c) in enumerate(zip(names, colours))),
                  limits([x])),
            Meter("velocity", "m/s", tuple(vel), limits([tr.values for tr in vel])),
            Meter("friction force", "N", tuple(Trace(nm, f[i], c) for i, (nm, c) in enumerate(zip(names, colours))),
                  limits([f]))]


def time_axis(t0: float, t1: float) -> tuple[float, str]:
    """``(factor, unit label)`` for a time axis from ``t0`` to ``t1`` (s)."""
    return prefixed(max(abs(t0), abs(t1)), "s")


# -- drawing on palette images -------------------------------------------------------------------
class MeterPanel:
    """One meter drawn in the box ``(x0, y0, x1, y1)`` (px) of a frame, over times ``t`` (s).

    :meth:`draw_static` paints the frame, grid, ticks, title and legend on the
    persistent layer; :meth:`advance` adds the trace columns up to a time;
    :meth:`draw_now` draws the cursor, the trace tips and the current values
    on one frame. ``slips``: intervals (s) shaded behind the traces.
    """

    TITLE = 17  # px: title row
    LEGEND = 15  # px: legend row (several traces)
    LEFT, BOTTOM, RIGHT = 40, 16, 8

    def __init__(self, meter: Meter, box, t, *, slips=(), font_size: int = 11):
        self.meter, self.t = meter, np.asarray(t, dtype=float)
        x0, y0, x1, y1 = (int(round(v)) for v in box)
        self.box = (x0, y0, x1, y1)
        self.size = font_size
        self.factor, self.unit_label = meter.scale
        # several traces: a legend with the current values, on the title row if it fits
        self.value_width = raster.text_size("-88.8 mN", font_size)[0]
        title_w = raster.text_size(self._title(), font_size + 1, True)[0] + 24
        entries = [raster.text_size(tr.label, font_size)[0] + 24 + self.value_width for tr in meter.traces]
        self.legend_inline = len(meter.traces) > 1 and title_w + sum(entries) < x1 - x0 - 8
        legend = self.LEGEND if len(meter.traces) > 1 and not self.legend_inline else 0
        self.plot = (x0 + self.LEFT, y0 + self.TITLE + legend + 4, x1 - self.RIGHT, y1 - self.BOTTOM - 2)
        px0, py0, px1, py1 = self.plot
        self.columns = px1 - px0 + 1
        self.t0, self.t1 = float(self.t[0]), float(self.t[-1])
        self.lo, self.hi = meter.limits
        self.factor, self.unit_label = meter.scale
        self.tfactor, self.tunit = time_axis(self.t0, self.t1)
        col = self.column(self.t)
        # per column and trace: first, min, max, last pixel row of the samples in the column
        order = np.arange(len(self.t))
        starts = np.flatnonzero(np.r_[True, np.diff(col) != 0])
        self.col_of_start = col[starts]
        self.envelopes = []
        for tr in meter.traces:
            y = self.row(np.asarray(tr.values, dtype=float))
            finite = np.isfinite(y)
            if not finite.any():
                self.envelopes.append(None)
                continue
            y = np.where(finite, y, np.nan)
            env = np.full((self.columns, 4), np.nan)
            with np.errstate(invalid="ignore"):
                env[col[starts], 0] = y[starts]
                env[col[starts], 1] = np.fmin.reduceat(y, starts)
                env[col[starts], 2] = np.fmax.reduceat(y, starts)
                last = np.r_[starts[1:] - 1, order[-1]]
                env[col[starts], 3] = y[last]
            self.envelopes.append(env)
        # columns where a trace leaves the axis (+1 above, -1 below): marked on the plot's edge
        self.off_axis = []
        for tr in meter.traces:
            v = np.asarray(tr.values, dtype=float)[: len(col)]
            c = col[: len(v)]
            marks = np.zeros(self.columns, dtype=np.int8)
            below = np.zeros(self.columns, dtype=np.int8)
            with np.errstate(invalid="ignore"):
                np.maximum.at(marks, c[v > self.hi], 1)
                np.maximum.at(below, c[v < self.lo], 1)
            self.off_axis.append(np.where(marks > 0, 1, np.where(below > 0, -1, 0)).astype(np.int8))
        self.band = np.zeros(self.columns, dtype=bool)
        for a, b in slips:
            ca, cb = self.column(np.array([a, b]))
            self.band[ca:cb + 1] = True
        self.tick_count = int(min(5, max(3, (py1 - py0) // 24)))
        self.grid_rows = [int(round(v)) for v in self.row(self.value_ticks()[0])]
        self.done = 0  # columns drawn on the persistent layer
        self.tail = [None] * len(meter.traces)  # each trace's last point drawn there (px)

    def value_ticks(self):
        return ticks(self.lo, self.hi, factor=self.factor, count=self.tick_count)

    def _title(self) -> str:
        return f"{self.meter.title} ({self.unit_label})"

    # coordinates
    def column(self, t) -> np.ndarray:
        """Plot column (0-based) of times ``t`` (s)."""
        span = self.t1 - self.t0
        frac = (np.asarray(t, dtype=float) - self.t0) / span if span > 0 else np.zeros(np.shape(t))
        return np.clip(np.round(frac * (self.columns - 1)), 0, self.columns - 1).astype(np.int64)

    def x_of(self, t) -> np.ndarray:
        """Pixel x of times ``t`` (s) (the cursor's column)."""
        return self.plot[0] + self.column(t)

    def row(self, values) -> np.ndarray:
        """Pixel y of ``values`` (SI), clipped to the plot."""
        _, py0, _, py1 = self.plot
        frac = (np.asarray(values, dtype=float) - self.lo) / (self.hi - self.lo)
        return np.clip(py1 - frac * (py1 - py0), py0, py1)

    # drawing
    def draw_static(self, img) -> None:
        from PIL import ImageDraw

        d = ImageDraw.Draw(img)
        I = raster.INDEX
        x0, y0, x1, y1 = self.box
        px0, py0, px1, py1 = self.plot
        d.rectangle(self.box, fill=I["panel"])
        d.rectangle((px0, py0, px1, py1), fill=I["white"])
        values, labels = self.value_ticks()
        for row, label in zip(self.grid_rows, labels):
            d.line([(px0, row), (px1, row)], fill=I["light"])
            raster.draw_text(img, (px0 - 4, row), label, colour="grey", bg="panel", size=self.size - 1,
                             anchor="rm")
        tvalues, tlabels = ticks(self.t0, self.t1, factor=self.tfactor, count=5)
        unit_w = raster.text_size(self.tunit, self.size - 1)[0]
        for tv, label in zip(tvalues, tlabels):
            cx = int(self.x_of(tv))
            d.line([(cx, py1), (cx, py1 + 3)], fill=I["grey"])
            if cx + raster.text_size(label, self.size - 1)[0] / 2 < px1 - unit_w - 4:  # clear of the unit
                raster.draw_text(img, (cx, py1 + 4), label, colour="grey", bg="panel", size=self.size - 1,
                                 anchor="ma")
        raster.draw_text(img, (px1, y1 - 1), self.tunit, colour="grey", bg="panel", size=self.size - 1,
                         anchor="rd")
        d.rectangle((px0 - 1, py0 - 1, px1 + 1, py1 + 1), outline=I["grey"])
        title = raster.draw_text(img, (x0 + 6, y0 + 3), self._title(), colour="black",
                                 bg="panel", size=self.size + 1, bold=True)
        self.legend_slots = []
        if len(self.meter.traces) > 1:
            x, y = (title[2] + 16, y0 + 4) if self.legend_inline else (x0 + 8, y0 + self.TITLE + 2)
            width = self.value_width
            for tr in self.meter.traces:
                d.line([(x, y + 7), (x + 12, y + 7)], fill=I[tr.colour], width=3)
                box = raster.draw_text(img, (x + 16, y), tr.label, colour="black", bg="panel", size=self.size)
                self.legend_slots.append((box[2] + 4, y))
                x = box[2] + 8 + width
        else:
            self.legend_slots.append((x1 - self.RIGHT, y0 + 3))
        self.done = 0
        self.tail = [None] * len(self.meter.traces)

    def advance(self, img, t_now: float) -> None:
        """Draw the trace columns before the cursor at ``t_now`` (s) that are not drawn yet."""
        from PIL import ImageDraw

        upto = int(self.column(t_now))  # the cursor's column stays partial
        if upto < self.done:
            raise ValueError("MeterPanel.advance: time went backwards; redraw the static layer")
        if upto == self.done:
            return
        d = ImageDraw.Draw(img)
        I = raster.INDEX
        a, b = self.done, upto
        px0, py0, px1, py1 = self.plot
        band = np.flatnonzero(self.band[a:b]) + a
        if band.size:
            for run in np.split(band, np.flatnonzero(np.diff(band) != 1) + 1):
                d.rectangle((px0 + run[0], py0, px0 + run[-1], py1), fill=I["slip_band"])
                for row in self.grid_rows:
                    d.line([(px0 + run[0], row), (px0 + run[-1], row)], fill=I["light"])
        for n, (tr, env) in enumerate(zip(self.meter.traces, self.envelopes)):
            if env is None:
                continue
            cols = np.flatnonzero(~np.isnan(env[a:b, 0])) + a
            if not cols.size:
                continue
            # from the last point drawn (columns without samples are bridged, as a line plot does)
            pts = [self.tail[n]] if self.tail[n] is not None else []
            for c in cols:
                x = px0 + int(c)
                pts += [(x, env[c, 0]), (x, env[c, 1]), (x, env[c, 2]), (x, env[c, 3])]
            self.tail[n] = pts[-1]
            if tr.dashed:
                for p, q in zip(pts[:-1], pts[1:]):
                    if (int(p[0]) // 4) % 2 == 0:
                        d.line([p, q], fill=I[tr.colour], width=1)
            else:
                d.line(pts, fill=I[tr.colour], width=1)
        for tr, off in zip(self.meter.traces, self.off_axis):
            cols = np.flatnonzero(off[a:b]) + a
            for run in (np.split(cols, np.flatnonzero(np.diff(cols) != 1) + 1) if cols.size else []):
                for side in (1, -1):  # a bar on the edge the values left by, a triangle at its start
                    part = run[off[run] == side]
                    if not part.size:
                        continue
                    y = py0 if side > 0 else py1
                    d.line([(px0 + part[0], y + side), (px0 + part[-1], y + side)], fill=I["slider_slip"], width=2)
                    x = px0 + int(part[0])
                    d.polygon([(x, y), (x - 3, y + 6 * side), (x + 3, y + 6 * side)], fill=I[tr.colour],
                              outline=I["cursor"])
        self.done = b

    def draw_now(self, img, k: int, *, values: bool = True) -> None:
        """Cursor, trace tips and current values at sample ``k`` on one frame ``img``."""
        from PIL import ImageDraw

        d = ImageDraw.Draw(img)
        I = raster.INDEX
        px0, py0, px1, py1 = self.plot
        cx = int(self.x_of(self.t[k]))
        for tr, env in zip(self.meter.traces, self.envelopes):
            if env is None:
                continue
            y = float(self.row(tr.values[k]))
            tail = self.tail[self.meter.traces.index(tr)]
            if tail is not None and not tr.dashed and np.isfinite(y):
                d.line([tail, (cx, y)], fill=I[tr.colour], width=1)
        d.line([(cx, py0), (cx, py1)], fill=I["cursor"], width=1)
        for tr, env in zip(self.meter.traces, self.envelopes):
            if env is None:
                continue
            value = float(tr.values[k])
            y = float(self.row(value))
            if value > self.hi or value < self.lo:  # off the axis: an arrowhead on the edge it left by
                side = 1 if value > self.hi else -1
                d.polygon([(cx, y - 2 * side), (cx - 5, y + 8 * side), (cx + 5, y + 8 * side)], fill=I[tr.colour],
                          outline=I["cursor"])
            else:
                d.ellipse((cx - 3, y - 3, cx + 3, y + 3), fill=I[tr.colour], outline=I["cursor"])
        if not values:
            return
        for (x, y), tr in zip(self.legend_slots, self.meter.traces):
            value = float(tr.values[k])
            text = si(value, self.meter.unit) if np.isfinite(value) else "–"
            if value > self.hi or value < self.lo:
                text = ("▲ " if value > self.hi else "▼ ") + text + (" off axis" if len(self.meter.traces) == 1 else "")
            anchor = "ra" if len(self.meter.traces) == 1 else "la"
            raster.draw_text(img, (x, y), text, colour=tr.colour if tr.colour in raster.TRACE_COLOURS
                             else "black", bg="panel", size=self.size + (1 if anchor == "ra" else 0),
                             bold=anchor == "ra", anchor=anchor, box=True)


__all__ = ["Meter", "MeterPanel", "Trace", "asperity_meters", "chain_meters", "limits", "nice_step",
           "ticks", "time_axis"]
