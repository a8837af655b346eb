"""Sphinx configuration of the asperity2d documentation.

Build (nitpicky, warnings are errors; the gallery runs every scene script in its quick setting)::

    pip install -e ".[docs]"
    python -m sphinx -n -W --keep-going -b html docs docs/_build/html

Offline: intersphinx reads the inventories in ``docs/_inv/`` (made from the installed packages by
``docs/_inv/make_inventories.py``, since the build has no network), and the math is typeset by a
MathJax copied into the site (``sphinx-mathjax-offline``).

``ASPERITY2D_DOCS_GALLERY=0`` skips running the scene scripts (the gallery pages then show the
code without outputs): for fast edits of the prose only.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(DOCS / "_ext"))
# The scene scripts' progress bars (tqdm, on stderr) would fill the gallery's captured output:
# off for the build and the processes it starts (the printed summaries stay).
os.environ["TQDM_DISABLE"] = "1"

import asperity2d  # noqa: E402
import asperity_docs  # noqa: E402  (docs/_ext/asperity_docs.py: generated tables and API pages)
import gallery  # noqa: E402  (docs/_ext/gallery.py: arguments and output scraper of the scenes)

project = "asperity2d"
author = "the asperity2d developers"
copyright = "the asperity2d developers, MIT licence"  # noqa: A001 - Sphinx's name
version = release = asperity2d.__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.intersphinx",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",  # a [source] link beside every documented name, to its highlighted module
    "sphinx-mathjax-offline",  # MathJax served from the site's _static/, not a CDN
    "numpydoc",
    "myst_parser",
    "sphinx_design",
    "sphinx_gallery.gen_gallery",
    "asperity_docs",  # docs/_ext/asperity_docs.py: the generated tables
    "gallery",  # docs/_ext/gallery.py: each notebook's first cell (a scene script's options)
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "data/README.md", "auto_scenes/*.ipynb", "auto_scenes/*.py",
                    "auto_scenes/*.zip", "auto_scenes/*.json", "auto_scenes/*.md5",
                    "auto_scenes/**/*.ipynb", "auto_scenes/**/*.py", "auto_scenes/**/*.zip",
                    "auto_scenes/**/*.json", "auto_scenes/**/*.md5", "tutorial/*.ipynb", "tutorial/*.py",
                    "tutorial/*.zip", "tutorial/*.json", "tutorial/*.md5", "tutorial_src/**"]
myst_enable_extensions = ["colon_fence", "dollarmath", "deflist"]
myst_heading_anchors = 3
suppress_warnings = ["config.cache"]  # sphinx-gallery's callables in the config cannot be pickled

# -- API reference ---------------------------------------------------------------------------
autosummary_generate = True
autosummary_imported_members = True
autodoc_default_options = {"members": True}  # no "Bases:" line: the bases are private mixins
autodoc_typehints = "none"  # numpydoc's parameter sections carry the types
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
templates_path = ["_templates"]  # autosummary: classes without member tables, constants as tables
numpydoc_xref_param_type = True  # the types in Parameters / Returns link (Python, NumPy, ..., ours)
numpydoc_xref_ignore = "all"  # only the names below link: units and words such as "optional" stay text
numpydoc_validation_checks = set()

# The inventories are files in docs/_inv/ (no network at build time); the links go to the sites.
intersphinx_mapping = {
    "python": ("https://docs.python.org/3", "_inv/python.inv"),
    "numpy": ("https://numpy.org/doc/stable", "_inv/numpy.inv"),
    "scipy": ("https://docs.scipy.org/doc/scipy", "_inv/scipy.inv"),
    "matplotlib": ("https://matplotlib.org/stable", "_inv/matplotlib.inv"),
    "pymunk": ("https://www.pymunk.org/en/latest", "_inv/pymunk.inv"),
}
nitpicky = True
nitpick_ignore: list[tuple[str, str]] = []
numpydoc_xref_aliases = asperity_docs.type_aliases()

# -- the gallery of scene scripts ----------------------------------------------------------------
sphinx_gallery_conf = {
    # the scene scripts in sections (copied from scenes/ by gallery.stage()), and the tutorial
    "examples_dirs": [gallery.stage().relative_to(DOCS).as_posix(), "tutorial_src"],
    "gallery_dirs": ["auto_scenes", "tutorial"],
    "subsection_order": gallery.subsection_order(),
    "first_notebook_cell": gallery.FIRST_NOTEBOOK_CELL,
    "filename_pattern": os.environ.get("ASPERITY2D_DOCS_PATTERN", r".*\.py$"),  # every script, not only plot_*.py
    "ignore_pattern": r"(__init__|make_measured_profile)\.py$",  # scenes/data/ builds a data file
    "within_subsection_order": gallery.ScriptOrder,
    "reset_argv": gallery.arguments,
    "image_scrapers": (gallery.scene_outputs,),
    "reset_modules": (gallery.reset,),
    "plot_gallery": os.environ.get("ASPERITY2D_DOCS_GALLERY", "1") != "0",
    "abort_on_example_error": False,
    "only_warn_on_example_error": False,
    "capture_repr": (),
    "download_all_examples": False,
    "show_memory": False,
    "min_reported_time": 1,
    "remove_config_comments": True,
    "matplotlib_animations": False,
    "parallel": int(os.environ.get("ASPERITY2D_DOCS_JOBS", "2")),
}

# -- HTML --------------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"asperity2d {release}"
html_static_path = ["_static"]
html_css_files = ["asperity2d.css"]
html_theme_options = {
    "navbar_align": "left",
    "header_links_before_dropdown": 8,  # the reference, validation and benchmarks in the top bar
    "navbar_persistent": ["search-button"],  # a search icon, not a wide field, so the eight links fit at 1280 px
    "show_toc_level": 2,
    "navigation_with_keys": False,
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version", "theme-version"],
}
html_show_sourcelink = False
# Pages without sub-pages: no left sidebar (it would hold an empty "Section Navigation" column)
html_sidebars = {page: [] for page in ("index", "getting_started", "findings", "validation", "benchmarks", "faq",
                                       "coming_from", "glossary", "changelog", "parameters", "layout")}
html_last_updated_fmt = None


# -- Generated tables ------------------------------------------------------------------------------
def write_events_table(app=None) -> Path:
    """The stick-slip events of the getting-started page's scene (8 lower asperities, 3 tips), as the
    CSV its table shows: made from ``asperity2d.analysis.events_table`` at every build (a few
    seconds), so the table is what the code finds now, in display units."""
    import asperity2d as a
    from asperity2d.analysis import events_table

    table = events_table(a.stick_slip_events(a.simulate(a.make_scene(lower_count=8, upper_count=3),
                                                        progress=False)))
    path = DOCS / "_build" / "generated" / "events_table.csv"
    path.parent.mkdir(parents=True, exist_ok=True)
    rows = ["t_stick (ns),t_slip (ns),force_peak (mN),force_drop (mN),slip_distance (µm),complete"]
    for k in range(len(table["t_slip"])):
        rows.append(f"{table['t_stick'][k] * 1e9:.1f},{table['t_slip'][k] * 1e9:.1f},"
                    f"{table['force_peak'][k] * 1e3:.2f},{table['force_drop'][k] * 1e3:.2f},"
                    f"{table['slip_distance'][k] * 1e6:.2f},{'yes' if table['complete'][k] else 'no'}")
    path.write_text("\n".join(rows) + "\n", encoding="utf-8")
    return path


def setup(app):
    app.connect("builder-inited", write_events_table)
