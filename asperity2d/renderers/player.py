"""An interactive player: one self-contained HTML file (no network), ``render(result, "run.html")``,
and the same player as a component of other pages (the workbench app, the notebook widget).

The file holds the player's JavaScript and CSS (package data beside this
module: ``assets/player.js``, ``assets/player.css``, ``assets/player.html``;
plain modern JavaScript drawing on canvases, no build step, no library) and
the run itself as JSON with its arrays as base64 little-endian typed arrays
(time and the slider's series in float64, so a meter's CSV export gives the
result's own numbers; contact flags and belt states in int8). It opens from
``file://`` in any current browser: play / pause, frame step, scrubbing,
playback speed, slow motion through slips (as in the GIF), zoom (wheel), pan
(drag) and a ruler on the scene, hover on a contact for its force, meters
with a channel to choose each (the GIF's four, normal force, slider y,
per-tip contact force, lower asperity deflections, the energy book), box
zoom in time (linked across meters) and value, double-click to reset, values
off the axis marked, CSV / PNG / SVG export of a meter and PNG / SVG of the
frame, and the stick–slip events beside the scene to jump into.
``window.asperityPlayer`` exposes the current frame's drawn state for tests
and scripts.

As a component (``window.AsperityPlayer.create(root, payload, options)``, see
the comment at the top of ``player.js``): :func:`scene_payload` is the static
payload of a scene before any sample, :func:`chunk_payload` a slice of a
record's samples for ``player.append`` (a run streamed as it is computed), and
:func:`final_payload` what ``player.finish`` takes; :func:`payload` is the
three at once for a finished run.

The record is decimated to at most ``max_samples`` samples: every sample
inside a slip (padded as the GIF's slow motion is) is kept, the samples in
between evenly thinned; the first and last samples and each event's own
samples are always kept.
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


def human_title(scene) -> str:
    """A title a person reads: "Ooten's fixed track — 16 regular lower asperities, 4-tip slider,
    spring drive 20 m/s" (not the scene's repr)."""
    from .._format import si
    from ..scene import RandomSpacing, RegularSpacing, SpringDrive

    lower, slider, drive = scene.lower, scene.slider, scene.drive
    setup = ("Ooten's fixed track" if slider.track == "fixed"
             else f"free slider under {si(slider.normal_load, 'N', trim=True)}")
    spacing = ("regular " if isinstance(lower.spacing, RegularSpacing)
               else "random " if isinstance(lower.spacing, RandomSpacing) else "")
    kind = {"full": "", "half": " half-triangle", "flat": " flat"}.get(lower.profile.kind, f" {lower.profile.kind}")
    if lower.shapes is not None:
        spacing, kind = "", " measured-profile"
    text = (f"{setup} \u2014 {lower.count} {spacing}lower{kind} asperit{'ies' if lower.count != 1 else 'y'}, "
            f"{slider.count}-tip slider, ")
    if isinstance(drive, SpringDrive):
        text += f"spring drive {si(drive.velocity, 'm/s', trim=True)}"
    else:
        text += f"constant force {si(drive.force, 'N', trim=True)}"
    return text


#: The meters the player opens with (channel ids), as on the GIF.
DEFAULT_METERS = ("drive", "contact", "position", "velocity")


def _hex(name: str) -> str:
    from . import raster

    return "#%02x%02x%02x" % raster.COLOURS[name]


