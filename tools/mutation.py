"""Mutation score of the measure code, with mutmut (``pip install -e ".[mutation]"``).

    python tools/mutation.py                      # the eight modules below, every mutant
    python tools/mutation.py stats geometry       # some of them
    python tools/mutation.py --sample 80          # a seeded sample of mutants per module
    python tools/mutation.py --rev ed006ba        # the code and tests of another commit

For each module it copies the project (``git archive`` of the working tree's files, or of
``--rev``) into a scratch directory, writes a ``[tool.mutmut]`` section that mutates that one
module and runs only its own test files (:data:`MODULES`), runs mutmut there and reads every
mutant's outcome from mutmut's ``.meta`` files. The score is killed / (killed + survived);
a mutant no test runs counts as survived, one that times out as killed (mutmut's own rule),
and the time-outs are counted apart. A mutant times out at ``--timeout-multiplier`` (default 4)
times its tests' clean time plus a second, not mutmut's default 15: a search mutated into an
endless loop then costs a minute, not ten (a mutant that only slows the tests down would have to
slow them 4-fold to be counted killed; the record counts the time-outs).
Writes ``docs/data/mutation/<module>.json`` (every mutant and its outcome, the commit and the
date; the Validation page's table reads these files, so commit them) and prints one line per
module. Not part of the default test run: critical.py takes about 12 minutes on two shared
cores (its mutants run simulations), events.py 18 on a loaded machine.
"""

from __future__ import annotations

import argparse
import json
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from asperity2d._io import atomic_write_text

ROOT = Path(__file__).resolve().parent.parent
#: module (path under the project) -> its test files
MODULES = {
    "critical": ("asperity2d/critical.py", ["tests/test_critical.py",
                                            "tests/test_ooten_studies.py::test_critical_force_brackets_correctly"]),
    "events": ("asperity2d/events.py", ["tests/test_analysis.py", "tests/test_events_table.py"]),
    "forces": ("asperity2d/forces.py", ["tests/test_analysis.py"]),
    "slip-thresholds": ("asperity2d/slip_thresholds.py", ["tests/test_analysis.py"]),
    "contact-states": ("asperity2d/contact_states.py", ["tests/test_contact_states.py"]),
    "stats": ("asperity2d/stats.py", ["tests/test_stats.py"]),
    "geometry": ("asperity2d/geometry.py", ["tests/test_geometry.py", "tests/test_scene_validation.py"]),
    "belt-events": ("asperity2d/belt/phases/events.py", ["tests/test_belt_events.py", "tests/test_belt_exact.py"]),
}
#: mutmut's exit codes in the .meta files (mutmut.stats.status_by_exit_code): a test failed
#: (1, 3), the time limit stopped it (36, +-24, 152, 255) or it crashed the process (-9, -11):
#: killed; it passed every test (0) or no test ran it (5, 33): survived
KILLED = {1, 3, 36, 24, -24, 152, 255, -9, -11}
SURVIVED = {0, 5, 33}
TIMED_OUT = {36, 24, -24, 152, 255}


def commit(rev: str | None) -> str:
    """The commit measured: ``rev``'s short hash, or HEAD's with "+changes" if the module or
    test files differ from it in the working tree."""
    out = subprocess.run(["git", "rev-parse", "--short", rev or "HEAD"], cwd=ROOT, check=True,
                         capture_output=True, text=True).stdout.strip()
    if rev:
        return out
    dirty = subprocess.run(["git", "status", "--porcelain", "--", "asperity2d", "tests"], cwd=ROOT,
                           check=True, capture_output=True, text=True).stdout.strip()
    return out + ("+changes" if dirty else "")


def copy_project(destination: Path, rev: str | None) -> None:
    """The project's tracked files (of ``rev``, or the working tree's) in ``destination``."""
    if rev:
        archive = subprocess.run(["git", "archive", rev], cwd=ROOT, check=True, capture_output=True).stdout
        subprocess.run(["tar", "xf", "-"], cwd=destination, input=archive, check=True)
        return
    files = subprocess.run(["git", "ls-files", "--cached", "--others", "--exclude-standard"], cwd=ROOT,
                           check=True, capture_output=True, text=True).stdout.split()
    for name in files:
        source = ROOT / name
        if source.is_file() and not name.startswith(("renders/", "benchmarks/")):
            target = destination / name
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source, target)


def configure(project: Path, module: str, tests: list[str], timeout_multiplier: float = 4.0) -> list[str]:
    """Write the [tool.mutmut] section for one module; return the test files that exist."""
    tests = [t for t in tests if (project / t.split("::")[0]).exists()]
    pyproject = project / "pyproject.toml"
    text = re.sub(r"\n\[tool\.mutmut\][^\[]*", "\n", pyproject.read_text())
    text += ("\n[tool.mutmut]\n"
             'source_paths = ["asperity2d"]\n'
             f"only_mutate = [{json.dumps(module)}]\n"
             f"pytest_add_cli_args_test_selection = {json.dumps(tests)}\n"
             # one process: mutmut records which test reaches which mutant only in its own process, and the
             # project's addopts start xdist workers (-n auto), where it would see none
             'pytest_add_cli_args = ["-p", "no:cacheprovider", "-q", "-m", "not slow", "-n", "0"]\n'
             f"timeout_multiplier = {float(timeout_multiplier)!r}\n")
    pyproject.write_text(text)
    return tests


