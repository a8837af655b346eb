"""Shared plumbing for the runnable scene scripts in ``scenes/``.

Every script has ``main(argv=None) -> int`` and accepts ``--quick`` (small
settings, used by the tests), ``--json`` (print one JSON object), ``-o DIR``
(where outputs go, default ``renders/<script name>``) and ``--no-gif``. Its
parser is the command line's (:class:`asperity2d.cli.Parser`): a bad argument
is one line on stderr and exit status 2, whether the script runs as
``python scenes/X.py`` or as ``asperity2d run scenes/X.py``.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from .._io import output_dir, print_json, write_json, writing
from .args import WORKERS_HELP, Parser, workers


def title(doc: str | None) -> str:
    """A script's one-line description for its ``--help``: the title of its docstring.

    Scene scripts open with a reStructuredText title (the documentation's gallery shows them),
    so the first line that is not blank and not an underline; "" when the docstring is empty
    (the gallery runs scripts with ``__doc__`` cleared).
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
    """
    status = main()
    if status:
        raise SystemExit(status)


def parser(description: str) -> argparse.ArgumentParser:
    """The common arguments of a scene script; ``p.error(message)`` reports a bad value."""
    p = Parser(description=description)
    p.add_argument("--quick", action="store_true", help="small, fast settings (tests, smoke runs)")
    p.add_argument("--json", action="store_true", help="print one JSON summary object")
    p.add_argument("-o", "--out-dir", help="output directory (default renders/<script>)")
    p.add_argument("--no-gif", action="store_true", help="skip the animation")
    p.add_argument("--frames", type=int, default=None, help="GIF frame count")
    return p


def study_args(description: str, argv, *, default_seeds: int, minimum_seeds: int = 2,
               quick_seeds: int = 2):
    """Parse a seed study's arguments: the common ones plus ``--seeds`` and ``--workers``.

    ``args.seeds`` is resolved (``default_seeds``, or ``quick_seeds`` with ``--quick``);
    fewer than ``minimum_seeds`` is a usage error (one line, exit status 2).
    """
    p = parser(description)
    p.add_argument("--seeds", type=int, default=None,
                   help=f"seeds per random variant (default {default_seeds}, quick {quick_seeds})")
    add_workers(p)
    args = p.parse_args(argv)
    args.seeds = args.seeds or (quick_seeds if args.quick else default_seeds)
    if args.seeds < minimum_seeds:
        p.error(f"`seeds` must be >= {minimum_seeds}, got {args.seeds}")
    return args


def add_workers(p) -> None:
    """``--workers auto|N`` (``args.workers``: None for auto, decided by cost, or N >= 1)."""
    p.add_argument("--workers", type=workers, default=None, help=WORKERS_HELP)


def out_dir(args, script_file: str) -> Path:
    """The output directory for a script (created); ``SceneError`` naming ``-o`` if it cannot be."""
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

    Strict JSON (:func:`asperity2d._io.to_json`): undefined statistics (NaN, infinities) are
    ``null``, NumPy values plain.
    """
    write_json(directory / "summary.json", summary)
    if args.json:
        print_json(summary)
    else:
        print("\n".join(lines + [f"outputs in {directory}"]))
    return 0
