"""Command line: ``asperity2d`` (also ``python -m asperity2d``).

Thin by design: it parses, calls the library, prints. Every subcommand that
computes something accepts ``--json`` and then prints exactly one JSON object.
Bad input -- a bad value, or a file that is missing, a directory, unreadable,
not UTF-8, not TOML or damaged -- prints one line on stderr
(``asperity2d: error: ...``, naming the argument) and exits with status 2,
before anything is computed where it can be checked up front. A user's own
scene script that raises shows its own traceback: the bug is in that script.

Start-up stays light: the parser of every subcommand is built here without
importing any implementation; a subcommand's handler (and NumPy, pymunk,
SciPy, matplotlib) is imported only when that subcommand runs.
"""

from __future__ import annotations

import argparse
import importlib
import math
import sys
import warnings

from ..errors import SceneError, SimulationError

PROG = "asperity2d"
PLOT_SUFFIXES = (".png", ".svg", ".pdf")


class Parser(argparse.ArgumentParser):
    """The one argument parser of asperity2d's commands and scene scripts.

    A usage error is one line on stderr, ``asperity2d: error: ...``, and exit
    status 2 (no usage dump); subparsers inherit this.
    """

    def error(self, message):
        self.exit(2, f"{PROG}: error: {message}\n")


def fail(message) -> int:
    """Print the one error line; return exit status 2."""
    print(f"{PROG}: error: {message}", file=sys.stderr)
    return 2


