"""What the asperity subcommands of ``asperity2d`` do: run, analyze, render, critical, compare.

Each handler checks every file argument before any work (so a bad ``--save``
is refused before a long run, not after it), calls the library and prints a
summary (text, or one JSON object with ``--json``). Errors are ``SceneError``
naming the argument as the user typed it; :func:`asperity2d.cli.main` prints
them as one line and exits with status 2. The parser is in :mod:`asperity2d.cli.main`.
"""

from __future__ import annotations

from pathlib import Path

from .. import _io
from .._inputs import show
from .._format import lines as text_lines
from .._format import si
from .args import PLOT_SUFFIXES, check_extra, check_runs, defines_main, fail, load_script
from ..errors import SceneError
# reading a TOML scene is the model's business; the CLI's name for it stays for callers
from ..scene_io import RUN_KEYS  # noqa: F401
from ..scene_io import read_scene as scene_from_toml

def _emit(args, summary: dict, lines: list[str]) -> None:
    if args.json:
        _io.print_json(summary)
    else:
        print("\n".join(lines))


def _checked_duration(scene, duration: float, arg: str) -> float:
    """``duration`` if it fits simulate's step budget at the scene's default dt (named as ``arg``;
    simulate checks settling too)."""
    from ..run import MAX_STEPS, default_dt

    dt = default_dt(scene)
    if duration > MAX_STEPS * dt:
        raise SceneError(f"`{arg}` = {duration:.3g} s is more than the {MAX_STEPS:.0e}-step budget at the "
                         f"default dt ({dt:.3g} s) of this scene: at most {MAX_STEPS * dt:.3g} s")
    return duration


def _engine(args, *, auto: bool = False) -> str | None:
    """``--engine`` as written, checked against the engine registry under the flag's own name (an
    installed package's engine, or "module:name", too); None or "auto" pass where ``auto``."""
    engine = getattr(args, "engine", None if auto else "pymunk")
    if not (auto and engine in (None, "auto")):
        from ..engine.registry import ENGINES

        ENGINES.lookup(engine, "--engine")
    return engine


def run(args) -> int:
    """``asperity2d run SCENE``: a scene script's ``main(argv)``, or a TOML scene."""
    path = _io.input_path("scene", args.scene)
    if path.suffix == ".py":
        return _run_script(path, args)
    engine = _engine(args)  # after the cheap checks: the registry imports the engines
    if path.suffix != ".toml":
        raise SceneError(f"`scene` must be a .py script or a .toml scene file, got {str(path)!r}")
    save = None if args.save is None else _io.output_path("--save", args.save, suffixes=(".npz",))
    output = None if args.output is None else _io.output_path("--output", args.output,
                                                              suffixes=_render_suffixes())
    check_extra("--output", output)
    scene, settings = scene_from_toml(path, overrides=_parse_set(getattr(args, "set", [])))
    if args.duration is not None:
        duration = _checked_duration(scene, args.duration, "--duration")
    elif "duration" in settings:
        duration = _checked_duration(scene, float(settings["duration"]), "duration")
    else:
        duration = None
    from ..run import simulate, stops_from_settings

    result = simulate(scene, duration, stop=stops_from_settings(scene, settings), engine=engine)
    written = []
    if save:
        with _io.argument("--save"), _io.writing("--save", save):
            written.append(str(result.save(save) or save))
    if output:
        from ..renderers import render as render_result

        with _io.argument("--output"), _io.writing("--output", output):
            written.append(str(render_result(result, output) or output))
    summary = result.summary()
    if written:
        summary["wrote"] = written
    _emit(args, summary, text_lines({k: v for k, v in summary.items() if k != "wrote"})
          + [f"wrote {w}" for w in written])
    return 0


def _run_script(path: Path, args) -> int:
    import sys

    for option, value in (("--save", args.save), ("--duration", args.duration), ("--set", args.set or None)):
        if value is not None:
            raise SceneError(f"`{option}` applies to TOML scenes; a script takes its own arguments")
    if not defines_main(path):  # refused before its body runs (a plain script would run it all first)
        raise SceneError(f"`scene` script {str(path)!r} has no main(argv) function "
                         f"(run a plain script with python {str(path)!r})")
    module = load_script(path)
    if not callable(getattr(module, "main", None)):
        raise SceneError(f"`scene` script {str(path)!r} has no main(argv) function")
    argv = list(args.script_args) + (["--json"] if args.json else [])
    argv += ["-o", args.output] if args.output is not None else []
    saved, sys.argv = sys.argv, [str(path), *argv]  # the script's usage names the script
    try:
        return int(module.main(argv) or 0)
    finally:
        sys.argv = saved


