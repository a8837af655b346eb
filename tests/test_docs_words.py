"""The built documentation speaks only the project's words.

A user page must not say "issue 28", quote a commit hash, read like a work diary ("this round")
or point at the developers' tooling (``tools/investigate``): those mean something only to the
people who wrote the page. This test reads the visible text of every HTML page of a built site
(``ASPERITY2D_DOCS_HTML``, default ``docs/_build/html``) and names each page and phrase it finds.

It runs when the site has been built (CI runs it right after the Sphinx build) and skips, saying
why, when it has not.
"""

from __future__ import annotations

import os
import re
from html.parser import HTMLParser
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SITE = Path(os.environ.get("ASPERITY2D_DOCS_HTML", ROOT / "docs" / "_build" / "html"))
#: not user pages: Sphinx's own index and search pages, and the copied sources and assets
SKIP_PARTS = {"_static", "_sources", "_images", "_downloads", "_modules"}  # _modules: highlighted source code (viewcode)
SKIP_NAMES = {"genindex.html", "search.html", "py-modindex.html"}

#: (what it is, pattern) -- case-insensitive
FORBIDDEN = (
    ("an issue number", r"\bissues?\s*#?\d+"),
    ("a commit hash", r"\bcommit\s+`?[0-9a-f]{7,40}\b"),
    # a bare short (7-10 hex digits) or full (40) hash; not a quoted value such as a sweep's
    # 16-digit run key, which is the package's own output
    ("a commit hash", r"(?<![\w./'\"=-])(?=[0-9a-f]*[a-f])(?=[0-9a-f]*[0-9])(?:[0-9a-f]{7,10}|[0-9a-f]{40})"
                      r"(?![\w/'\"-])"),
    ("a work-diary phrase", r"\b(?:this|last|next|previous|the previous) round\b"),
    ("a work-diary phrase", r"\b(?:work diary|TODO|FIXME)\b"),
    ("a tooling path", r"\btools/investigate\b"),
)


class _Text(HTMLParser):
    """The visible text of a page: no tags, no script or style."""

    def __init__(self):
        super().__init__()
        self.parts: list[str] = []
        self._hidden = 0

    def handle_starttag(self, tag, attrs):
        if tag in ("script", "style"):
            self._hidden += 1

    def handle_endtag(self, tag):
        if tag in ("script", "style") and self._hidden:
            self._hidden -= 1

    def handle_data(self, data):
        if not self._hidden:
            self.parts.append(data)


def visible_text(html: str) -> str:
    parser = _Text()
    parser.feed(html)
    return " ".join(" ".join(parser.parts).split())


def findings(text: str) -> list[str]:
    """Every forbidden phrase in ``text``, as "what: 'the phrase in context'"."""
    out = []
    for what, pattern in FORBIDDEN:
        for m in re.finditer(pattern, text, re.I):
            out.append(f"{what}: {text[max(0, m.start() - 40):m.end() + 40]!r}")
    return out


def user_pages() -> list[Path]:
    return sorted(p for p in SITE.rglob("*.html")
                  if not SKIP_PARTS & set(p.relative_to(SITE).parts) and p.name not in SKIP_NAMES)


@pytest.mark.parametrize("text, bad", [
    ("as issue 28 asked", True), ("see Issue #14", True), ("fixed at commit c2009e3", True),
    ("the hash 4f0a9b2 of it", True), ("measured before this round", True), ("tools/investigate/x.py", True),
    ("a critical force of 12.5 mN, 1e-06 m, x0.412 [0.309, 0.515]", False),
    ("RunSpec(key='b0556b2bd3086a4e', variant='regular')", False), ("measured at c2009e3fa1", True),
    ("24 seeds, p 6e-8, 2,409 px, version 0.2.0", False), ("no issues with 4 tips", False),
])
def test_the_patterns_catch_what_they_should(text, bad):
    """The patterns themselves: each kind is caught, and numbers, units and ratios are not."""
    assert bool(findings(text)) is bad, findings(text)


def test_pages_use_only_the_projects_words():
    if not (SITE / "index.html").exists():
        pytest.skip(f"no built documentation at {SITE} (build it: python -m sphinx -n -W --keep-going -b html "
                    "docs docs/_build/html, or set ASPERITY2D_DOCS_HTML)")
    pages = user_pages()
    assert len(pages) > 50, f"only {len(pages)} pages under {SITE}: not a full build"
    bad = {}
    for page in pages:
        found = findings(visible_text(page.read_text(encoding="utf-8")))
        if found:
            bad[str(page.relative_to(SITE))] = found
    assert not bad, "words that are not the project's on user pages:\n" + "\n".join(
        f"  {page}: {'; '.join(found)}" for page, found in bad.items())
