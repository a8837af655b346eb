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

The output formats are one registry, :data:`FORMATS`: extension -> :class:`OutputFormat`,
each entry carrying its description and, per result kind it accepts, the function that
draws it. ``render()``, the command line's help and its checks read it; a new format is one
:func:`register_format` call (the contract is :class:`OutputFormat`'s docstring).
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import Callable

from .._registry import Registry
from ..errors import SceneError

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


def _asperities_plot(asperities, path, **options):
    from .surface import plot_asperities

    if "profile" not in options:
        raise SceneError("`profile` is needed to draw asperities: render(asperities, path, profile=...)")
    return plot_asperities(options.pop("profile"), asperities, path, **options)


def _spectrum_plot(spectrum, path, **options):
    from .surface import plot_spectrum

    return plot_spectrum(spectrum, path, **options)


def _comparison_plot(comparison, path, **options):
    from .plots import plot_comparison

    return plot_comparison(comparison, path, **options)


@dataclass(frozen=True)
class OutputFormat:
    """One output format: a file extension and how each kind of result is drawn to it.

    Contract -- a new output format must:

    1. have an ``extension`` of its own (lower case, with the dot: ``".csv"``); the path's
       extension (case-insensitive) selects it;
    2. say in ``description`` what the file holds, in a few words (the command line's help
       prints them);
    3. map every result kind it accepts (``"asperity"``, ``"belt"``: a result's ``kind``) to a
       function ``draw(result, path, **options) -> path written``; the function imports its
       heavy libraries itself (matplotlib, imageio), so choosing a renderer imports nothing,
       writes the file (atomically where it can) and refuses bad ``options`` with a
       ``SceneError`` naming the option;
    4. be deterministic: the same result and options give the same file (the golden and
       picture tests rely on it).

    Parameters
    ----------
    extension : str
        The file extension, lower case with its dot (``".csv"``).
    description : str
        What the file holds, in a few words.
    drawers : mapping of str to callable
        Result kind (``"asperity"``, ``"belt"``, ...) -> ``draw(result, path, **options)``.
    renderer : str
        The family (``"plot"``, ``"animation"``...) for the text.

    Raises
    ------
    SceneError
        An extension that is not lower case with its dot, or drawers that are not kind -> function.

    Examples
    --------
    >>> from asperity2d.renderers import OutputFormat
    >>> def write_txt(result, path, **options):
    ...     return path
    >>> fmt = OutputFormat(".txt", "the time series as text", {"belt": write_txt}, "table")
    >>> fmt.kinds
    ('belt',)
    >>> OutputFormat("TXT", "text", {"belt": write_txt})
    Traceback (most recent call last):
    asperity2d.errors.SceneError: `extension` must be a lower-case extension with its dot ('.csv'), got 'TXT'
    """

    extension: str
    description: str
    drawers: Mapping[str, Callable]
    renderer: str = ""

    def __post_init__(self):
        ext = self.extension
        if not isinstance(ext, str) or not ext.startswith(".") or len(ext) < 2 or ext != ext.lower():
            raise SceneError(f"`extension` must be a lower-case extension with its dot ('.csv'), got {ext!r}")
        if not self.drawers or not all(isinstance(k, str) and callable(f) for k, f in self.drawers.items()):
            raise SceneError(f"`drawers` of {ext} must map result kinds to functions, got {self.drawers!r}")
        object.__setattr__(self, "drawers", MappingProxyType(dict(self.drawers)))

    @property
    def kinds(self) -> tuple[str, ...]:
        """The result kinds this format accepts."""
        return tuple(self.drawers)


def _check_format(fmt) -> OutputFormat:
    if not isinstance(fmt, OutputFormat):
        raise SceneError(f"`fmt` must be an OutputFormat, got {type(fmt).__name__}")
    return fmt


#: The output formats: extension -> :class:`OutputFormat`. :func:`render` chooses by it. A
#: ``Registry`` (``asperity2d._registry``): an installed package adds its formats through the
#: entry-point group ``asperity2d.formats`` (each entry point names an :class:`OutputFormat`).
FORMATS: Registry = Registry("output format", "asperity2d.formats", key=lambda f: f.extension,
                             check=_check_format, param="fmt", modules=False)


def register_format(fmt: OutputFormat, *, replace: bool = False) -> OutputFormat:
    """Add ``fmt`` to :data:`FORMATS` (see :class:`OutputFormat` for the contract).

    Parameters
    ----------
    fmt : OutputFormat
        The format to add.
    replace : bool
        Replace a format already registered for the same extension.

    Returns
    -------
    OutputFormat
        ``fmt``.

    Raises
    ------
    SceneError
        ``fmt`` is not an OutputFormat, or its extension is taken and ``replace`` is false.

    See Also
    --------
    unregister_format : removes it again.

    Examples
    --------
    >>> from asperity2d.renderers import OutputFormat, register_format, unregister_format
    >>> def write_t(result, path, **options):
    ...     path.write_text("\\n".join(map(repr, result.t)))
    ...     return path
    >>> fmt = register_format(OutputFormat(".times", "the sample times", {"belt": write_t}, "table"))
    >>> register_format(fmt)
    Traceback (most recent call last):
    ...
    asperity2d.errors.SceneError: `fmt` '.times' is already registered (pass replace=True)
    >>> unregister_format(".times").extension
    '.times'
    """
    return FORMATS.register(fmt, replace=replace)


def unregister_format(extension: str) -> OutputFormat:
    """Remove the format of ``extension`` from :data:`FORMATS` and return it; the result kinds
    given its drawers (:func:`register_kind_drawers`) lose them too.

    Parameters
    ----------
    extension : str
        A registered extension, with its dot (``".txt"``).

    Returns
    -------
    OutputFormat
        The format removed.

    Raises
    ------
    SceneError
        No format is registered for ``extension`` (the message names the nearest ones).

    Examples
    --------
    >>> from asperity2d.renderers import FORMATS, OutputFormat, register_format, unregister_format
    >>> fmt = register_format(OutputFormat(".stamp", "the run's length", {"belt": lambda r, p, **o: p}))
    >>> unregister_format(".stamp") is fmt, ".stamp" in FORMATS
    (True, False)
    """
    from ..saved import forget_drawers

    fmt = FORMATS.unregister(extension)
    forget_drawers(fmt.renderer, fmt.drawers)
    return fmt


_BOTH = ("asperity", "belt")
for _fmt in (
    OutputFormat(".gif", "animation with meters", dict.fromkeys(_BOTH, _animation), "animation"),
    OutputFormat(".mp4", "the animation as a video (needs the video extra)", dict.fromkeys(_BOTH, _animation),
                 "animation"),
    OutputFormat(".html", "the interactive player, one self-contained page", dict.fromkeys(_BOTH, _player),
                 "player"),
    *(OutputFormat(ext, "time-series plot (a comparison: its values per variant; a surface's asperities or "
                        "its power spectrum)",
                   {"asperity": _plot, "belt": _chain_plot, "comparison": _comparison_plot,
                    "asperities": _asperities_plot, "spectrum": _spectrum_plot}, "plot")
      for ext in (".png", ".svg", ".pdf")),
    OutputFormat(".wav", "the slider's sound", dict.fromkeys(_BOTH, _sound), "sound"),
):
    register_format(_fmt)
del _fmt


class _Renderers(Mapping):
    """Extension -> renderer family, read from :data:`FORMATS` (the table as it was before the
    formats carried their metadata)."""

    def __getitem__(self, ext):
        return FORMATS[ext].renderer

    def __iter__(self):
        return iter(FORMATS)

    def __len__(self):
        return len(FORMATS)


class _Drawers(Mapping):
    """(result kind, renderer family) -> function, read from :data:`FORMATS`."""

    def _table(self):
        return {(kind, fmt.renderer): draw for fmt in FORMATS.values() for kind, draw in fmt.drawers.items()}

    def __getitem__(self, key):
        return self._table()[key]

    def __iter__(self):
        return iter(self._table())

    def __len__(self):
        return len(self._table())


#: Views of :data:`FORMATS`: extension -> renderer family, and (kind, family) -> function.
RENDERERS: Mapping[str, str] = _Renderers()
DRAWERS: Mapping[tuple[str, str], Callable] = _Drawers()


def register_kind_drawers() -> None:
    """Give each registered result kind (``asperity2d.saved.RESULT_KINDS``) the drawers of its
    family read from :data:`FORMATS`: one registry says how a kind is drawn, and a kind registered
    from outside may bring drawers of its own. Imports the result kinds (NumPy), so it runs on
    first use, not on import (``asperity2d --help`` stays light).

    Examples
    --------
    >>> from asperity2d.renderers import register_kind_drawers
    >>> from asperity2d.saved import RESULT_KINDS
    >>> register_kind_drawers()
    >>> sorted(RESULT_KINDS["belt"].drawers)
    ['animation', 'player', 'plot', 'sound']
    """
    from ..saved import register_drawers

    for family in {kind for fmt in FORMATS.values() for kind in fmt.drawers}:
        register_drawers(family, {fmt.renderer: draw for fmt in FORMATS.values()
                                  for kind, draw in fmt.drawers.items() if kind == family})


def suffixes(kind: str) -> tuple[str, ...]:
    """The output extensions a result of ``kind`` renders to.

    Parameters
    ----------
    kind : str
        A result kind: ``"asperity"``, ``"belt"``, ``"comparison"``, ...

    Returns
    -------
    tuple of str
        The extensions, in :data:`FORMATS`' order (empty for a kind no format draws).

    Examples
    --------
    >>> from asperity2d.renderers import suffixes
    >>> suffixes("belt")
    ('.gif', '.mp4', '.html', '.png', '.svg', '.pdf', '.wav')
    >>> suffixes("comparison")
    ('.png', '.svg', '.pdf')
    """
    return tuple(ext for ext, fmt in FORMATS.items() if kind in fmt.drawers)


def describe() -> str:
    """The formats in words, for a help text: ``".gif: animation with meters; ..."``.

    Returns
    -------
    str
        Each description once, after the extensions that share it.

    Examples
    --------
    >>> from asperity2d.renderers import describe
    >>> describe().split("; ")[0]
    '.gif: animation with meters'
    """
    groups: dict[str, list[str]] = {}
    for ext, fmt in FORMATS.items():
        groups.setdefault(fmt.description, []).append(ext)
    return "; ".join(f"{', '.join(exts)}: {text}" for text, exts in groups.items())


def render(result, path: str | os.PathLike, **options) -> Path:
    """Render ``result`` (a result of either kind, or the path of a saved one) to ``path``,
    choosing the renderer by the result's kind and the path's extension.

    ``options`` go to ``render_animation`` (``.gif``, ``.mp4``),
    ``write_player`` (``.html``),
    ``plot_run`` or, for a belt chain,
    ``plot_chain`` (``.png``, ``.svg``, ``.pdf``)
    or ``write_wav`` (``.wav``). A :class:`~asperity2d.Comparison` plots as its values per
    variant and seed, with each variant's mean and 95 % interval, in its measure's unit
    (``.png``, ``.svg``, ``.pdf``; ``label=`` names the axis, ``reference=`` draws a line). A
    rough surface's :class:`~asperity2d.surface.Asperities` draw over their profile
    (``profile=``, required; ``x_range=``, ``highlight=``, ``level=``) and its
    :class:`~asperity2d.surface.PowerSpectrum` on log-log axes (``fit=`` draws a Hurst fit).

    Parameters
    ----------
    result : Result, BeltResult, Comparison, Asperities, PowerSpectrum, str or os.PathLike
        A run or a comparison, or the path of one saved with ``save`` (read with
        :func:`asperity2d.load`).
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
    fmt = FORMATS.get(path.suffix.lower())
    if fmt is None:
        raise SceneError(f"`path` must end in one of {', '.join(FORMATS)}, got {str(path)!r}")
    if isinstance(result, (str, os.PathLike)):
        from ..saved import load

        result = load(result)
    kind = getattr(result, "kind", None)  # the family: a contact result draws as a belt chain
    draw = fmt.drawers.get(kind)
    from ..saved import kind_of_result

    register_kind_drawers()
    entry = kind_of_result(result)
    if draw is None and entry is not None:  # a kind from outside, with drawers of its own
        draw = entry.drawers.get(fmt.renderer)
    if draw is None:
        if kind not in {k for f in FORMATS.values() for k in f.drawers}:
            raise SceneError(f"`result` must be a Result, a BeltResult, a Comparison, Asperities or a PowerSpectrum, "
                             f"got {type(result).__name__}")
        raise SceneError(f"`path` must end in one of {', '.join(suffixes(kind))} for a {kind} result, "
                         f"got {str(path)!r}")
    return draw(result, path, **options)


__all__ = ["render", "FORMATS", "OutputFormat", "register_format", "unregister_format", "RENDERERS", "DRAWERS",
           "suffixes", "describe", "register_kind_drawers"]
