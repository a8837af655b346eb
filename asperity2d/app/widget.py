"""``asperity2d.explore(scene)``: the workbench as a notebook widget (anywidget: JupyterLab,
Notebook 7, VS Code, marimo).

The same front end as the web app (``assets/app.js``, with the player's script before it, as one
ES module) and the same protocol (:class:`~asperity2d.app.session.Session`), carried by the
widget's custom messages instead of a WebSocket. The synced state (``values``, ``status``,
``samples``, ``toml``) lets a notebook read what the workbench holds.
"""

from __future__ import annotations

import json

from ..errors import SceneError
from . import controls


def _module() -> tuple[str, str]:
    """The widget's ES module and CSS: the player's, then the workbench's."""
    from .server import asset

    return asset("player.js") + "\n" + asset("app.js"), asset("player.css") + "\n" + asset("app.css")


def _widget_class():
    try:
        import anywidget
        import traitlets
    except ImportError:
        raise SceneError('explore() needs anywidget: pip install "asperity2d[app]"') from None
    esm, css = _module()

    class Workbench(anywidget.AnyWidget):
        """The workbench widget; ``session`` is its protocol end (``session.handle(message)``)."""

        _esm = esm
        _css = css
        values = traitlets.Dict().tag(sync=True)
        status = traitlets.Unicode("ready").tag(sync=True)
        samples = traitlets.Int(0).tag(sync=True)
        toml = traitlets.Unicode("").tag(sync=True)

        def __init__(self, values: dict, *, workers=None, **kwargs):
            super().__init__(**kwargs)
            from .session import Session

            self.values = dict(values)
            self.session = Session(self._deliver, values=values, workers=workers)
            self.on_msg(self._received)

        def _received(self, widget, content, buffers) -> None:
            self.session.handle(content if isinstance(content, (dict, str)) else {})

        def _deliver(self, text: str) -> None:
            message = json.loads(text)
            kind = message.get("type")
            if kind == "valid":
                self.values = dict(self.session.values)
                self.toml = controls.to_toml(self.session.params, self.session.run_settings)
            elif kind == "run-start":
                self.status, self.samples = "computing", 0
            elif kind == "run-chunk":
                self.samples = self.samples + int(message["chunk"]["t"]["shape"][0])
            elif kind == "run-end":
                self.status = f"done: {message['summary'].get('status', '')}".strip()
            elif kind == "invalid":
                self.status = "refused: " + "; ".join(message["errors"].values())
            self.send({"m": text})

        def close(self) -> None:
            self.session.close()
            super().close()

    return Workbench


_CLASS = None


def explore(scene=None, *, workers: int | None = None, duration: float | None = None, **params):
    """The workbench widget, starting from ``scene``: None (the default scene), a Scene made by
    ``make_scene`` (rebuilt from its name and fields, checked equal), a dict of ``make_scene``
    arguments, or keyword arguments (``explore(spacing="random", seed=3)``).
    Display it (the last line of a cell) to use it; change a control and the run streams in."""
    global _CLASS
    from ..scene import Scene

    if isinstance(scene, Scene):
        scene = controls.params_of(scene)
    elif scene is not None and not isinstance(scene, dict):
        raise SceneError(f"`scene` must be a Scene or a dict of make_scene arguments, got {type(scene).__name__}")
    given = {**(scene or {}), **params}
    run = {} if duration is None else {"duration": duration}
    scene_obj, errors = controls.build(given)
    if errors:
        raise SceneError(next(iter(errors.values())))
    del scene_obj
    if _CLASS is None:
        _CLASS = _widget_class()
    return _CLASS(controls.texts(given, run), workers=workers)
