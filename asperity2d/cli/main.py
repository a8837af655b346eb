"""Command line: ``asperity2d`` (also ``python -m asperity2d``).

Thin by design: it parses, calls the library, prints. Every subcommand that
computes something accepts ``--json`` and then prints exactly one JSON object.
Bad input -- a bad value, or a file that is missing, a directory, unreadable,
not UTF-8, not TOML or damaged -- prints one line on stderr
(``asperity2d: error: ...``, naming the argument) and exits with status 2,
before anything is computed where it can be checked up front. A user's own
scene script that raises shows its own traceback: the bug is in that script.

Start-up stays light: the handler modules are imported here, but each imports
its implementation (and NumPy, pymunk, SciPy, matplotlib) only when its
subcommand runs. Each subcommand's parser names its handler function
(``set_defaults(handler=...)``); ``belt basins`` is a subcommand of ``belt``.
"""

from __future__ import annotations

import argparse
import os
import sys
import warnings

from .._inputs import show
from ..errors import SceneError, SimulationError
from ..renderers import FORMATS
from ..renderers import describe as describe_formats
from .args import LazyHelp
from . import asperity, basins, belt, explore, sweep
from .args import MAX_RUNS, PLOT_SUFFIXES, PROG, WORKERS_HELP, Parser, Subcommands, fail, positive_float, tolerance
from .args import port as port_arg
from .args import positive_int, seeds_or_auto
from .args import workers as workers_arg

__all__ = ["main", "build_parser", "Parser", "PROG", "PLOT_SUFFIXES", "fail", "positive_float",
           "positive_int"]


