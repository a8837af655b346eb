"""The workbench's two targets, default scene, this machine (not timed tests):

* **first frames within 1 s of a change**: from the moment a control changes to the first
  samples of the new run drawn by the player. Measured two ways: through the protocol in this
  process (the change handed to a :class:`~asperity2d.app.session.Session` -> the first
  ``run-chunk`` message ready to send), and end to end in headless Chromium against a real
  ``asperity2d explore`` (the control's change event -> the first chunk appended to the player
  and drawn), when Chromium and its driver are installed;
* **the whole run within 1.2x simulate()**: the Session's streamed run (in pieces, every chunk
  encoded as the player's JSON and sent) against ``simulate()`` of the same scene in the same
  process.

Runs alternate (simulate, session, simulate, session, ...) so that load on this shared machine
hits both alike; each figure is the median over ``--repeats`` rounds. Prints a table and stores
it under ``results["workbench"]`` in ``benchmarks/results.json`` (keeping every other key).

Run: ``python benchmarks/bench_workbench.py [--repeats N] [--no-browser]``.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
FIRST_FRAMES_S = 1.0
WHOLE_RUN_RATIO = 1.2


def protocol_round(values: dict) -> dict:
    """One change through a Session: seconds to the first chunk and to the run's end."""
    from asperity2d.app.session import Session

    marks, done = {}, threading.Event()

    def send(text: str) -> None:
        kind = text[9:30]
        now = time.perf_counter()
        if '"run-chunk"' in text[:30] and "chunk" not in marks:
            marks["chunk"] = now
        if '"run-end"' in text[:30]:
            marks["end"] = now
            done.set()
        del kind

    session = Session(send)
    start = time.perf_counter()
    session.handle({"type": "set", "values": values})
    done.wait(600)
    session.close()
    return {"first_chunk_s": marks["chunk"] - start, "whole_s": marks["end"] - start}


def simulate_round() -> float:
    import asperity2d as a

    scene = a.make_scene()
    start = time.perf_counter()
    a.simulate(scene, progress=False)
    return time.perf_counter() - start


def browser_rounds(repeats: int) -> list[float] | str:
    """End to end: a real server and headless Chromium; ms from the change to the first drawn chunk."""
    chromium, driver_path = "/usr/bin/chromium", "/usr/bin/chromedriver"
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
    except ImportError:
        return "selenium not installed"
    if not (os.path.exists(chromium) and os.path.exists(driver_path)):
        return "chromium / chromedriver not installed"
    proc = subprocess.Popen([sys.executable, "-m", "asperity2d", "explore", "--no-browser"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    url = proc.stdout.readline().strip()
    options = webdriver.ChromeOptions()
    options.binary_location = chromium
    for flag in ("--headless", "--no-sandbox", "--disable-gpu", "--window-size=1280,800"):
        options.add_argument(flag)
    profile = tempfile.mkdtemp(prefix="asperity2d-bench-")
    options.add_argument(f"--user-data-dir={profile}")
    driver = webdriver.Chrome(service=Service(driver_path), options=options)
    out = []
    try:
        driver.get(url)

        def state(expr):
            return driver.execute_script(f"const s = window.asperityWorkbench.state(); return {expr};")

        def wait(expr, timeout=300):
            end = time.monotonic() + timeout
            while not state(expr):
                if time.monotonic() > end:
                    raise TimeoutError(expr)
                time.sleep(0.05)

        wait("s.run.finished")
        for k in range(repeats):
            job = state("s.run.job")
            # the change as a person makes it: the control's text and its change event
            driver.execute_script("window.asperityWorkbench.set('drive_velocity', arguments[0])", f"{20.0 + 0.01 * (k + 1)}")
            wait(f"s.run.job > {job} && s.run.firstChunkMs !== null")
            out.append(state("s.run.firstChunkMs") / 1000.0)
            wait("s.run.finished")
    finally:
        driver.quit()
        proc.terminate()
        proc.communicate(timeout=20)
        shutil.rmtree(profile, ignore_errors=True)
    return out


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--no-browser", action="store_true")
    p.add_argument("-o", "--output", default=str(HERE / "results.json"))
    args = p.parse_args(argv)

    import asperity2d as a

    a.simulate(a.make_scene(lower_count=4, upper_count=2), 1e-8, progress=False)  # imports, caches
    # the app has always run a scene before the user's first change (the page's hello runs one):
    # the player's modules are imported then, not in the measured change
    protocol_round({"lower_count": "4", "upper_count": "2", "duration": "1e-8"})
    sims, rounds = [], []
    for k in range(args.repeats):
        sims.append(simulate_round())
        rounds.append(protocol_round({"drive_velocity": f"{20.0 + 0.01 * (k + 1)}"}))
        print(f"round {k + 1}: simulate {sims[-1]:.2f} s, session first chunk {rounds[-1]['first_chunk_s']:.3f} s, "
              f"whole {rounds[-1]['whole_s']:.2f} s", flush=True)
    sim = statistics.median(sims)
    whole = statistics.median(r["whole_s"] for r in rounds)
    first = statistics.median(r["first_chunk_s"] for r in rounds)
    ratios = [r["whole_s"] / s for r, s in zip(rounds, sims)]
    browser = "skipped (--no-browser)" if args.no_browser else browser_rounds(args.repeats)
    report = {
        "scene": "make_scene() (the default: Ooten's fixed track, 16/4, spring drive), simulate() to its end",
        "cpus": os.cpu_count(), "load_average": list(os.getloadavg()), "repeats": args.repeats,
        "simulate_s": sim, "session_whole_s": whole, "whole_run_ratio": statistics.median(ratios),
        "whole_run_ratios": ratios, "whole_run_target": WHOLE_RUN_RATIO,
        "protocol_first_chunk_s": first, "first_frames_target_s": FIRST_FRAMES_S,
        "browser_first_frames_s": browser if isinstance(browser, list) else None,
        "browser_note": browser if isinstance(browser, str) else "change event -> first chunk drawn, in Chromium",
    }
    if isinstance(browser, list) and browser:
        report["browser_first_frames_median_s"] = statistics.median(browser)
    print(json.dumps(report, indent=1))
    path = Path(args.output)
    data = json.loads(path.read_text()) if path.exists() else {}
    data["workbench"] = report
    path.write_text(json.dumps(data, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