def _render_suffixes() -> tuple[str, ...]:
    from ..renderers import FORMATS

    return tuple(FORMATS)


def _load_result(arg: str, path):
    from ..saved import load

    with _io.argument(arg):
        return load(path)


def analyze(args) -> int:
    """``asperity2d analyze RESULT``: what a saved run did, by its kind: an asperity run's
    stick-slip events and breakaway force; a belt chain's per-mass stick/slip record and regime."""
    result = _load_result("result", args.result)
    summary = result.summary()
    if result.kind == "belt":
        from ..belt.regime import classify

        summary["regime"] = classify(result)
        lines = text_lines({k: v for k, v in summary.items() if k != "masses"})
        lines += [f"mass {m['mass']}: {m['sticks']} sticks, stuck {si(m['stuck_s'], 's', 4)} "
                  f"({m['stuck_fraction']:.1%}), {m['slip_starts']} stick-to-slip transitions"
                  for m in summary["masses"]]
        _emit(args, summary, lines)
        return 0
    from ..analysis import breakaway_force, event_statistics, stick_slip_events

    summary["events"] = event_statistics(stick_slip_events(result))
    try:
        summary["breakaway_force_N"] = breakaway_force(result)
    except SceneError:  # constant-force drive, or no stick-to-slip transition
        summary["breakaway_force_N"] = None
    _emit(args, summary, text_lines(summary))
    return 0


def render(args) -> int:
    """``asperity2d render RESULT -o FILE``: render a saved run (either kind) again."""
    from ..renderers import render as render_result
    from ..renderers import suffixes

    output = _io.output_path("--output", args.output, suffixes=_render_suffixes())
    check_extra("--output", output)
    result = _load_result("result", args.result)
    if output.suffix.lower() not in suffixes(result.kind):
        raise SceneError(f"`--output` must end in one of {', '.join(suffixes(result.kind))} for a "
                         f"{result.kind} result, got {str(output)!r}")
    with _io.argument("--output"), _io.writing("--output", output):
        out = render_result(result, output)
    _emit(args, {"output": str(out)}, [f"wrote {out}"])
    return 0


def critical(args) -> int:
    """``asperity2d critical SCENE``: the critical constant drive force (bisection)."""
    path = _io.input_path("scene", args.scene)
    if path.suffix != ".toml":
        raise SceneError(f"`scene` must be a .toml scene file, got {str(path)!r}")
    scene, _ = scene_from_toml(path)
    engine = _engine(args)
    from ..critical import critical_force_brackets

    bracket = critical_force_brackets([scene], start=args.start, rel_tol=args.rel_tol, engine=engine)[0]
    summary = {"critical_force_N": bracket.value, "stops_N": bracket.stops,
               "passes_N": bracket.passes, "runs": bracket.runs, "monotone": bracket.monotone,
               "band_N": list(bracket.band) if bracket.band else None, "start": args.start, "engine": engine}
    text = (f"critical force {si(bracket.value, 'N', 4)}: the slider stops at {si(bracket.stops, 'N', 4)} "
            f"and passes at {si(bracket.passes, 'N', 4)} ({bracket.runs} runs, bisection to "
            f"{100 * args.rel_tol:g} %, from {args.start}"
            + ("" if engine == "pymunk" else f", engine {engine}") + ")")
    if bracket.band:
        text += (f"; passing is not monotone in the force between {si(bracket.band[0], 'N', 4)} and "
                 f"{si(bracket.band[1], 'N', 4)}: the value is the smallest force seen to pass")
    _emit(args, summary, [text])
    return 0


def _parse_set(items: list[str]) -> dict:
    """``key=value`` pairs (values parsed as TOML scalars) into make_scene arguments; an empty key,
    or a key given twice, is refused (the last one silently winning would hide a typo)."""
    import tomllib

    out = {}
    for item in items:
        key, sep, text = item.partition("=")
        if not sep:
            raise SceneError(f"`--set` takes key=value, got {show(item)}")
        key = key.strip()
        if not key:
            raise SceneError(f"`--set` key is empty in {show(item)}: write key=value, e.g. lower_count=4")
        try:
            value = tomllib.loads(f"v = {text}")["v"]
        except (tomllib.TOMLDecodeError, RecursionError):  # not a TOML value: the text itself
            value = text
        if key in out:
            raise SceneError(f"`--set {key[:60]}` is given twice ({show(out[key], 30)} and {show(value, 30)}): "
                             "give each key once")
        out[key] = value
    return out


