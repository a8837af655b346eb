"""Saved results of every kind, read by their format tag: :func:`load` (``asperity2d.load``).

Every kind of result is one entry of ``RESULT_KINDS`` (a :class:`ResultKind`): its format
tag, its class, its loader, its exporter and the renderers that draw it. :func:`load` reads a
file's tag and calls that kind's loader; the protocol tests run over every entry, so a kind that
is registered is a kind that is tested. The kinds of this release:

============  ======================================  ======================================
A record streamed to disk as its run went (a directory, ``asperity2d.streamed``) is an
asperity run too, read lazily. The previous release wrote no tag; its files are told apart by
their metadata's records (a ``scene``; a ``chain`` and a ``normal``; a ``chain``) and still load.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Callable

from ._io import FileError, load_npz
from ._registry import Registry
from .errors import SceneError


@dataclass(frozen=True)
class ResultKind:
    """One kind of result: what a saved file of it is, and how to read, export and draw it.

    The contract an entry of ``RESULT_KINDS`` keeps (``register`` checks what it can):

    1. ``name`` is unique, and ``tag`` (``"owner.kind/version"``) is unique; the result's
       ``save(path)`` writes an ``.npz`` whose JSON metadata carries ``format = tag``.
    2. ``cls`` follows the result protocol: ``kind`` (the renderer family, ``family`` here),
       ``status``, ``message``, ``success``, ``summary()``, ``save(path)``, ``export(path)``.
    3. ``load(path)`` returns a ``cls`` with every array and record ``save`` wrote (equal to the
       bit), refuses a file of another tag, and raises ``FileError`` naming
       ``path`` for anything it cannot use -- missing, foreign, damaged, arrays that do not fit
       together, time running backwards, a malformed record: never a KeyError or a traceback.
    4. ``export(result, path)`` writes to ``.mat`` every array ``save`` writes, by name; to
       ``.csv`` every ``(T,)`` array as a column and, when ``csv_per_element``, every ``(n, T)``
       array as columns ``name_1`` ... ``name_n`` (an asperity run's thousands of lower
       asperities stay in the ``.mat``); another extension is a ``SceneError`` naming ``path``.
    5. ``untagged`` names the metadata records that mark a file of the previous release (which
       wrote no tag), or is empty; such files keep loading.
    6. ``drawers`` maps a renderer (``"animation"``, ``"player"``, ``"plot"``, ``"sound"``) to
       ``function(result, path, **options) -> path``; the renderers package fills in its own for a
       ``family`` from its output formats (:func:`register_drawers`, called by
       ``asperity2d.renderers.register_kind_drawers`` on first use), and a kind from outside
       brings its own.
    7. ``saved`` lists the arrays ``save`` writes (each ``(T,)`` or per element ``(n, T)``);
       the protocol tests compare each one after a round trip.
    """

    name: str
    tag: str
    cls: type
    load: Callable
    export: Callable
    family: str
    saved: tuple
    untagged: tuple = ()
    csv_per_element: bool = True
    drawers: dict = field(default_factory=dict, compare=False)


def _check_kind(kind) -> ResultKind:
    if not isinstance(kind, ResultKind):
        raise SceneError(f"`kind` must be a ResultKind, got {type(kind).__name__}")
    if "/" not in kind.tag or not kind.tag.rpartition("/")[2].isdigit():
        raise SceneError(f"`kind.tag` must be 'name/version', got {kind.tag!r}")
    for other in RESULT_KINDS.loaded().values():  # the entries so far (checking must not load entry points)
        if other.name != kind.name and other.tag == kind.tag:
            raise SceneError(f"`kind.tag` {kind.tag!r} is already the tag of {other.name!r}")
    return kind


#: Kind name -> :class:`ResultKind`, in registration order. A
#: ``Registry`` (``asperity2d._registry``): an installed package adds its kinds through the
#: entry-point group ``asperity2d.result_kinds`` (each entry point names a :class:`ResultKind`).
RESULT_KINDS: Registry = Registry("result kind", "asperity2d.result_kinds", key=lambda k: k.name,
                                  check=_check_kind, param="kind")


def register(kind: ResultKind, *, replace: bool = False) -> ResultKind:
    """Add ``kind`` to ``RESULT_KINDS`` (its contract: :class:`ResultKind`); a name already taken
    raises ``SceneError`` unless ``replace``; return it."""
    return RESULT_KINDS.register(kind, replace=replace)


def unregister(name: str) -> ResultKind:
    """Remove the kind ``name`` from ``RESULT_KINDS`` and return it."""
    return RESULT_KINDS.unregister(name)


def register_drawers(family: str, drawers: dict) -> None:
    """Give every registered kind of ``family`` the ``drawers`` (renderer -> function) it lacks."""
    for kind in RESULT_KINDS.values():
        if kind.family == family:
            for renderer, draw in drawers.items():
                kind.drawers.setdefault(renderer, draw)


def forget_drawers(renderer: str, drawers: dict) -> None:
    """Take back the drawers (family -> function) of the renderer family ``renderer`` that
    :func:`register_drawers` gave the kinds from an output format now removed (a drawer a kind
    brought of its own stays)."""
    for kind in RESULT_KINDS.values():
        if kind.drawers.get(renderer) is not None and kind.drawers[renderer] is drawers.get(kind.family):
            del kind.drawers[renderer]


def kind_of_result(result) -> ResultKind | None:
    """The registered kind of the object ``result`` (its class or nearest registered base), or None."""
    for cls in type(result).__mro__:
        for kind in RESULT_KINDS.values():
            if kind.cls is cls:
                return kind
    return None


def _builtin() -> None:
    from .belt.contact.result import ContactResult, load_contact
    from .belt.result import BeltResult, load as load_belt
    from .result import LOWER_SERIES, SERIES, Result, load as load_asperity

    register(ResultKind("asperity", "asperity2d.result/2", Result, load_asperity, Result.export, "asperity",
                        SERIES + LOWER_SERIES, untagged=("scene",), csv_per_element=False))
    register(ResultKind("belt", BeltResult.FORMAT, BeltResult, load_belt, BeltResult.export, "belt",
                        BeltResult.SAVED, untagged=("chain",)))
    register(ResultKind("belt-contact", ContactResult.FORMAT, ContactResult, load_contact, ContactResult.export,
                        "belt", ContactResult.SAVED, untagged=("chain", "normal")))


_builtin()

def _what() -> str:
    return "an asperity2d result file (" + ", ".join(RESULT_KINDS) + ")"


def result_kind(path: str | os.PathLike) -> ResultKind:
    """The :class:`ResultKind` of the file saved at ``path`` (only its metadata is read).

    A file that is none raises ``FileError`` naming ``path``."""
    _, meta = load_npz(path, (), kind=_what())
    tag = meta.get("format")
    if tag is None:
        # the previous release's files: the kind whose records are all there, the most specific first
        for kind in sorted(RESULT_KINDS.values(), key=lambda k: -len(k.untagged)):
            if kind.untagged and all(record in meta for record in kind.untagged):
                return kind
        raise FileError("path", path, f"is not {_what()}",
                        "it has no format tag and no scene or chain record")
    for kind in RESULT_KINDS.values():
        if kind.tag == tag:
            return kind
    raise FileError("path", path, f"is not {_what()}",
                    f"its format is {tag!r}, expected one of {', '.join(repr(k.tag) for k in RESULT_KINDS.values())}")


def kind_of(path: str | os.PathLike) -> str:
    """The renderer family (``"asperity"`` or ``"belt"``) of the result saved at ``path``; a record
    streamed to a directory is ``"asperity"``. :func:`result_kind` gives the full entry."""
    from .streamed import is_record

    if is_record(path):
        return "asperity"
    return result_kind(path).family


def load(path: str | os.PathLike):
    """Read a result saved with ``save``, as the kind that was saved (``RESULT_KINDS``,
    chosen by the file's format tag) with every array and record: a
    :class:`~asperity2d.result.Result`, a :class:`~asperity2d.belt.BeltResult` or a
    :class:`~asperity2d.belt.ContactResult`; or a record streamed to a directory
    (``simulate(..., record_to=path)``), read lazily.

    Parameters
    ----------
    path : str or os.PathLike
        A ``.npz`` file written by a result's ``save``, or a directory
        written by ``simulate(..., record_to=path)``.

    Returns
    -------
    Result, BeltResult or ContactResult
        The run as it was saved, every array bit for bit.

    Raises
    ------
    FileError
        A file that is neither (missing, empty, foreign, damaged, malformed), naming
        ``path`` (a subclass of :class:`~asperity2d.SceneError`).

    See Also
    --------
    asperity2d.Result.save : write a result; ``export`` for MATLAB (``.mat``) or CSV.
    asperity2d.Result.export
    asperity2d.render : draws a saved result without re-simulating.

    Examples
    --------
    >>> import numpy as np
    >>> import asperity2d as a
    >>> result = a.simulate(a.make_scene(lower_count=4, upper_count=2))
    >>> path = result.save("run.npz")
    >>> again = a.load(path)
    >>> again
    Result(3731 samples, t_end=412.4 ns, status='passed')
    >>> np.array_equal(again.x, result.x)
    True
    """
    from .streamed import is_record, load as load_streamed

    if is_record(path):
        return load_streamed(path)
    return result_kind(path).load(path)


def export(result, path: str | os.PathLike):
    """Write every array of ``result`` (any registered kind) to ``path`` (``.csv`` or ``.mat``)."""
    kind = kind_of_result(result)
    if kind is None:
        raise SceneError(f"`result` must be one of the result kinds ({', '.join(RESULT_KINDS)}), "
                         f"got {type(result).__name__}")
    return kind.export(result, path)


__all__ = ["RESULT_KINDS", "ResultKind", "export", "kind_of", "kind_of_result", "load", "register",
           "register_drawers", "forget_drawers", "result_kind"]
