"""What every command-line module shares: the parser class, the argument types, loading a script.

The lowest module of :mod:`asperity2d.cli`: the parser (:mod:`.main`), the handlers
(:mod:`.asperity`, :mod:`.belt`, :mod:`.basins`, :mod:`.sweep`) and the scripts' harness
(:mod:`asperity2d.scripting`) import it; it imports none of them. Light: no NumPy, no pymunk.
"""

from __future__ import annotations

import argparse
import sys

from .._inputs import MAX_RUNS, check_int, check_positive, check_tolerance
from .._inputs import check_runs as _check_runs
from ..errors import SceneError

PROG = "asperity2d"
PLOT_SUFFIXES = (".png", ".svg", ".pdf")


class Parser(argparse.ArgumentParser):
    """The one argument parser of asperity2d's commands and scene scripts.

    A usage error is one line on stderr, ``asperity2d: error: ...``, and exit
    status 2 (no usage dump); subparsers inherit this.
    """

    def error(self, message):
        self.exit(2, f"{PROG}: error: {message}\n")

    def _check_value(self, action, value):
        # a family of subcommands with a default one (see Subcommands) takes any first word
        if isinstance(action, Subcommands) and action.default_command is not None:
            return
        super()._check_value(action, value)


class Subcommands(argparse._SubParsersAction):
    """Subcommands where a first word that names none of them goes to ``default_command``.

    ``asperity2d belt chain.toml`` is ``asperity2d belt run chain.toml``; ``asperity2d belt
    basins ...`` is the ``basins`` subcommand, with its own parser and help. Created by
    ``parser.add_subparsers(action=Subcommands, default_command="run")``.
    """

    def __init__(self, *args, default_command: str | None = None, **kwargs):
        super().__init__(*args, **kwargs)
        self.default_command = default_command

    def __call__(self, parser, namespace, values, option_string=None):
        if self.default_command is not None and values and values[0] not in self._name_parser_map:
            values = [self.default_command, *values]
        name, rest = values[0], values[1:]
        setattr(namespace, self.dest, name)
        sub = self._name_parser_map[name]
        # Parsed into the parent's namespace (argparse's own action parses into a fresh one and
        # copies it over, so an option given before the first word -- `belt -o x.png chain.toml`
        # -- would be reset to the subcommand's default); the subcommand's set_defaults
        # (its handler) do replace the parent's.
        for key, value in sub._defaults.items():
            setattr(namespace, key, value)
        _, extras = sub.parse_known_args(rest, namespace)
        if extras:
            vars(namespace).setdefault(argparse._UNRECOGNIZED_ARGS_ATTR, []).extend(extras)


class LazyHelp(str):
    """A help text written when the help is printed, not when the parser is built: a registry it
    lists (the output formats) loads its installed packages' entry points only for ``--help``,
    not for every command. argparse fills a help text in with ``%``; this one computes itself
    there (the placeholder is what it is as a plain string)."""

    def __new__(cls, make):
        self = super().__new__(cls, "(listed in --help)")
        self.make = make
        return self

    def __mod__(self, params):
        return self.make().replace("%", "%%") % params


def check_runs(runs: int, max_runs: int | None, why: str) -> None:
    """Refuse a command that would start more than ``--max-runs`` runs (see
    :func:`asperity2d._inputs.check_runs`)."""
    _check_runs(runs, max_runs, why, name="--max-runs")


def fail(message) -> int:
    """Print the one error line; return exit status 2."""
    print(f"{PROG}: error: {message}", file=sys.stderr)
    return 2


def _checked(check, convert, text: str):
    """``check("value", convert(text))`` as an argparse type: the package's own rule and message
    (:mod:`asperity2d._inputs`), argparse prefixing the option's name."""
    try:
        value = convert(text)
    except ValueError:
        value = text  # the check names it: "must be a real number, got 'x'"
    try:
        return check("value", value)
    except SceneError as exc:
        raise argparse.ArgumentTypeError(str(exc).removeprefix("`value` ")) from None


