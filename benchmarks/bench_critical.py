"""A critical force against a bare pymunk loop of the very runs it makes (issue 28: <= 1.3x).

    python benchmarks/bench_critical.py [--quick] [--json]

``critical_force(make_scene(drive="force", lower_count=16, upper_count=4, track=...))`` on both
set-ups, from rest (the default) and with ``start="run-up"``. Its runs are recorded (the force
and the steps of each, and the settling steps) and the same steps are then taken, from the same
settled state, by a bare public-API pymunk loop (``body.force = ...; space.step(dt)``: no
stick/slip switch, projection, record or stop conditions), which is the CPU time a run loop with
no overhead at all would take. The code of both is ``bench_studies._CODE``, one fresh
interpreter each, after the same warm-up. Each critical force is timed with the engine's C step
loop (the default where the extension was built) and with its Python loop
(``ASPERITY2D_KERNEL=0``), interleaved, and the two must give the same critical force to the
bit. CPU time (``time.process_time``); each ratio is the median of the per-run ratios, with
their range.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_studies import _measure  # noqa: E402

TARGET = 1.3
STARTS = {"rest": "critical-rest", "run-up": "critical"}  # bench_studies._CODE's names


def _against_bare(setup: str, what: str, repeats: int) -> dict:
    """A critical force (``what``: "critical-rest" from rest, "critical" with a run-up) against a
    bare pymunk loop of its own runs, with the engine's C step loop and with its Python loop
    (interleaved; the answers must be the same to the bit)."""
    runs = {"c": [], "python": []}
    for _ in range(repeats):
        runs["c"].append(_measure(None, setup, what, 0, new=True, kernel=True))
        runs["python"].append(_measure(None, setup, what, 0, new=True, kernel=False))
    if {r["value"] for r in runs["c"] + runs["python"]} != {runs["c"][0]["value"]}:
        raise AssertionError(f"{setup}/{what}: the C and Python step loops gave different critical forces")
    out = {"steps": runs["c"][0]["steps"], "repeats": repeats, "new_value_N": runs["c"][0]["value"]}
    for loop, rs in runs.items():
        pairs = [r["cpu_s"] / r["bare_cpu_s"] for r in rs]
        key = "new" if loop == "c" else "python_loop"
        out.update({f"{key}_cpu_s": statistics.median(r["cpu_s"] for r in rs),
                    f"{key}_over_bare": statistics.median(pairs), f"{key}_over_bare_min": min(pairs),
                    f"{key}_over_bare_max": max(pairs)})
    out["bare_cpu_s"] = statistics.median(r["bare_cpu_s"] for r in runs["c"])
    return out


def run(quick: bool = False) -> dict:
    repeats = 1 if quick else 7
    rows = {f"{setup}/{start}": _against_bare(setup, what, repeats)
            for setup in ("free", "fixed") for start, what in STARTS.items()}
    return {"target": TARGET, "rows": rows}


def headline(res):
    out = []
    for key, r in res["rows"].items():
        setup, start = key.split("/")
        where = "from rest (the default)" if start == "rest" else "start='run-up'"
        out.append((f"critical_force(make_scene(drive='force', track='{setup}')), {where}: now / a bare pymunk "
                    f"loop of the same runs (range {r['new_over_bare_min']:.2f}-{r['new_over_bare_max']:.2f}; "
                    f"the engine's Python step loop: {r['python_loop_over_bare']:.2f})", r["new_over_bare"],
                    f"<= {res['target']}"))
    return out


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="one repeat")
    p.add_argument("--json", action="store_true")
    args = p.parse_args(argv)
    out = run(quick=args.quick)
    if args.json:
        print(json.dumps(out))
        return 0
    for key, r in out["rows"].items():
        print(f"{key:14s} {r['new_cpu_s']:.2f} s CPU, {r['new_over_bare']:.2f}x a bare pymunk loop of the same "
              f"{r['steps']} steps (range {r['new_over_bare_min']:.2f}-{r['new_over_bare_max']:.2f}; target <= "
              f"{TARGET}); the Python step loop {r['python_loop_over_bare']:.2f}x "
              f"({r['python_loop_over_bare_min']:.2f}-{r['python_loop_over_bare_max']:.2f})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
