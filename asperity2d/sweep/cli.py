"""``asperity2d sweep``: run, inspect, summarise and export studies.

    asperity2d sweep run STUDY --store DIR [--workers N | --scheduler ADDRESS]
    asperity2d sweep status DIR [--json]
    asperity2d sweep report DIR [-o summary.png] [--json]
    asperity2d sweep export DIR -o runs.csv|runs.npy

The CLI only parses, calls :mod:`asperity2d.sweep` and prints. Bad input
prints one line on stderr and exits with status 2.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import warnings
from pathlib import Path

import numpy as np

from ..errors import SceneError
from .report import plot_summary, summarize
from .runner import run_study
from .store import ResultStore
from .study import variant_label

PROG = "asperity2d sweep"


def _positive_int(text: str) -> int:
    # validated here so "--workers 0" is one clear line, like every other bad input
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"`workers` must be an int >= 1, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"`workers` must be an int >= 1, got {value}")
    return value


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``sweep`` and its subcommands on an ``add_subparsers()`` object."""
    parser = subparsers.add_parser(
        "sweep", help="run parameter studies over grids and seeds (resumable)",
        description="Run parameter studies (grid x seeds) into a resumable results store.",
    )
    parser.set_defaults(func=run)
    sub = parser.add_subparsers(dest="sweep_command", metavar="{run,status,report,export}")
    sub.required = True

    p = sub.add_parser("run", help="run the unfinished runs of a study (.toml or .py)")
    p.add_argument("study", help="study file: .toml, or .py defining STUDY")
    p.add_argument("--store", required=True, help="results directory of the study")
    p.add_argument("--workers", type=_positive_int, default=None,
                   help="local worker processes (default: CPU count; 1 = in-process)")
    p.add_argument("--scheduler", default=None,
                   help="Dask scheduler address tcp://host:port, or 'local' for a LocalCluster")
    p.add_argument("--retry-failed", action="store_true", help="re-run runs recorded as failed")
    p.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    p.add_argument("--json", action="store_true", help="print one JSON object")

    p = sub.add_parser("status", help="count done / failed / pending runs of a store")
    p.add_argument("store", help="results directory")
    p.add_argument("--json", action="store_true", help="print one JSON object")

    p = sub.add_parser("report", help="mean, CI and Mann-Whitney U per variant; summary plot")
    p.add_argument("store", help="results directory")
    p.add_argument("-o", "--output", default=None,
                   help="figure path (.png/.pdf/.svg; default: STORE/summary.png)")
    p.add_argument("--confidence", type=float, default=0.95, help="CI level (default 0.95)")
    p.add_argument("--json", action="store_true", help="print one JSON object")

    p = sub.add_parser("export", help="table of finished runs as CSV or .npy (structured)")
    p.add_argument("store", help="results directory")
    p.add_argument("-o", "--output", required=True, help="output file: .csv or .npy")
    return parser


def _fmt(x) -> str:
    return "nan" if x is None or (isinstance(x, float) and not math.isfinite(x)) else f"{x:.6g}"


def _cmd_run(args) -> int:
    summary = run_study(args.study, store=args.store, workers=args.workers,
                        scheduler=args.scheduler, progress=not args.no_progress,
                        retry_failed=args.retry_failed)
    if args.json:
        print(json.dumps(summary.to_dict()))
    else:
        print(f"{summary.study}: {summary.done} done, {summary.failed} failed, "
              f"{summary.pending} pending of {summary.total} (ran {summary.ran} in "
              f"{summary.wall_time:.1f} s on {summary.executor}) -> {summary.store}")
    return 0


def _cmd_status(args) -> int:
    store = ResultStore(args.store)
    study = store.study()
    status = store.status(study)
    if args.json:
        print(json.dumps({"study": study.name, **status.to_dict()}))
    else:
        print(f"{study.name}: {status.total} runs: {status.done} done, {status.failed} failed, "
              f"{status.pending} pending ({status.corrupt} corrupt), {status.orphaned} orphaned")
    return 0


def _cmd_report(args) -> int:
    store = ResultStore(args.store)
    summary = summarize(store, confidence=args.confidence)
    output = Path(args.output) if args.output else store.path / "summary.png"
    figure = plot_summary(summary, output) if summary.quantities else None
    if args.json:
        print(json.dumps({**summary.to_dict(), "figure": str(figure) if figure else None}))
        return 0
    level = f"{summary.confidence:.0%}"
    print(f"{summary.study}: mean, std and {level} CI per variant")
    for variant, (done, failed) in zip(summary.variants, summary.counts):
        print(f"  {variant_label(variant)}  (done {done}, failed {failed})")
        for q in summary.quantities:
            s = summary.stat(variant, q)
            print(f"    {q}: n={s.n} mean={_fmt(s.mean)} std={_fmt(s.std)} "
                  f"CI=[{_fmt(s.ci_low)}, {_fmt(s.ci_high)}]")
    for c in summary.comparisons:
        print(f"  Mann-Whitney U {c.quantity}, {c.parameter}: {variant_label(c.variant_a)} vs "
              f"{variant_label(c.variant_b)}: U={_fmt(c.u)} p={_fmt(c.p_value)}")
    print(f"figure: {figure}" if figure else "figure: none (no finished runs)")
    return 0


def _cmd_export(args) -> int:
    store = ResultStore(args.store)
    output = Path(args.output)
    suffix = output.suffix.lower()
    if suffix == ".csv":
        store.export_csv(output)
    elif suffix == ".npy":
        from .._io import atomic_write

        table = store.table()
        atomic_write(output, lambda fh: np.save(fh, table, allow_pickle=False))
    else:
        raise SceneError(f"`output` must end in .csv or .npy, got {str(output)!r}")
    print(f"wrote {output}")
    return 0


_COMMANDS = {"run": _cmd_run, "status": _cmd_status, "report": _cmd_report, "export": _cmd_export}


def run(args: argparse.Namespace) -> int:
    """Execute a parsed ``sweep`` command; return the exit status (2: bad input)."""

    def one_line(message, category, filename, lineno, file=None, line=None):
        print(f"{PROG}: warning: {message}", file=sys.stderr)

    with warnings.catch_warnings():
        warnings.showwarning = one_line
        try:
            return _COMMANDS[args.sweep_command](args)
        except SceneError as exc:
            print(f"{PROG}: error: {exc}", file=sys.stderr)
            return 2
        except OSError as exc:
            print(f"{PROG}: error: {exc}", file=sys.stderr)
            return 1
        except KeyboardInterrupt:
            print(f"{PROG}: interrupted; finished runs are saved, run again to resume",
                  file=sys.stderr)
            return 130


class _OneLineParser(argparse.ArgumentParser):
    """Argument errors as one line on stderr, exit status 2 (no usage dump)."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}\n")


def main(argv: list[str] | None = None) -> int:
    """Stand-alone entry point (``python -m asperity2d.sweep``)."""
    parser = _OneLineParser(prog="asperity2d", description="asperity2d sweeps")
    subparsers = parser.add_subparsers(dest="command", required=True)
    add_parser(subparsers)
    try:
        args = parser.parse_args(["sweep", *(sys.argv[1:] if argv is None else argv)])
    except SystemExit as exc:  # --help (0) or a bad argument (2), already printed
        return exc.code if isinstance(exc.code, int) else 2
    return run(args)
