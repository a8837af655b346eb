"""Every benchmark figure the issues ask for, measured in one run.

    python benchmarks/run_all.py [--quick] [--only core,gif,...] [-o benchmarks/results.json]

Runs each ``benchmarks/bench_*.py`` module's ``run(quick)`` in turn, prints one
table of the headline ratios next to their targets, and writes everything
(the headline rows and each module's full output, plus the machine) as JSON.
The machine is shared and noisy: each module reports medians of repeats and
ratios measured side by side, never single absolute times.

The JSON is updated, not replaced: the modules run now replace their own results and
headline rows, each stamped with when it was measured and the load average before and
after (``measured``); the others keep theirs. ``long_run`` (a 1e8-step run, hours) runs
only when named in ``--only``.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import platform
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from asperity2d._io import atomic_write_text  # noqa: E402


def _sweep(res):
    cpu = res["overhead"]["cpu"]
    thr = res["throughput"]["cpu"]
    eff = thr["efficiency"]
    hw = thr.get("hardware_efficiency", float("nan"))
    return [("sweep per-run overhead, warm pool, ~1 s runs (%)", 100 * cpu["pool1-warm"]["relative"], "< 5"),
            ("sweep per-run overhead, in-process (%)", 100 * cpu["in-process"]["relative"], "< 5"),
            ("sweep parallel efficiency, 2 workers, CPU-bound", float("nan") if eff is None else eff,
             "<= 1" if eff is not None else f"refused as noise (measured {thr['efficiency_measured']:.2f} > 1)"),
            ("bare 2-process efficiency of this machine", float("nan") if hw > 1 else hw,
             "stated" if hw <= 1 else f"refused as noise (measured {hw:.2f} > 1)")]


def _generic(res, prefix=""):
    rows = []
    for key, value in res.items():
        if isinstance(value, bool):
            continue
        if isinstance(value, (int, float)):
            rows.append((f"{prefix}{key}", float(value), ""))
        elif isinstance(value, dict) and len(rows) < 40:
            rows += _generic(value, prefix=f"{prefix}{key}.")
    return rows


HEADLINES = {"sweep": _sweep}  # the other modules define headline()
ORDER = ("core", "steel", "studies", "critical", "batched", "parallel", "belt", "basins", "gif", "surface", "sweep",
         "startup")


def _load(name):
    path = HERE / f"bench_{name}.py"
    if not path.exists():
        return None
    spec = importlib.util.spec_from_file_location(f"bench_{name}", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="fewer repeats and smaller sizes")
    p.add_argument("--only", default=",".join(ORDER), help="comma-separated benchmark names")
    p.add_argument("-o", "--output", default=str(HERE / "results.json"))
    p.add_argument("--merge", action="append", default=[], metavar="NAME=FILE",
                   help="take module NAME's results from FILE (its --json output, run on its own) "
                        "instead of running it")
    args = p.parse_args(argv)
    merged = dict(item.split("=", 1) for item in args.merge)
    if merged:
        args.only = ",".join(merged)
    machine = {"platform": platform.platform(), "python": platform.python_version(),
               "cpus": os.cpu_count(), "load_average": os.getloadavg()}
    out = {"machine": machine, "quick": args.quick, "results": {}, "headline": []}
    previous = Path(args.output)
    if previous.exists() and not args.quick:  # keep what other modules measured before
        try:
            old = json.loads(previous.read_text())
            out["results"] = dict(old.get("results", {}))
            out["headline"] = list(old.get("headline", []))
        except ValueError:
            pass
    for name in args.only.split(","):
        module = _load(name)
        if module is None or not hasattr(module, "run"):
            print(f"[{name}] no benchmarks/bench_{name}.py with run(); skipped", file=sys.stderr)
            continue
        print(f"[{name}] running ...", file=sys.stderr, flush=True)
        start = time.perf_counter()
        load = os.getloadavg()
        if name in merged:
            res = json.loads(Path(merged[name]).read_text())
            stamp = time.localtime(Path(merged[name]).stat().st_mtime)
            res["measured"] = {"date": time.strftime("%Y-%m-%d %H:%M", stamp),
                               "load_average_before": res.get("load_average_before"),
                               "load_average_after": res.get("load_average_after")}
        else:
            res = module.run(quick=args.quick)
            res["measured"] = {"date": time.strftime("%Y-%m-%d %H:%M"), "load_average_before": load,
                               "load_average_after": os.getloadavg()}
        out["results"][name] = res
        headline = getattr(module, "headline", None) or HEADLINES.get(name) or _generic
        out["headline"] = [r for r in out["headline"] if r.get("benchmark") != name]
        for label, value, target in headline(res):
            out["headline"].append({"benchmark": name, "figure": label, "value": value, "target": target,
                                    "measured": res["measured"]["date"]})
        print(f"[{name}] done in {time.perf_counter() - start:.0f} s", file=sys.stderr, flush=True)
        if not args.quick:  # saved after every module: a later one that fails loses nothing
            atomic_write_text(args.output, json.dumps(out, indent=2, default=float) + "\n")
    out["machine"]["load_average_after"] = os.getloadavg()
    atomic_write_text(args.output, json.dumps(out, indent=2, default=float) + "\n")
    width = max((len(r["figure"]) for r in out["headline"]), default=10)
    print(f"{'figure':<{width}}  {'value':>12}  target")
    for r in out["headline"]:
        print(f"{r['figure']:<{width}}  {r['value']:>12.4g}  {r['target']}")
    print(f"machine: {machine['platform']}, Python {machine['python']}, {machine['cpus']} CPUs, "
          f"load {machine['load_average'][0]:.2f} -> {out['machine']['load_average_after'][0]:.2f}")
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