def compare(args) -> int:
    """``asperity2d compare``: a measure of each spacing over seeds, with statistics."""
    engine = _engine(args, auto=True)
    save = None if args.save is None else _io.output_path("--save", args.save, suffixes=(".json",))
    output = None if args.output is None else _io.output_path("--output", args.output, suffixes=PLOT_SUFFIXES)
    from ..experiments.compare import Comparison
    from ..experiments.compare import compare as run_compare

    if args.load:
        with _io.argument("--load"):
            comparison = Comparison.load(_io.input_path("--load", args.load))
    else:
        variants = {name: {"spacing": name} for name in args.variants.split(",")}
        base = _parse_set(args.set)
        for key in ("spacing", "seed"):
            if key in base:
                raise SceneError(f"`--set {key}=...` cannot be used with compare: each variant of "
                                 f"`--variants` sets `spacing`, and `--seeds` the seeds")
        auto = args.seeds == "auto"
        if args.max_seeds is not None and not auto:
            raise SceneError("`--max-seeds` is the budget of `--seeds auto`; give it with --seeds auto")
        budget = (args.max_seeds or 40) if auto else args.seeds
        check_runs(len(variants) * budget, args.max_runs,
                   f"`--variants` ({len(variants)}) x `--{'max-' * auto}seeds` ({budget:,})")
        from ..experiments.measures import MEASURES

        # the registry, not a list here: a new measure (an installed package's too, or "module:name")
        # is known at once, and a misspelt one gets the nearest names
        base.setdefault("drive", MEASURES.lookup(args.measure, "--measure").drive)
        comparison = run_compare(args.measure, variants, "auto" if auto else range(args.seeds), base=base,
                                 progress=not args.json, workers=args.workers, scheduler=args.scheduler,
                                 max_seeds=args.max_seeds if auto else None,
                                 engine=engine)
    if save:
        with _io.argument("--save"), _io.writing("--save", save):
            comparison.save(save)
    if output:
        from ..renderers.plots import plot_comparison

        with _io.argument("--output"), _io.writing("--output", output):
            plot_comparison(comparison, output)
    reference = "regular" if "regular" in comparison.values else None  # each other spacing against it
    summary, lines = comparison.report(reference, subject="{name} spacing")
    _emit(args, summary, lines)
    return 0


def validate(args) -> int:
    """``asperity2d validate [CHECK ...]``: run the closed-form checks, a line each; status 1 if one fails."""
    from ..closed_forms import CHECKS, ENGINES_OF, using

    unknown = [i for i in args.checks if i not in CHECKS]
    if unknown:
        return fail(f"argument CHECK: unknown check {unknown[0]!r}; known: {', '.join(CHECKS)}")
    engine = _engine(args)
    other = [i for i in args.checks if engine not in ENGINES_OF[i]]
    if other:
        return fail(f"argument CHECK: {other[0]!r} does not run on --engine {engine} (the reference's own check)")
    ids = list(args.checks) or [i for i in CHECKS if engine in ENGINES_OF[i]]
    checks, lines = [], []
    with using(engine):
        for check_id in ids:
            checks.append(CHECKS[check_id]())
            if not args.json:
                print(checks[-1].line(), flush=True)
    failed = sum(not c.passed for c in checks)
    lines.append(f"{len(checks) - failed} of {len(checks)} checks within tolerance"
                 + ("" if engine == "pymunk" or args.checks else
                    f" on engine {engine}; {len(CHECKS) - len(ids)} more are the reference's own (the energy "
                    "books, the belt chains, the other contact laws): --engine pymunk runs them"))
    _emit(args, {"checks": [{"id": i, **c.to_dict()} for i, c in zip(ids, checks)], "failed": failed,
                 "engine": engine}, lines)
    return 1 if failed else 0


def measures(args) -> int:
    """``asperity2d measures``: the named measures, each with its unit, drive, kind and label."""
    from ..experiments.measures import MEASURES

    import sys

    entries = [m.to_dict() for m in MEASURES.values()]
    width = max(len(m["name"]) for m in entries)
    lines = [f"{m['name']:<{width}}  [{m['unit']}]  {m['drive']} drive, {m['kind']}, step {m['step']}: "
             f"{m['label']}" for m in entries]
    for line in MEASURES.failures.values():  # an installed package whose measure would not load
        print(f"asperity2d: warning: {line}", file=sys.stderr)
    _emit(args, {"measures": entries, "failed_entry_points": list(MEASURES.failures.values())}, lines)
    return 0
