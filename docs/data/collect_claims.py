"""Run the full-size study scripts and keep their claim records for the documentation.

The pages of docs/studies/ render their claim tables from ``docs/data/claims/<script>.json``
(``.. claims-table:: <script>``, docs/_ext/asperity_docs.py), never from pasted numbers. Each
file holds the claim records a full-size run of ``scenes/<script>.py`` wrote to its summary,
with the command, the commit and the date it was made at and the CPU time it took::

    python docs/data/collect_claims.py belt_2dof belt_3dof     # run these two, full size
    python docs/data/collect_claims.py --all                   # every study script (hours)
    python docs/data/collect_claims.py ooten_spacing --from renders/ooten_spacing
                                                               # keep a run made already

A claim file is written only when its run finished; an interrupted collection keeps the files
it finished. The claims of the quick runs in the gallery are shown on the gallery pages instead.
"""

from __future__ import annotations

import argparse
import datetime
import json
import resource
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CLAIMS = Path(__file__).resolve().parent / "claims"
#: The study scripts whose summaries carry claim records, with extra arguments for a full run.
#: (The spectra, basins, steel ladder, tribometer and MATLAB lattice scripts report measurements
#: without claim records: their findings are in docs/findings.md and the guide.)
STUDIES = {
    "quickstart": ["--no-gif"], "ooten_spacing": ["--no-gif"], "ooten_profiles": ["--no-gif"],
    "ooten_damping": ["--no-gif"], "ooten_drive": ["--no-gif"], "ooten_stickslip": ["--no-gif"],
    "micro_spacing": ["--no-gif"], "stick_slip_law": ["--no-gif"],
    "belt_2dof": [], "belt_3dof": [], "belt_parameters": [], "belt_contact": [],
    "rough_height_spread": [], "rough_hurst": [], "rough_contact_fraction": [], "rough_measured": [],
}


def claims_of(directory: Path) -> list[dict]:
    """The claim records a script wrote to ``directory`` (its summary.json; a folder without one,
    as the belt studies wrote before they used the common script harness: every <name>.json in
    it), in the order written."""
    found = []
    candidates = [directory / "summary.json"] if (directory / "summary.json").exists() else \
        sorted(directory.glob("*.json"))
    for path in candidates:
        data = json.loads(path.read_text(encoding="utf-8"))
        if isinstance(data, dict) and isinstance(data.get("claims"), list):
            found += data["claims"]
    return found


def commit() -> str:
    try:
        out = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], check=True,
                             capture_output=True, text=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--", "asperity2d", "scenes"],
                               check=True, capture_output=True, text=True).stdout.strip()
        return out + ("+changes" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def collect(name: str, *, source: Path | None = None) -> Path:
    """Run ``scenes/<name>.py`` full size (or read ``source``) and write its claim file."""
    command = f"python scenes/{name}.py " + " ".join(STUDIES.get(name, []))
    cpu = None
    with tempfile.TemporaryDirectory() as tmp:
        directory = source
        if directory is None:
            directory = Path(tmp) / name
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            subprocess.run([sys.executable, str(ROOT / "scenes" / f"{name}.py"), *STUDIES.get(name, []),
                            "-o", str(directory)], check=True, cwd=ROOT)
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        claims = claims_of(Path(directory))
        if not claims:
            raise SystemExit(f"{name}: no claim records in {directory}")
        record = {"script": name, "command": command.strip(), "commit": commit(),
                  "date": datetime.date.today().isoformat(), "cpu_s": cpu, "claims": claims}
        CLAIMS.mkdir(parents=True, exist_ok=True)
        path = CLAIMS / f"{name}.json"
        tmp_path = path.with_suffix(".json.tmp")
        tmp_path.write_text(json.dumps(record, indent=1, ensure_ascii=False, allow_nan=False) + "\n",
                            encoding="utf-8")
        tmp_path.replace(path)  # atomic: a half-written claim file never replaces a good one
    return path


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scripts", nargs="*", help=f"study scripts ({', '.join(STUDIES)})")
    parser.add_argument("--all", action="store_true", help="every study script")
    parser.add_argument("--from", dest="source", type=Path, help="read an existing output directory")
    args = parser.parse_args(argv)
    names = list(STUDIES) if args.all else args.scripts
    if not names:
        parser.error("name a study script, or --all")
    unknown = [n for n in names if n not in STUDIES]
    if unknown:
        parser.error(f"unknown study script {unknown[0]!r}; known: {', '.join(STUDIES)}")
    if args.source and len(names) != 1:
        parser.error("--from reads one script's output directory: name exactly one script")
    for name in names:
        print(f"{name}: wrote {collect(name, source=args.source)}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
