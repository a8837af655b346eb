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
    """The workbench as a notebook widget: change a parameter, watch the run stream in, measure
    and compare (the same front end as ``asperity2d explore`` in the browser).

    Parameters
    ----------
    scene : Scene, dict or None, optional
        The scene to start from: a :func:`~asperity2d.make_scene` scene, a dict of its
        arguments, or None for the default (Ooten's set-up).
    **options
        ``make_scene`` arguments (they override ``scene``'s), and ``workers`` (the ensemble's
        worker processes) or ``duration`` (s) of each run.

    Returns
    -------
    anywidget.AnyWidget
        The widget; shown when it is the last value of a notebook cell.

    Raises
    ------
    SceneError
        A refused parameter, named.

    See Also
    --------
    asperity2d.simulate : the run the widget streams.

    Examples
    --------
    Skipped here: the widget needs the ``app`` extra and a notebook front end to draw it.

    >>> import asperity2d as a
    >>> widget = a.explore(lower_count=6, upper_count=2)  # doctest: +SKIP
    >>> widget  # doctest: +SKIP
    """
    from .widget import explore as _explore

    return _explore(scene, **options)


def serve(**options):
    """Serve the workbench on 127.0.0.1 (see :func:`asperity2d.app.server.serve`)."""
    from .server import serve as _serve

    return _serve(**options)