def asperity_channels(result=None, n_lower: int | None = None) -> list[dict]:
    """What a meter of an asperity run can show: ``{id, title, unit, group, limits, traces: [{label,
    series, row, colour, dashed}]}``; ``limits`` (SI) from the whole ``result`` for the four meters
    the GIF has (the same axes), else None (the player fits them to the samples it holds)."""
    from . import raster

    specs = asperity_meters(result) if result is not None else None
    lim = (lambda k: list(specs[k].limits)) if specs is not None else (lambda k: None)
    position = [{"label": "slider", "series": "x", "colour": _hex("c0")}]
    if result is None or np.isfinite(np.asarray(result.drive_x, float)).any():
        position.append({"label": "drive end", "series": "drive_x", "colour": _hex("c6"), "dashed": True})
    n = n_lower if n_lower is not None else int(result.scene.lower.count)
    colours = ["#%02x%02x%02x" % raster.COLOURS[raster.TRACE_COLOURS[j % len(raster.TRACE_COLOURS)]]
               for j in range(n)]
    out = [
        {"id": "drive", "title": "drive force", "unit": "N", "group": "slider", "limits": lim(0),
         "traces": [{"label": "drive", "series": "drive_force", "colour": _hex("c1")}]},
        {"id": "contact", "title": "contact force on the slider", "unit": "N", "group": "slider", "limits": lim(1),
         "traces": [{"label": "friction (total)", "series": "friction_force", "colour": _hex("c2")},
                    {"label": "tangential", "series": "tangential_force", "colour": _hex("c3")}]},
        {"id": "position", "title": "position", "unit": "m", "group": "slider", "limits": lim(2),
         "include_zero": False, "traces": position},
        {"id": "velocity", "title": "slider velocity", "unit": "m/s", "group": "slider", "limits": lim(3),
         "traces": [{"label": "slider", "series": "v", "colour": _hex("c4")}]},
        {"id": "normal", "title": "normal force on the slider", "unit": "N", "group": "slider", "limits": None,
         "traces": [{"label": "normal", "series": "normal_force", "colour": _hex("c5")}]},
        {"id": "y", "title": "slider height y", "unit": "m", "group": "slider", "limits": None,
         "include_zero": False, "traces": [{"label": "slider y", "series": "y", "colour": _hex("c0")}]},
        {"id": "vy", "title": "slider vertical velocity", "unit": "m/s", "group": "slider", "limits": None,
         "traces": [{"label": "slider vy", "series": "vy", "colour": _hex("c4")}]},
        {"id": "lower_dy", "title": "lower asperity deflections", "unit": "m", "group": "lower asperities",
         "limits": None, "traces": [{"label": f"tip {j + 1}", "series": "lower_dy", "row": j, "colour": colours[j]}
                                    for j in range(n)]},
    ]
    out += [{"id": f"lower_dy_{j}", "title": f"lower asperity {j + 1} deflection", "unit": "m",
             "group": "lower asperities", "limits": None,
             "traces": [{"label": f"tip {j + 1}", "series": "lower_dy", "row": j, "colour": colours[j]}]}
            for j in range(n)]
    return out


#: Scalar series of an asperity run the player carries (float64: a meter's CSV gives the result's
#: own numbers), and the per-asperity ones.
SCALARS = ("x", "y", "v", "vy", "drive_x", "drive_force", "friction_force", "tangential_force", "normal_force")


def _asperity_series(result, idx, slipping) -> dict:
    r = result
    series = {name: _b64(np.asarray(getattr(r, name), float)[idx], "f8") for name in SCALARS}
    series["lower_dy"] = _b64(np.asarray(r.lower_dy, float)[:, idx], "f8")
    series["lower_contact"] = _b64(np.asarray(r.lower_contact)[:, idx], "i1")
    series["slipping"] = _b64(np.asarray(slipping)[idx], "i1")
    if np.any(np.asarray(r.lower_dx) != 0):
        series["lower_dx"] = _b64(np.asarray(r.lower_dx, float)[:, idx], "f4")
    return series


def payload(result, *, max_samples: int = 8000, camera: str = "follow") -> dict:
    """The JSON-ready record the player draws (see the module docstring): :func:`scene_payload`'s
    static part, every kept sample (:func:`chunk_payload`'s keys) and :func:`final_payload`."""
    from .animate import is_chain

    if len(result.t) < 1:
        raise SceneError("`result` has no samples to play")
    if isinstance(max_samples, bool) or not isinstance(max_samples, (int, np.integer)) or max_samples < 100:
        raise SceneError(f"`max_samples` must be an integer >= 100, got {max_samples!r}")
    t = np.asarray(result.t, dtype=float)
    slips = slip_intervals(result)
    keep = keep_indices(t, slips, int(max_samples))
    data = {"format": "asperity2d.player/2", "version": __version__, "samples": int(len(keep)),
            "recorded": int(len(t)), "t": _b64(t[keep], "f8"), "complete": True}
    data.update(final_payload(result, slips=slips))
    if is_chain(result):
        data["kind"] = "chain"
        data["scene"], data["series"] = _chain_scene(result, keep)
        data["channels"] = _chain_channels(result)
        data["meters"] = [c["id"] for c in data["channels"]]
    else:
        data["kind"] = "asperity"
        data["scene"], stage = _asperity_geometry(result, camera, keep)
        data["series"] = _asperity_series(result, keep, stage.slipping)
        data["series"]["camera_left"] = _b64(stage.lefts[keep], "f8")
        data["channels"] = asperity_channels(result)
        data["meters"] = list(DEFAULT_METERS)
    return data


