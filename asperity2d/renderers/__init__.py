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


#: (result kind, renderer) -> function(result, path, **options) -> path written.
DRAWERS = {("asperity", "animation"): _animation, ("asperity", "player"): _player, ("asperity", "plot"): _plot,
           ("asperity", "sound"): _sound, ("belt", "animation"): _animation, ("belt", "player"): _player,
           ("belt", "plot"): _chain_plot, ("belt", "sound"): _sound}


def suffixes(kind: str) -> tuple[str, ...]:
    """The output extensions a result of ``kind`` (``"asperity"``, ``"belt"``) renders to."""
    return tuple(ext for ext, renderer in RENDERERS.items() if (kind, renderer) in DRAWERS)


def render(result, path: str | os.PathLike, **options) -> Path:
    """Render ``result`` (a result of either kind, or the path of a saved one) to ``path``,
    choosing the renderer by the result's kind and the path's extension.

    ``options`` go to ``render_animation`` (``.gif``, ``.mp4``),
    ``write_player`` (``.html``),
    ``plot_run`` or, for a belt chain,
    ``plot_chain`` (``.png``, ``.svg``, ``.pdf``)
    or ``write_wav`` (``.wav``).

    Raises
    ------
    SceneError
        Unknown extension, or one this kind of result has no renderer for (named `path`), or
        bad options.
    """
    path = Path(path)
    renderer = RENDERERS.get(path.suffix.lower())
    if renderer is None:
        raise SceneError(f"`path` must end in one of {', '.join(RENDERERS)}, got {str(path)!r}")
    if isinstance(result, (str, os.PathLike)):
        from ..saved import load

        result = load(result)
    kind = getattr(result, "kind", None)
    draw = DRAWERS.get((kind, renderer))
    if draw is None:
        if kind not in {k for k, _ in DRAWERS}:
            raise SceneError(f"`result` must be a Result or a BeltResult, got {type(result).__name__}")
        raise SceneError(f"`path` must end in one of {', '.join(suffixes(kind))} for a {kind} result, "
                         f"got {str(path)!r}")
    return draw(result, path, **options)


__all__ = ["render", "RENDERERS", "DRAWERS", "suffixes"]
