"""Renderers chosen by the result's kind and the output file's extension (like pyinstrument's).

``render(result, "run.gif")`` writes an animation with meters, ``"run.mp4"``
the same as a video (:mod:`.animate`: palette frames drawn with Pillow; MP4
needs the ``video`` extra); ``.html`` the interactive player, one
self-contained file (:mod:`.player`); ``.png`` / ``.svg`` / ``.pdf`` the
time-series plot (:mod:`.plots`, matplotlib, imported only when used; a belt
chain's: :func:`.belt.plot_chain`); ``.wav`` the sound of the run and its
spectrogram (:mod:`.sound`). ``result`` may be an asperity
:class:`~asperity2d.result.Result`, a :class:`~asperity2d.belt.result.BeltResult`,
or the path of either saved with ``save`` (:func:`asperity2d.load`), so a run is
rendered again without re-simulating.

Which renderer draws what is one table, :data:`DRAWERS`: (result kind, renderer) -> the
function; a renderer for another kind of result is one more entry.
"""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import SceneError
from ..saved import RESULT_KINDS, kind_of_result, register_drawers

#: Output extensions and the renderer each selects.
RENDERERS = {".gif": "animation", ".mp4": "animation", ".html": "player", ".png": "plot",
             ".svg": "plot", ".pdf": "plot", ".wav": "sound"}


def _animation(result, path, **options):
    from .animate import render_animation

    return render_animation(result, path, **options)


def _player(result, path, **options):
    from .player import write_player

    return write_player(result, path, **options)


def _plot(result, path, **options):
    from .plots import plot_run

    return plot_run(result, path, **options)


def _sound(result, path, **options):
    from .sound import write_wav

    return write_wav(result, path, **options).path


def _chain_plot(result, path, **options):
    from .belt import plot_chain

    return plot_chain(result, path, **options)


#: (result family, renderer) -> function(result, path, **options) -> path written. Each is
#: registered with the result kinds of its family (:func:`asperity2d.saved.register_drawers`),
#: so a kind's drawers are its entry's in :data:`asperity2d.saved.RESULT_KINDS`.
DRAWERS = {("asperity", "animation"): _animation, ("asperity", "player"): _player, ("asperity", "plot"): _plot,
           ("asperity", "sound"): _sound, ("belt", "animation"): _animation, ("belt", "player"): _player,
           ("belt", "plot"): _chain_plot, ("belt", "sound"): _sound}
for _family in {family for family, _ in DRAWERS}:
    register_drawers(_family, {renderer: draw for (f, renderer), draw in DRAWERS.items() if f == _family})


def _drawers(kind: str) -> dict:
    """Renderer -> function for a result kind's name or family (``"asperity"``, ``"belt"``, ...)."""
    entry = RESULT_KINDS.get(kind)
    if entry is not None:
        return entry.drawers
    return {renderer: draw for (family, renderer), draw in DRAWERS.items() if family == kind}


def suffixes(kind: str) -> tuple[str, ...]:
    """The output extensions a result of ``kind`` (a kind's name or family: ``"asperity"``,
    ``"belt"``, ``"belt-contact"``) renders to."""
    drawers = _drawers(kind)
    return tuple(ext for ext, renderer in RENDERERS.items() if renderer in drawers)


def render(result, path: str | os.PathLike, **options) -> Path:
    """Render ``result`` (a result of either kind, or the path of a saved one) to ``path``,
    choosing the renderer by the result's kind and the path's extension.

    ``options`` go to ``render_animation`` (``.gif``, ``.mp4``),
    ``write_player`` (``.html``),
    ``plot_run`` or, for a belt chain,
    ``plot_chain`` (``.png``, ``.svg``, ``.pdf``)
    or ``write_wav`` (``.wav``).

    Parameters
    ----------
    result : Result, BeltResult, str or os.PathLike
        A run, or the path of one saved with ``save`` (read with :func:`asperity2d.load`).
    path : str or os.PathLike
        The output file; its extension picks the renderer (``RENDERERS``): ``.gif``,
        ``.mp4``, ``.html``, ``.png``, ``.svg``, ``.pdf`` or ``.wav``.
    **options
        Passed to the renderer (e.g. ``frames=40`` for an animation, ``events=`` for a plot).

    Returns
    -------
    pathlib.Path
        The file written.

    Raises
    ------
    SceneError
        Unknown extension, or one this kind of result has no renderer for (named `path`), or
        bad options.

    See Also
    --------
    asperity2d.load : a saved run, rendered again without re-simulating.
    asperity2d.stick_slip_events : the events a plot marks (``events=``).

    Examples
    --------
    >>> import asperity2d as a
    >>> result = a.simulate(a.make_scene(lower_count=4, upper_count=2))
    >>> a.render(result, "timeseries.png", events=a.stick_slip_events(result)).name
    'timeseries.png'
    >>> a.render(result, "run.gif", frames=10).stat().st_size > 0
    True

    The extension decides; one this package cannot write is one line:

    >>> a.render(result, "run.jpg")
    Traceback (most recent call last):
    ...
    asperity2d.errors.SceneError: `path` must end in one of .gif, .mp4, .html, .png, .svg, .pdf, .wav, got 'run.jpg'
    """
    path = Path(path)
    renderer = RENDERERS.get(path.suffix.lower())
    if renderer is None:
        raise SceneError(f"`path` must end in one of {', '.join(RENDERERS)}, got {str(path)!r}")
    if isinstance(result, (str, os.PathLike)):
        from ..saved import load

        result = load(result)
    entry = kind_of_result(result)
    if entry is None:
        kind = getattr(result, "kind", None)  # a streamed record reads as an asperity Result
        drawers = _drawers(kind) if isinstance(kind, str) else {}
        if not drawers:
            raise SceneError(f"`result` must be a Result or a BeltResult, got {type(result).__name__}")
        name = kind
    else:
        drawers, name = entry.drawers, entry.name
    draw = drawers.get(renderer)
    if draw is None:
        raise SceneError(f"`path` must end in one of {', '.join(suffixes(name))} for a {name} result, "
                         f"got {str(path)!r}")
    return draw(result, path, **options)


__all__ = ["render", "RENDERERS", "DRAWERS", "suffixes"]
