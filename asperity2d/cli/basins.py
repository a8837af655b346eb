"""``asperity2d belt basins``: an initial-condition basin map of a belt chain.

    asperity2d belt basins --preset table2-3dof --x x1 --x-range=-0.3,0.9 \\
        --y v1 --y-range=-0.6,0.6 --grid 41 --t-end 100 -o basins.png --json

writes the map (``basins.png``), a JSON summary beside it (``basins.json``)
and keeps every run in a resumable sweep store (``basins.runs/`` unless
``--store`` says otherwise): run the same command again and only unfinished
grid points are computed. ``--workers N`` local processes, or ``--scheduler``
a Dask address. Write a range that starts with a minus sign with ``=``
(``--x-range=-0.3,0.9``), or argparse takes it for an option. The options
are the ``basins`` subcommand's of the ``belt`` parser (:mod:`asperity2d.cli.main`; ``--preset``,
``--t-end`` and ``--json`` shared with ``belt``); bad input raises ``SceneError`` (one
line, exit status 2).
"""

from __future__ import annotations

from pathlib import Path

from .. import _io
from ..errors import SceneError
from .args import check_runs

PLOTS = (".png", ".svg", ".pdf")
#: Length of every run of a preset's map when ``--t-end`` is not given (s). The presets keep the
#: multi-DOF belt thesis' own windows (10 s for the 3-DOF chains), which see only the base case's
#: transient: a 10 s map calls most points irregular, a 100 s map (scenes/belt_basins.py, the
#: documented findings) finds most of them at rest. A chain file's own ``t_end`` is kept.
PRESET_T_END = 100.0
#: Samples per second of a preset's runs (the classifier reads velocities over the last quarter).
PRESET_RATE = 20.0


def _numbers(text: str, name: str, cast=float) -> list:
    try:
        return [cast(p) for p in str(text).split(",")]
    except ValueError:
        raise SceneError(f"`{name}` must be numbers separated by a comma, got {text!r}") from None


def _chain(args) -> tuple[dict, str]:
    if args.preset and args.chain_file:
        raise SceneError("give either `--preset` or `--chain-file`, not both")
    if args.preset:
        from ..belt import presets

        return presets.preset(args.preset), args.preset
    if args.chain_file:
        from ..belt.chainfile import read_chain

        return read_chain(args.chain_file), str(args.chain_file)
    raise SceneError("`belt basins` needs `--preset` or `--chain-file`")


def run(args) -> int:
    """Run the parsed ``belt basins`` command: the map, its JSON summary, the store; return 0."""
    import numpy as np

    from .._io import print_json, write_json
    from ..dynamics import basins as b
    from ..renderers.dynamics import plot_basins

    chain, source = _chain(args)
    if args.t_end is not None:
        chain["t_end"] = args.t_end
    elif args.preset:
        chain["t_end"] = PRESET_T_END
    if args.preset:
        chain["n_samples"] = min(int(PRESET_RATE * chain["t_end"]) + 1, 100_001)
    grid = _numbers(args.grid, "grid", int)
    nx, ny = (grid[0], grid[0]) if len(grid) == 1 else grid if len(grid) == 2 else (0, 0)
    if nx < 1 or ny < 1:
        raise SceneError(f"`grid` must be N or NX,NY with positive integers, got {args.grid!r}")
    axes = []
    for text, name, count in ((args.x_range, "x-range", nx), (args.y_range, "y-range", ny)):
        lo_hi = _numbers(text, name)
        if len(lo_hi) != 2 or not lo_hi[0] < lo_hi[1]:
            raise SceneError(f"`{name}` must be LO,HI with LO < HI, got {text!r}")
        axes.append(np.linspace(*lo_hi, count) if count > 1 else np.array([0.5 * sum(lo_hi)]))
    out = _io.output_path("--output", "basins.png" if args.output is None else args.output, suffixes=PLOTS)
    store = _io.output_dir("--store", out.with_suffix(".runs") if args.store is None else args.store)
    check_runs(nx * ny, args.max_runs, f"`--grid` {args.grid} is {nx:,} x {ny:,} points, one run each")
    result = b.chain_basins(chain, x=(args.x, axes[0]), y=(args.y, axes[1]), rtol=args.rtol,
                            store=store, workers=args.workers, scheduler=args.scheduler,
                            progress=not args.json)
    picture = plot_basins(result, out, title=f"{source}: basins over ({args.x}, {args.y})")
    summary = {"source": source, **result.to_dict(), "store": str(store), "output": str(picture),
               "summary": str(out.with_suffix(".json"))}
    write_json(out.with_suffix(".json"), summary, indent=None)
    if args.json:
        print_json(summary)
    else:
        total = sum(summary["counts"].values()) or 1
        counts = ", ".join(f"{k} {v} ({100 * v / total:.1f} %)" for k, v in summary["counts"].items() if v)
        print(f"{source}: {nx} x {ny} basin map over t_end = {summary['t_end_s']:g} s: {counts}; "
              f"wrote {picture} and {summary['summary']} (runs in {store})")
    return 0