class _Version(argparse.Action):
    """``--version``: read from the installed metadata only when asked (it costs ~80 ms), and which
    step loop the engine uses (the C one, or Python and why: the numbers are the same)."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS, help=None):
        super().__init__(option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        from .._version import __version__
        from ..engine import kernel

        loop = "C" if kernel.KERNEL else f"Python ({kernel.KERNEL_REASON})"
        print(f"{PROG} {__version__}\nengine step loop: {loop}")
        parser.exit(0)


def _json_flag(p) -> None:
    p.add_argument("--json", action="store_true", help="print one JSON object")


def build_parser() -> Parser:
    """The whole command line; each subcommand names its handler function."""
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
                   help=LazyHelp(lambda: f"render to this file ({', '.join(FORMATS)}); a script's output directory"))
    p.add_argument("--save", help="save the Result (.npz) (TOML scenes)")
    p.add_argument("--duration", type=positive_float, help="simulated time in s (TOML scenes)")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="override a make_scene argument of a TOML scene (repeatable; values read as TOML)")
    _engine_flag(p)
    _json_flag(p)
    p.set_defaults(handler=asperity.run, print_run_help=p.print_help)

    p = sub.add_parser("explore", help="the workbench in the browser: change a parameter, watch the run "
                                       "stream in, measure and compare (needs the app extra)",
                       description="Serve the workbench on 127.0.0.1 with a random token in its URL and "
                                   "open the browser on it; Ctrl-C stops it.")
    p.add_argument("scene", nargs="?", help="TOML scene file to start from (default: the default scene)")
    p.add_argument("--port", type=port_arg, default=0, help="port on 127.0.0.1 (default: a free one)")
    p.add_argument("--no-browser", action="store_true",
                   help="do not open a browser; print the URL (with its token) and keep serving")
    p.add_argument("--workers", type=workers_arg, default=None,
                   help="worker processes of the ensemble comparisons (default: every core)")
    p.set_defaults(handler=explore.run)

    p = sub.add_parser("analyze", help="stick-slip events and breakaway force of a saved result "
                                       "(a belt chain's: stick/slip per mass)")
    p.add_argument("result", help="a result saved with --save / Result.save / BeltResult.save (.npz)")
    _json_flag(p)
    p.set_defaults(handler=asperity.analyze)

    p = sub.add_parser("render", help="render a saved result; the extension picks the renderer")
    p.add_argument("result", help="a result saved with --save / Result.save / BeltResult.save (.npz)")
    p.add_argument("-o", "--output", required=True,
                   help=LazyHelp(lambda: f"the extension picks the format: {describe_formats()}"))
    _json_flag(p)
    p.set_defaults(handler=asperity.render)

    p = sub.add_parser("critical", help="critical constant drive force of a TOML scene")
    p.add_argument("scene", help="TOML scene file")
    p.add_argument("--rel-tol", type=tolerance, default=0.0025, help="bracket width (default 0.0025)")
    p.add_argument("--start", choices=("rest", "entry", "run-up"), default="rest",
                   help="how each run begins: at rest on the surface (default), at rest against the first "
                        "flank, or from the builder's start with a run-up")
    _engine_flag(p)
    _json_flag(p)
    p.set_defaults(handler=asperity.critical)

    p = sub.add_parser("compare", help="compare spacings over seeds (critical force, stick forces)")
    p.add_argument("--measure", default="critical",
                   help="a named measure (default critical, the constant force that moves the slider "
                        "across from rest); `asperity2d measures` lists them with their units")
    p.add_argument("--variants", default="regular,random", help="comma-separated spacings")
    p.add_argument("--seeds", type=seeds_or_auto, default=20,
                   help="seeds per variant (default 20), or auto: added in stages of 10 until every "
                        "verdict against the regular spacing is decided (a sequential design that keeps "
                        "the false-positive rate at the measure's alpha)")
    p.add_argument("--max-seeds", type=positive_int, default=None,
                   help="the seed budget of --seeds auto (default 40)")
    p.add_argument("--workers", type=workers_arg, default=None, help=WORKERS_HELP)
    p.add_argument("--scheduler", help="a Dask scheduler address, or 'local' to start one")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="make_scene argument shared by every variant (repeatable)")
    p.add_argument("--save", help="save the comparison (.json) to re-plot later")
    p.add_argument("--load", help="re-use a saved comparison instead of running")
    p.add_argument("-o", "--output", help="comparison plot (.png, .svg, .pdf)")
    _max_runs(p)
    _engine_flag(p, ensemble=True)
    _json_flag(p)
    p.set_defaults(handler=asperity.compare)

    p = sub.add_parser("measures", help="list the named measures of compare, with their units")
    _json_flag(p)
    p.set_defaults(handler=asperity.measures)

    p = sub.add_parser("validate", help="run the closed-form checks of both models (exit status 1 if one fails)")
    p.add_argument("checks", nargs="*", metavar="CHECK", help="checks to run (default all)")
    _engine_flag(p)
    _json_flag(p)
    p.set_defaults(handler=asperity.validate)

    _add_belt(sub)
    _add_sweep(sub)
    return parser


def _max_runs(p) -> None:
    p.add_argument("--max-runs", type=positive_int, default=None,
                   help=f"refuse to start more runs than this (default {MAX_RUNS:,})")


def _belt_common() -> Parser:
    """The options ``belt`` (a chain run) and ``belt basins`` share."""
    common = Parser(add_help=False)
    common.add_argument("--preset", help="named preset from the tables of the multi-DOF belt thesis (see --list-presets)")
    common.add_argument("--t-end", type=positive_float, help="override the duration (s)")
    _json_flag(common)
    return common


#: The built-in asperity engines, for --help only (named here so that --help imports no engine); the
#: flag takes any name the registry knows (asperity2d.engine.ENGINES: an installed package's engine
#: too, or "module:name"), and the registry refuses an unknown one in one line with the nearest names.
ENGINE_NAMES = ("pymunk", "batched")


def _engine_flag(p, *, ensemble: bool = False) -> None:
    if ensemble:  # compare: the API's default (auto with --seeds auto: batched where installed and covered)
        p.add_argument("--engine", default=None, metavar="ENGINE",
                       help=f"the engine that steps the scenes ({', '.join(ENGINE_NAMES)}, an installed one, or "
                            "auto: batched where installed and every scene is covered; pip install "
                            "\"asperity2d[batch]\" for batched); default: auto with --seeds auto, else pymunk")
        return
    p.add_argument("--engine", default="pymunk", metavar="ENGINE",
                   help=f"the engine that steps the scenes ({', '.join(ENGINE_NAMES)} or an installed one; "
                        "default pymunk, the reference; batched: many scenes in one compiled loop, pip install "
                        "\"asperity2d[batch]\")")


def _add_belt(subparsers) -> None:
    """``asperity2d belt [run] CHAIN|--preset NAME ...`` and ``asperity2d belt basins ...``."""
    common = _belt_common()
    description = ("Run a chain from a TOML file or a named preset (see asperity2d.cli.belt for the "
                   "chain file's keys); `belt basins` maps the initial-condition basins of a chain.")
    parser = subparsers.add_parser("belt", help="masses on a moving belt (exact stick/slip)",
                                   description=description, parents=[common])
    _belt_run_options(parser, chain=False)
    sub = parser.add_subparsers(dest="belt_command", metavar="{run,basins}", action=Subcommands,
                                default_command="run")
    parser.set_defaults(handler=belt.run, belt_command="run", chain=None)  # `belt --preset NAME`

    p = sub.add_parser("run", help="run a chain (the default: `belt CHAIN` is `belt run CHAIN`)",
                       description=description, parents=[common])
    _belt_run_options(p)
    p.set_defaults(handler=belt.run)

    p = sub.add_parser("basins", help="initial-condition basin map of a chain (resumable)",
                       description="An initial-condition basin map of a chain: the map, a JSON summary "
                                   "beside it and a resumable sweep store. Each run of a preset lasts "
                                   "--t-end (default 100 s: the presets' own 10 s window of the thesis "
                                   "sees only the transient); a chain file keeps its own t_end.",
                       parents=[common])
    p.add_argument("-o", "--output", help="basin map (.png, .svg, .pdf; default basins.png)")
    p.add_argument("--chain-file", help="TOML chain file (instead of --preset)")
    p.add_argument("--x", default="x1", help="first coordinate: x1..xn (m) or v1..vn (m/s)")
    p.add_argument("--y", default="v1", help="second coordinate (default v1)")
    p.add_argument("--x-range", default="-0.5,0.5",
                   help="LO,HI of the first coordinate (write --x-range=-0.5,0.5 when LO < 0)")
    p.add_argument("--y-range", default="-0.5,0.5", help="LO,HI of the second")
    p.add_argument("--grid", default="41", help="points per axis: N or NX,NY")
    p.add_argument("--store", help="sweep store directory (default: <output>.runs)")
    p.add_argument("--workers", type=workers_arg, default=None, help=WORKERS_HELP)
    p.add_argument("--scheduler", help="Dask scheduler address, or 'local'")
    p.add_argument("--rtol", type=tolerance, default=1e-6, help="relative tolerance of the limit-cycle test")
    _max_runs(p)
    p.set_defaults(handler=basins.run)


def _belt_run_options(p, *, chain: bool = True) -> None:
    if chain:  # `belt chain.toml` reaches the run subcommand (Subcommands' default)
        p.add_argument("chain", nargs="?", help="TOML chain file")
    p.add_argument("--list-presets", action="store_true", help="print the preset names and exit")
    # checked against the registry when the chain runs (listing it here would import the solver for
    # --help): an installed package's method, or "module:name", is accepted as the built-in ones
    p.add_argument("--method", help="override the solver: exact, sign, a method an installed package adds "
                                    "(asperity2d.belt.METHODS), or package.module:name")
    p.add_argument("--max-wall-time", type=positive_float, default=None,
                   help="stop a run after this many seconds of wall-clock time (default 30)")
    p.add_argument("-o", "--output", help="plot (.png/.svg/.pdf), animation (.gif/.mp4), player (.html), "
                                           "sound (.wav), result (.npz) or table (.csv)")


def _add_sweep(subparsers) -> None:
    parser = subparsers.add_parser(
        "sweep", help="run parameter studies over grids and seeds (resumable)",
        description="Run parameter studies (grid x seeds) into a resumable results store.")
    sub = parser.add_subparsers(dest="sweep_command", required=True, metavar="{run,status,report,export}")

    p = sub.add_parser("run", help="run the unfinished runs of a study (.toml or .py)")
    p.add_argument("study", help="study file: .toml, or .py defining STUDY")
    p.add_argument("--store", required=True, help="results directory of the study")
    p.add_argument("--workers", type=workers_arg, default=None, help=WORKERS_HELP)
    p.add_argument("--scheduler", default=None,
                   help="Dask scheduler address tcp://host:port, or 'local' for a LocalCluster")
    p.add_argument("--retry-failed", action="store_true", help="re-run runs recorded as failed")
    p.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    _max_runs(p)
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
    parser.set_defaults(handler=sweep.run)


def _exit_status(exc: SystemExit) -> int:
    """The status ``sys.exit`` would give: None -> 0; a message is printed and gives 1."""
    if exc.code is None or isinstance(exc.code, int):
        return exc.code or 0
    print(exc.code, file=sys.stderr)
    return 1


def _one_line_warning(message, category, filename, lineno, file=None, line=None):
    print(f"{PROG}: warning: {message}", file=sys.stderr)


#: The exit status of a command whose reader went away (``asperity2d validate | head -1``): what a
#: shell reports for a process ended by SIGPIPE (128 + 13).
BROKEN_PIPE = 141


def main(argv: list[str] | None = None) -> int:
    """Run the command line on ``argv`` (default ``sys.argv[1:]``); return the exit status.

    A reader that closes the pipe early (``| head -1``) ends the command quietly (status 141, as a
    shell reports SIGPIPE): Python's recipe, the rest of the output pointed at ``/dev/null``."""
    try:
        status = _main(argv)
        sys.stdout.flush()  # here, not at exit, where a closed pipe is an "Exception ignored" message
        return status
    except BrokenPipeError:
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
        except (OSError, ValueError, AttributeError):  # a stdout without a descriptor (a test's capture)
            pass
        return BROKEN_PIPE


