"""Belt-chain benchmark: exact event-driven solver against the thesis' sign() + LSODA method.

Run ``python benchmarks/bench_belt.py [--quick]``; ``run(quick=False) -> dict`` returns the figures.

1. Speed, Table 2 case: the exact solver over 1000 s; sign() mode (LSODA, rtol 1e-6, MATLAB's
   AbsTol 1e-6) is far too slow to cover 1000 s (its step collapses to ~AbsTol/jump while it
   chatters about belt speed), so both are timed side by side on the same opening window
   (which contains the first stick phases), and the sign() cost for 1000 s is extrapolated
   from its cost per simulated second in that window (labelled as an extrapolation).
2. Accuracy against the analytic 1-DOF case: a mass on the orbit x = muN/k + (V/w) sin(wt)
   (the stick-slip limit cycle of mu_s = mu_k), max |x - x_ref| / (V/w) over the run.
3. Cost per event for chains of n = 3 ... 300 masses; fitted exponent of cost/event against n.
Medians of repeats throughout.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from asperity2d.belt import simulate_chain
from asperity2d.belt.presets import preset


def _timed(fn, repeats):
    times, out = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def speed(quick):
    repeats = 1 if quick else 3
    long_run = 100.0 if quick else 1000.0
    window = 0.045 if quick else 0.06
    base = preset("table2-3dof", n_samples=2001)
    t_exact_long, r = _timed(lambda: simulate_chain(**{**base, "t_end": long_run}), repeats)
    win = {**base, "t_end": window, "n_samples": 201}
    t_exact_win, _ = _timed(lambda: simulate_chain(**win), repeats)
    t_sign_win, s = _timed(lambda: simulate_chain(**win, method="sign", integrator="LSODA", rtol=1e-6, atol=1e-6), 1)
    return {
        "exact_seconds_for_run": t_exact_long, "run_length_s": long_run, "exact_events": r.meta["n_events"],
        "window_s": window, "exact_seconds_window": t_exact_win, "sign_seconds_window": t_sign_win,
        "sign_nfev_window": s.meta["nfev"], "speed_ratio_window": t_sign_win / t_exact_win,
        "sign_seconds_for_run_extrapolated": t_sign_win / window * long_run,
        "speed_ratio_run_extrapolated": t_sign_win / window * long_run / t_exact_long,
    }


def accuracy(quick):
    k, mu, V = 10.0, 0.2, 0.1
    w = np.sqrt(k)
    x0 = mu * 9.81 / k
    kw = dict(masses=[1.0], springs=[k, 0.0], dampers=[0.0, 0.0], mu_s=mu, v_belt=V, x0=[x0], v0=[V],
              t_end=100.0 if quick else 1000.0, n_samples=20001)
    out = {}
    for label, extra in (("exact", {}), ("sign_lsoda_rtol1e-6", {"method": "sign", "rtol": 1e-6, "atol": 1e-6})):
        secs, r = _timed(lambda: simulate_chain(**kw, **extra), 1)
        ref = x0 + V / w * np.sin(w * r.t)
        out[label] = {"max_rel_error": float(np.max(np.abs(r.x[0] - ref)) / (V / w)), "seconds": secs}
    return out


def scaling(quick):
    sizes = [3, 10, 30, 100] if quick else [3, 10, 30, 100, 300]
    rng = np.random.default_rng(1)
    rows = []
    for n in sizes:
        kw = dict(masses=[1.0] * n, springs=[10.0] * (n + 1), dampers=[0.0] * (n + 1), mu_s=0.3, mu_k=0.2,
                  v_belt=0.1, x0=rng.uniform(-0.05, 0.05, n).tolist(), v0=rng.uniform(0.0, 0.1, n).tolist(),
                  t_end=max(4.0, 400.0 / n), n_samples=201)
        secs, r = _timed(lambda: simulate_chain(**kw), 1 if quick or n >= 100 else 3)
        rows.append({"n": n, "events": r.meta["n_events"], "seconds": secs,
                     "ms_per_event": 1e3 * secs / max(r.meta["n_events"], 1)})
    n = np.log([r["n"] for r in rows])
    c = np.log([r["ms_per_event"] for r in rows])
    big = [i for i, r in enumerate(rows) if r["n"] >= 10]
    return {"rows": rows, "exponent_all": float(np.polyfit(n, c, 1)[0]),
            "exponent_n_ge_10": float(np.polyfit(n[big], c[big], 1)[0])}


def run(quick: bool = False) -> dict:
    return {"speed": speed(quick), "accuracy": accuracy(quick), "scaling": scaling(quick), "quick": quick}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    res = run(parser.parse_args(argv).quick)
    sp, ac, sc = res["speed"], res["accuracy"], res["scaling"]
    print(f"Table 2, {sp['run_length_s']:.0f} s: exact {sp['exact_seconds_for_run']:.3f} s ({sp['exact_events']} events)")
    print(f"window 0-{sp['window_s']} s side by side: exact {sp['exact_seconds_window']:.4f} s, sign/LSODA "
          f"{sp['sign_seconds_window']:.2f} s ({sp['sign_nfev_window']} f-evals): ratio {sp['speed_ratio_window']:.0f}x")
    print(f"sign/LSODA for the whole run (extrapolated): {sp['sign_seconds_for_run_extrapolated']:.3g} s, "
          f"ratio ~{sp['speed_ratio_run_extrapolated']:.3g}x")
    for label, a in ac.items():
        print(f"1-DOF analytic orbit, {label:22s} max error / amplitude {a['max_rel_error']:.2e}  ({a['seconds']:.2f} s)")
    print(f"{'n':>5} {'events':>7} {'seconds':>9} {'ms/event':>9}")
    for r in sc["rows"]:
        print(f"{r['n']:>5} {r['events']:>7} {r['seconds']:>9.3f} {r['ms_per_event']:>9.3f}")
    print(f"cost per event ~ n^{sc['exponent_all']:.2f} (all sizes), n^{sc['exponent_n_ge_10']:.2f} (n >= 10)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