def positive_float(text: str) -> float:
    """An argparse type: a finite number > 0 (the message is prefixed with the option's name)."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be a finite number > 0, got {text!r}")
    return value


def positive_int(text: str) -> int:
    """An argparse type: an integer >= 1."""
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be an integer >= 1, got {text!r}")
    return value


class _Version(argparse.Action):
    """``--version``: read from the installed metadata only when asked (it costs ~80 ms)."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS, help=None):
        super().__init__(option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        from .._version import __version__

        print(f"{PROG} {__version__}")
        parser.exit(0)


def _json_flag(p) -> None:
    p.add_argument("--json", action="store_true", help="print one JSON object")


#: The names of asperity2d.experiments.measures.MEASURES (kept here so --help imports nothing; a test
#: checks they agree).
COMPARE_MEASURES = ("critical", "critical-run-up", "quasi-static-breakaway", "first-breakaway", "peak-stick",
                    "mean-stick", "travel")


def build_parser() -> Parser:
    """The whole command line; each subcommand names its handler as ``"module:function"``."""
    parser = Parser(prog=PROG, description="Friction at the asperity scale in 2D (pymunk), and "
                                           "masses on a moving belt with exact stick/slip.")
    parser.add_argument("--version", action=_Version, help="print the version and exit")
    sub = parser.add_subparsers(dest="command", required=True, metavar="command")

    # allow_abbrev=False: a script's own --out must not be read as an abbreviated --output
    p = sub.add_parser("run", help="run a scene script (.py) or a TOML scene file", allow_abbrev=False,
                       add_help=False)
    p.add_argument("-h", "--help", action="store_true", dest="run_help",
                   help="show this help; after a .py script, the script's own help")
    p.add_argument("scene", nargs="?",
                   help="scene script (.py; other arguments go to its main()) or .toml")
    p.add_argument("-o", "--output",
                   help="render to this file (.gif, .mp4, .png, .svg, .pdf, .wav); a script's output directory")
    p.add_argument("--save", help="save the Result (.npz) (TOML scenes)")
    p.add_argument("--duration", type=positive_float, help="simulated time in s (TOML scenes)")
    _json_flag(p)
    p.set_defaults(handler="asperity2d.cli.asperity:run", print_run_help=p.print_help)

    p = sub.add_parser("analyze", help="stick-slip events and breakaway force of a saved result")
    p.add_argument("result", help="a result saved with --save / Result.save (.npz)")
    _json_flag(p)
    p.set_defaults(handler="asperity2d.cli.asperity:analyze")

    p = sub.add_parser("render", help="render a saved result; the extension picks the renderer")
    p.add_argument("result", help="a result saved with --save / Result.save (.npz)")
    p.add_argument("-o", "--output", required=True,
                   help=".gif, .mp4 (needs the video extra), .png, .svg, .pdf or .wav (the slider's sound)")
    _json_flag(p)
    p.set_defaults(handler="asperity2d.cli.asperity:render")

    p = sub.add_parser("critical", help="critical constant drive force of a TOML scene")
    p.add_argument("scene", help="TOML scene file")
    p.add_argument("--rel-tol", type=positive_float, default=0.0025, help="bracket width (default 0.0025)")
    _json_flag(p)
    p.set_defaults(handler="asperity2d.cli.asperity:critical")

    p = sub.add_parser("compare", help="compare spacings over seeds (critical force, stick forces)")
    p.add_argument("--measure", choices=COMPARE_MEASURES, default="critical",
                   help="critical: constant force that moves the slider across from rest on the "
                        "surface, a step load (default); critical-run-up; quasi-static-breakaway: "
                        "a slowly ramped force; first-breakaway / peak-stick / mean-stick: stick "
                        "forces of spring-driven passes; travel: distance under the scene's "
                        "drive_force")
    p.add_argument("--variants", default="regular,random", help="comma-separated spacings")
    p.add_argument("--seeds", type=positive_int, default=20)
    p.add_argument("--workers", type=positive_int, default=1)
    p.add_argument("--scheduler", help="a Dask scheduler address, or 'local' to start one")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="make_scene argument shared by every variant (repeatable)")
    p.add_argument("--save", help="save the comparison (.json) to re-plot later")
    p.add_argument("--load", help="re-use a saved comparison instead of running")
    p.add_argument("-o", "--output", help="comparison plot (.png, .svg, .pdf)")
    _json_flag(p)
    p.set_defaults(handler="asperity2d.cli.asperity:compare")

    p = sub.add_parser("belt", help="masses on a moving belt (exact stick/slip)",
                       description="Run a chain from a TOML file or a named preset (see "
                                   "asperity2d.cli.belt for the chain file's keys).")
    p.add_argument("chain", nargs="?", help="TOML chain file")
    p.add_argument("--preset", help="named preset from the thesis tables (see --list-presets)")
    p.add_argument("--list-presets", action="store_true", help="print the preset names and exit")
    p.add_argument("--method", choices=("exact", "sign"), help="override the solver")
    p.add_argument("--t-end", type=positive_float, help="override the duration (s)")
    p.add_argument("-o", "--output", help="plot (.png/.svg/.pdf), result (.npz) or table (.csv)")
    _json_flag(p)
    p.set_defaults(handler="asperity2d.cli.belt:run")
    _add_belt_basins(p)

    _add_sweep(sub)
    return parser


def _add_belt_basins(p) -> None:
    """``asperity2d belt basins ...`` options (used after the word ``basins``; see asperity2d.cli.basins)."""
    g = p.add_argument_group("basins: asperity2d belt basins (--preset|--chain-file) [options]")
    g.add_argument("--x", dest="basins_x", default="x1", help="first coordinate: x1..xn (m) or v1..vn (m/s)")
    g.add_argument("--y", dest="basins_y", default="v1", help="second coordinate (default v1)")
    g.add_argument("--x-range", dest="basins_x_range", default="-0.5,0.5",
                   help="LO,HI of the first coordinate (write --x-range=-0.5,0.5 when LO < 0)")
    g.add_argument("--y-range", dest="basins_y_range", default="-0.5,0.5", help="LO,HI of the second")
    g.add_argument("--grid", dest="basins_grid", default="41", help="points per axis: N or NX,NY")
    g.add_argument("--chain-file", dest="basins_chain", help="TOML chain file (instead of --preset)")
    g.add_argument("--store", dest="basins_store", help="sweep store directory (default: <output>.runs)")
    g.add_argument("--workers", dest="basins_workers", type=positive_int, help="local worker processes")
    g.add_argument("--scheduler", dest="basins_scheduler", help="Dask scheduler address, or 'local'")
    g.add_argument("--rtol", dest="basins_rtol", type=positive_float, default=1e-6,
                   help="relative tolerance of the limit-cycle test")