def mutant_names(project: Path, module: str) -> list[str]:
    """Every mutant mutmut generated for ``module`` (from its mutated copy)."""
    source = (project / "mutants" / module).read_text()
    return sorted(set(re.findall(r"def (x\w*__mutmut_\d+)\(", source)),
                  key=lambda n: (n.rsplit("__mutmut_", 1)[0], int(n.rsplit("_", 1)[1])))


def outcomes(project: Path, module: str) -> dict[str, int]:
    meta = json.loads((project / "mutants" / (module + ".meta")).read_text())
    return meta["exit_code_by_key"]


def run_module(name: str, *, sample: int, rev: str | None, seed: int, timeout_multiplier: float = 4.0) -> dict:
    module, tests = MODULES[name]
    started = time.time()
    measured = commit(rev)
    with tempfile.TemporaryDirectory(prefix=f"mutation-{name}-") as scratch:
        project = Path(scratch)
        copy_project(project, rev)
        tests = configure(project, module, tests, timeout_multiplier)
        if not tests:  # never let mutmut fall back to the whole suite
            raise SystemExit(f"{module}: none of its test files exist in {rev or 'the working tree'}")
        env = {**os.environ, "MPLBACKEND": "Agg", "PYTHONDONTWRITEBYTECODE": "1"}
        quiet = {"cwd": project, "env": env, "stdout": subprocess.DEVNULL, "stderr": subprocess.PIPE,
                 "text": True}
        dotted = module[:-3].replace("/", ".")
        if sample:
            # generate the mutants and the clean run with one mutant, then run a seeded sample
            first = subprocess.run([sys.executable, "-m", "mutmut", "run", f"{dotted}.x__no_such__mutmut_1"],
                                   **quiet)
            names = [f"{dotted}.{n}" for n in mutant_names(project, module)]
            chosen = sorted(random.Random(seed).sample(names, min(sample, len(names))))
            proc = subprocess.run([sys.executable, "-m", "mutmut", "run", *chosen], **quiet)
        else:
            first = None
            proc = subprocess.run([sys.executable, "-m", "mutmut", "run"], **quiet)
            names = [f"{dotted}.{n}" for n in mutant_names(project, module)]
            chosen = names
        codes = outcomes(project, module) if (project / "mutants" / (module + ".meta")).exists() else {}
    results = {n: codes.get(n) for n in chosen}
    killed = sum(1 for c in results.values() if c in KILLED)
    timeouts = sum(1 for c in results.values() if c in TIMED_OUT)
    survived = sorted(n for n, c in results.items() if c in SURVIVED)
    unknown = sorted(n for n, c in results.items() if c not in KILLED | SURVIVED)
    judged = killed + len(survived)
    out = {"module": module, "tests": tests, "rev": rev or "working tree", "commit": measured,
           "date": time.strftime("%Y-%m-%d"), "mutants": len(names),
           "run": len(chosen), "killed": killed, "timeouts": timeouts,
           "timeout_multiplier": timeout_multiplier, "survived": survived, "unknown": unknown,
           "score": killed / judged if judged else float("nan"), "seconds": round(time.time() - started),
           "mutmut_stderr": (proc.stderr or "")[-2000:] if not judged else "",
           "setup_stderr": (first.stderr or "")[-2000:] if first is not None and not judged else ""}
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("modules", nargs="*", help=f"any of {', '.join(MODULES)} (default: all)")
    parser.add_argument("--sample", type=int, default=0, help="mutants per module (0: all)")
    parser.add_argument("--seed", type=int, default=25, help="seed of the sample")
    parser.add_argument("--timeout-multiplier", type=float, default=4.0,
                        help="a mutant times out at this many times its tests' clean time (mutmut: 15)")
    parser.add_argument("--rev", help="measure this commit's code and tests instead of the working tree")
    parser.add_argument("-o", "--out", default=str(ROOT / "docs" / "data" / "mutation"), help="output directory")
    args = parser.parse_args(argv)
    if not args.timeout_multiplier > 0:
        parser.error(f"--timeout-multiplier must be > 0, got {args.timeout_multiplier!r}")
    unknown = [m for m in args.modules if m not in MODULES]
    if unknown:
        parser.error(f"unknown module {unknown[0]!r}: choose from {', '.join(MODULES)}")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for name in args.modules or list(MODULES):
        result = run_module(name, sample=args.sample, rev=args.rev, seed=args.seed,
                            timeout_multiplier=args.timeout_multiplier)
        tag = f"{name}{'@' + args.rev if args.rev else ''}"
        atomic_write_text(out / f"{tag}.json", json.dumps(result, indent=1) + "\n")  # a committed record
        print(f"{result['module']}: {100 * result['score']:.1f} % killed ({result['killed']} of "
              f"{result['killed'] + len(result['survived'])} judged, {result['timeouts']} of the kills time-outs; {result['run']} of {result['mutants']} mutants "
              f"run; {len(result['unknown'])} without an outcome; {result['seconds']} s) tests: "
              f"{' '.join(result['tests'])}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
