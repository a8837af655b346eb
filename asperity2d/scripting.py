"""The harness of a study script: its command line, its output folder and its summary.

Every script in ``scenes/`` -- and a user's own study -- is built the same way: its lesson in
functions or cells of the package's public calls, and ``main(argv=None) -> int`` that reads the
options, runs them and prints::

    from asperity2d import scripting

    def main(argv=None) -> int:
        args = scripting.study_args(scripting.title(__doc__), argv, default_seeds=8)
        out = scripting.out_dir(args, __file__)
        summary = {...}                                  # what the study measured
        return scripting.finish(args, summary, out, ["one line per verdict"])

    if __name__ == "__main__":
        scripting.run(main)

Every script accepts ``--quick`` (small settings, used by the tests and the documentation),
``--json`` (print one JSON object), ``-o DIR`` (where outputs go, default
``renders/<script name>``), ``--no-gif`` and ``--frames``; a seed study adds ``--seeds`` and
``--workers``. A bad argument is one line on stderr and exit status 2, whether the script runs
as ``python scenes/X.py`` or as ``asperity2d run scenes/X.py``. :func:`si` writes a number the
way the package prints it (an SI prefix chosen from the value).
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from ._format import si
from ._io import output_dir, print_json, write_json, writing
from .cli.args import WORKERS_HELP, Parser, workers

__all__ = ["title", "parser", "study_args", "add_workers", "out_dir", "finish", "run", "si"]


def title(doc: str | None) -> str:
    """A script's one-line description for its ``--help``: the title of its docstring.

    Scene scripts open with a reStructuredText title (the documentation's gallery shows them),
    so the first line that is not blank and not an underline; "" when the docstring is empty
    (the gallery runs scripts with ``__doc__`` cleared).

    Parameters
    ----------
    doc : str or None
        The script's docstring (``__doc__``).

    Returns
    -------
    str
        Its title line, or "".

    Examples
    --------
    >>> from asperity2d import scripting
    >>> scripting.title("My study\\n========\\n\\nWhat it does.")
    'My study'
    """
    for line in (doc or "").splitlines():
        text = line.strip()
        if text and set(text) - set("=-~^"):
            return text
    return ""


def run(main) -> None:
    """Run a script's ``main()`` as a program: exit with its status if it is not 0.

    A script ends with ``if __name__ == "__main__": scripting.run(main)``. Success returns
    normally rather than raising ``SystemExit(0)``, so a host that runs the script in its own
    process -- the documentation's gallery -- carries on after it.

    Parameters
    ----------
    main : callable
        The script's ``main()``, returning its exit status.

    Examples
    --------
    >>> from asperity2d import scripting
    >>> scripting.run(lambda: 0)          # success: returns
    >>> scripting.run(lambda: 1)          # failure: exits with the status
    Traceback (most recent call last):
    SystemExit: 1
    """
    status = main()
    if status:
        raise SystemExit(status)


def parser(description: str) -> argparse.ArgumentParser:
    """The common arguments of a script: ``--quick``, ``--json``, ``-o``, ``--no-gif``, ``--frames``.

    Add your own with ``p.add_argument``; ``p.error(message)`` reports a bad value as one line on
    stderr and exit status 2.

    Parameters
    ----------
    description : str
        The script's one-line description (``--help``), e.g. :func:`title` of its docstring.

    Returns
    -------
    argparse.ArgumentParser
        The parser, with the common arguments.

    Examples
    --------
    >>> from asperity2d import scripting
    >>> p = scripting.parser("My study")
    >>> _ = p.add_argument("--load", type=float, default=0.01, help="normal load (N)")
    >>> args = p.parse_args(["--quick", "--load", "0.02"])
    >>> args.quick, args.load, args.json
    (True, 0.02, False)
    """
    p = Parser(description=description)
    p.add_argument("--quick", action="store_true", help="small, fast settings (tests, smoke runs)")
    p.add_argument("--json", action="store_true", help="print one JSON summary object")
    p.add_argument("-o", "--out-dir", help="output directory (default renders/<script>)")
    p.add_argument("--no-gif", action="store_true", help="skip the animation")
    p.add_argument("--frames", type=int, default=None, help="GIF frame count")
    return p


def study_args(description: str, argv, *, default_seeds: int | str, minimum_seeds: int = 2,
               quick_seeds: int = 2, auto: bool = False, default_max_seeds: int = 40):
    """Parse a seed study's arguments: the common ones plus ``--seeds`` and ``--workers``.

    Parameters
    ----------
    description : str
        The script's one-line description (``--help``).
    argv : list of str or None
        The arguments (None: the command line's).
    default_seeds : int or "auto"
        Seeds without ``--seeds`` or ``--quick``.
    minimum_seeds : int
        Fewest seeds accepted: fewer is a usage error (one line, exit status 2).
    quick_seeds : int
        Seeds with ``--quick``.
    auto : bool
        Also take ``--seeds auto`` (``args.seeds == "auto"``: seeds added in stages until the
        study's verdicts are decided, ``compare(..., seeds="auto")``) with the budget
        ``--max-seeds`` (``args.max_seeds``).
    default_max_seeds : int
        The budget of ``--seeds auto`` without ``--max-seeds``.

    Returns
    -------
    argparse.Namespace
        The arguments, ``args.seeds`` resolved and ``args.workers`` None (auto) or N >= 1.

    Examples
    --------
    >>> from asperity2d import scripting
    >>> args = scripting.study_args("My study", ["--quick"], default_seeds=8)
    >>> args.seeds, args.workers
    (2, None)
    >>> scripting.study_args("My study", ["--seeds", "12", "--workers", "1"], default_seeds=8).seeds
    12
    >>> args = scripting.study_args("My study", ["--seeds", "auto", "--max-seeds", "30"], default_seeds=8, auto=True)
    >>> args.seeds, args.max_seeds
    ('auto', 30)
    """
    p = parser(description)

    def seeds_arg(text: str):
        if auto and text == "auto":
            return text
        try:
            return int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"must be an integer{' or auto' if auto else ''}, got {text!r}") from None

    p.add_argument("--seeds", type=seeds_arg, default=None,
                   help=f"seeds per random variant{', or auto (added in stages until decided)' if auto else ''} "
                        f"(default {default_seeds}, quick {quick_seeds})")
    if auto:
        p.add_argument("--max-seeds", type=int, default=default_max_seeds,
                       help=f"the seed budget of --seeds auto (default {default_max_seeds})")
    add_workers(p)
    args = p.parse_args(argv)
    args.seeds = args.seeds or (quick_seeds if args.quick else default_seeds)
    if args.seeds == "auto":
        if args.max_seeds < max(minimum_seeds, 2):
            p.error(f"`max-seeds` must be >= {max(minimum_seeds, 2)}, got {args.max_seeds}")
    elif args.seeds < minimum_seeds:
        p.error(f"`seeds` must be >= {minimum_seeds}, got {args.seeds}")
    return args


def add_workers(p) -> None:
    """Add ``--workers auto|N`` to parser ``p`` (``args.workers``: None for auto, decided by cost,
    or N >= 1).

    Parameters
    ----------
    p : argparse.ArgumentParser
        The script's parser (:func:`parser`).

    Examples
    --------
    >>> from asperity2d import scripting
    >>> p = scripting.parser("My study")
    >>> scripting.add_workers(p)
    >>> p.parse_args(["--workers", "2"]).workers
    2
    """
    p.add_argument("--workers", type=workers, default=None, help=WORKERS_HELP)


def out_dir(args, script_file: str) -> Path:
    """The output directory for a script (created); ``SceneError`` naming ``-o`` if it cannot be.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed arguments (:func:`parser`): ``-o DIR`` if given is the directory.
    script_file : str
        The script's path (``__file__``): without ``-o``, the directory is ``renders/<script
        name>`` beside the script's folder (or under ``$ASPERITY2D_RENDERS``).

    Returns
    -------
    pathlib.Path
        The directory, created.

    Examples
    --------
    >>> from asperity2d import scripting
    >>> args = scripting.parser("My study").parse_args(["-o", "outputs"])
    >>> scripting.out_dir(args, "my_study.py").name
    'outputs'
    """
    if args.out_dir:
        path = Path(args.out_dir)
    else:
        root = Path(os.environ.get("ASPERITY2D_RENDERS", Path(script_file).resolve().parent.parent / "renders"))
        path = root / Path(script_file).stem
    output_dir("-o", path)
    with writing("-o", path):
        path.mkdir(parents=True, exist_ok=True)
    return path


def finish(args, summary: dict, directory: Path, lines: list[str]) -> int:
    """Write ``summary.json`` atomically and print the summary (JSON or text).

    Strict JSON: undefined statistics (NaN, infinities) are
    ``null``, NumPy values plain.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed arguments: ``--json`` prints the summary as JSON instead of ``lines``.
    summary : dict
        What the script found, written to ``directory / "summary.json"``.
    directory : pathlib.Path
        The output directory (:func:`out_dir`).
    lines : list of str
        The summary in words, printed followed by ``outputs in DIRECTORY``.

    Returns
    -------
    int
        0, the script's exit status.

    Examples
    --------
    >>> from asperity2d import scripting
    >>> args = scripting.parser("My study").parse_args(["-o", "outputs"])
    >>> out = scripting.out_dir(args, "my_study.py")
    >>> scripting.finish(args, {"peak_N": 0.0123}, out, [f"peak {scripting.si(0.0123, 'N')}"])
    peak 12.3 mN
    outputs in outputs
    0
    """
    write_json(directory / "summary.json", summary)
    if args.json:
        print_json(summary)
    else:
        print("\n".join(lines + [f"outputs in {directory}"]))
    return 0
