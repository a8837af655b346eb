"""An interactive player: one self-contained HTML file (no network), ``render(result, "run.html")``.

The file holds the player's JavaScript and CSS (package data beside this
module: ``assets/player.js``, ``assets/player.css``, ``assets/player.html``;
plain modern JavaScript drawing on canvases, no build step, no library) and
the run itself as JSON with its arrays as base64 little-endian typed arrays
(time in float64, the rest float32; contact flags and belt states in int8).
It opens from ``file://`` in any current browser: play / pause, frame step,
scrubbing, playback speed, slow motion through slips (as in the GIF),
zoom (wheel) and pan (drag) of the scene, the same meters as the GIF
(:mod:`.meters`) with a cursor and hover read-outs in engineering units, and
the stick–slip events on a timeline to jump to. ``window.asperityPlayer``
exposes the current frame's drawn state for tests and scripts.

The record is decimated to at most ``max_samples`` samples: every sample
inside a slip (padded as the GIF's slow motion is) is kept, the samples in
between evenly thinned; the first and last samples and each event's own
samples are always kept. The main job's run (12,210 samples) fits whole.
"""

from __future__ import annotations

import base64
import json
import re
import os
from importlib import resources
from pathlib import Path

import numpy as np

from .. import __version__
from .._io import atomic_write_text
from ..errors import SceneError
from .meters import asperity_meters, chain_meters
from .timeline import schedule, slip_intervals

#: Playback at normal speed: the run's stick phases take about this long (s of wall time).
PLAYBACK_SECONDS = 30.0


def _b64(array, dtype) -> dict:
    """``{"dtype", "shape", "data"}``: the array as base64 little-endian bytes of ``dtype`` (f8, f4, i1)."""
    array = np.ascontiguousarray(array, dtype=np.dtype(dtype).newbyteorder("<"))
    return {"dtype": dtype, "shape": list(array.shape), "data": base64.b64encode(array.tobytes()).decode()}


def _clean(value):
    """``value`` with non-finite floats as None (JSON has no NaN)."""
    if isinstance(value, dict):
        return {k: _clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_clean(v) for v in value]
    if isinstance(value, (float, np.floating)):
        return float(value) if np.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.bool_):
        return bool(value)
    return value


def keep_indices(t, slips, max_samples: int, *, pad: float = 0.25) -> np.ndarray:
    """Sample indices to keep: all inside the (padded) slips, evenly thinned elsewhere, ends kept."""
    t = np.asarray(t, dtype=float)
    n = len(t)
    if n <= max_samples:
        return np.arange(n)
    inside = np.zeros(n, dtype=bool)
    marks = []
    for a, b in slips:
        length = b - a
        inside |= (t >= a - pad * length) & (t <= b + pad * length)
        marks += [a, b]
    budget = max_samples - int(inside.sum())
    outside = np.flatnonzero(~inside)
    if budget < 0.2 * max_samples:  # slips alone fill the budget: thin everything evenly
        keep = np.unique(np.linspace(0, n - 1, max_samples).round().astype(np.int64))
    else:
        step = max(1, int(np.ceil(len(outside) / budget)))
        keep = np.union1d(np.flatnonzero(inside), outside[::step])
    exact = np.searchsorted(t, marks) if marks else np.array([], dtype=np.int64)
    return np.union1d(keep, np.clip(np.r_[0, n - 1, exact], 0, n - 1)).astype(np.int64)


def _events(result) -> list[dict]:
    if hasattr(result, "stick_intervals"):
        return [{"t": float(e.t), "mass": int(e.mass), "kind": str(e.kind)} for e in result.events]
    from ..analysis import stick_slip_events
    from ..scene import SpringDrive

    if not isinstance(result.scene.drive, SpringDrive):
        return []
    return [{"t_stick": e.t_stick, "t_slip": e.t_slip, "t_end": e.t_end, "force_peak": e.force_peak,
             "force_drop": e.force_drop, "slip_distance": e.slip_distance, "complete": e.complete}
            for e in stick_slip_events(result)]


