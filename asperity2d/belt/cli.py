"""The ``belt`` subcommand: run a chain from a TOML file or a named preset.

    asperity2d belt --preset table2-3dof --json
    asperity2d belt chain.toml -o run.png          # plot chosen by extension (.png/.svg/.pdf)
    asperity2d belt --preset table3-k20 -o run.npz # or save the result (.npz) / export (.csv)
    asperity2d belt basins --preset table2-3dof -o basins.png   # initial-condition basin map

A chain file holds the keyword arguments of ``simulate_chain`` at top level
(masses, springs, dampers, mu_s, mu_k, v_belt, x0, v0, t_end, g, normal_load,
method, n_samples, rtol) and optionally a ``[friction]`` table
(``law = "Stribeck"`` plus its parameters). Thin: parse, call, print.
"""

from __future__ import annotations

import argparse
import json
import sys
import tomllib
from pathlib import Path

from ..errors import SceneError, SimulationError

ALLOWED = {"masses", "springs", "dampers", "mu_s", "mu_k", "v_belt", "x0", "v0", "t_end", "g", "normal_load",
           "method", "n_samples", "rtol", "atol", "integrator", "friction"}


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``belt`` on an ``argparse`` subparsers object; ``run`` is set as the handler."""
    p = subparsers.add_parser("belt", help="masses on a moving belt (exact stick/slip)",
                              description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("chain", nargs="?", type=Path, help="TOML chain file")
    p.add_argument("--preset", help="named preset from the thesis tables (see --list-presets)")
    p.add_argument("--list-presets", action="store_true", help="print the preset names and exit")
    p.add_argument("--method", choices=("exact", "sign"), help="override the solver")
    p.add_argument("--t-end", type=float, help="override the duration (s)")
    p.add_argument("-o", "--output", type=Path, help="plot (.png/.svg/.pdf), result (.npz) or table (.csv)")
    p.add_argument("--json", action="store_true", help="print one JSON summary object")
    p.set_defaults(func=run)
    from ..dynamics.cli import add_basins_arguments  # `belt basins ...` (asperity2d.dynamics.cli)

    add_basins_arguments(p)
    return p


def load_chain(path: Path) -> dict:
    """Keyword arguments for ``simulate_chain`` from a TOML file."""
    from ..friction import law_from_dict

    try:
        data = tomllib.loads(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise SceneError(f"`chain` file not found: {str(path)!r}") from None
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"`chain` is not valid TOML: {exc}") from None
    unknown = sorted(set(data) - ALLOWED)
    if unknown:
        raise SceneError(f"`{unknown[0]}` is not a chain parameter (allowed: {', '.join(sorted(ALLOWED))})")
    if "friction" in data:
        try:
            data["friction"] = law_from_dict(data["friction"])
        except TypeError as exc:
            raise SceneError(f"`friction` table is invalid: {exc}") from None
    return data


def run(args) -> int:
    """Run the subcommand; 0 on success, 2 on bad input (one line on stderr)."""
    from . import presets

    if args.chain is not None and str(args.chain) == "basins":
        from ..dynamics.cli import run_basins

        return run_basins(args)
    try:
        if args.list_presets:
            for name in presets.names():
                print(f"{name:20s} {presets.describe(name)}")
            return 0
        if (args.chain is None) == (args.preset is None):
            raise SceneError("give either a `chain` TOML file or `--preset`")
        kwargs = presets.preset(args.preset) if args.preset else load_chain(args.chain)
        if args.method:
            kwargs["method"] = args.method
        if args.t_end is not None:
            kwargs["t_end"] = args.t_end
        out = args.output
        if out is not None and out.suffix.lower() not in (".png", ".svg", ".pdf", ".npz", ".csv"):
            raise SceneError(f"`--output` must end in .png, .svg, .pdf, .npz or .csv, got {str(out)!r}")
        from .regime import classify
        from .solver import simulate_chain

        result = simulate_chain(**kwargs)
        written = None
        if out is not None:
            suffix = out.suffix.lower()
            if suffix == ".npz":
                written = result.save(out)
            elif suffix == ".csv":
                written = result.export(out)
            else:
                from .plots import plot_chain

                written = plot_chain(result, out, title=args.preset or str(args.chain))
    except (SceneError, SimulationError, TypeError) as exc:
        print(f"asperity2d belt: error: {exc}", file=sys.stderr)
        return 2
    summary = {
        "source": args.preset or str(args.chain),
        "n": result.n,
        "t_end": float(result.t[-1]),
        "method": result.meta["method"],
        "events": len(result.events),
        "stick_intervals": result.stick_intervals,
        "regime": classify(result),
        "energy_balance_error": result.energy_balance_error(),
        "final_x": result.x[:, -1].tolist(),
        "wall_time_s": result.meta["wall_time"],
        "output": str(written) if written else None,
    }
    if args.json:
        print(json.dumps(summary))
    else:
        print(f"{summary['source']}: {result!r}, regime {summary['regime']}, "
              f"energy balance error {summary['energy_balance_error']:.2e}" + (f", wrote {written}" if written else ""))
    return 0


def main(argv=None) -> int:
    """Stand-alone entry (``python -m asperity2d.belt.cli``) until the top-level CLI wires ``add_parser``."""
    parser = argparse.ArgumentParser(prog="asperity2d")
    add_parser(parser.add_subparsers(dest="command", required=True))
    args = parser.parse_args(argv)
    return args.func(args)


if __name__ == "__main__":
    raise SystemExit(main())
