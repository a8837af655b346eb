"""The workbench's long jobs, each cancellable: a run streamed in chunks, a measure in a child
process, an ensemble comparison on the ensemble engine.

:class:`Lane` runs one job at a time: a new request cancels the job in flight and replaces any
request still waiting, so however fast the requests come exactly one job computes. The
measures' metadata is read in one place, :func:`measure_info`.
"""

from __future__ import annotations

import math
import os
import threading
import time
import traceback

from ..errors import SceneError, SimulationError


class Cancelled(Exception):
    """The job was replaced or cancelled."""


class Job:
    """One request being worked on; ``cancelled`` turns True when it is replaced or cancelled."""

    def __init__(self, ident: int, request):
        self.id, self.request = ident, request
        self._cancel = threading.Event()

    @property
    def cancelled(self) -> bool:
        return self._cancel.is_set()

    def cancel(self) -> None:
        self._cancel.set()

    def check(self) -> None:
        if self._cancel.is_set():
            raise Cancelled


class Lane:
    """A worker thread that runs ``work(job)`` for the newest request only.

    ``submit(request)`` cancels the job in flight (it stops at its next check) and replaces the
    request waiting, if any; ``cancel()`` cancels both; ``close()`` also ends the thread.
    ``work`` reports through its own callbacks; an exception it raises goes to ``on_error(job,
    exc)`` (a :class:`Cancelled` is silent)."""

    def __init__(self, name: str, work, on_error):
        self.name, self._work, self._on_error = name, work, on_error
        self._cond = threading.Condition()
        self._pending: Job | None = None
        self.current: Job | None = None
        self._closed = False
        self._count = 0
        self._thread = threading.Thread(target=self._loop, name=f"asperity2d-{name}", daemon=True)
        self._thread.start()

    def submit(self, request) -> int:
        with self._cond:
            self._count += 1
            if self.current is not None:
                self.current.cancel()
            self._pending = Job(self._count, request)
            self._cond.notify()
            return self._count

    def cancel(self) -> None:
        with self._cond:
            self._pending = None
            if self.current is not None:
                self.current.cancel()

    def close(self, timeout: float | None = 5.0) -> None:
        with self._cond:
            self._closed = True
            self._pending = None
            if self.current is not None:
                self.current.cancel()
            self._cond.notify()
        if threading.current_thread() is not self._thread:
            self._thread.join(timeout)

    @property
    def busy(self) -> bool:
        with self._cond:
            return self.current is not None or self._pending is not None

    def _loop(self) -> None:
        while True:
            with self._cond:
                while self._pending is None and not self._closed:
                    self._cond.wait()
                if self._closed:
                    return
                job, self._pending = self._pending, None
                self.current = job
            try:
                self._work(job)
            except Cancelled:
                pass
            except BaseException as exc:  # noqa: BLE001 -- reported to the page, never kills the lane
                self._on_error(job, exc)
            finally:
                with self._cond:
                    self.current = None


def error_text(exc: BaseException) -> str:
    """One line for the page: the package's own errors as they are; anything else named as
    unexpected (its traceback is not shown)."""
    if isinstance(exc, (SceneError, SimulationError)):
        text = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        return text
    return f"unexpected {type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"[:400]


# -- measures ----------------------------------------------------------------------------------------
#: The measures the workbench offers on a click, in this order.
OFFERED = ("critical", "critical-run-up", "quasi-static-breakaway", "first-breakaway", "peak-stick",
           "mean-stick")


def measure_info(name: str) -> dict:
    """What the workbench needs of a named measure, read from its registry entry
    (:data:`asperity2d.experiments.measures.MEASURES`): function, label, unit, drive, kind."""
    from ..experiments.measures import MEASURES

    if name not in MEASURES:
        raise SceneError(f"`measure` must be one of {', '.join(MEASURES)}, got {str(name)[:60]!r}")
    entry = MEASURES[name]
    return {"name": name, "fn": entry.function, "label": entry.label, "unit": entry.unit,
            "drive": entry.drive, "kind": entry.kind}


def measure_scene(name: str, params: dict):
    """The scene a measure runs on: ``params`` under the measure's drive."""
    from .controls import build

    scene, errors = build({**params, "drive": measure_info(name)["drive"]})
    if errors:
        raise SceneError(next(iter(errors.values())))
    return scene


