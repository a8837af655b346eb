"""The workbench's controls, generated from the parameter records (not a second list).

:func:`schema` turns :data:`asperity2d.builders.KEYWORDS` and :data:`asperity2d.builders.PARAMETERS`
into the controls the front end draws, grouped as the parameter reference groups them (the
named keywords, Ooten's fixed track, everything else), each with its default, unit and
meaning. The front end sends what the user typed, as text; :func:`parse` reads each value as
``asperity2d run --set KEY=VALUE`` does (a TOML scalar, else the text itself), and
:func:`build` asks :func:`asperity2d.make_scene` -- the validation layer -- whether the scene
is valid: its ``SceneError`` is the control's message, attributed to the parameter it names.
:func:`to_toml` writes the scene file ``asperity2d run`` reproduces; :func:`to_python` the
``make_scene(...)`` call.
"""

from __future__ import annotations

import json
import math
import re
import tomllib

from ..errors import SceneError

#: The run settings beside the scene (a TOML scene's ``[run]`` table): the duration and the
#: "stop when" conditions (:data:`asperity2d.run.STOP_SETTINGS`).
RUN_CONTROLS = ({"name": "duration", "default": None, "unit": "s", "kind": "number",
                 "meaning": "simulated time after settling (default: until the slider has passed the "
                            "lower surface, or a time limit)"},
                {"name": "stop_pitches", "default": None, "unit": "1", "kind": "number",
                 "meaning": "stop when the slider has moved this many pitches"},
                {"name": "stop_force", "default": None, "unit": "N", "kind": "number",
                 "meaning": "stop when the drive force crosses this value"},
                {"name": "stop_first_slip", "default": "false", "unit": "-", "kind": "flag",
                 "meaning": "stop at the first slip"},
                {"name": "stop_stuck", "default": "false", "unit": "-", "kind": "flag",
                 "meaning": "stop when the slider stops"})
#: Run settings that are numbers, and those that are flags.
RUN_NUMBERS, RUN_FLAGS = ("duration", "stop_pitches", "stop_force"), ("stop_first_slip", "stop_stuck")
#: The edits made on the stage that make_scene has no keyword for: the lower asperities' x
#: positions (m), written into the scene as ``ExplicitSpacing`` (see :func:`build`).
EDITS = {"lower_positions": {"name": "lower_positions", "unit": "m",
                             "meaning": "x of each lower asperity (m), set by dragging it on the stage"}}
_NONFINITE = re.compile(r"[+-]?(nan|inf|infinity)", re.IGNORECASE)
#: Longest text a control takes (a path, a list of per-asperity values).
MAX_TEXT = 20_000


def _choices() -> dict:
    """The allowed values of the parameters that take one of a few words (from the builders'
    own tuples)."""
    from .. import builders
    from ..geometry import KINDS

    surface = ("regular", "random")
    return {"spacing": builders.SPACINGS, "profile": KINDS, "drive": ("spring", "force"),
            "track": ("fixed", "free"), "half_shape": builders.HALF_SHAPES,
            "lower_spacing": surface, "upper_spacing": surface, "lower_profile": KINDS,
            "upper_profile": KINDS, "height_distribution": builders.DISTRIBUTIONS,
            "surface_unit": tuple(builders.UNITS),
            "contact_law": tuple(k for k, e in builders.LAWS.items() if e.model == "asperity")}


def groups() -> list[tuple[str, tuple]]:
    """``(title, parameter records)`` as the parameter reference groups them."""
    from ..builders import KEYWORDS, PARAMETERS
    from ..scene import OOTEN_PARAMETERS

    n = len(OOTEN_PARAMETERS)
    return [("make_scene's named keywords", KEYWORDS),
            ("Ooten's fixed track", PARAMETERS[:n]),
            ("everything else", PARAMETERS[n:])]


def _kind(record, choices: dict) -> str:
    if record.name in choices:
        return "choice"
    d = record.default
    if isinstance(d, bool):
        return "flag"
    if isinstance(d, int):
        return "integer"
    if isinstance(d, float):
        return "number"
    if isinstance(d, str):
        return "text"
    return "value"  # derived by default: a number, a list, a path (read as --set reads it)


