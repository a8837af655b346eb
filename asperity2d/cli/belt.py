"""The ``belt`` subcommand: run a chain from a TOML file or a named preset.

    asperity2d belt --preset table2-3dof --json
    asperity2d belt chain.toml -o run.png          # plot chosen by extension (.png/.svg/.pdf)
    asperity2d belt --preset table3-k20 -o run.npz # or save the result (.npz) / export (.csv)
    asperity2d belt --preset table3-k20 -o run.gif # or anything render() draws (.gif .mp4 .html .wav)
    asperity2d belt basins --preset table2-3dof -o basins.png   # initial-condition basins (asperity2d.cli.basins)

A chain file holds the keyword arguments of ``simulate_chain`` at top level:
``masses``, ``springs``, ``dampers``, ``v_belt``, ``x0``, ``v0``, ``t_end`` and
``mu_s`` are required (``mu_s`` unless a ``[friction]`` table gives the law,
e.g. ``law = "Stribeck"`` plus its parameters); ``mu_k``, ``g``,
``normal_load``, ``method``, ``n_samples``, ``rtol``, ``atol`` and
``integrator`` are optional. The parser is built in :mod:`asperity2d.cli.main`;
this module only runs the parsed command. Thin: parse, call, print.
"""

from __future__ import annotations

from pathlib import Path

from .. import _io
from ..errors import SceneError

REQUIRED = ("masses", "springs", "dampers", "v_belt", "x0", "v0", "t_end")
OPTIONAL = ("mu_s", "mu_k", "g", "normal_load", "method", "n_samples", "rtol", "atol", "integrator",
            "friction")
ALLOWED = frozenset(REQUIRED + OPTIONAL)
#: Settings that the solver uses without checking their type first.
_TYPES = {"method": (str,), "integrator": (str,), "n_samples": (int,), "rtol": (int, float)}
#: What ``-o`` writes besides what :func:`asperity2d.render` draws of a chain (its suffixes come
#: from the renderers' table, :func:`outputs`): the result (.npz) and its table (.csv).
DATA_OUTPUTS = (".npz", ".csv")


def outputs() -> tuple[str, ...]:
    """Every extension ``belt -o`` takes: the result and table, and every one ``render()`` takes
    for a chain (.png/.svg/.pdf plot, .gif/.mp4 animation, .html player, .wav sound)."""
    from ..renderers import suffixes

    return DATA_OUTPUTS + suffixes("belt")


def load_chain(path) -> dict:
    """Keyword arguments for ``simulate_chain`` from a TOML chain file (``SceneError`` if unusable)."""
    data = _io.read_toml("chain", path)
    unknown = sorted(set(data) - ALLOWED)
    if unknown:
        raise SceneError(f"`{unknown[0]}` in {str(path)!r} is not a chain parameter "
                         f"(allowed: {', '.join(sorted(ALLOWED))})")
    missing = [key for key in REQUIRED if key not in data]
    if "mu_s" not in data and "friction" not in data:
        missing.append("mu_s")
    if missing:
        raise SceneError(f"`{missing[0]}` is missing from chain file {str(path)!r} (required: "
                         f"{', '.join(REQUIRED)}, and mu_s or a [friction] table)")
    for key, types in _TYPES.items():
        if key in data and (isinstance(data[key], bool) or not isinstance(data[key], types)):
            raise SceneError(f"`{key}` in {str(path)!r} must be of type "
                             f"{' or '.join(t.__name__ for t in types)}, got {data[key]!r}")
    if "friction" in data:
        from ..friction.laws import law_from_dict

        if not isinstance(data["friction"], dict):
            raise SceneError(f"`friction` in {str(path)!r} must be a [friction] table with a `law`, "
                             f"got {data['friction']!r}")
        try:
            data["friction"] = law_from_dict(data["friction"])
        except TypeError as exc:  # a parameter the law does not take
            raise SceneError(f"`friction` table is invalid: {exc}") from None
    return data


def run(args) -> int:
    """Run the parsed ``belt`` command; bad input raises ``SceneError`` (one line, exit 2)."""
    if (args.chain is None) == (args.preset is None) and not args.list_presets:
        raise SceneError("give either a `chain` TOML file or `--preset`")
    out = None if args.output is None else _io.output_path("--output", args.output, suffixes=outputs())
    # the user's file is read (and refused) before the solver and NumPy are imported
    kwargs = None if args.chain is None or args.list_presets else load_chain(args.chain)
    from ..belt import presets

    if args.list_presets:
        for name in presets.names():
            print(f"{name:20s} {presets.describe(name)}")
        return 0
    kwargs = kwargs if kwargs is not None else presets.preset(args.preset)
    if args.method:
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
