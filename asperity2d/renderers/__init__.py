"""Renderers chosen by the output file's extension (like pyinstrument's renderers).

``render(result, "run.gif")`` writes an animation with meters, ``"run.mp4"``
the same as a video (:mod:`.animate`: palette frames drawn with Pillow; MP4
needs the ``video`` extra); ``.html`` the interactive player, one
self-contained file (:mod:`.player`); ``.png`` / ``.svg`` / ``.pdf`` the
time-series plot (:mod:`.plots`, matplotlib, imported only when used; a belt
chain's: :func:`.belt.plot_chain`); ``.wav`` the sound of the run and its
spectrogram (:mod:`.sound`). ``result`` may be a
:class:`~asperity2d.result.Result`, a
:class:`~asperity2d.belt.result.BeltResult` (told apart by type), or the path
of a Result saved with ``Result.save``, so a run is rendered again without
re-simulating.
"""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import SceneError

#: Output extensions and the renderer each selects.
RENDERERS = {".gif": "animation", ".mp4": "animation", ".html": "player", ".png": "plot",
             ".svg": "plot", ".pdf": "plot", ".wav": "sound"}


def render(result, path: str | os.PathLike, **options) -> Path:
    """Render ``result`` to ``path``, choosing the renderer by extension.

    ``options`` go to :func:`~asperity2d.renderers.animate.render_animation` (``.gif``, ``.mp4``),
    :func:`~asperity2d.renderers.player.write_player` (``.html``),
    :func:`~asperity2d.renderers.plots.plot_run` or, for a belt chain,
    :func:`~asperity2d.renderers.belt.plot_chain` (``.png``, ``.svg``, ``.pdf``)
    or :func:`~asperity2d.renderers.sound.write_wav` (``.wav``).

    Raises
    ------
    SceneError
        Unknown extension (named `path`), or bad options.
    """
    path = Path(path)
    kind = RENDERERS.get(path.suffix.lower())
    if kind is None:
        raise SceneError(f"`path` must end in one of {', '.join(RENDERERS)}, got {str(path)!r}")
    if isinstance(result, (str, os.PathLike)):
        from ..result import load

        result = load(result)
    if kind == "sound":
        from .sound import write_wav

        return write_wav(result, path, **options).path
    if kind == "animation":
        from .animate import render_animation

        return render_animation(result, path, **options)
    if kind == "player":
        from .player import write_player

        return write_player(result, path, **options)
    from .animate import is_chain

    if is_chain(result):
        from .belt import plot_chain

        return plot_chain(result, path, **options)
    from .plots import plot_run

    return plot_run(result, path, **options)


__all__ = ["render", "RENDERERS"]
