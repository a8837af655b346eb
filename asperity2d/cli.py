"""Command line: ``asperity2d`` (also ``python -m asperity2d``).

Thin by design: it parses, calls the library, prints. Every subcommand that
computes something accepts ``--json`` and then prints exactly one JSON object.
Bad input prints one line on stderr and exits with status 2.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import sys
import tomllib
from pathlib import Path

from .errors import SceneError, SimulationError


def _load_script(path: Path):
    spec = importlib.util.spec_from_file_location(f"_asperity2d_scene_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # so worker processes can pickle its functions
    spec.loader.exec_module(module)
    return module


def scene_from_toml(path: Path):
    """A scene from a TOML file: make_scene's arguments, optionally under ``[scene]``."""
    from .builders import make_scene

    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, tomllib.TOMLDecodeError) as exc:
        raise SceneError(f"`scene` file {str(path)!r} could not be read: {exc}") from None
    params = data.get("scene", data)
    run = data.get("run", {})
    from .surface.source import resolve_paths  # profile files named relative to the TOML file

    return make_scene(**resolve_paths(params, path.parent)), run


def _emit(args, summary: dict, lines: list[str]) -> None:
    if args.json:
        print(json.dumps(summary, default=float))
    else:
        print("\n".join(lines))


def cmd_run(args) -> int:
    path = Path(args.scene)
    if not path.exists():
        raise SceneError(f"`scene` file does not exist: {str(path)!r}")
    if path.suffix == ".py":
        module = _load_script(path)
        if not hasattr(module, "main"):
            raise SceneError(f"`scene` script {str(path)!r} has no main(argv) function")
        argv = list(args.script_args)
        if args.json:
            argv.append("--json")
        if args.output:
            argv += ["-o", args.output]
        return int(module.main(argv) or 0)
    if path.suffix != ".toml":
        raise SceneError(f"`scene` must be a .py script or a .toml scene file, got {str(path)!r}")
    from .simulate import simulate

    scene, run = scene_from_toml(path)
    duration = args.duration if args.duration is not None else run.get("duration")
    result = simulate(scene, duration)
    if args.save:
        result.save(args.save)
    if args.output:
        from .render import render

        render(result, args.output)
    summary = result.summary()
    _emit(args, summary, [f"{k}: {v}" for k, v in summary.items()])
    return 0


def cmd_analyze(args) -> int:
    from .analysis import breakaway_force, event_statistics, stick_slip_events
    from .result import load

    result = load(args.result)
    summary = result.summary()
    events = stick_slip_events(result)
    summary["events"] = event_statistics(events)
    try:
        summary["breakaway_force_N"] = breakaway_force(result)
    except SceneError:  # constant-force drive, or no stick-to-slip transition
        summary["breakaway_force_N"] = None
    _emit(args, summary, [f"{k}: {v}" for k, v in summary.items()])
    return 0


def cmd_render(args) -> int:
    from .render import render
    from .result import load

    out = render(load(args.result), args.output)
    _emit(args, {"output": str(out)}, [f"wrote {out}"])
    return 0


def cmd_critical(args) -> int:
    from .critical import critical_force_bracket

    scene, _ = scene_from_toml(Path(args.scene))
    bracket = critical_force_bracket(scene, rel_tol=args.rel_tol)
    summary = {"critical_force_N": bracket.value, "stops_N": bracket.stops,
               "passes_N": bracket.passes, "runs": bracket.runs}
    _emit(args, summary, [f"{k}: {v}" for k, v in summary.items()])
    return 0


MEASURES = {"critical": "critical_force_of", "breakaway": "breakaway_force_of"}


def _parse_set(items: list[str]) -> dict:
    """``key=value`` pairs (values parsed as TOML scalars) into make_scene arguments."""
    out = {}
    for item in items:
        key, sep, text = item.partition("=")
        if not sep:
            raise SceneError(f"`--set` takes key=value, got {item!r}")
        try:
            out[key.strip()] = tomllib.loads(f"v = {text}")["v"]
        except tomllib.TOMLDecodeError:
            out[key.strip()] = text
    return out


