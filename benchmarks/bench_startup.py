"""Start-up: ``asperity2d --help``, a bad-input error and ``import asperity2d`` against ``import pymunk``.

What a user waits for before anything is computed. Each command is a fresh
interpreter; the commands are run in interleaved rounds (every command once
per round, ``repeats`` rounds) so that load on this shared machine hits them
alike, and each figure is the median over rounds of the wall time (and of the
child's CPU time, user + system, from ``getrusage``). The reference is
``python -c "import pymunk"``: the least any asperity2d command could cost,
since every simulation needs pymunk. Target: ``asperity2d --help`` <= 3x it.

It also lists which heavy modules each command loads (SciPy, matplotlib,
Dask, NumPy, the belt solver): none should be loaded before first use.

Run: ``python benchmarks/bench_startup.py [--quick]`` (prints the table and
stores it under ``results["startup"]`` in ``benchmarks/results.json``, keeping
every other key).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
TARGET = 3.0
HEAVY = ("numpy", "scipy", "matplotlib", "dask", "pymunk", "asperity2d.belt.solver", "PIL", "tqdm")


def _cli() -> list[str]:
    """The installed console script if there is one (what users type), else ``python -m``."""
    script = Path(sys.executable).with_name("asperity2d")
    return [str(script)] if script.exists() else [sys.executable, "-m", "asperity2d"]


def commands(missing: str) -> dict[str, list[str]]:
    py = sys.executable
    return {
        "python -c pass": [py, "-c", "pass"],
        "import pymunk": [py, "-c", "import pymunk"],
        "asperity2d --help": [*_cli(), "--help"],
        "asperity2d run missing.toml (error)": [*_cli(), "run", missing],
        "import asperity2d": [py, "-c", "import asperity2d"],
        "asperity2d belt --help": [*_cli(), "belt", "--help"],
        "asperity2d belt missing.toml (error)": [*_cli(), "belt", missing],
    }


def _time(argv: list[str]) -> tuple[float, float]:
    """Wall and child CPU time (s) of one run of ``argv``."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


_PROBE = """
import json, sys
sys.argv = ["asperity2d", *json.loads(sys.argv[1])]
if sys.argv[1:] == ["<import>"]:
    import asperity2d
else:
    from asperity2d.cli import main
    try:
        main()
    except SystemExit:
        pass
heavy = {heavy!r}
print(json.dumps(sorted(m for m in heavy if m in sys.modules)), file=sys.stderr)
"""


def heavy_modules(argv: list[str]) -> list[str]:
    """Which of :data:`HEAVY` a command has imported when it exits."""
    code = _PROBE.format(heavy=HEAVY)
    proc = subprocess.run([sys.executable, "-c", code, json.dumps(argv)], capture_output=True,
                          text=True, check=False)
    return json.loads(proc.stderr.strip().splitlines()[-1])


def run(quick: bool = False) -> dict:
    repeats = 5 if quick else 15
    with tempfile.TemporaryDirectory() as tmp:
        cmds = commands(os.path.join(tmp, "missing.toml"))
        for argv in cmds.values():  # warm the file cache once
            _time(argv)
        wall = {name: [] for name in cmds}
        cpu = {name: [] for name in cmds}
        for _ in range(repeats):
            for name, argv in cmds.items():
                w, c = _time(argv)
                wall[name].append(w)
                cpu[name].append(c)
        loaded = {"asperity2d --help": heavy_modules(["--help"]),
                  "asperity2d run missing.toml (error)": heavy_modules(["run", cmds["asperity2d run missing.toml (error)"][-1]]),
                  "import asperity2d": heavy_modules(["<import>"]),
                  "asperity2d belt --help": heavy_modules(["belt", "--help"]),
                  "asperity2d belt missing.toml (error)": heavy_modules(["belt", cmds["asperity2d run missing.toml (error)"][-1]])}
    ref_wall = statistics.median(wall["import pymunk"])
    ref_cpu = statistics.median(cpu["import pymunk"])
    rows = {}
    for name in cmds:
        w, c = statistics.median(wall[name]), statistics.median(cpu[name])
        rows[name] = {"wall_ms": 1e3 * w, "cpu_ms": 1e3 * c, "wall_vs_pymunk": w / ref_wall,
                      "cpu_vs_pymunk": c / ref_cpu, "heavy_modules": loaded.get(name)}
    return {"repeats": repeats, "target_help_vs_pymunk": TARGET, "rows": rows,
            "load_average": os.getloadavg()}


def headline(res: dict) -> list[tuple[str, float, str]]:
    rows = res["rows"]
    out = [("asperity2d --help / import pymunk (wall, median)", rows["asperity2d --help"]["wall_vs_pymunk"],
            f"<= {TARGET:g}")]
    out += [(f"{name} / import pymunk (wall)", rows[name]["wall_vs_pymunk"], "stated")
            for name in ("asperity2d run missing.toml (error)", "import asperity2d", "asperity2d belt --help",
                         "asperity2d belt missing.toml (error)")]
    return out


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="5 rounds instead of 15")
    p.add_argument("-o", "--output", default=str(HERE / "results.json"),
                   help="results file to update (its other keys are kept)")
    p.add_argument("--no-save", action="store_true", help="print only")
    args = p.parse_args(argv)
    res = run(quick=args.quick)
    print(f"start-up, medians of {res['repeats']} interleaved rounds (load {res['load_average'][0]:.2f}):")
    print(f"{'command':40s} {'wall ms':>8s} {'cpu ms':>8s} {'x pymunk':>9s}  heavy modules loaded")
    for name, r in res["rows"].items():
        heavy = "" if r["heavy_modules"] is None else (", ".join(r["heavy_modules"]) or "none")
        print(f"{name:40s} {r['wall_ms']:8.1f} {r['cpu_ms']:8.1f} {r['wall_vs_pymunk']:9.2f}  {heavy}")
    ratio = res["rows"]["asperity2d --help"]["wall_vs_pymunk"]
    print(f"asperity2d --help = {ratio:.2f}x import pymunk (target <= {TARGET:g}x): "
          f"{'met' if ratio <= TARGET else 'NOT met'}")
    if not args.no_save:
        sys.path.insert(0, str(HERE.parent))
        from asperity2d._io import atomic_write_text

        path = Path(args.output)
        data = json.loads(path.read_text("utf-8")) if path.exists() else {}
        data.setdefault("results", {})["startup"] = res
        data["headline"] = [h for h in data.get("headline", []) if h.get("benchmark") != "startup"]
        data["headline"] += [{"benchmark": "startup", "figure": f, "value": v, "target": t}
                             for f, v, t in headline(res)]
        atomic_write_text(path, json.dumps(data, indent=2, default=float) + "\n")
        print(f"wrote results['startup'] to {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
