"""Make what the README and the docs show of the main job from the main job itself: nothing pasted.

    python tools/showcase.py            # run the main job (scenes/quickstart.py, ~3-4 min on 2 cores), then
                                        # write what it printed and copy the animation it wrote
    python tools/showcase.py --check    # exit 1, saying which, if a committed copy differs from the files

The main job writes ``renders/quickstart/run.gif`` and prints its summary. This script runs it
exactly as the README says (``python scenes/quickstart.py``, from the repository root), and writes

* ``docs/data/main_job_output.txt``: what it printed, the checkout's path replaced by
  ``/path/to/asperity2d`` (``docs/getting_started.md`` includes this file);
* the README's ``text`` block of the same output (the block that starts with the job's first line);
* ``renders/showcase/stick_slip.gif``: a copy of the ``run.gif`` the job wrote (the README's animation).

``tests/test_showcase.py`` holds the three to one another and renders the animation again from the
job's own function (``stick_slip_run`` of ``scenes/quickstart.py``) to compare it frame by frame.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
OUTPUT = ROOT / "docs" / "data" / "main_job_output.txt"
README = ROOT / "README.md"
GIF = ROOT / "renders" / "showcase" / "stick_slip.gif"
JOB_GIF = ROOT / "renders" / "quickstart" / "run.gif"
#: what the checkout's own path is shown as (it is wherever a reader cloned)
PLACEHOLDER = "/path/to/asperity2d"
#: the job's first printed line starts so; the README's block of its output is found by it
FIRST_LINE = "stick-slip run on Ooten's set-up"


def run_main_job() -> str:
    """Run ``python scenes/quickstart.py`` from the repository root; return what it printed (stdout),
    with the checkout's path shown as :data:`PLACEHOLDER`."""
    env = {**os.environ, "TQDM_DISABLE": "1"}
    env.pop("ASPERITY2D_RENDERS", None)  # the job's own default folder: renders/quickstart
    done = subprocess.run([sys.executable, "scenes/quickstart.py"], cwd=ROOT, env=env, capture_output=True,
                          text=True, check=False)
    if done.returncode != 0:
        sys.exit(f"the main job failed (exit {done.returncode}):\n{done.stderr[-4000:]}")
    return done.stdout.replace(str(ROOT), PLACEHOLDER)


def readme_block(text: str) -> tuple[int, int]:
    """(start, end) character offsets of the README's ``text`` block of the main job's output (its
    content, without the fences); ValueError if there is none."""
    fence = "```text\n" + FIRST_LINE
    start = text.find(fence)
    if start < 0:
        raise ValueError(f"README.md has no ```text block starting with {FIRST_LINE!r}")
    start += len("```text\n")
    end = text.find("```", start)
    if end < 0:
        raise ValueError("README.md: the main job's ```text block is not closed")
    return start, end


def with_output(readme: str, output: str) -> str:
    """``readme`` with its block of the main job's output replaced by ``output``."""
    start, end = readme_block(readme)
    return readme[:start] + output.rstrip("\n") + "\n" + readme[end:]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true",
                        help="compare the committed copies with one another instead of running the job")
    args = parser.parse_args(argv)
    if args.check:
        readme = README.read_text(encoding="utf-8")
        start, end = readme_block(readme)
        if readme[start:end] != OUTPUT.read_text(encoding="utf-8"):
            print(f"README.md's block of the main job's output differs from {OUTPUT.relative_to(ROOT)}; "
                  "run: python tools/showcase.py")
            return 1
        print("README.md and docs/data/main_job_output.txt agree")
        return 0
    output = run_main_job()
    OUTPUT.parent.mkdir(parents=True, exist_ok=True)
    OUTPUT.write_text(output, encoding="utf-8")
    README.write_text(with_output(README.read_text(encoding="utf-8"), output), encoding="utf-8")
    GIF.parent.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(JOB_GIF, GIF)
    print(output, end="")
    print(f"wrote {OUTPUT.relative_to(ROOT)}, README.md's block and {GIF.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
