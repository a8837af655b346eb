"""The workbench's message protocol, the same for both hosts (the web server's WebSocket and the
notebook widget's custom messages): JSON objects with a ``type``.

From the page:

* ``{"type": "hello"}`` -> ``schema`` (the controls), ``measures``, ``values`` (the scene's
  texts), and a first run;
* ``{"type": "set", "values": {name: text}}`` -> ``invalid`` (one line per refused control;
  nothing runs) or ``valid`` and a new run (the one in flight cancelled): ``run-start`` (the
  player's static payload), ``run-chunk`` (samples as they are computed, the player's chunk
  payload), ``run-end`` (the player's final payload and the summary);
* ``{"type": "cancel", "lane": "run"|"measure"|"variants"|"ensemble"}``;
* ``{"type": "measure", "name": ...}`` -> ``measure-progress`` (elapsed s) then ``measure-result``
  (value, unit, label) or ``measure-error``;
* ``{"type": "variants", "preset": "spacing"|"profile"|"damping"}`` (or ``"variants": {name:
  {param: text}}``) -> ``variants-start`` and, per variant, ``variant-start`` / ``variant-chunk``
  / ``variant-end``, each streamed into its own player;
* ``{"type": "ensemble", "measure", "seeds": N, "variants": {...}|"preset"}`` ->
  ``ensemble-start``, ``ensemble-value`` per (variant, seed) as it arrives, ``ensemble-stats``
  (running ratio, interval, Wilcoxon p, verdict), ``ensemble-end``; with ``"seeds": "auto"``
  (and ``"max_seeds"``, ``"stage_seeds"``) the seeds come in stages until every verdict is
  decided, as ``compare(seeds="auto")``: an ``ensemble-stage`` before each, the ``look`` of each
  ``ensemble-stats`` (an interim one between looks; ``more``: about how many seeds would decide
  an undecided row), and the seeds spent and whether it was decided in ``ensemble-end``;
* ``{"type": "export", "what": "toml"|"python"|"npz"}`` -> ``export`` with the text, or the
  ``.npz`` file of the last finished run as base64.

Every refusal and failure is a message (``error`` with the lane); nothing the page sends can
raise out of :meth:`Session.handle`.
"""

from __future__ import annotations

import base64
import json
import logging
import math
import os
import threading
import time

from ..errors import SceneError
from . import controls
from .jobs import OFFERED, Lane, ensemble, error_text, format_exception, measure_in_child, measure_info

log = logging.getLogger("asperity2d.app")

#: A chunk of samples goes to the page at most this often (s), and the first one at once.
CHUNK_INTERVAL = 0.12
#: The run yields its partial record every this many samples (the cancellation granularity).
EVERY = 20
#: Largest message the page may send (characters).
MAX_MESSAGE = 200_000
#: Variant presets: two or more scenes side by side.
PRESETS = {
    "spacing": {"regular": {"spacing": "regular"}, "random": {"spacing": "random"}},
    "profile": {"full": {"profile": "full"}, "half": {"profile": "half"}},
    "damping": {"damped": {"damping_ratio": 0.1}, "undamped": {"damping_ratio": 0.0}},
}
MAX_SEEDS = 200
#: The seed budget of an ensemble with ``seeds: "auto"`` when the page gives none (compare()'s).
AUTO_MAX_SEEDS = 40


def _whole(value, name: str, low: int, high: int, *, also: str = "") -> int:
    """A whole number from the page in [low, high], else one line naming it."""
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise SceneError(f"`{name}` must be a whole number from {low} to {high}{' ' + also if also else ''}, "
                         f"got {str(value)[:40]!r}")
    return value


def dumps(message: dict) -> str:
    """Strict JSON (NaN and infinities as null), as the player's payloads are."""
    from ..renderers.player import _clean

    return json.dumps(_clean(message), separators=(",", ":"), allow_nan=False)


