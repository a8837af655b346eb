"""``asperity2d belt basins``: an initial-condition basin map of a belt chain.

    asperity2d belt basins --preset table2-3dof --x x1 --x-range=-0.3,0.9 \\
        --y v1 --y-range=-0.6,0.6 --grid 41 --t-end 100 -o basins.png --json

writes the map (``basins.png``), a JSON summary beside it (``basins.json``)
and keeps every run in a resumable sweep store (``basins.runs/`` unless
``--store`` says otherwise): run the same command again and only unfinished
grid points are computed. ``--workers N`` local processes, or ``--scheduler``
a Dask address. Write a range that starts with a minus sign with ``=``
(``--x-range=-0.3,0.9``), or argparse takes it for an option. The options
are registered on the ``belt`` parser (which owns ``--preset``, ``--t-end``,
``-o`` and ``--json``) and used only after the word ``basins``.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from ..errors import SceneError, SimulationError


def add_basins_arguments(parser) -> None:
    """Register the basin-map options on the ``belt`` subcommand's parser."""
    g = parser.add_argument_group("basins (asperity2d belt basins ...)")
    g.add_argument("--x", dest="basins_x", default="x1", help="first coordinate: x1..xn (m) or v1..vn (m/s)")
    g.add_argument("--y", dest="basins_y", default="v1", help="second coordinate (default v1)")
    g.add_argument("--x-range", dest="basins_x_range", default="-0.5,0.5",
                   help="LO,HI of the first coordinate (write --x-range=-0.5,0.5 when LO < 0)")
    g.add_argument("--y-range", dest="basins_y_range", default="-0.5,0.5", help="LO,HI of the second coordinate")
    g.add_argument("--grid", dest="basins_grid", default="41", help="points per axis: N or NX,NY")
    g.add_argument("--chain-file", dest="basins_chain", type=Path, help="TOML chain file (instead of --preset)")
    g.add_argument("--store", dest="basins_store", type=Path, help="sweep store directory (default: <output>.runs)")
    g.add_argument("--workers", dest="basins_workers", type=int, help="local worker processes")
    g.add_argument("--scheduler", dest="basins_scheduler", help="Dask scheduler address, or 'local'")
    g.add_argument("--rtol", dest="basins_rtol", type=float, default=1e-6,
                   help="relative tolerance of the limit-cycle test")


def _pair(text: str, name: str, cast=float):
    parts = str(text).split(",")
    try:
        values = [cast(p) for p in parts]
    except ValueError:
        raise SceneError(f"`{name}` must be numbers separated by a comma, got {text!r}") from None
    return values


def run_basins(args) -> int:
    """Run the basin map; 0 on success, 2 on bad input (one line on stderr)."""
    import numpy as np

    from . import basins as b
    from .plots import plot_basins

    try:
        if args.preset and args.basins_chain:
            raise SceneError("give either `--preset` or `--chain-file`, not both")
        if args.preset:
            from ..belt import presets

            chain, source = presets.preset(args.preset), args.preset
        elif args.basins_chain:
            from ..belt.cli import load_chain

            chain, source = load_chain(args.basins_chain), str(args.basins_chain)
        else:
            raise SceneError("`belt basins` needs `--preset` or `--chain-file`")
        if args.t_end is not None:
            chain["t_end"] = args.t_end
        grid = _pair(args.basins_grid, "grid", int)
        nx, ny = (grid[0], grid[0]) if len(grid) == 1 else grid[:2] if len(grid) == 2 else (0, 0)
        if nx < 1 or ny < 1:
            raise SceneError(f"`grid` must be N or NX,NY with positive integers, got {args.basins_grid!r}")
        ranges = []
        for text, name in ((args.basins_x_range, "x-range"), (args.basins_y_range, "y-range")):
            lo_hi = _pair(text, name)
            if len(lo_hi) != 2 or not lo_hi[0] < lo_hi[1]:
                raise SceneError(f"`{name}` must be LO,HI with LO < HI, got {text!r}")
            ranges.append(lo_hi)
        out = Path(args.output) if args.output else Path("basins.png")
        if out.suffix.lower() not in (".png", ".svg", ".pdf"):
            raise SceneError(f"`--output` must end in .png, .svg or .pdf for a basin map, got {str(out)!r}")
        store = args.basins_store or out.with_suffix(".runs")
        xs = np.linspace(*ranges[0], nx) if nx > 1 else np.array([np.mean(ranges[0])])
        ys = np.linspace(*ranges[1], ny) if ny > 1 else np.array([np.mean(ranges[1])])
        result = b.chain_basins(chain, x=(args.basins_x, xs), y=(args.basins_y, ys), rtol=args.basins_rtol,
                                store=store, workers=args.basins_workers, scheduler=args.basins_scheduler,
                                progress=not args.json)
        picture = plot_basins(result, out, title=f"{source}: basins over ({args.basins_x}, {args.basins_y})")
        summary = {"source": source, **result.to_dict(), "store": str(store), "output": str(picture),
                   "summary": str(out.with_suffix(".json"))}
        from .._io import atomic_write_text
        from ..scripting import _strict

        text = json.dumps(_strict(summary), sort_keys=True, allow_nan=False)
        atomic_write_text(out.with_suffix(".json"), text + "\n")
    except (SceneError, SimulationError) as exc:
        print(f"asperity2d belt basins: error: {exc}", file=sys.stderr)
        return 2
    if args.json:
        print(text)
    else:
        counts = ", ".join(f"{k} {v}" for k, v in summary["counts"].items() if v)
        print(f"{source}: {nx} x {ny} basin map over t_end = {summary['t_end_s']:g} s: {counts}; "
              f"wrote {picture} and {summary['summary']} (runs in {store})")
    return 0