def _measure_main() -> None:
    """The child process's side (``python -c``): read ``{"name", "params"}`` as JSON on stdin,
    write ``{"value"}`` or ``{"error"}`` as JSON on stdout."""
    import json
    import sys

    parent = os.getppid()

    def orphaned() -> None:  # the server went away (killed, Ctrl-C): stop computing for no one
        while True:
            time.sleep(0.5)
            if os.getppid() != parent:
                os._exit(3)

    threading.Thread(target=orphaned, daemon=True).start()
    request = json.loads(sys.stdin.read())
    try:
        value = float(measure_info(request["name"])["fn"](measure_scene(request["name"], request["params"])))
        answer = {"value": value if math.isfinite(value) else None}
    except BaseException as exc:  # noqa: BLE001 -- the parent shows it as one line
        answer = {"error": error_text(exc)}
    sys.stdout.write(json.dumps(answer))
    sys.stdout.flush()


def measure_in_child(name: str, params: dict, job: Job, on_progress, *, poll: float = 0.25) -> float:
    """Measure in a child process (a fresh interpreter: nothing of the server is inherited),
    reporting the elapsed time every ``poll`` s; a cancelled job kills the child at once."""
    import json
    import subprocess
    import sys
    import tempfile

    start = time.monotonic()
    with tempfile.TemporaryFile() as out:
        proc = subprocess.Popen([sys.executable, "-c", "from asperity2d.app.jobs import _measure_main; _measure_main()"],
                                stdin=subprocess.PIPE, stdout=out, stderr=subprocess.DEVNULL)
        try:
            proc.stdin.write(json.dumps({"name": name, "params": params}).encode())
            proc.stdin.close()
            while proc.poll() is None:
                if job.cancelled:
                    raise Cancelled
                try:
                    proc.wait(poll)
                except subprocess.TimeoutExpired:
                    on_progress(time.monotonic() - start)
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait(5)
        out.seek(0)
        text = out.read().decode(errors="replace")
    try:
        answer = json.loads(text)
    except ValueError:
        raise SimulationError(f"the measure's process ended without an answer (exit code {proc.returncode})") from None
    if "error" in answer:
        raise SceneError(answer["error"])
    return math.nan if answer["value"] is None else answer["value"]


# -- ensemble comparison ----------------------------------------------------------------------------
def verdict(comparison, name: str, reference: str, measure: str) -> dict:
    """The running numbers of variant ``name`` against ``reference`` -- Wilcoxon p, the
    Hodges-Lehmann ratio and its 95 % interval -- and the plain-words verdict by the measure's
    own rule (:meth:`asperity2d.Comparison.verdict`), the line the command line's ``compare``
    prints."""
    from ..experiments.verdicts import verdict_line

    record = comparison.verdict(name, reference, subject=name)
    numbers = record["numbers"]
    p = numbers["p_wilcoxon"]
    return {"variant": name, "reference": reference, "ratio": numbers["ratio_hl"],
            "ratio_ci": [numbers["ratio_ci_low"], numbers["ratio_ci_high"]], "p_wilcoxon": p,
            # the p the verdict line prints, formatted once here (Python rounds half to even, the
            # page's toPrecision half up: 0.0625 would read 0.062 in one line and 0.063 in the next)
            "p_text": f"{p:.2g}" if p is not None and math.isfinite(p) else "\u2013",
            "verdict": record["verdict"], "line": verdict_line(record), "n": numbers.get("n"),
            "seeds_needed": numbers.get("seeds_needed")}


def more_seeds(row: dict, seeds_done: int) -> int | None:
    """How many seeds beyond ``seeds_done`` would decide an undecided verdict row at the spread
    observed (its ``seeds_needed``, :func:`asperity2d.experiments.verdicts.seeds_needed`, is a
    total); None when no practical number would."""
    needed = row.get("seeds_needed")
    return None if needed is None else max(1, int(needed) - int(seeds_done))