def payload(result, *, max_samples: int = 8000, camera: str = "follow") -> dict:
    """The JSON-ready record the player draws (see the module docstring)."""
    from .animate import is_chain

    if len(result.t) < 1:
        raise SceneError("`result` has no samples to play")
    if isinstance(max_samples, bool) or not isinstance(max_samples, (int, np.integer)) or max_samples < 100:
        raise SceneError(f"`max_samples` must be an integer >= 100, got {max_samples!r}")
    t = np.asarray(result.t, dtype=float)
    slips = slip_intervals(result)
    keep = keep_indices(t, slips, int(max_samples))
    plan = schedule(t, slips, max(2, int(PLAYBACK_SECONDS * 20)))
    data = {"format": "asperity2d.player/1", "version": __version__, "samples": int(len(keep)),
            "recorded": int(len(t)), "t": _b64(t[keep], "f8"), "events": _events(result),
            "slips": [[float(a), float(b)] for a, b in slips],
            "slow": [[a, b, s] for a, b, s in plan.intervals],
            "frame_step": plan.normal_step, "fps": 20}
    series: dict[str, dict] = {}
    meters = chain_meters(result) if is_chain(result) else asperity_meters(result)
    data["meters"] = []
    for m, spec in enumerate(meters):
        js = spec.to_json()
        for j, trace in enumerate(js["traces"]):
            name = f"m{m}_{j}"
            series[name] = _b64(np.asarray(trace.pop("values"), float)[keep], "f4")
            trace["series"] = name
        data["meters"].append(js)
    if is_chain(result):
        data["kind"] = "chain"
        data["scene"], extra = _chain_scene(result, keep)
        data["title"] = f"belt chain, {result.n} masses"
    else:
        data["kind"] = "asperity"
        data["scene"], extra = _asperity_scene(result, keep, camera)
        data["title"] = repr(result.scene)
    series.update(extra)
    data["series"] = series
    return data


def _asperity_scene(result, keep, camera):
    from .stage import ARROW_PX, Stage, tip_force_scale

    scene = result.scene
    # the GIF's own camera, computed for every kept sample (the player's default view)
    stage = Stage(result, width=960, height=200, camera=camera, frames=keep)
    whole = Stage(result, width=960, height=200, camera="whole", exaggeration=stage.exaggeration)
    lower, slider = scene.lower, scene.slider
    geometry = {
        "base": scene.base, "pitch": stage.pitch, "floor": stage.floor,
        "lower_x": stage.lower_x.tolist(), "levels": stage.levels.tolist(), "summits": stage.summits.tolist(),
        "lower_polys": [np.asarray(p, float).tolist() for p in lower.outlines()],
        "stiffness": [float(k) for k in lower.stiffness],
        "upper_x": stage.upper_x.tolist(), "upper_polys": [np.asarray(p, float).tolist() for p in slider.outlines()],
        "rear": stage.rear, "front": stage.front, "has_drive": stage.has_drive,
        "substrate": [np.asarray(line, float).tolist() for line in stage.substrate],
        "camera": camera, "view_width": stage.width / stage.scale, "exaggeration": stage.exaggeration,
        "whole_left": float(whole.lefts[0]), "whole_width": whole.width / whole.scale,
        "y_top": float(np.nanmax(stage.y)), "lateral": bool(np.any(np.asarray(result.lower_dx) != 0)),
        "n_lower": int(lower.count),
    }
    r = result
    series = {"x": _b64(np.asarray(r.x)[keep], "f8"), "y": _b64(np.asarray(r.y)[keep], "f8"),
              "v": _b64(np.asarray(r.v)[keep], "f4"),
              "drive_x": _b64(np.asarray(r.drive_x)[keep], "f8"),
              "friction_force": _b64(np.asarray(r.friction_force)[keep], "f4"),
              "normal_force": _b64(np.asarray(r.normal_force)[keep], "f4"),
              "lower_dy": _b64(np.asarray(r.lower_dy)[:, keep], "f4"),
              "lower_contact": _b64(np.asarray(r.lower_contact)[:, keep], "i1"),
              "slipping": _b64(stage.slipping[keep], "i1"),
              "camera_left": _b64(stage.lefts[keep], "f8")}
    if geometry["lateral"]:
        series["lower_dx"] = _b64(np.asarray(r.lower_dx)[:, keep], "f4")
    geometry["force_scale"], geometry["arrow_px"] = tip_force_scale(result, keep), ARROW_PX
    return geometry, series