def _text(value) -> str:
    """A default or a value as the control shows it."""
    if value is None:
        return ""
    if isinstance(value, str):
        return value
    return toml_value(value)


def schema() -> dict:
    """The controls as JSON: ``{"groups": [{"title", "controls": [...]}], "run": [...]}``; a
    control has ``name``, ``default`` (as text), ``unit``, ``meaning``, ``kind`` (choice, flag,
    integer, number, text, value) and ``choices``."""
    choices = _choices()
    out = []
    for title, records in groups():
        out.append({"title": title, "controls": [
            {"name": r.name, "default": _text(r.default), "derived": r.default is None, "unit": r.unit,
             "meaning": r.meaning, "kind": _kind(r, choices), "choices": list(choices.get(r.name, ()))}
            for r in records]})
    return {"groups": out, "run": [dict(c) for c in RUN_CONTROLS]}


def names() -> set[str]:
    return {r.name for _, records in groups() for r in records} | set(EDITS)


def _record(name: str):
    for _, records in groups():
        for r in records:
            if r.name == name:
                return r
    return None


def parse(values) -> tuple[dict, dict, dict]:
    """``(make_scene arguments, run settings, errors)`` from ``{name: text}``: an empty text is
    the default (left out); a name that is no parameter, or a text that is not one, is an error
    of that name (one line)."""
    params, run, errors = {}, {}, {}
    if not isinstance(values, dict):
        return {}, {}, {"": "the values must be an object of name -> text"}
    known = names()
    for name, text in values.items():
        if not isinstance(name, str) or len(name) > 100:
            errors[""] = "a parameter name must be a short text"
            continue
        if isinstance(text, (bool, int, float)) and not isinstance(text, bool):
            text = repr(text)
        if isinstance(text, bool):
            text = "true" if text else "false"
        if not isinstance(text, str):
            errors[name] = f"`{name}` must be given as text, got {type(text).__name__}"
            continue
        if len(text) > MAX_TEXT:
            errors[name] = f"`{name}` is longer than {MAX_TEXT:,} characters"
            continue
        text = text.strip()
        if not text:
            continue
        if name in RUN_NUMBERS:
            try:
                d = float(text)
            except ValueError:
                errors[name] = f"`{name}` must be a number, got {text[:40]!r}"
                continue
            if name == "stop_force":
                if not math.isfinite(d):
                    errors[name] = f"`stop_force` must be a finite number of N, got {text[:40]!r}"
                    continue
            elif not (math.isfinite(d) and d > 0):
                errors[name] = f"`{name}` must be a finite number > 0, got {text[:40]!r}"
                continue
            run[name] = d
            continue
        if name in RUN_FLAGS:
            if text.lower() not in ("true", "false"):
                errors[name] = f"`{name}` must be true or false, got {text[:40]!r}"
                continue
            if text.lower() == "true":
                run[name] = True
            continue
        if name in EDITS:
            value = scalar(text)
            if not isinstance(value, list) or not all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                                      for v in value):
                errors[name] = f"`{name}` must be a list of numbers (m), got {text[:40]!r}"
                continue
            params[name] = [float(v) for v in value]
            continue
        if name not in known:
            errors[name] = f"`{name}` is not a make_scene parameter"
            continue
        record = _record(name)
        if isinstance(record.default, str) and not isinstance(record.default, bool):
            params[name] = text  # a choice or a text: the words themselves
        elif _NONFINITE.fullmatch(text):  # "nan", "NaN", "-Inf": one reading, one message
            params[name] = float(text)
        else:
            params[name] = scalar(text)
    return params, run, errors


