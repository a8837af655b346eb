"""The documentation's gallery: every scene script sits in exactly one section, and the
quickstart opens the first one (docs/_ext/gallery.py's SECTIONS)."""

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def sections():
    spec = importlib.util.spec_from_file_location("docs_gallery", ROOT / "docs" / "_ext" / "gallery.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.SECTIONS


def test_every_scene_script_is_in_exactly_one_section():
    listed = [name for *_, names in sections() for name in names]
    scripts = sorted(p.stem for p in (ROOT / "scenes").glob("*.py"))
    assert sorted(listed) == scripts, (sorted(set(scripts) - set(listed)), sorted(set(listed) - set(scripts)))
    assert len(listed) == len(set(listed))


def test_the_quickstart_comes_first():
    folder, title, _, names = sections()[0]
    assert (folder, title, names[0]) == ("getting_started", "Getting started", "quickstart")
