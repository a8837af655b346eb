"""The ``belt`` subcommand: run a chain from a TOML file or a named preset.

    asperity2d belt --preset table2-3dof --json
    asperity2d belt chain.toml -o run.png          # plot chosen by extension (.png/.svg/.pdf)
    asperity2d belt --preset table3-k20 -o run.npz # or save the result (.npz) / export (.csv)
    asperity2d belt --preset table3-k20 -o run.gif # or anything render() draws (.gif .mp4 .html .wav)
    asperity2d belt basins --preset table2-3dof -o basins.png   # initial-condition basins (asperity2d.cli.basins)

A chain file holds the keyword arguments of ``simulate_chain`` (a normal contact as a
``[normal]`` table with ``y0`` / ``vy0``); the model reads it (:mod:`asperity2d.belt.chainfile`,
``ChainSpec.from_toml``), which lists its keys. The parser is built in
:mod:`asperity2d.cli.main`; this module only runs the parsed command. Thin: parse, call, print.
"""

from __future__ import annotations

from pathlib import Path

from .. import _io
from ..belt.chainfile import read_chain
from ..errors import SceneError
from .args import check_extra

#: What ``-o`` writes besides what :func:`asperity2d.render` draws of a chain (its suffixes come
#: from the renderers' table, :func:`outputs`): the result (.npz) and its table (.csv).
DATA_OUTPUTS = (".npz", ".csv")


def outputs() -> tuple[str, ...]:
    """Every extension ``belt -o`` takes: the result and table, and every one ``render()`` takes
    for a chain (.png/.svg/.pdf plot, .gif/.mp4 animation, .html player, .wav sound)."""
    from ..renderers import suffixes

    return DATA_OUTPUTS + suffixes("belt")


def run(args) -> int:
    """Run the parsed ``belt`` command; bad input raises ``SceneError`` (one line, exit 2)."""
    if (args.chain is None) == (args.preset is None) and not args.list_presets:
        raise SceneError("give either a `chain` TOML file or `--preset`")
    out = None if args.output is None else _io.output_path("--output", args.output, suffixes=outputs())
    check_extra("--output", out)
    # the user's file is read (and refused) before the solver and NumPy are imported
    if args.chain is None or args.list_presets:
        kwargs = None
    else:
        kwargs = read_chain(args.chain)
    from ..belt import presets

    if args.list_presets:
        for name in presets.names():
            print(f"{name:20s} {presets.describe(name)}")
        return 0
    kwargs = kwargs if kwargs is not None else presets.preset(args.preset)
    from ..belt.solver import METHODS

    if args.method is not None:
        METHODS.lookup(args.method, "--method")  # the registry's names, "did you mean" included
        kwargs["method"] = args.method
    if args.t_end is not None:
        kwargs["t_end"] = args.t_end
    if args.max_wall_time is not None:
        kwargs["max_wall_time"] = args.max_wall_time
    from ..belt.regime import classify
    from ..belt.solver import simulate_chain

    result = simulate_chain(**kwargs)
    written = None
    if out:
        with _io.argument("--output"), _io.writing("--output", out):
            written = _write(result, Path(out), title=args.preset or str(args.chain))
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
        _io.print_json(summary)
    else:
        from .._format import si

        sticks = ", ".join(f"mass {i + 1}: {len(per)} sticks" for i, per in enumerate(result.stick_intervals))
        print(f"{summary['source']}: {result.n} masses over {si(summary['t_end'], 's', 3, trim=True)}, "
              f"{summary['events']} events, regime {summary['regime']} ({sticks}); energy books close "
              f"to {summary['energy_balance_error']:.1e}" + (f"; wrote {written}" if written else ""))
    return 0


def _write(result, out: Path, *, title: str) -> Path:
    suffix = out.suffix.lower()
    if suffix == ".npz":
        return result.save(out)
    if suffix == ".csv":
        return result.export(out)
    if suffix in (".png", ".svg", ".pdf"):
        from ..renderers.belt import plot_chain

        return plot_chain(result, out, title=title)
    from ..renderers import render

    return render(result, out)