def scene_payload(scene, *, camera: str = "follow", duration: float | None = None) -> dict:
    """The player's static payload of ``scene`` before any sample (a run to be streamed in with
    :func:`chunk_payload` and closed with :func:`final_payload`): geometry, channels (their axes
    fitted to the samples as they come), a human title. ``duration`` (s): the time axes' span
    while the run streams (default: the samples so far)."""
    from .stage import rest_record

    rest = rest_record(scene)
    geometry, _ = _asperity_geometry(rest, camera, None)
    geometry["force_scale"] = 0.0  # known at the end (final_payload)
    return {"format": "asperity2d.player/2", "version": __version__, "kind": "asperity", "complete": False,
            "samples": 0, "recorded": 0, "t": _b64(np.zeros(0), "f8"), "series": {}, "scene": geometry,
            "channels": asperity_channels(None, n_lower=int(scene.lower.count)), "meters": list(DEFAULT_METERS),
            "events": [], "slips": [], "slow": [], "frame_step": None, "fps": 20,
            "duration": float(duration) if duration else None, "title": human_title(scene)}


def chunk_payload(result, start: int, stop: int | None = None) -> dict:
    """Samples ``start`` to ``stop`` (exclusive; default: all held) of ``result`` (a whole or
    partial record: any object with the Result's arrays) for ``player.append``: the same per-sample
    keys and encoding as :func:`payload`. A sample is "slipping" by the events found in the
    samples held so far (the last slip of a partial record may end later)."""
    from .stage import slip_mask

    n = len(result.t)
    stop = n if stop is None else int(stop)
    if not (0 <= int(start) <= stop <= n):
        raise SceneError(f"`start`, `stop` must satisfy 0 <= start <= stop <= {n}, got {start!r}, {stop!r}")
    idx = np.arange(int(start), stop)
    try:
        slipping = slip_mask(result)
    except Exception:  # too few samples for the event finder: nothing is slipping yet
        slipping = np.zeros(n, dtype=bool)
    return {"format": "asperity2d.player.chunk/2", "start": int(start),
            "t": _b64(np.asarray(result.t, float)[idx], "f8"), "series": _asperity_series(result, idx, slipping)}


def final_payload(result, *, slips=None) -> dict:
    """What ``player.finish`` takes once ``result`` is complete: events, slips, slow-motion
    intervals, frame step, the GIF's meter axes, the arrows' force scale, the title."""
    from .animate import is_chain

    t = np.asarray(result.t, dtype=float)
    slips = slip_intervals(result) if slips is None else slips
    frames = max(2, int(PLAYBACK_SECONDS * 20))
    if is_chain(result):
        plan = schedule(t, slips, frames)
    else:  # the GIF's slow motion: slower still where the slider moves fast (a frame step < a pitch)
        plan = schedule(t, slips, frames, x=result.x, pitch=result.scene.lower.spacing.mean_pitch)
    slow = plan.rates or plan.intervals
    out = {"events": _events(result), "slips": [[float(a), float(b)] for a, b in slips],
           "slow": [[a, b, s] for a, b, s in slow if s > 1], "frame_step": plan.normal_step, "fps": 20,
           "recorded": int(len(t))}
    if is_chain(result):
        out["title"] = f"belt chain, {result.n} masses"
    else:
        from .stage import tip_force_scale

        out["title"] = human_title(result.scene)
        out["limits"] = {c["id"]: c["limits"] for c in asperity_channels(result) if c["limits"] is not None}
        out["force_scale"] = tip_force_scale(result, np.arange(len(t)))
    return out