class Session:
    """One page's workbench: its scene texts, the lanes of its jobs, the last finished run.

    ``send(text)`` delivers one JSON message to the page (from any thread). ``values`` are the
    starting texts (``controls.texts`` of a scene file)."""

    def __init__(self, send, *, values: dict | None = None, workers: int | None = None):
        self._send = send
        self.values = dict(values or {})
        self.params, self.run_settings = {}, {}
        self.workers = workers
        self.result = None  # the last finished run
        self.closed = False
        self.lanes = {name: Lane(name, work, self._failed) for name, work in (
            ("run", self._run), ("measure", self._measure), ("variants", self._variants),
            ("ensemble", self._ensemble))}

    # -- plumbing ------------------------------------------------------------------------------
    def emit(self, message: dict) -> None:
        if self.closed:
            return
        try:
            self._send(dumps(message))
        except Exception as exc:  # the page went away: stop its work
            log.debug("send failed: %s", exc)
            self.close()

    def _failed(self, job, exc) -> None:
        lane = next((n for n, ln in self.lanes.items() if ln.current is job), "")
        log.debug("job failed:\n%s", format_exception(exc))
        self.emit({"type": "error", "lane": lane, "job": job.id, "message": error_text(exc)})

    def close(self) -> None:
        """Stop every job of this page (the tab was closed), and the ensemble's worker processes
        when no other page's ensemble uses them."""
        if self.closed:
            return
        self.closed = True
        for lane in self.lanes.values():
            lane.close(timeout=0)
        with _ENSEMBLES_LOCK:
            used = _ENSEMBLES.pop(self, None)
            others = set().union(*_ENSEMBLES.values()) if _ENSEMBLES else set()
        for workers in (used or set()) - others:
            stop_workers(workers)

    def handle(self, message) -> None:
        """Act on one message from the page (text or a decoded object); never raises."""
        try:
            if isinstance(message, (str, bytes)):
                if len(message) > MAX_MESSAGE:
                    raise SceneError(f"a message must be under {MAX_MESSAGE:,} characters")
                message = json.loads(message)
            if not isinstance(message, dict) or not isinstance(message.get("type"), str):
                raise SceneError("a message must be an object with a `type`")
            kind = message["type"]
            handler = getattr(self, "_on_" + kind.replace("-", "_"), None) if kind.isidentifier() or \
                kind.replace("-", "_").isidentifier() else None
            if handler is None:
                raise SceneError(f"unknown message type {kind[:40]!r}")
            handler(message)
        except (SceneError, ValueError, TypeError, KeyError, RecursionError) as exc:
            self.emit({"type": "error", "lane": "", "message": error_text(exc) if isinstance(exc, SceneError)
                       else f"bad message: {type(exc).__name__}"})
        except Exception as exc:  # noqa: BLE001 -- one line to the page, the traceback to the debug log
            log.debug("message failed:\n%s", format_exception(exc))
            self.emit({"type": "error", "lane": "", "message": error_text(exc)})

    # -- messages ------------------------------------------------------------------------------
    def _on_hello(self, message) -> None:
        self.emit({"type": "schema", **controls.schema()})
        self.emit({"type": "measures", "measures": [
            {k: v for k, v in measure_info(n).items() if k != "fn"} for n in OFFERED],
            "presets": {k: list(v) for k, v in PRESETS.items()}})
        self.emit({"type": "values", "values": self.values})
        self._on_set({"values": self.values})

    def _scene_of(self, values, changed=None):
        params, run, errors = controls.parse(values)
        if errors:
            return None, params, run, errors
        scene, errors = controls.build(params, changed)
        if errors:
            return None, params, run, errors
        try:  # what simulate would refuse (the step budget, a stop), refused before any run starts
            controls.check_run(scene, run)
        except SceneError as exc:
            text = str(exc).splitlines()[0]
            return None, params, run, {controls.blame(text, {**params, **run}, changed): text}
        return scene, params, run, None

    def _on_set(self, message) -> None:
        values = message.get("values", {})
        changed = message.get("changed")
        changed = changed if isinstance(changed, str) and isinstance(values, dict) and changed in values else None
        scene, params, run, errors = self._scene_of(values, changed)
        if errors:  # nothing runs; the run on screen stays
            self.emit({"type": "invalid", "errors": errors})
            return
        self.values, self.params, self.run_settings = dict(values), params, run
        self.emit({"type": "valid", "python": controls.to_python(params, run), "values": self.values,
                   "bodies": bodies(scene)})
        self.lanes["run"].submit((scene, run))

    def _on_cancel(self, message) -> None:
        lane = message.get("lane", "run")
        if lane not in self.lanes:
            raise SceneError(f"`lane` must be one of {', '.join(self.lanes)}")
        self.lanes[lane].cancel()
        self.emit({"type": "cancelled", "lane": lane})

    def _on_measure(self, message) -> None:
        name = message.get("name")
        if name not in OFFERED:
            raise SceneError(f"`measure` must be one of {', '.join(OFFERED)}")
        self.lanes["measure"].submit((name, dict(self.params)))

    def _variant_set(self, message) -> dict:
        preset = message.get("preset")
        if preset is not None:
            if preset not in PRESETS:
                raise SceneError(f"`preset` must be one of {', '.join(PRESETS)}")
            return PRESETS[preset]
        variants = message.get("variants")
        if not isinstance(variants, dict) or not 2 <= len(variants) <= 6:
            raise SceneError("`variants` must name 2 to 6 variants")
        out = {}
        for name, values in variants.items():
            params, _, errors = controls.parse(values)
            if errors:
                raise SceneError(next(iter(errors.values())))
            out[str(name)[:40]] = params
        return out

    def _on_variants(self, message) -> None:
        variants = self._variant_set(message)
        scenes = {}
        for name, kw in variants.items():
            scene, errors = controls.build({**self.params, **kw})
            if errors:
                raise SceneError(f"variant {name}: {next(iter(errors.values()))}")
            scenes[name] = scene
        self.lanes["variants"].submit((scenes, self.run_settings.get("duration")))

    def _on_ensemble(self, message) -> None:
        name = message.get("measure")
        if name not in OFFERED:
            raise SceneError(f"`measure` must be one of {', '.join(OFFERED)}")
        seeds = message.get("seeds", 4)
        auto = None
        if seeds == "auto":  # stages until decided, as compare(seeds="auto", max_seeds=...)
            auto = {"max_seeds": _whole(message.get("max_seeds", AUTO_MAX_SEEDS), "max_seeds", 2, MAX_SEEDS)}
            if "stage_seeds" in message:
                auto["stage_seeds"] = _whole(message["stage_seeds"], "stage_seeds", 2, auto["max_seeds"])
        else:
            seeds = _whole(seeds, "seeds", 2, MAX_SEEDS, also="or 'auto'")
        variants = self._variant_set(message)
        base = {k: v for k, v in self.params.items() if k not in ("seed",)}
        for vname, kw in variants.items():  # refused before anything runs
            _, errors = controls.build({**base, **kw, "seed": 0})
            if errors:
                raise SceneError(f"variant {vname}: {next(iter(errors.values()))}")
        self.lanes["ensemble"].submit({"measure": name, "variants": variants, "base": base,
                                       **({"auto": auto} if auto else {"seeds": list(range(seeds))})})

    def _on_export(self, message) -> None:
        what = message.get("what")
        if what == "toml":
            self.emit({"type": "export", "what": "toml", "filename": "scene.toml", "mime": "application/toml",
                       "text": controls.to_toml(self.params, self.run_settings)})
        elif what == "python":
            self.emit({"type": "export", "what": "python", "filename": "scene.py", "mime": "text/x-python",
                       "text": controls.to_python(self.params, self.run_settings)})
        elif what == "npz":
            if self.result is None:
                raise SceneError("no finished run to save yet")
            self.emit({"type": "export", "what": "npz", "filename": "run.npz", "mime": "application/octet-stream",
                       "base64": base64.b64encode(npz_bytes(self.result)).decode()})
        else:
            raise SceneError("`what` must be toml, python or npz")

    # -- the jobs ------------------------------------------------------------------------------
    def _stream(self, scene, duration, job, kinds: tuple[str, str, str], extra: dict, stop=()) -> object:
        """Run ``scene`` in pieces, sending its samples as they come (``kinds``: the start, chunk
        and end message types); return the Result. Stops at the first check after a cancel.
        ``stop``: the run's stop conditions (``simulate``'s ``stop``)."""
        from ..renderers.player import chunk_payload, final_payload, scene_payload
        from ..run import Simulation, default_duration

        start, chunk, end = kinds
        sim = Simulation(scene, duration, every=EVERY, progress=False, stop=list(stop))
        # the time axes while it streams: the last run's length (a change rarely moves it much)
        expected = duration or (float(self.result.t[-1]) if self.result is not None and len(self.result.t) > 1
                                else None) or _expected_duration(scene, default_duration)
        self.emit({"type": start, "job": job.id, **extra, "player": scene_payload(scene, duration=expected)})
        sent, last = 0, 0.0
        try:
            for run in sim:
                job.check()
                now = time.monotonic()
                n = run.samples
                if n > sent and (sent == 0 or now - last >= CHUNK_INTERVAL):
                    part = run.result()
                    self.emit({"type": chunk, "job": job.id, **extra, "chunk": chunk_payload(part, sent, n),
                               "t": float(part.t[-1])})
                    sent, last = n, now
        except BaseException:
            sim.close()
            raise
        result = sim.result
        job.check()
        if len(result.t) > sent:
            self.emit({"type": chunk, "job": job.id, **extra, "chunk": chunk_payload(result, sent),
                       "t": float(result.t[-1])})
        if start == "run-start":
            self.result = result  # before the page hears it has ended (it may ask to save it)
        self.emit({"type": end, "job": job.id, **extra, "final": final_payload(result),
                   "summary": _summary(result)})
        return result

    def _run(self, job) -> None:
        from ..run import stops_from_settings

        scene, run = job.request
        try:
            self._stream(scene, run.get("duration"), job, ("run-start", "run-chunk", "run-end"), {},
                         stop=stops_from_settings(scene, run))
        except SceneError as exc:  # not expected (check_run refused these before): the control's message
            text = str(exc).splitlines()[0]
            self.emit({"type": "invalid", "errors": {controls.blame(text, {"duration": 1, **self.params}): text}})

    def _variants(self, job) -> None:
        scenes, duration = job.request
        self.emit({"type": "variants-start", "job": job.id, "names": list(scenes)})
        for name, scene in scenes.items():
            self._stream(scene, duration, job, ("variant-start", "variant-chunk", "variant-end"), {"variant": name})

    def _measure(self, job) -> None:
        name, params = job.request
        info = measure_info(name)
        self.emit({"type": "measure-start", "job": job.id, "name": name, "label": info["label"]})
        value = measure_in_child(name, params, job, lambda elapsed: self.emit(
            {"type": "measure-progress", "job": job.id, "name": name, "elapsed": elapsed}))
        self.emit({"type": "measure-result", "job": job.id, "name": name, "label": info["label"],
                   "unit": info["unit"], "value": value, "kind": info["kind"], "drive": info["drive"]})

    def _ensemble(self, job) -> None:
        n = self.workers or os.cpu_count() or 1
        with _ENSEMBLES_LOCK:
            if self.closed:
                return
            _ENSEMBLES.setdefault(self, set()).add(n)
        ensemble(job.request, job, self.emit, workers=n)