def scalar(text: str):
    """``text`` as a TOML value (``1e-6``, ``true``, ``[1, 2]``, ``"a"``), else the text itself
    (as ``--set KEY=VALUE`` reads it)."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except (tomllib.TOMLDecodeError, RecursionError, ValueError):
        return text


_NAMED = re.compile(r"`([A-Za-z_][A-Za-z0-9_]*)`")


def blame(message: str, given, changed: str | None = None) -> str:
    """The control a refusal belongs to: ``changed`` (the one the user just typed in, when it is
    among ``given``: the change made the scene invalid, whatever parameter the message names),
    else the parameter the message names first among ``given``, else the first it names at
    all ("" if none)."""
    if changed and changed in given:
        return changed
    named = ["lower_positions" if n == "positions" else n for n in _NAMED.findall(message)]
    for name in named:
        if name in given:
            return name
    for name in named:
        if name in names():
            return name
    return ""


def build(params: dict, changed: str | None = None):
    """``(scene, None)`` or ``(None, {name: one-line message})``: the scene of ``params``, as the
    validation layer judges it. ``lower_positions`` (not a make_scene keyword) moves the lower
    asperities: the scene's lower spacing becomes ``ExplicitSpacing`` of those x (m), one per
    asperity. ``changed``: the control the user typed in, which a refusal marks."""
    import dataclasses

    from ..builders import make_scene
    from ..geometry import ExplicitSpacing

    params = dict(params)
    positions = params.pop("lower_positions", None)
    try:
        scene = make_scene(**params)
        if positions is not None:
            if len(positions) != scene.lower.count:
                raise SceneError(f"`lower_positions` must hold one x per lower asperity ({scene.lower.count}), "
                                 f"got {len(positions)}")
            lower = dataclasses.replace(scene.lower, spacing=ExplicitSpacing(
                positions=tuple(positions), mean_pitch=scene.lower.spacing.mean_pitch))
            lower.tips()  # overlapping bases are refused here, naming `positions`
            scene = scene.replace(lower=lower)
    except SceneError as exc:
        text = str(exc).splitlines()[0] if str(exc) else "refused"
        return None, {blame(text, {**params, **({} if positions is None else {"lower_positions": 1})}, changed): text}
    except (TypeError, ValueError, OverflowError, MemoryError, RecursionError) as exc:  # not expected: say so
        text = f"refused: {type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"[:300]
        return None, {changed or "": text}
    return scene, None


def check_run(scene, run: dict) -> None:
    """Refuse (SceneError) a run of ``scene`` with ``run`` settings that ``simulate`` would
    refuse -- the step budget, the stop conditions -- before anything is built or sent: the
    same checks, in the same order, as :func:`asperity2d.simulate` makes first."""
    from ..run import MAX_STEPS, check_budget, default_dt, default_duration, settle_cap, stops_from_settings

    duration = run.get("duration")
    check_budget(scene, default_dt(scene), MAX_STEPS, settle=settle_cap(scene) if scene.slider.track == "free" else 0.0,
                 duration=default_duration(scene) if duration is None else duration)
    stops_from_settings(scene, run)


def toml_value(value) -> str:
    """``value`` (a TOML-able Python value) as TOML text that reads back equal."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            return {math.inf: "inf", -math.inf: "-inf"}.get(value, "nan")
        text = repr(value)
        return text if any(c in text for c in ".en") else text + ".0"
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    raise SceneError(f"a {type(value).__name__} cannot be written to a TOML scene file")


def to_toml(params: dict, run: dict | None = None) -> str:
    """The scene file ``asperity2d run`` reproduces: ``[scene]`` with ``params``, ``[run]`` with
    the run settings; with asperities moved on the stage (``lower_positions``), the whole scene
    as :meth:`Scene.to_toml <asperity2d.scene.Scene.to_toml>` writes it (every number exact).
    Checked to read back equal."""
    from .._version import __version__

    if "lower_positions" in params:
        from .._io import toml_text
        from ..scene import TOML_FORMAT, _drop_none, spec_from_toml

        scene, errors = build(params)
        if errors:
            raise SceneError(next(iter(errors.values())))
        tables = {"format": TOML_FORMAT, **({"run": dict(run)} if run else {}), "spec": _drop_none(scene.to_dict())}
        text = toml_text(tables, header=f"asperity2d {__version__} scene, edited on the workbench: "
                                        "`asperity2d run THIS.toml` reproduces its run")
        back = tomllib.loads(text)
        if spec_from_toml(back, "scene.toml") != scene or back.get("run", {}) != (run or {}):
            raise SceneError("the scene does not survive a round trip through TOML")
        return text
    lines = [f"# asperity2d {__version__} scene: `asperity2d run THIS.toml` reproduces the workbench's run",
             "[scene]"]
    lines += [f"{k} = {toml_value(v)}" for k, v in params.items()]
    if run:
        lines += ["", "[run]"] + [f"{k} = {toml_value(v)}" for k, v in run.items()]
    text = "\n".join(lines) + "\n"
    back = tomllib.loads(text)
    if back.get("scene", {}) != params or back.get("run", {}) != (run or {}):
        raise SceneError("the scene does not survive a round trip through TOML")
    return text


