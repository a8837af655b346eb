"""Scenes to and from TOML files: the input format of ``asperity2d run`` and ``critical``.

Two layouts, one reader (:func:`read_scene`):

* ``make_scene``'s arguments, at top level or under ``[scene]`` -- what a person writes;
* a whole scene, ``format = "asperity2d.scene/1"`` and a ``[spec]`` table, written by
  :meth:`Scene.to_toml <asperity2d.scene.Scene.to_toml>` -- every number exact, so
  running the file reproduces the scene's run bit for bit.

Either may hold a ``[run]`` table (``duration`` in s, and the stop conditions of
:data:`RUN_KEYS`). The command line only calls this.
"""

from __future__ import annotations

import math
from pathlib import Path

from . import _io
from .errors import SceneError

#: Keys of a TOML scene's ``[run]`` table: ``duration`` (s) and the stop conditions of
#: :data:`asperity2d.run.STOP_SETTINGS` (``stop_pitches``, ``stop_force``, ``stop_first_slip``,
#: ``stop_stuck``; :func:`asperity2d.run.stops_from_settings` turns them into ``simulate``'s ``stop``).
RUN_KEYS = ("duration", "stop_pitches", "stop_force", "stop_first_slip", "stop_stuck")


def read_scene(path, *, arg: str = "scene", overrides: dict | None = None):
    """``(Scene, run settings)`` from a TOML scene file.

    The file holds ``make_scene``'s arguments, at top level or under
    ``[scene]``, or a whole scene written by :meth:`Scene.to_toml
    <asperity2d.scene.Scene.to_toml>` (``format = "asperity2d.scene/1"`` and a
    ``[spec]`` table), and optionally a ``[run]`` table (``duration`` in s).
    Every problem -- the file, its TOML, a table of the wrong type, an unknown
    key -- is a ``SceneError`` naming it. ``overrides`` (``--set KEY=VALUE``) replace or add
    make_scene arguments.
    """
    data = _io.read_toml(arg, path)
    whole = "format" in data
    run = data.pop("run", {})
    if not isinstance(run, dict):
        raise SceneError(f"`run` in {str(path)!r} must be a [run] table, got {_kind(run)}")
    for key in run:
        if key not in RUN_KEYS:
            raise SceneError(f"`{key}` in [run] of {str(path)!r} is not a run setting "
                             f"(allowed: {', '.join(RUN_KEYS)})")
    if "duration" in run:
        d = run["duration"]
        if isinstance(d, bool) or not isinstance(d, (int, float)) or not (math.isfinite(d) and d > 0):
            raise SceneError(f"`duration` in [run] of {str(path)!r} must be a number > 0, got {_kind(d)}")
    for key in ("stop_pitches", "stop_force"):
        v = run.get(key)
        if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v)
                              or (key == "stop_pitches" and v <= 0)):
            raise SceneError(f"`{key}` in [run] of {str(path)!r} must be a finite number"
                             f"{' > 0' if key == 'stop_pitches' else ''}, got {_kind(v)}")
    for key in ("stop_first_slip", "stop_stuck"):
        if key in run and not isinstance(run[key], bool):
            raise SceneError(f"`{key}` in [run] of {str(path)!r} must be true or false, got {_kind(run[key])}")
    if whole:
        if overrides:
            raise SceneError(f"`--set` changes make_scene arguments, and {str(path)!r} holds a whole "
                             "scene: set the values in a TOML of make_scene arguments")
        from .scene import spec_from_toml

        return spec_from_toml({**data, "run": run}, path), run
    if "scene" in data:
        params = data.pop("scene")
        if not isinstance(params, dict):
            raise SceneError(f"`scene` in {str(path)!r} must be a [scene] table of make_scene "
                             f"arguments, got {_kind(params)}")
        if data:
            raise SceneError(f"`{next(iter(data))}` in {str(path)!r} is outside [scene]: put every "
                             "make_scene argument under [scene] (or all at top level)")
    else:
        params = data
    from .builders import make_scene
    from .surface.source import resolve_paths  # profile files named relative to the TOML file

    params = {**params, **(overrides or {})}
    return make_scene(**resolve_paths(params, Path(path).parent)), run


def _kind(value) -> str:
    """A value for a message, never failing (a table nested thousands deep has no ``repr``)."""
    from ._inputs import show

    return f"{type(value).__name__} {show(value)}"[:80]