#: The pages whose ensembles started worker processes, and how many each (the pool's size).
_ENSEMBLES: dict = {}
_ENSEMBLES_LOCK = threading.Lock()


def stop_workers(workers: int) -> None:
    """Shut down the warm pool of ``workers`` processes the ensemble engine keeps (its queued calls
    cancelled; a call in flight finishes first), in the background: closing a tab must not wait."""
    from ..sweep.executors import _pools, _pools_lock, discard_pool

    with _pools_lock:
        pool = _pools.get(workers)
    if pool is not None:
        threading.Thread(target=discard_pool, args=(pool,), name="asperity2d-stop-workers", daemon=True).start()


def bodies(scene) -> dict:
    """What the stage's selection panel shows of each body (SI): every lower asperity's x, height,
    stiffness, damping and mass, and the slider's mass, track, load and start (None: the set-up's)."""
    lower, slider = scene.lower, scene.slider
    return {"lower": {"x": [float(v) for v in lower.tips()], "height": [float(v) for v in lower.heights()],
                      "stiffness": list(lower.stiffness), "damping": list(lower.damping), "mass": list(lower.mass),
                      "pitch": float(lower.spacing.mean_pitch), "base": float(lower.profile.base)},
            "slider": {"mass": float(slider.mass), "track": slider.track, "normal_load": float(slider.normal_load),
                       "count": int(slider.count), "start": slider.start}}


def _expected_duration(scene, default_duration) -> float:
    """The time axis while a run without a duration streams: the default run's time limit."""
    try:
        return float(default_duration(scene))
    except Exception:  # noqa: BLE001
        return math.nan


def _summary(result) -> dict:
    out = result.summary()
    out["samples"] = int(len(result.t))
    return out


def npz_bytes(result) -> bytes:
    """The result's ``.npz`` file (what ``Result.save`` writes) as bytes."""
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory(prefix="asperity2d-app-") as tmp:
        path = Path(tmp) / "run.npz"
        result.save(path)
        return path.read_bytes()


__all__ = ["Session", "PRESETS", "dumps", "npz_bytes"]
