"""``asperity2d sweep``: run, inspect, summarise and export studies.

    asperity2d sweep run STUDY --store DIR [--workers N | --scheduler ADDRESS] [--json]
    asperity2d sweep status DIR [--json]
    asperity2d sweep report DIR [-o summary.png] [--json]
    asperity2d sweep export DIR -o runs.csv|runs.npy [--json]

The parser is built in :mod:`asperity2d.cli`; this module runs the parsed
command: it checks the files, calls :mod:`asperity2d.sweep` and prints. Bad
input raises ``SceneError`` naming the argument (one line on stderr, exit 2).
"""

from __future__ import annotations

import math
import sys

from .. import _io
from .args import PROG


def _fmt(x, unit: str | None = None) -> str:
    """A statistic in engineering units (4 significant digits); "n/a" when undefined."""
    from .._format import value

    return value(None if x is None else float(x), unit)


def _store(path):
    from ..sweep.store import ResultStore

    return ResultStore(_io.input_path("store", path, directory=True))


def _cmd_run(args) -> int:
    from ..sweep.runner import run_study, study_size
    from ..sweep.study import load_study
    from .args import check_runs

    study = load_study(_io.input_path("study", args.study))
    check_runs(len(study), args.max_runs, study_size(study))
    store = _io.output_dir("--store", args.store)
    try:
        summary = run_study(study, store=store, workers=args.workers, scheduler=args.scheduler,
                            progress=not args.no_progress, retry_failed=args.retry_failed,
                            max_runs=args.max_runs)
    except OSError as exc:
        # the store's own files (a read-only mount, a full disk); any other OSError is not ours
        if exc.filename is None or not str(exc.filename).startswith(str(store)):
            raise
        raise _io.FileError("--store", store, "could not be written", exc.strerror) from None
    if args.json:
        _io.print_json(summary.to_dict())
    else:
        print(f"{summary.study}: {summary.done} done, {summary.failed} failed, "
              f"{summary.pending} pending of {summary.total} (ran {summary.ran} in "
              f"{summary.wall_time:.1f} s on {summary.executor}) -> {summary.store}")
    if summary.total and summary.failed == summary.total:
        # nothing came out of the sweep: a script that exits 0 here would hide it
        from ..sweep.store import ResultStore

        first = next((r.error.splitlines()[0] for r in ResultStore(store).records(study).values() if r.error), None)
        print(f"{PROG}: error: every run of {summary.study!r} failed" + (f"; the first: {first}" if first else ""),
              file=sys.stderr)
        return 1
    return 0


def _cmd_status(args) -> int:
    store = _store(args.store)
    study = store.study()
    status = store.status(study)
    if args.json:
        _io.print_json({"study": study.name, **status.to_dict()})
    else:
        print(f"{study.name}: {status.total} runs: {status.done} done, {status.failed} failed, "
              f"{status.pending} pending ({status.corrupt} corrupt), {status.orphaned} orphaned")
    return 0


def _cmd_report(args) -> int:
    from .._format import split_unit
    from ..renderers.sweep import plot_summary
    from ..sweep.report import summarize
    from ..sweep.study import variant_label

    store = _store(args.store)
    output = _io.output_path("--output", args.output or store.path / "summary.png",
                             suffixes=(".png", ".pdf", ".svg"))
    summary = summarize(store, confidence=args.confidence)
    figure = None
    if summary.quantities:
        with _io.argument("--output"), _io.writing("--output", output):
            figure = plot_summary(summary, output)
    if args.json:
        _io.print_json({**summary.to_dict(), "figure": str(figure) if figure else None})
        return 0
    level = f"{summary.confidence:.0%}"
    print(f"{summary.study}: mean, std and {level} CI per variant")
    for variant, (done, failed) in zip(summary.variants, summary.counts):
        print(f"  {variant_label(variant)}  (done {done}, failed {failed})")
        for q in summary.quantities:
            s = summary.stat(variant, q)
            name, unit = split_unit(q)
            print(f"    {name}: mean {_fmt(s.mean, unit)}, std {_fmt(s.std, unit)}, "
                  f"{level} CI [{_fmt(s.ci_low, unit)}, {_fmt(s.ci_high, unit)}] (n = {s.n})")
    for c in summary.comparisons:
        p_value = "n/a" if c.p_value is None or not math.isfinite(c.p_value) else f"{c.p_value:.2g}"
        print(f"  {split_unit(c.quantity)[0]}, {variant_label(c.variant_a)} against "
              f"{variant_label(c.variant_b)}: Mann-Whitney U test p = {p_value}")
    print(f"figure: {figure}" if figure else "figure: none (no finished runs)")
    return 0


def _cmd_export(args) -> int:
    import numpy as np

    store = _store(args.store)
    output = _io.output_path("--output", args.output, suffixes=(".csv", ".npy"))
    table = store.table()
    with _io.argument("--output"), _io.writing("--output", output):
        if output.suffix.lower() == ".csv":
            store.export_csv(output)
        else:
            _io.atomic_write(output, lambda fh: np.save(fh, table, allow_pickle=False))
    if args.json:
        _io.print_json({"output": str(output), "runs": int(len(table))})
    else:
        print(f"wrote {output} ({len(table)} runs)")
    return 0


_COMMANDS = {"run": _cmd_run, "status": _cmd_status, "report": _cmd_report, "export": _cmd_export}


def run(args) -> int:
    """Execute a parsed ``sweep`` command; return the exit status (bad input raises SceneError)."""
    try:
        return _COMMANDS[args.sweep_command](args)
    except KeyboardInterrupt:
        print("asperity2d: interrupted; finished runs are saved, run again to resume", file=sys.stderr)
        return 130

