"""Notebook display: a Scene as an SVG drawing, a run as the player, a comparison as a table and plot.

The model's ``_repr_*_`` methods are one line each: they ask :func:`represent` here through
:mod:`asperity2d._display`, which imports this module by name when Jupyter first asks (so
``import asperity2d`` stays light and the model never imports the renderers):

* :func:`scene_svg` -- the scene at rest, drawn with the animation's own
  geometry (:class:`~asperity2d.renderers.stage.Stage` on a one-sample
  record of the scene at rest, whole-surface camera), as SVG text;
* :func:`result_html` -- the interactive player (:mod:`.player`) in an
  ``<iframe srcdoc>`` (its script and styles kept apart from the notebook's);
* :func:`comparison_html` -- the comparison's statistics as an HTML table in
  engineering units, with its strip-and-box plot as an inline PNG.
"""

from __future__ import annotations

import base64
import html
import tempfile
from pathlib import Path

import numpy as np

from .._format import si
from . import raster
from .stage import rest_record  # noqa: F401  (the scene at rest; here for the notebook's callers)

SVG_WIDTH, SVG_HEIGHT = 720, 240


def _hex(name: str) -> str:
    return "#%02x%02x%02x" % raster.COLOURS[name]


def _points(pts) -> str:
    return " ".join(f"{x:.1f},{y:.1f}" for x, y in pts)


def scene_svg(scene, *, width: int = SVG_WIDTH, height: int = SVG_HEIGHT) -> str:
    """``scene`` at rest as an SVG document (whole surface, scale bar, "vertical ×N" if exaggerated)."""
    from .stage import FOOTER, HEADER, Stage

    stage = Stage(rest_record(scene), width=width, height=height, camera="whole", arrows=False)
    s = stage.shapes(0)
    W, H = stage.width, stage.height
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" viewBox="0 0 {W} {H}" '
           f'font-family="DejaVu Sans, sans-serif" font-size="12">',
           f'<rect width="{W}" height="{H}" fill="white"/>']
    g = s["ground"][1]
    if g < H - FOOTER - 1:
        out.append(f'<rect x="0" y="{g:.1f}" width="{W}" height="{H - FOOTER - g:.1f}" fill="{_hex("ground")}"/>')
        out += [f'<line x1="{a[0]:.1f}" y1="{a[1]:.1f}" x2="{b[0]:.1f}" y2="{b[1]:.1f}" stroke="{_hex("hatch")}"/>'
                for a, b in s["hatch"]]
        out.append(f'<line x1="0" y1="{g:.1f}" x2="{W}" y2="{g:.1f}" stroke="{_hex("outline")}"/>')
    out += [f'<polyline points="{_points(p)}" fill="none" stroke="{_hex("substrate")}" stroke-width="2"/>'
            for p in s["substrate"]]
    out += [f'<polyline points="{_points(p)}" fill="none" stroke="{_hex("track")}"/>' for p in s["tracks"]]
    out += [f'<polygon points="{_points(p)}" fill="{_hex(c)}" stroke="{_hex("outline")}"/>' for p, c in s["lower"]]
    out += [f'<polygon points="{_points(p)}" fill="{_hex(s["upper_colour"])}" stroke="{_hex("outline")}"/>'
            for p in s["upper"]]
    x0, y0, x1, y1 = s["bar"]
    out.append(f'<rect x="{x0:.1f}" y="{y0:.1f}" width="{x1 - x0:.1f}" height="{y1 - y0:.1f}" '
               f'fill="{_hex(s["bar_colour"])}" stroke="{_hex("outline")}"/>')
    mid = 0.5 * (y0 + y1)
    if s["drive"] is not None:
        out.append(f'<polyline points="{_points(s["spring"])}" fill="none" stroke="{_hex("spring")}" stroke-width="2"/>')
        a, b, c, d = s["drive"]
        out.append(f'<rect x="{a:.1f}" y="{b:.1f}" width="{c - a:.1f}" height="{d - b:.1f}" fill="{_hex("drive")}"/>')
        label = f"spring {si(scene.drive.stiffness, 'N/m', trim=True)}, end at {si(scene.drive.velocity, 'm/s', trim=True)} →"
        out.append(f'<text x="{c + 6:.1f}" y="{mid + 4:.1f}" fill="{_hex("spring")}">{html.escape(label)}</text>')
    else:
        out.append(f'<line x1="{x1:.1f}" y1="{mid:.1f}" x2="{x1 + 40:.1f}" y2="{mid:.1f}" stroke="{_hex("arrow")}" '
                   f'stroke-width="3"/><polygon points="{x1 + 48:.1f},{mid:.1f} {x1 + 38:.1f},{mid - 5:.1f} '
                   f'{x1 + 38:.1f},{mid + 5:.1f}" fill="{_hex("arrow")}"/>')
        out.append(f'<text x="{x1 + 52:.1f}" y="{mid + 4:.1f}" fill="{_hex("arrow")}">'
                   f'{html.escape(si(scene.drive.force, "N", trim=True))}</text>')
    title = scene.name or "scene"
    out.append(f'<text x="8" y="{HEADER - 8}" font-weight="bold" font-size="13">{html.escape(title)} (at rest)</text>')
    # scale bar
    length = raster.nice_length(80.0 / stage.scale)
    px = length * stage.scale
    y = H - FOOTER / 2
    out.append(f'<rect x="10" y="{y - 2:.1f}" width="{px:.1f}" height="4" fill="black"/>')
    extra = f"   vertical ×{stage.exaggeration:g}" if stage.exaggeration > 1 else ""
    out.append(f'<text x="{16 + px:.1f}" y="{y + 4:.1f}">{html.escape(si(length, "m", 1) + extra)}</text>')
    out.append("</svg>")
    return "\n".join(out)


