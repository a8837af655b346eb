"""Belt-chain benchmark: the exact solver against what a user would otherwise run, like with like.

    OPENBLAS_NUM_THREADS=1 python benchmarks/bench_belt.py [--quick] [--no-save]

Every figure is measured (never extrapolated) as CPU time (``time.process_time``),
median of interleaved repeats, on the multi-DOF belt thesis' Table 2 3-DOF base case
(``presets.preset("table2-3dof")``, 2001 output samples):

1. speed at 10 s and 1000 s against (a) the fastest honest ``solve_ivp`` we could write
   (DOP853, rtol 1e-10, atol 1e-12, one linear right-hand side and one event function per
   mode, restarted at each event; :func:`belt_baselines.ivp_events`), beside the same method
   written straightforwardly (:func:`belt_baselines.ivp_plain`, which (a) must beat), and
   (b) a plain matrix-exponential stepper (independent code). Each ratio is the median over
   interleaved rounds (exact, ivp, plain, expm, exact, ...) of the per-round ratio, with its
   range; the stick intervals of every solver are checked against the exact ones (same
   count, largest difference of an end in s). The thesis' ``sign()`` + LSODA method with
   MATLAB ode113's default tolerances (RelTol 1e-3, AbsTol 1e-6) on the opening window
   (1 s; 0.1 s with --quick) is context, not a like-with-like ratio: at those tolerances its
   error is of the order of the motion itself (see 2.);
2. accuracy: the error of each against the analytic 1-DOF orbit x = mu N/k + (V/omega)
   sin(omega t) over 1000 s (a limit cycle that touches belt speed once per period), and on
   the 3-DOF case against the matrix-exponential reference (exact propagation, events by
   brentq to 1e-15 s);
3. cost per event of the exact solver for chains of n = 3 ... 300 masses (random initial
   state, static/kinetic friction) and the fitted exponent of cost/event against n.

Each figure is printed with its target; ``run(quick)`` returns them, ``headline(res)`` gives
the table rows, and ``main`` appends them to ``benchmarks/results.json`` under ``belt``
(other keys kept). Multithreaded BLAS on a shared machine burns CPU spinning (a 100 x 100
eigh costs 60 ms instead of 1 ms here): the script pins one BLAS thread before NumPy loads;
``run_all.py`` should be run with ``OPENBLAS_NUM_THREADS=1`` for the same conditions.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))

from belt_baselines import expm_stepper, ivp_events, ivp_plain  # noqa: E402

from asperity2d._io import atomic_write_text  # noqa: E402
from asperity2d.belt import presets, simulate_chain  # noqa: E402

G = 9.81


def _cpu(fn):
    start = time.process_time()
    out = fn()
    return time.process_time() - start, out


def _interleaved(fns: dict, repeats: int, raw: dict | None = None) -> tuple[dict, dict]:
    """Median CPU seconds of each callable over ``repeats`` interleaved rounds, and its last output
    (``raw``, if given, receives every round's times)."""
    times, outs = {k: [] for k in fns}, {}
    for _ in range(repeats):
        for name, fn in fns.items():
            dt, outs[name] = _cpu(fn)
            times[name].append(dt)
    if raw is not None:
        raw.update(times)
    return {k: statistics.median(v) for k, v in times.items()}, outs


def _ratio(raw: dict, slow: str, fast: str) -> dict:
    """Per-round ratios slow / fast of interleaved rounds: median, min, max."""
    r = [a / b for a, b in zip(raw[slow], raw[fast])]
    return {"median": statistics.median(r), "min": min(r), "max": max(r), "rounds": len(r)}


def _interval_error(exact, other) -> float:
    """Largest difference (s) between the ends of matching stick intervals; inf if they differ in number."""
    worst = 0.0
    for a, b in zip(exact, other):
        if len(a) != len(b):
            return float("inf")
        for (s0, e0), (s1, e1) in zip(a, b):
            worst = max(worst, abs(s0 - s1), abs(e0 - e1))
    return worst


def _exact(kw, samples):
    r = simulate_chain(**kw, t_eval=samples, include_events=False, max_steps=10**8)
    return r.t, r.x, r.meta["n_events"], r.stick_intervals


def speed(quick: bool) -> dict:
    out = {}
    for t_end in (10.0, 100.0 if quick else 1000.0):
        kw = presets.preset("table2-3dof", t_end=t_end)
        samples = np.linspace(0.0, t_end, 2001)
        raw: dict = {}
        med, outs = _interleaved({"exact": lambda: _exact(kw, samples),
                                  "solve_ivp+events": lambda: ivp_events(kw, samples),
                                  "solve_ivp+events, straightforward": lambda: ivp_plain(kw, samples),
                                  "expm stepper": lambda: expm_stepper(kw, samples)},
                                 repeats=3 if quick else (5 if t_end > 10 else 9), raw=raw)
        ref = outs["expm stepper"][1]
        exact_intervals = outs["exact"][3]
        out[f"{t_end:g}s"] = {
            "cpu_s": med, "cpu_s_rounds": raw, "switches": {k: v[2] for k, v in outs.items()},
            "ivp_over_exact": med["solve_ivp+events"] / med["exact"],
            "ivp_over_exact_rounds": _ratio(raw, "solve_ivp+events", "exact"),
            "plain_over_ivp_rounds": _ratio(raw, "solve_ivp+events, straightforward", "solve_ivp+events"),
            "expm_over_exact": med["expm stepper"] / med["exact"],
            "expm_over_exact_rounds": _ratio(raw, "expm stepper", "exact"),
            "stick_intervals": {k: [len(i) for i in exact_intervals] for k in ("exact",)},
            "stick_interval_error_s": {k: _interval_error(exact_intervals, outs[k][3])
                                       for k in ("solve_ivp+events", "solve_ivp+events, straightforward")},
            "error_vs_expm_reference_m": {k: float(np.max(np.abs(v[1] - ref))) for k, v in outs.items()},
        }
    window = 0.1 if quick else 1.0
    kw = presets.preset("table2-3dof", t_end=window)
    samples = np.linspace(0.0, window, 201)
    sign_kw = dict(method="sign", integrator="LSODA", rtol=1e-3, atol=1e-6, t_eval=samples, max_steps=10**8,
                   max_wall_time=3600.0)  # the chatter is what is timed: past the default 30 s budget
    med, outs = _interleaved({"exact": lambda: _exact(kw, samples),
                              "sign": lambda: simulate_chain(**kw, **sign_kw)}, repeats=3)
    out["sign_window"] = {
        "window_s": window, "cpu_s": med, "sign_over_exact": med["sign"] / med["exact"],
        "sign_nfev": outs["sign"].meta["nfev"],
        "sign_error_m": float(np.max(np.abs(outs["sign"].x - outs["exact"][1]))),
    }
    return out


def accuracy(quick: bool) -> dict:
    """Error against the analytic 1-DOF orbit (m = 1, k = 10, mu = 0.2, V = 0.1)."""
    k, mu, V = 10.0, 0.2, 0.1
    omega = np.sqrt(k)
    x_k = mu * G / k
    t_end = 100.0 if quick else 1000.0
    kw = dict(masses=[1.0], springs=[k, 0.0], dampers=[0.0, 0.0], mu_s=mu, mu_k=mu, v_belt=V, x0=[x_k], v0=[V],
              t_end=t_end)
    samples = np.linspace(0.0, t_end, 20001)
    exact_x = x_k + V / omega * np.sin(omega * samples)
    runs = {
        "exact": lambda: _exact(kw, samples)[:2],
        "solve_ivp+events": lambda: ivp_events(kw, samples)[:2],
        "expm stepper": lambda: expm_stepper(kw, samples)[:2],
        "sign (rtol 1e-3, atol 1e-6)": lambda: (lambda r: (r.t, r.x))(simulate_chain(
            **kw, t_eval=samples, method="sign", rtol=1e-3, atol=1e-6, max_steps=10**8, max_wall_time=3600.0)),
    }
    out = {}
    for name, fn in runs.items():
        dt, (t, x) = _cpu(fn)
        out[name] = {"max_error_over_amplitude": float(np.max(np.abs(x[0] - np.interp(t, samples, exact_x)))
                                                       / (V / omega)), "cpu_s": dt}
    return {"t_end_s": t_end, "errors": out}


def scaling(quick: bool) -> dict:
    sizes = [3, 10, 30, 100] if quick else [3, 10, 30, 100, 300]
    rng = np.random.default_rng(1)
    rows = []
    for n in sizes:
        kw = dict(masses=[1.0] * n, springs=[10.0] * (n + 1), dampers=[0.0] * (n + 1), mu_s=0.3, mu_k=0.2,
                  v_belt=0.1, x0=rng.uniform(-0.05, 0.05, n).tolist(), v0=rng.uniform(0.0, 0.1, n).tolist(),
                  t_end=max(4.0, 400.0 / n), n_samples=201)
        med, outs = _interleaved({"exact": lambda: simulate_chain(**kw)}, repeats=1 if quick or n >= 100 else 3)
        events = outs["exact"].meta["n_events"]
        rows.append({"n": n, "events": events, "cpu_s": med["exact"], "ms_per_event": 1e3 * med["exact"] / events})
    logn, logc = np.log([r["n"] for r in rows]), np.log([r["ms_per_event"] for r in rows])
    big = [i for i, r in enumerate(rows) if r["n"] >= 10]
    return {"rows": rows, "exponent_all": float(np.polyfit(logn, logc, 1)[0]),
            "exponent_n_ge_10": float(np.polyfit(logn[big], logc[big], 1)[0])}


def run(quick: bool = False) -> dict:
    return {"speed": speed(quick), "accuracy": accuracy(quick), "scaling": scaling(quick), "quick": quick,
            "blas_threads": os.environ.get("OPENBLAS_NUM_THREADS")}


def headline(res: dict) -> list[tuple[str, float, str]]:
    """(figure, value, target) rows for the README table and results.json."""
    sp, ac, sc = res["speed"], res["accuracy"]["errors"], res["scaling"]
    short, long_ = list(sp)[:2]
    rows = [
        (f"belt {short}: best solve_ivp+events (DOP853 1e-10/1e-12) CPU / exact CPU",
         sp[short]["ivp_over_exact_rounds"]["median"], ">= 5"),
        (f"belt {long_}: best solve_ivp+events (DOP853 1e-10/1e-12) CPU / exact CPU",
         sp[long_]["ivp_over_exact_rounds"]["median"], ">= 150"),
        (f"belt {short}: straightforward solve_ivp+events / best (the baseline is the faster)",
         sp[short]["plain_over_ivp_rounds"]["median"], ">= 1"),
        (f"belt {short}: stick intervals, max |solve_ivp - exact| (s)",
         sp[short]["stick_interval_error_s"]["solve_ivp+events"], "~1e-9"),
        (f"belt {long_}: stick intervals, max |solve_ivp - exact| (s)",
         sp[long_]["stick_interval_error_s"]["solve_ivp+events"], "~1e-9"),
        (f"belt {short}: matrix-exponential stepper CPU / exact CPU", sp[short]["expm_over_exact_rounds"]["median"],
         ">= 1"),
        (f"belt {long_}: matrix-exponential stepper CPU / exact CPU", sp[long_]["expm_over_exact_rounds"]["median"],
         ">= 1"),
        (f"belt 0-{sp['sign_window']['window_s']:g} s: sign()/LSODA at MATLAB tolerances CPU / exact CPU "
         "(context: its error is of the motion's size)", sp["sign_window"]["sign_over_exact"], "stated"),
    ]
    for name, err in ac.items():
        rows.append((f"belt 1-DOF orbit, {res['accuracy']['t_end_s']:g} s: max error / amplitude, {name}",
                     err["max_error_over_amplitude"], "exact below solve_ivp+events"))
    for name in ("exact", "solve_ivp+events"):
        rows.append((f"belt {long_}: max |x - x_expm reference| (m), {name}",
                     sp[long_]["error_vs_expm_reference_m"][name], "exact below solve_ivp+events"))
    rows.append(("belt cost per event ~ n^p, p (n = 3 ... 300)", sc["exponent_all"], "<= 1.2 (near-linear)"))
    return rows


def save(res: dict, path: Path) -> None:
    """Put the results under ``results.belt`` and refresh the belt headline rows, keeping everything else."""
    data = json.loads(path.read_text()) if path.exists() else {"results": {}, "headline": []}
    data.setdefault("results", {})["belt"] = res
    rows = [r for r in data.get("headline", []) if r.get("benchmark") != "belt"]
    rows += [{"benchmark": "belt", "figure": f, "value": v, "target": t} for f, v, t in headline(res)]
    data["headline"] = rows
    atomic_write_text(path, json.dumps(data, indent=2, default=float) + "\n")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="shorter runs and fewer repeats")
    parser.add_argument("--no-save", action="store_true", help="do not touch benchmarks/results.json")
    args = parser.parse_args(argv)
    res = run(args.quick)
    sp = res["speed"]
    for key in list(sp)[:2]:
        s = sp[key]
        print(f"Table 2, {key}: exact {1e3 * s['cpu_s']['exact']:.1f} ms, solve_ivp+events "
              f"{1e3 * s['cpu_s']['solve_ivp+events']:.1f} ms, expm stepper {1e3 * s['cpu_s']['expm stepper']:.1f} ms "
              f"(switches {s['switches']})")
    sw = sp["sign_window"]
    print(f"window 0-{sw['window_s']:g} s: exact {1e3 * sw['cpu_s']['exact']:.1f} ms, sign()/LSODA "
          f"{sw['cpu_s']['sign']:.2f} s ({sw['sign_nfev']} f-evals, max |x - x_exact| {sw['sign_error_m']:.2e} m)")
    print(f"{'n':>5} {'events':>7} {'CPU s':>8} {'ms/event':>9}")
    for r in res["scaling"]["rows"]:
        print(f"{r['n']:>5} {r['events']:>7} {r['cpu_s']:>8.3f} {r['ms_per_event']:>9.3f}")
    width = max(len(f) for f, _, _ in headline(res))
    for figure, value, target in headline(res):
        print(f"{figure:<{width}}  {value:>10.3g}   target {target}")
    if not args.no_save:
        save(res, HERE / "results.json")
        print(f"appended under 'belt' in {HERE / 'results.json'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