def to_python(params: dict, run: dict | None = None) -> str:
    """The ``make_scene(...)`` call of ``params`` (the moved asperities as an ``ExplicitSpacing``
    of the lower surface), and the ``simulate`` call of the run with its stop conditions."""
    params = dict(params)
    positions = params.pop("lower_positions", None)
    args = ", ".join(f"{k}={v!r}" for k, v in params.items())
    run = dict(run or {})
    duration = run.pop("duration", None)
    imports = "from asperity2d import make_scene, simulate\n"
    body = f"scene = make_scene({args})\n"
    if positions is not None:
        imports = "import dataclasses\n\n" + imports + "from asperity2d.geometry import ExplicitSpacing\n"
        body += ("scene = scene.replace(lower=dataclasses.replace(scene.lower, spacing=ExplicitSpacing(\n"
                 f"    positions={tuple(positions)!r},\n    mean_pitch=scene.lower.spacing.mean_pitch)))\n")
    stop = ""
    if run:
        imports += "from asperity2d.run import stops_from_settings\n"
        stop = f", stop=stops_from_settings(scene, {run!r})"
    return (imports + "\n" + body +
            f"result = simulate(scene{'' if duration is None else f', {duration!r}'}{stop})\n")


def texts(params: dict, run: dict | None = None) -> dict:
    """``{name: text}`` of a scene file's values (what the controls show)."""
    out = {k: _text(v) for k, v in params.items()}
    out.update({k: _text(v) for k, v in (run or {}).items()})
    return out


#: make_scene argument -> where a Scene keeps it (for :func:`params_of`).
_FIELDS = {"lower_count": "lower.count", "upper_count": "slider.spacing.count", "mass": "lower.mass",
           "stiffness": "lower.stiffness", "damping_ratio": "lower.damping_ratio", "slider_mass": "slider.mass",
           "normal_load": "slider.normal_load", "mu_static": "contact.mu_static",
           "restitution": "contact.restitution", "drive_stiffness": "drive.stiffness",
           "drive_velocity": "drive.velocity", "drive_force": "drive.force", "drive_damping": "drive.damping",
           "drive_preload": "drive.preload", "gravity": "gravity",
           "pitch": "lower.spacing.pitch", "slider_start": "slider.start"}


def params_of(scene) -> dict:
    """make_scene arguments that rebuild ``scene`` exactly (``make_scene(**params_of(s)) == s``),
    read from its name (spacing, profile, drive, track, seed) and its fields; a SceneError if the
    scene was not made that way (a profile surface, a hand-built Scene, ...)."""
    from ..builders import DEFAULTS, KEYWORDS, make_scene

    match = re.fullmatch(r"(regular|random|random-upper|random-lower)-(full|half|flat)-(spring|force)-"
                         r"(fixed|free)-seed(\d+)", scene.name or "")
    if match is None:
        raise SceneError("`scene` has no make_scene name to rebuild it from: pass its make_scene arguments "
                         "as a dict, explore(dict(spacing='random', seed=3))")
    spacing, profile, drive, track, seed = match.groups()
    params = {"spacing": spacing, "seed": int(seed), "profile": profile, "drive": drive, "track": track}
    defaults = {**{k.name: k.default for k in KEYWORDS}, **DEFAULTS}
    for name, path in _FIELDS.items():
        value = scene
        for part in path.split("."):
            value = getattr(value, part, None)
        if isinstance(value, (int, float)) and not isinstance(value, bool) and value != defaults.get(name):
            params[name] = value
    params = {k: v for k, v in params.items() if v != defaults.get(k)}
    try:
        same = make_scene(**params) == scene
    except SceneError:
        same = False
    if not same:
        raise SceneError("`scene` cannot be rebuilt from the parameters the workbench shows: pass its "
                         "make_scene arguments as a dict, explore(dict(spacing='random', seed=3))")
    return params
