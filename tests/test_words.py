"""User-facing text names the source studies; "seed" means a random seed only (issue 23).

The two source documents are E. Ooten's thesis and the multi-DOF belt thesis; they were once
called "seed 000" and "seed 001", which a newcomer reads as random seeds 0 and 1.
"""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
OLD_NAMES = re.compile(r"seed[ _-]?00[01]|seed00|SEED_00", re.IGNORECASE)


def user_facing_files():
    yield ROOT / "README.md"
    for folder, patterns in (("docs", ("*.md", "*.rst", "*.py")), ("asperity2d", ("*.py", "*.html", "*.js")),
                             ("scenes", ("*.py", "*.toml", "*.rst"))):
        for pattern in patterns:
            for path in (ROOT / folder).rglob(pattern):
                if not {"_build", "api", "auto_scenes"} & set(path.relative_to(ROOT / folder).parts):
                    yield path


def test_no_user_facing_text_calls_a_source_study_a_seed():
    hits = [f"{path.relative_to(ROOT)}:{i}: {line.strip()}"
            for path in user_facing_files()
            for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
            if OLD_NAMES.search(line)]
    assert not hits, "\n".join(hits)


def test_every_scene_script_names_its_source_in_its_title_block():
    """Each script's docstring opens with a title and, for a study of a source document, names it
    by author or title (the gallery page's header)."""
    for path in sorted((ROOT / "scenes").glob("*.py")):
        doc = path.read_text(encoding="utf-8").split('"""')[1]
        title, underline = doc.splitlines()[:2]
        assert title and set(underline) == {"="} and len(underline) >= len(title), path.name
        if path.stem.startswith(("ooten_", "belt_")):
            assert "Ooten" in doc or "Vibration Analysis of Multi Degree of Freedom" in doc, path.name
