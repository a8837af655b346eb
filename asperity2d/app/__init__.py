"""The workbench: change a parameter, watch the run stream in, measure and compare.

One front end (``assets/app.js``, an ES module, drawing runs with the player component of
:mod:`asperity2d.renderers.player`) and one message protocol (:mod:`.session`), two hosts:

* ``asperity2d explore [SCENE.toml]`` -- a local web server (:mod:`.server`: Starlette under
  uvicorn, loopback only, a random token in the URL, cross-origin requests refused), the
  protocol over a WebSocket;
* ``asperity2d.explore(scene)`` in a notebook -- an anywidget widget (:mod:`.widget`), the
  protocol over the widget's custom messages.

The controls are generated from :data:`asperity2d.builders.PARAMETERS` (:mod:`.controls`); a run
streams into the player while it is computed (:class:`asperity2d.run.Simulation`), and a new
change cancels the run in flight. Needs the ``app`` extra (starlette, uvicorn, anywidget).
"""

from __future__ import annotations

__all__ = ["explore", "serve"]


def explore(scene=None, **options):
    """The workbench as a notebook widget (see ``asperity2d.app.widget.explore``)."""
    from .widget import explore as _explore

    return _explore(scene, **options)


def serve(**options):
    """Serve the workbench on 127.0.0.1 (see :func:`asperity2d.app.server.serve`)."""
    from .server import serve as _serve

    return _serve(**options)
