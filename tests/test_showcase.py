"""What the README and the docs show of the main job is what the main job makes (``tools/showcase.py``).

The printed output is stored once, in ``docs/data/main_job_output.txt`` (written by the job's run
through the tool), included by ``docs/getting_started.md`` and held equal to the README's block
here. The README's animation is rendered again from the job's own function and compared frame by
frame (slow: the job's full-size stick-slip run, ~40 s; CI's ``.ci/run`` runs it with the notebooks).
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent


def _load(path: Path, name: str):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


showcase = _load(ROOT / "tools" / "showcase.py", "showcase_tool")


def test_the_readme_shows_the_stored_output_of_the_main_job():
    readme = showcase.README.read_text(encoding="utf-8")
    start, end = showcase.readme_block(readme)
    stored = showcase.OUTPUT.read_text(encoding="utf-8")
    assert readme[start:end] == stored, "run: python tools/showcase.py"
    assert stored.startswith(showcase.FIRST_LINE) and stored.rstrip().splitlines()[-1].startswith("outputs in ")


def test_getting_started_includes_the_stored_output_and_pastes_none():
    page = (ROOT / "docs" / "getting_started.md").read_text(encoding="utf-8")
    assert "```{literalinclude} data/main_job_output.txt" in page
    assert showcase.FIRST_LINE not in page  # no pasted copy left to drift


def test_the_readme_block_is_replaced_in_place():
    readme = "intro\n\n```text\n" + showcase.FIRST_LINE + " old\nold line\n```\n\nafter\n```text\nother\n```\n"
    new = showcase.with_output(readme, showcase.FIRST_LINE + " new\nnew line\n")
    assert new == "intro\n\n```text\n" + showcase.FIRST_LINE + " new\nnew line\n```\n\nafter\n```text\nother\n```\n"
    with pytest.raises(ValueError, match="no ```text block"):
        showcase.readme_block("no block here")


@pytest.mark.slow
def test_the_readme_animation_is_what_the_main_job_renders_now(tmp_path):
    """Same seed, same parameters, same bits: the job's stick-slip run rendered with its 120 frames
    must decode to the committed GIF's frames exactly."""
    from PIL import Image, ImageSequence

    quickstart = _load(ROOT / "scenes" / "quickstart.py", "quickstart_for_showcase")
    quickstart.stick_slip_run(tmp_path, {}, 120, progress=False)

    def frames(path):
        with Image.open(path) as im:
            return [np.asarray(f.convert("RGB")) for f in ImageSequence.Iterator(im)]

    fresh, committed = frames(tmp_path / "run.gif"), frames(showcase.GIF)
    assert len(fresh) == len(committed) == 120
    differ = [j for j, (a, b) in enumerate(zip(fresh, committed)) if not np.array_equal(a, b)]
    assert not differ, f"{len(differ)} frames differ (first {differ[0]}): run python tools/showcase.py"