#: The options ``asperity2d`` itself takes before a command.
TOP_OPTIONS = ("-h", "--help", "--version")
#: Spellings of other tools' options, and what this one calls them.
_ALIASES = {"-V": "--version", "-v": "--version", "-version": "--version", "-help": "--help"}


def _unknown_leading_option(argv: list[str]) -> str | None:
    """The message for an option before the command that ``asperity2d`` does not take
    (``asperity2d --verison``), naming it and the nearest one; None if there is none."""
    import difflib

    for token in argv:
        if not token.startswith("-") or token == "-":
            return None  # the command: its own parser judges what follows
        if token == "--":
            return None
        name = token.partition("=")[0]
        if name in TOP_OPTIONS or (name.startswith("--") and len(name) > 2
                                   and sum(o.startswith(name) for o in TOP_OPTIONS) == 1):
            continue  # an option, or argparse's unambiguous abbreviation of one (--vers)
        close = ([_ALIASES[name]] if name in _ALIASES
                 else difflib.get_close_matches(name, TOP_OPTIONS, n=1, cutoff=0.75))
        hint = f" (did you mean {close[0]}?)" if close else " (options of a command go after it)"
        return f"unrecognized option {show(token, 40)}{hint}"
    return None


def _main(argv: list[str] | None) -> int:
    parser = build_parser()
    bad = _unknown_leading_option(sys.argv[1:] if argv is None else list(argv))
    if bad is not None:
        return fail(bad)
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
    handler = args.handler
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
