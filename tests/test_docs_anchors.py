"""Every in-site link of the built documentation lands on an anchor that exists.

A link ``page.html#anchor`` whose page has no element with ``id="anchor"`` drops the reader at
the top of the page (links to ``#module-asperity2d.experiments.measures`` did, on pages whose
module is documented without its module anchor). This reads the built site
(``ASPERITY2D_DOCS_HTML``, default ``docs/_build/html``) and names each broken link; it skips,
saying so, when no site has been built (CI runs it right after the Sphinx build).
"""

from __future__ import annotations

import os
import re
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urldefrag

import pytest

ROOT = Path(__file__).resolve().parent.parent
SITE = Path(os.environ.get("ASPERITY2D_DOCS_HTML", ROOT / "docs" / "_build" / "html"))


class _Page(HTMLParser):
    def __init__(self):
        super().__init__()
        self.ids, self.links = set(), []

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if attrs.get("id"):
            self.ids.add(attrs["id"])
        if tag == "a" and attrs.get("name"):
            self.ids.add(attrs["name"])
        if tag == "a" and attrs.get("href"):
            self.links.append(attrs["href"])


def _parse(path: Path) -> _Page:
    page = _Page()
    page.feed(path.read_text(encoding="utf-8", errors="replace"))
    return page


@pytest.mark.skipif(not (SITE / "index.html").exists(), reason=f"no built site at {SITE} (build the docs first)")
def test_in_site_links_land_on_existing_anchors():
    pages = {p: _parse(p) for p in SITE.rglob("*.html") if "_static" not in p.parts and "_sources" not in p.parts}
    # (the highlighted source pages, _modules/, are link targets but not checked as sources: their
    # "[docs]" links back name a re-exported object by its public name, asperity2d.Scene, on the page
    # of asperity2d.scene.Scene; they land on the right page, at its top)
    broken = []
    for path, page in pages.items():
        if "_modules" in path.relative_to(SITE).parts:
            continue
        for href in page.links:
            if re.match(r"^[a-z]+:", href):  # http:, mailto:, ... : not ours
                continue
            target, anchor = urldefrag(href)
            if not anchor:
                continue
            file = (path.parent / unquote(target)).resolve() if target else path
            if file.suffix != ".html" or file not in pages:
                continue
            if unquote(anchor) not in pages[file].ids:
                broken.append(f"{path.relative_to(SITE)}: {href}")
    assert not broken, f"{len(broken)} links to missing anchors:\n" + "\n".join(sorted(set(broken))[:60])