def ensemble(request: dict, job: Job, emit, *, workers: int | None = None) -> None:
    """Measure every variant on every seed with the ensemble engine (every core), emitting each
    value as it arrives and the running statistics over the seeds every variant has finished.

    ``request["auto"]`` (``{"max_seeds": N, "stage_seeds": k}``) runs the seeds in stages until
    every variant's verdict against the reference is decided or N seeds are spent: the design,
    the looks and the verdicts of ``asperity2d.compare(seeds="auto", max_seeds=N)``
    (:func:`~asperity2d.experiments.sequential.run_in_stages`), streamed. Between two looks the
    running numbers are shown as an interim (judged at the design's last level); only a look
    stops the comparison."""
    from ..experiments.sequential import STAGE_SEEDS, Design, plan, run_in_stages
    from ..experiments.verdicts import DECIDED

    name = request["measure"]
    info = measure_info(name)
    variants, base = request["variants"], {**request["base"], "drive": info["drive"]}
    names = list(variants)
    auto = request.get("auto")
    n = workers or os.cpu_count() or 1
    design = None
    if auto:
        from ..experiments.measures import MEASURES

        design = Design(stages=plan(auto["max_seeds"], auto.get("stage_seeds", STAGE_SEEDS)),
                        alpha=MEASURES[name].rule.alpha)
        reference = "regular" if "regular" in variants else names[0]  # compare()'s default reference
        seeds = list(range(design.stages[-1]))
    else:
        reference, seeds = names[0], list(request["seeds"])
    values = {v: [math.nan] * len(seeds) for v in variants}
    done = {v: [False] * len(seeds) for v in variants}
    looks: list[dict] = []
    state = {"decided": False}

    def comparison(k: list[int]):
        from ..experiments.compare import Comparison

        record = {} if design is None else {
            "stages": list(design.stages), "alpha": design.alpha, "spending": design.spending,
            "reference": reference, "method": design.to_dict()["method"], "looks": list(looks)}
        return Comparison(values={v: tuple(values[v][j] for j in k) for v in names},
                          seeds=tuple(seeds[j] for j in k), measure=name, design=record)

    def stats(k: list[int], look: dict | None = None) -> list[dict]:
        comp = comparison(k)
        rows = [verdict(comp, other, reference, name) for other in names if other != reference]
        for row in rows:
            if row["verdict"] == "undecided":
                row["more"] = more_seeds(row, len(k))
        message = {"type": "ensemble-stats", "job": job.id, "seeds_done": len(k), "reference": reference,
                   "summary": comp.summary(), "versus": rows}
        if design is not None:
            message["look"] = look or {"interim": True, "stage": len(looks) + 1, "of": len(design.stages),
                                       "next": design.stages[len(looks)]}
        emit(message)
        return rows

    def measure_seeds(first: int, last: int) -> None:
        jobs, where = [], []
        for j in range(first, last):  # variants interleaved per seed: the verdict fills in from the second seed
            for vname, kw in variants.items():
                scene = measure_scene(name, {**base, **kw, "seed": seeds[j]})
                jobs.append((info["fn"], scene, f"variant {vname!r} with seed {seeds[j]}"))
                where.append((vname, j))
        job.check()
        calls = run_calls(_evaluate, jobs, workers=n)
        try:
            for outcome in calls:
                job.check()
                vname, j = where[outcome.index]
                value = float(outcome.value) if outcome.ok else math.nan
                values[vname][j], done[vname][j] = value, True
                message = {"type": "ensemble-value", "job": job.id, "variant": vname, "seed": seeds[j], "value": value}
                if not outcome.ok:
                    message["error"] = error_text(outcome.exception) if outcome.exception else "failed"
                emit(message)
                complete = [k for k in range(len(seeds)) if all(done[v][k] for v in names)]
                if len(names) >= 2 and len(complete) >= 2 and not (design is not None and len(complete) == last):
                    stats(complete)  # a look's own numbers follow from decide()
        finally:
            calls.close()  # a cancelled comparison shuts its workers down

    from ..experiments.compare import _evaluate
    from ..sweep.engine import run_calls

    emit({"type": "ensemble-start", "job": job.id, "measure": name, "label": info["label"], "unit": info["unit"],
          "variants": names, "reference": reference, "seeds": [] if design is not None else list(seeds),
          "workers": n, **({"design": {**design.to_dict(), "text": design.describe()}} if design is not None else {})})
    if design is None:
        measure_seeds(0, len(seeds))
        emit({"type": "ensemble-end", "job": job.id})
        return

    def on_stage(k: int, first: int, last: int) -> None:
        emit({"type": "ensemble-stage", "job": job.id, "stage": k + 1, "of": len(design.stages),
              "seeds": seeds[first:last]})

    def decide(k: int, nominal: float) -> bool:  # compare()'s look: the same record, the same verdicts
        last = design.stages[k]
        looks.append({"stage": k + 1, "seeds": list(range(design.stages[k - 1] if k else 0, last)),
                      "nominal_alpha": nominal})
        rows = stats(list(range(last)), {"stage": k + 1, "of": len(design.stages), "nominal_alpha": nominal})
        looks[-1]["verdicts"] = {row["variant"]: row["verdict"] for row in rows}
        state["decided"] = all(row["verdict"] in DECIDED for row in rows)
        return state["decided"]

    _, measured = run_in_stages(design, lambda k, first, last: measure_seeds(first, last), decide,
                                on_stage=on_stage)
    emit({"type": "ensemble-end", "job": job.id, "seeds_done": measured, "looks": len(looks),
          "decided": state["decided"], "max_seeds": design.stages[-1]})


def format_exception(exc: BaseException) -> str:
    """The traceback, for the server's debug log only."""
    return "".join(traceback.format_exception(exc))