def _asperity_geometry(result, camera, keep):
    from .stage import ARROW_PX, Stage, tip_force_scale

    scene = result.scene
    # the GIF's own camera, computed for every kept sample (the player's default view)
    stage = Stage(result, width=960, height=200, camera=camera, frames=keep)
    whole = Stage(result, width=960, height=200, camera="whole", exaggeration=stage.exaggeration)
    lower, slider = scene.lower, scene.slider
    from ..scene import SpringDrive

    geometry = {
        "base": scene.base, "pitch": stage.pitch, "floor": stage.floor,
        "lower_x": stage.lower_x.tolist(), "levels": stage.levels.tolist(), "summits": stage.summits.tolist(),
        "lower_polys": [np.asarray(p, float).tolist() for p in lower.outlines()],
        "stiffness": [float(k) for k in lower.stiffness],
        "upper_x": stage.upper_x.tolist(), "upper_polys": [np.asarray(p, float).tolist() for p in slider.outlines()],
        "rear": stage.rear, "front": stage.front, "has_drive": isinstance(scene.drive, SpringDrive),
        "substrate": [np.asarray(line, float).tolist() for line in stage.substrate],
        "camera": camera, "view_width": stage.width / stage.scale, "exaggeration": stage.exaggeration,
        "whole_left": float(whole.lefts[0]), "whole_width": whole.width / whole.scale,
        "y_top": float(np.nanmax(stage.y)), "n_lower": int(lower.count),
        "slider_mass": float(slider.mass),
        "drive_stiffness": float(scene.drive.stiffness) if isinstance(scene.drive, SpringDrive) else 0.0,
    }
    frames = np.arange(len(result.t)) if keep is None else keep
    geometry["force_scale"], geometry["arrow_px"] = tip_force_scale(result, frames), ARROW_PX
    return geometry, stage


def _chain_channels(result) -> list[dict]:
    specs = chain_meters(result)
    names = ("position", "velocity", "friction")
    series = {"position": "x", "velocity": "v", "friction": "f"}
    out = []
    for key, spec in zip(names, specs):
        js = spec.to_json()
        traces = []
        for j, tr in enumerate(js["traces"]):
            name = "belt_v" if tr["label"] == "belt" else f"{series[key]}{j}"
            traces.append({"label": tr["label"], "series": name, "colour": tr["colour"], "dashed": tr["dashed"]})
        out.append({"id": key, "title": spec.title, "unit": spec.unit, "group": "masses",
                    "limits": list(spec.limits), "traces": traces})
    return out


def _chain_scene(result, keep):
    from .belt_stage import ChainStage

    stage = ChainStage(result, width=960, height=220)
    x = np.asarray(result.x, float)
    v = np.asarray(result.v, float)
    geometry = {"n": result.n, "k": stage.k.tolist(), "c": stage.c.tolist(),
                "reach": float(np.max(np.abs(x))) if x.size else 0.0,
                "force_scale": float(np.percentile(np.abs(stage.friction), 99)) if stage.friction.size else 0.0,
                "belt": stage.belt_v is not None}
    series = {f"x{i}": _b64(x[i, keep], "f8") for i in range(result.n)}
    series.update({f"v{i}": _b64(v[i, keep], "f8") for i in range(result.n)})
    series.update({f"f{i}": _b64(np.asarray(result.friction_force, float)[i, keep], "f8") for i in range(result.n)})
    series["state"] = _b64(np.asarray(result.state)[:, keep], "i1")
    series["belt_s"] = _b64(stage.belt_s[keep], "f8")
    if result.chain is not None:
        belt_v = np.asarray(result.chain.belt_velocity(result.t), float) * np.ones(len(result.t))
        series["belt_v"] = _b64(belt_v[keep], "f8")
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
    return f"asperity2d player: {human_title(result.scene)}"


def _escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace('"', "&quot;")


def write_player(result, path: str | os.PathLike, *, max_samples: int = 8000, camera: str = "follow") -> Path:
    """Write the player for ``result`` (Result or BeltResult) to ``path`` (``.html``) atomically."""
    path = Path(path)
    if path.suffix.lower() not in (".html", ".htm"):
        raise SceneError(f"`path` must end in .html, got {str(path)!r}")
    return atomic_write_text(path, page(result, max_samples=max_samples, camera=camera))


__all__ = ["DEFAULT_METERS", "PLAYBACK_SECONDS", "asperity_channels", "asset", "chunk_payload", "final_payload",
           "human_title", "keep_indices", "page", "payload", "scene_payload", "script_json", "write_player"]