def cmd_compare(args) -> int:
    from . import studies
    from .compare import Comparison, compare

    if args.load:
        comparison = Comparison.load(args.load)
    else:
        if args.seeds < 1:
            raise SceneError(f"`seeds` must be >= 1, got {args.seeds}")
        measure = getattr(studies, MEASURES[args.measure])
        variants = {name: {"spacing": name} for name in args.variants.split(",")}
        comparison = compare(measure, variants, range(args.seeds), base=_parse_set(args.set),
                             progress=not args.json, workers=args.workers)
    if args.save:
        comparison.save(args.save)
    if args.output:
        from .render.plots import plot_comparison

        plot_comparison(comparison, args.output)
    summary = {"measure": comparison.measure, "seeds": len(comparison.seeds),
               "variants": comparison.summary()}
    names = list(comparison.values)
    if len(names) >= 2:
        summary["mann_whitney_p"] = {f"{names[0]} vs {other}": comparison.mann_whitney(names[0], other)
                                     for other in names[1:]}
    lines = [f"{name}: mean {stats['mean']:.5g}, 95 % CI [{stats['ci_low']:.5g}, {stats['ci_high']:.5g}] "
             f"(n = {stats['n']})" for name, stats in comparison.summary().items()]
    lines += [f"Mann-Whitney U {pair}: p = {p:.3g}" for pair, p in summary.get("mann_whitney_p", {}).items()]
    _emit(args, summary, lines)
    return 0


class _Parser(argparse.ArgumentParser):
    """Usage errors as one line on stderr and exit status 2 (subparsers inherit this)."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="asperity2d", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True)

    p = sub.add_parser("run", help="run a scene script (.py) or a TOML scene file")
    p.add_argument("scene", help="scene script (.py; other arguments go to its main()) or .toml")
    p.add_argument("-o", "--output",
                   help="render to this file (.gif, .png, .svg, .pdf); a script's output directory")
    p.add_argument("--save", help="save the Result (.npz) (TOML scenes)")
    p.add_argument("--duration", type=float, help="simulated time in s (TOML scenes)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_run)

    p = sub.add_parser("analyze", help="stick-slip events and breakaway force of a saved result")
    p.add_argument("result")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_analyze)

    p = sub.add_parser("render", help="render a saved result; the extension picks the renderer")
    p.add_argument("result")
    p.add_argument("-o", "--output", required=True)
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_render)

    p = sub.add_parser("critical", help="critical constant drive force of a TOML scene")
    p.add_argument("scene")
    p.add_argument("--rel-tol", type=float, default=0.01)
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_critical)

    p = sub.add_parser("compare", help="compare spacings over seeds (critical or breakaway force)")
    p.add_argument("--measure", choices=sorted(MEASURES), default="breakaway")
    p.add_argument("--variants", default="regular,random", help="comma-separated spacings")
    p.add_argument("--seeds", type=int, default=20)
    p.add_argument("--workers", type=int, default=1)
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="make_scene argument shared by every variant (repeatable)")
    p.add_argument("--save", help="save the comparison (.json) to re-plot later")
    p.add_argument("--load", help="re-use a saved comparison instead of running")
    p.add_argument("-o", "--output", help="comparison plot (.png, .svg, .pdf)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_compare)

    from .belt.cli import add_parser as add_belt_parser
    from .sweep.cli import add_parser as add_sweep_parser

    add_belt_parser(sub)
    add_sweep_parser(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args, extra = parser.parse_known_args(argv)
    if extra and not (args.command == "run" and args.scene.endswith(".py")):
        parser.error(f"unrecognized arguments: {' '.join(extra)}")
    args.script_args = extra
    try:
        return int(args.func(args) or 0)
    except (SceneError, SimulationError, FileNotFoundError) as exc:
        print(f"asperity2d: error: {exc}", file=sys.stderr)
        return 2