def positive_float(text: str) -> float:
    """An argparse type: a finite number > 0 (:func:`asperity2d._inputs.check_positive`)."""
    return _checked(check_positive, float, text)


def tolerance(text: str) -> float:
    """An argparse type: a relative tolerance a float can meet
    (:func:`asperity2d._inputs.check_tolerance`)."""
    return _checked(check_tolerance, float, text)


def positive_int(text: str) -> int:
    """An argparse type: an integer >= 1 (:func:`asperity2d._inputs.check_int`)."""
    return _checked(lambda name, value: check_int(name, value, minimum=1, maximum=None), int, text)


def seeds_or_auto(text: str) -> int | str:
    """An argparse type: a seed count >= 1, or ``auto`` (seeds added in stages until decided)."""
    if text == "auto":
        return text
    try:
        return positive_int(text)
    except argparse.ArgumentTypeError as exc:
        raise argparse.ArgumentTypeError(f"{exc} (or auto)") from None


def port(text: str) -> int:
    """An argparse type: a TCP port, 0 (a free one) to 65535."""
    return _checked(lambda name, value: check_int(name, value, minimum=0, maximum=65535), int, text)


def workers(text: str) -> int | None:
    """An argparse type: ``auto`` (None: decided by cost,
    :func:`asperity2d.sweep.engine.decide_workers`) or an integer >= 1."""
    if text.strip().lower() == "auto":
        return None
    return positive_int(text)


#: The help of every ``--workers`` option.
WORKERS_HELP = ("local worker processes: auto (the default: in this process when the runs are "
                "too cheap to pay for starting workers, else every core) or N")


def check_extra(arg: str, path) -> None:
    """Refuse, before any work, an output whose writer needs an optional extra that is not
    installed (``.mp4``: the video extra), naming the option the user typed."""
    import importlib.util
    from pathlib import Path

    if path is not None and Path(path).suffix.lower() == ".mp4" and importlib.util.find_spec("imageio_ffmpeg") is None:
        raise SceneError(f"`{arg}` {str(path)!r}: writing .mp4 needs the optional video extra: "
                         "pip install \"asperity2d[video]\" (imageio-ffmpeg)")


def defines_main(path) -> bool:
    """Whether the script at ``path`` binds ``main`` at module level (a ``def``, an assignment or
    an import), read without running it. A script that does not parse, or is not text, counts as
    defining it: :func:`load_script` then reports its own error."""
    import ast
    import importlib.util

    from .._io import read_bytes

    try:
        tree = ast.parse(importlib.util.decode_source(read_bytes("scene", path)))
    except (SyntaxError, ValueError, UnicodeDecodeError, LookupError, RecursionError, MemoryError):
        return True

    def binds(node) -> bool:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            return node.name == "main"
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            return any((alias.asname or alias.name.partition(".")[0]) == "main" or alias.name == "*"
                       for alias in node.names)
        if isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            return any(isinstance(n, ast.Name) and n.id == "main" for t in targets for n in ast.walk(t))
        if isinstance(node, (ast.If, ast.Try, ast.With)):  # main defined conditionally
            return any(binds(child) for child in ast.iter_child_nodes(node) if isinstance(child, ast.stmt))
        return False

    return any(binds(node) for node in tree.body)


def load_script(path):
    """Import a scene script as a module (registered in ``sys.modules``, so worker processes
    can pickle its functions). The file must be a readable Python text file; what the
    script itself raises is the script's own error and propagates unchanged."""
    import importlib.util
    from pathlib import Path

    from .._io import FileError, read_bytes

    path = Path(path)
    data = read_bytes("scene", path)
    if b"\0" in data:
        raise FileError("scene", path, "is not a Python script", "it contains NUL bytes")
    try:
        importlib.util.decode_source(data)  # UTF-8 unless a coding line says otherwise
    except (UnicodeDecodeError, SyntaxError, LookupError) as exc:
        raise FileError("scene", path, "is not UTF-8 text (and declares no other encoding)",
                        str(exc)) from None
    spec = importlib.util.spec_from_file_location(f"_asperity2d_scene_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module