def _chain_scene(result, keep):
    from .belt_stage import ChainStage

    stage = ChainStage(result, width=960, height=220)
    x = np.asarray(result.x, float)
    geometry = {"n": result.n, "k": stage.k.tolist(), "c": stage.c.tolist(),
                "reach": float(np.max(np.abs(x))) if x.size else 0.0,
                "force_scale": float(np.percentile(np.abs(stage.friction), 99)) if stage.friction.size else 0.0,
                "belt": stage.belt_v is not None}
    series = {f"x{i}": _b64(x[i, keep], "f8") for i in range(result.n)}
    series.update({f"f{i}": _b64(stage.friction[i, keep], "f4") for i in range(result.n)})
    series["state"] = _b64(np.asarray(result.state)[:, keep], "i1")
    series["belt_s"] = _b64(stage.belt_s[keep], "f8")
    if stage.belt_v is not None:
        series["belt_v"] = _b64(stage.belt_v[keep], "f4")
    return geometry, series


def asset(name: str) -> str:
    """The text of one of the player's package data files (``assets/<name>``)."""
    return resources.files(__package__).joinpath("assets", name).read_text(encoding="utf-8")


def page(result, **options) -> str:
    """The player's whole HTML document for ``result``."""
    data = script_json(_clean(payload(result, **options)))
    parts = {"{{TITLE}}": _escape(data_title(result)), "/*{{CSS}}*/": asset("player.css"),
             "/*{{JS}}*/": asset("player.js"), "{{DATA}}": data}
    # one pass over the template: a scene named "{{DATA}}" stays text and is not filled in
    return re.sub("|".join(map(re.escape, parts)), lambda m: parts[m.group(0)], asset("player.html"))


#: Characters JSON may hold that HTML would read inside a ``<script>`` element (``</script>``,
#: ``<!--`` starting the script's "double escaped" state, which hides the rest of the page), or an
#: attribute (``&``), and the two line separators old JavaScript parsers reject in strings.
_SCRIPT_UNSAFE = {"<": "\\u003c", ">": "\\u003e", "&": "\\u0026", "\u2028": "\\u2028", "\u2029": "\\u2029"}


def script_json(value) -> str:
    """``value`` as JSON safe to embed in an HTML ``<script>`` element: every ``<``, ``>`` and
    ``&`` written as a ``\\u`` escape (the same string to JavaScript), so no data -- a scene named
    ``<!--<script>`` -- can end the element or blank the page."""
    text = json.dumps(value, separators=(",", ":"), allow_nan=False)
    for char, escaped in _SCRIPT_UNSAFE.items():
        text = text.replace(char, escaped)
    return text


def data_title(result) -> str:
    from .animate import is_chain

    if is_chain(result):
        return f"asperity2d player: belt chain of {result.n} masses"
    return f"asperity2d player: {result.scene.name or 'asperity run'}"


def _escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace('"', "&quot;")


def write_player(result, path: str | os.PathLike, *, max_samples: int = 8000, camera: str = "follow") -> Path:
    """Write the player for ``result`` (Result or BeltResult) to ``path`` (``.html``) atomically."""
    path = Path(path)
    if path.suffix.lower() not in (".html", ".htm"):
        raise SceneError(f"`path` must end in .html, got {str(path)!r}")
    return atomic_write_text(path, page(result, max_samples=max_samples, camera=camera))


__all__ = ["PLAYBACK_SECONDS", "asset", "keep_indices", "page", "payload", "script_json", "write_player"]