def _add_sweep(subparsers) -> None:
    parser = subparsers.add_parser(
        "sweep", help="run parameter studies over grids and seeds (resumable)",
        description="Run parameter studies (grid x seeds) into a resumable results store.")
    sub = parser.add_subparsers(dest="sweep_command", required=True, metavar="{run,status,report,export}")

    p = sub.add_parser("run", help="run the unfinished runs of a study (.toml or .py)")
    p.add_argument("study", help="study file: .toml, or .py defining STUDY")
    p.add_argument("--store", required=True, help="results directory of the study")
    p.add_argument("--workers", type=positive_int, default=None,
                   help="local worker processes (default: CPU count; 1 = in-process)")
    p.add_argument("--scheduler", default=None,
                   help="Dask scheduler address tcp://host:port, or 'local' for a LocalCluster")
    p.add_argument("--retry-failed", action="store_true", help="re-run runs recorded as failed")
    p.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    _json_flag(p)

    p = sub.add_parser("status", help="count done / failed / pending runs of a store")
    p.add_argument("store", help="results directory")
    _json_flag(p)

    p = sub.add_parser("report", help="mean, CI and Mann-Whitney U per variant; summary plot")
    p.add_argument("store", help="results directory")
    p.add_argument("-o", "--output", default=None,
                   help="figure path (.png/.pdf/.svg; default: STORE/summary.png)")
    p.add_argument("--confidence", type=float, default=0.95, help="CI level (default 0.95)")
    _json_flag(p)

    p = sub.add_parser("export", help="table of finished runs as CSV or .npy (structured)")
    p.add_argument("store", help="results directory")
    p.add_argument("-o", "--output", required=True, help="output file: .csv or .npy")
    _json_flag(p)
    parser.set_defaults(handler="asperity2d.cli.sweep:run")


def _load_script(path):
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


def _exit_status(exc: SystemExit) -> int:
    """The status ``sys.exit`` would give: None -> 0; a message is printed and gives 1."""
    if exc.code is None or isinstance(exc.code, int):
        return exc.code or 0
    print(exc.code, file=sys.stderr)
    return 1


def _one_line_warning(message, category, filename, lineno, file=None, line=None):
    print(f"{PROG}: warning: {message}", file=sys.stderr)


def main(argv: list[str] | None = None) -> int:
    """Run the command line on ``argv`` (default ``sys.argv[1:]``); return the exit status."""
    parser = build_parser()
    try:
        args, extra = parser.parse_known_args(argv)
        script = args.command == "run" and (args.scene or "").endswith(".py")
        if args.command == "run" and args.run_help:
            if not script:
                args.print_run_help()
                return 0
            extra.append("--help")  # `asperity2d run x.py --help`: the script's own help
        if args.command == "run" and args.scene is None:
            parser.error("the following arguments are required: scene")
        if extra and not script:
            parser.error(f"unrecognized arguments: {' '.join(extra)}")
    except SystemExit as exc:  # --help, --version, or a usage error already printed
        return _exit_status(exc)
    args.script_args = extra
    module, _, name = args.handler.partition(":")
    handler = getattr(importlib.import_module(module), name)
    with warnings.catch_warnings():
        warnings.showwarning = _one_line_warning
        try:
            return int(handler(args) or 0)
        except (SceneError, SimulationError) as exc:
            return fail(exc)
        except SystemExit as exc:  # a scene script's own sys.exit / argparse error
            return _exit_status(exc)
        except KeyboardInterrupt:
            print(f"{PROG}: interrupted", file=sys.stderr)
            return 130
