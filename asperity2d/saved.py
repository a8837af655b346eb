"""Saved results of either kind, read by their format tag: :func:`~asperity2d.load` (``asperity2d.load``).

A record streamed to disk as its run went (a directory, :mod:`asperity2d.streamed`) is an
asperity run too, read lazily. An asperity run (:class:`asperity2d.result.Result`,
``"asperity2d.result/2"``) and a belt chain
(:class:`asperity2d.belt.BeltResult`, ``"asperity2d.belt-result/2"``) share one result protocol
and one file layout: an ``.npz`` of arrays plus a JSON ``metadata`` entry carrying the tag. The
previous release wrote no tag; its files are told apart by their metadata (a ``scene`` record or
a ``chain`` record) and still load.
"""

from __future__ import annotations

import os

from ._io import FileError, load_npz

#: Format tag -> kind of result; the untagged files of the previous release by their record.
KINDS = {"asperity2d.result/2": "asperity", "asperity2d.belt-result/2": "belt"}
_UNTAGGED = {"scene": "asperity", "chain": "belt"}


def kind_of(path: str | os.PathLike) -> str:
    """``"asperity"`` or ``"belt"``: the kind of result saved at ``path`` (only its metadata is
    read). A file that is neither raises :class:`~asperity2d._io.FileError` naming ``path``."""
    what = "an asperity2d result file (asperity run or belt chain)"
    from .streamed import is_record

    if is_record(path):
        return "asperity"
    _, meta = load_npz(path, (), kind=what)
    tag = meta.get("format")
    if tag is None:
        kind = next((k for record, k in _UNTAGGED.items() if record in meta), None)
        if kind is None:
            raise FileError("path", path, f"is not {what}", "it has no format tag and no scene or chain record")
        return kind
    if tag not in KINDS:
        raise FileError("path", path, f"is not {what}", f"its format is {tag!r}, expected one of "
                        f"{', '.join(map(repr, KINDS))}")
    return KINDS[tag]


def load(path: str | os.PathLike):
    """Read a result saved with ``save``: a :class:`~asperity2d.result.Result` or a
    :class:`~asperity2d.belt.BeltResult`, chosen by the file's format tag; or a record streamed
    to a directory (``simulate(..., record_to=path)``), read lazily.

    Parameters
    ----------
    path : str or os.PathLike
        A ``.npz`` file written by ``Result.save`` or ``BeltResult.save``, or a directory
        written by ``simulate(..., record_to=path)``.

    Returns
    -------
    Result or BeltResult
        The run as it was saved, bit for bit.

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
    if kind_of(path) == "belt":
        from .belt.result import load as load_belt

        return load_belt(path)
    from .streamed import is_record, load as load_streamed

    if is_record(path):
        return load_streamed(path)
    from .result import load as load_asperity

    return load_asperity(path)