def result_html(result, *, max_samples: int = 4000, height: int = 1020) -> str:
    """The player for ``result`` inside an ``<iframe srcdoc>`` (decimated to ``max_samples``)."""
    from .player import page

    doc = page(result, max_samples=max_samples)
    return (f'<iframe srcdoc="{html.escape(doc, quote=True)}" style="width:100%;height:{height}px;border:0" '
            f'sandbox="allow-scripts" title="asperity2d player"></iframe>')


def _unit(measure: str) -> str:
    from ..experiments.compare import MEASURES

    known = {key for key in MEASURES} | {fn.__name__ for fn, _ in MEASURES.values()}
    return "N" if measure in known or "force" in measure else ""


def comparison_html(comparison) -> str:
    """``comparison`` as an HTML table (per variant: n, mean, std, median, 95 % CI) and its plot."""
    from ..experiments.compare import measure_label
    from .plots import plot_comparison

    unit = _unit(comparison.measure)
    rows = []
    for name, d in comparison.summary().items():
        cells = [html.escape(name), str(d["n"]) + (f" ({d['missing']} missing)" if d["missing"] else "")]
        if np.isfinite(d["std"]) and d["std"] <= 1e-9 * abs(d["mean"]):
            d["std"] = 0.0  # the same value for every seed: rounding, not spread
        cells += [si(d[k], unit) if np.isfinite(d[k]) else "–" for k in ("mean", "std", "median")]
        ci = (f"{si(d['ci_low'], unit)} – {si(d['ci_high'], unit)}" if np.isfinite(d["ci_low"]) else "–")
        rows.append("<tr>" + "".join(f'<td style="padding:2px 8px">{c}</td>' for c in cells + [ci]) + "</tr>")
    head = "".join(f"<th>{h}</th>" for h in ("variant", "n", "mean", "std", "median", "95 % CI of the mean"))
    table = (f'<table style="border-collapse:collapse;text-align:right"><caption style="text-align:left">{html.escape(measure_label(comparison.measure))} over '
             f'{len(comparison.seeds)} seeds</caption><thead><tr>{head}</tr></thead><tbody>{"".join(rows)}'
             f"</tbody></table>")
    picture = ""
    if comparison.values and any(len(comparison.finite(n)) for n in comparison.values):
        with tempfile.TemporaryDirectory(prefix="asperity2d-notebook-") as tmp:
            png = plot_comparison(comparison, Path(tmp) / "comparison.png", dpi=80,
                                  unit="mN" if unit == "N" else "")
            data = base64.b64encode(png.read_bytes()).decode()
        picture = f'<img alt="comparison plot" src="data:image/png;base64,{data}"/>'
    return f'<div class="asperity2d-comparison">{table}{picture}</div>'


__all__ = ["comparison_html", "rest_record", "result_html", "scene_svg"]


def represent(obj, mime: str) -> str:
    """``obj`` for a notebook as ``mime``: a scene as ``"svg"``; a run (either kind) or a comparison
    as ``"html"`` (the back end of :mod:`asperity2d._display`)."""
    from ..scene import Scene

    if mime == "svg" and isinstance(obj, Scene):
        return scene_svg(obj)
    if mime == "html" and getattr(obj, "kind", None) in ("asperity", "belt"):
        return result_html(obj)
    if mime == "html" and hasattr(obj, "versus"):
        return comparison_html(obj)
    raise TypeError(f"no {mime} display for {type(obj).__name__}")
