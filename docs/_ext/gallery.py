"""The gallery of scene scripts: how sphinx-gallery runs them and what it shows of them.

Every script in ``scenes/`` is a plain runnable script with ``main(argv)``; the gallery runs it
as ``python scenes/X.py --quick -o DIR`` (the settings its tests use, so the build fits CI) and
shows what it wrote to ``DIR``: GIFs (animated) and plots as images, the interactive player
(``.html``) and sounds (``.wav``) as downloads. Scripts that run ensembles get ``--workers 1``:
sphinx-gallery runs them in a stand-in ``__main__`` module whose functions worker processes
cannot import (the gallery runs two scripts at a time instead).

These are module-level functions so sphinx-gallery's parallel runner can pickle them.
"""

from __future__ import annotations

import shutil
from pathlib import Path

DOCS = Path(__file__).resolve().parent.parent
#: File kinds shown as images, and offered as downloads.
IMAGES = (".gif", ".png", ".svg")
DOWNLOADS = (".html", ".wav")
#: Scripts whose quick run writes no plots unless asked (the belt chain studies of the multi-DOF
#: belt thesis: their tests run without plots).
WANTS_PLOTS = ("belt_2dof", "belt_3dof", "belt_parameters", "belt_damping", "belt_friction",
               "belt_mass", "belt_speed", "belt_stiffness", "belt_regime_map")


#: The gallery's sections, in order: (folder, title, what the section teaches, its scripts in
#: reading order). Every script in ``scenes/`` is in exactly one (tests/test_gallery_sections.py).
SECTIONS = (
    ("getting_started", "Getting started",
     "Start here: the main job (a stick-slip run, then regular against random spacing over seeds), "
     "a spring drive's stick-slip cycles and a constant force's stop-or-run.",
     ("quickstart", "stick_slip", "constant_force")),
    ("ooten", "Ooten's thesis",
     "The senior thesis of E. Ooten, *Precision Motion Control at Low Velocities in the Presence "
     "of Friction* (Texas A&M University, 1997-98): each of its comparisons, then what lies beyond it "
     "(steel micro-asperities, the MATLAB lattice, a virtual tribometer and the friction law it finds, "
     "the spacing verdict under other contact laws).",
     ("ooten_spacing", "ooten_profiles", "ooten_damping", "ooten_drive", "ooten_stickslip",
      "micro_spacing", "steel_table1", "matlab_lattice", "tribometer", "stick_slip_law",
      "contact_laws_spacing")),
    ("belt", "The belt thesis",
     "*Vibration Analysis of Multi Degree of Freedom Self-excited Systems*: masses on a moving belt, "
     "solved exactly event by event; its two- and three-mass chains, its parameter tables, and "
     "contacts that open.",
     ("belt_2dof", "belt_3dof", "belt_parameters", "belt_stiffness", "belt_damping", "belt_mass",
      "belt_speed", "belt_friction", "belt_contact")),
    ("rough", "Rough surfaces",
     "Beyond both theses: surfaces whose asperities differ, from a measured-style profile, a spread "
     "of heights or a self-affine surface of given Hurst exponent.",
     ("profile_asperities", "rough_measured", "rough_height_spread", "rough_hurst",
      "rough_contact_fraction")),
    ("dynamics", "Dynamics",
     "Spectra, regime maps and basins of attraction: what kind of motion a system settles into.",
     ("belt_regime_map", "belt_spectra", "belt_basins", "asperity_spectrum")),
)
#: Where the sectioned copy of ``scenes/`` is laid out for sphinx-gallery (sections are folders).
STAGED = DOCS / "_build" / "gallery_src"
SCENES = DOCS.parent / "scenes"

#: The first cell of every downloaded notebook. The scripts read their options from the command
#: line (a kernel's own ``-f`` would be refused) and find their data beside ``__file__``;
#: ``SCRIPT`` becomes the script's name (:func:`notebook_first_cells`).
FIRST_NOTEBOOK_CELL = (
    "# Runs from any folder. A lesson that reads data (scenes/data/) or a sibling script runs from\n"
    "# the scenes/ folder of an asperity2d source archive or checkout (How-tos: Get the code).\n"
    "# Its options, as on its command line: the quick settings\n"
    "# the documentation ran (drop \"--quick\" for the full study), outputs written to ./outputs.\n"
    "import sys\n"
    "from pathlib import Path\n"
    "\n"
    "sys.argv = [\"SCRIPT.py\", \"--quick\", \"-o\", \"outputs\"]\n"
    "__file__ = str(Path(\"SCRIPT.py\").resolve())"
)


def first_cell(name: str) -> str:
    """The first notebook cell of scene script ``name``."""
    return FIRST_NOTEBOOK_CELL.replace("SCRIPT", name)


def stage() -> Path:
    """Lay ``scenes/`` out as the gallery's sections under :data:`STAGED` (files are rewritten only
    when they change, so sphinx-gallery re-runs only what changed); return the folder."""
    STAGED.mkdir(parents=True, exist_ok=True)

    def put(path: Path, text: str) -> None:
        path.parent.mkdir(parents=True, exist_ok=True)
        if not path.exists() or path.read_text(encoding="utf-8") != text:
            path.write_text(text, encoding="utf-8")

    put(STAGED / "GALLERY_HEADER.rst", (SCENES / "GALLERY_HEADER.rst").read_text(encoding="utf-8"))
    for folder, title, blurb, names in SECTIONS:
        put(STAGED / folder / "GALLERY_HEADER.rst", f"{title}\n{'-' * len(title)}\n\n{blurb}\n")
        for name in names:
            put(STAGED / folder / f"{name}.py", (SCENES / f"{name}.py").read_text(encoding="utf-8"))
    return STAGED


def subsection_order() -> list[str]:
    """The sections' folders in :data:`SECTIONS`' order, relative to ``docs/`` as sphinx-gallery's
    explicit order wants them."""
    return [(STAGED / folder).relative_to(DOCS).as_posix() for folder, *_ in SECTIONS]


class ScriptOrder:
    """Sort key of the scripts within a section: :data:`SECTIONS`' reading order."""

    def __init__(self, src_dir):
        self.src_dir = src_dir

    def __call__(self, filename: str) -> int:
        order = [name for *_, names in SECTIONS for name in names]
        stem = Path(filename).stem
        return order.index(stem) if stem in order else len(order)

    def __repr__(self) -> str:  # sphinx-gallery hashes the configuration by repr
        return "ScriptOrder"


def output_dir(src_file) -> Path:
    """The directory the gallery run of ``src_file`` writes to: beside the staged copy it runs
    as, named after it, so the script is given a relative ``-o`` (sphinx-gallery runs each
    script in its own folder) and what it prints names no folder of the build machine."""
    return Path(src_file).parent / Path(src_file).stem


def arguments(gallery_conf, script_vars) -> list[str]:
    """``sys.argv[1:]`` for a scene script: quick settings, its own output directory.

    sphinx-gallery does not define ``__file__`` for an example; the scripts use it to find their
    data and default output folder, so it is set here (the example's globals exist by now).
    """
    src = Path(script_vars["src_file"])
    if not (SCENES / src.name).exists():  # the tutorial: no scene options
        return []
    script_vars["example_globals"]["__file__"] = str(SCENES / src.name)  # its data are there
    text = src.read_text(encoding="utf-8")
    argv = ["--quick", "-o", output_dir(src).name]
    if "--workers" in text or "study_args(" in text:
        argv += ["--workers", "1"]
    if src.stem in WANTS_PLOTS:
        argv.append("--plots")
    return argv


def quiet_progress_bars() -> None:
    """No tqdm progress bar in the pages: the scripts ask for bars (``progress=True``), which
    ``TQDM_DISABLE`` does not override, and sphinx-gallery would show them as output."""
    import tqdm

    if getattr(tqdm.tqdm.__init__, "_asperity2d_quiet", False):
        return
    original = tqdm.tqdm.__init__

    def init(self, *args, **kwargs):
        kwargs["disable"] = True
        original(self, *args, **kwargs)

    init._asperity2d_quiet = True
    tqdm.tqdm.__init__ = init


def reset(gallery_conf, fname, when=None) -> None:
    """Before each script: an empty output directory, no open matplotlib figures, no progress
    bars (in the process that runs it)."""
    import matplotlib.pyplot as plt

    quiet_progress_bars()
    plt.close("all")
    stem = Path(fname).stem  # sphinx-gallery passes the script's file name only
    folder = next((folder for folder, *_, names in SECTIONS if stem in names), None)
    if folder is not None and when in (None, "before"):
        out = output_dir(STAGED / folder / f"{stem}.py")
        shutil.rmtree(out, ignore_errors=True)
        out.mkdir(parents=True, exist_ok=True)
        _SEEN.pop(str(out), None)
        _SEEN.pop(str(out) + "#claims", None)


_SEEN: dict[str, set[str]] = {}


def _outputs(out: Path) -> list[Path]:
    """The files a script wrote, GIFs first, then in the order written; sweep stores skipped."""
    files = [p for p in out.rglob("*") if p.is_file() and p.suffix.lower() in IMAGES + DOWNLOADS
             and not any(part.endswith(".runs") for part in p.relative_to(out).parts)]
    return sorted(files, key=lambda p: (p.suffix.lower() != ".gif", p.stat().st_mtime_ns, p.name))


def scene_outputs(block, block_vars, gallery_conf) -> str:
    """Image scraper: the pictures and files the script wrote since the last call, as reST."""
    from sphinx_gallery.scrapers import figure_rst, matplotlib_scraper

    if not (SCENES / Path(block_vars["src_file"]).name).exists():  # the tutorial: its figures
        return matplotlib_scraper(block, block_vars, gallery_conf)
    out = output_dir(block_vars["src_file"])
    seen = _SEEN.setdefault(str(out), set())
    new = [p for p in _outputs(out) if str(p) not in seen]
    seen.update(str(p) for p in new)
    images, downloads = [], []
    paths = block_vars["image_path_iterator"]
    for path in new:
        if path.suffix.lower() in IMAGES:
            target = Path(next(paths)).with_suffix(path.suffix.lower())
            shutil.copyfile(path, target)
            images.append(target)
        else:  # not an image: beside them, without taking a number sphinx-gallery checks for
            target = Path(paths.image_path).with_name(f"sphx_glr_{out.name}_{path.name}")
            shutil.copyfile(path, target)
            downloads.append((path, target))
    rst = ""
    for image in images:  # one figure per output, captioned with the file name the script wrote
        rst += figure_rst([image], gallery_conf["src_dir"], fig_titles=_caption(image, new, images))
    if downloads:
        src_dir = Path(gallery_conf["src_dir"])
        rst += "\n\nAlso written:\n\n" + "".join(
            f"* :download:`{original.name} </{target.relative_to(src_dir).as_posix()}>`"
            f"{' (the interactive player: open it in a browser)' if original.suffix == '.html' else ''}"
            f"{' (a sound: the friction force, heard)' if original.suffix == '.wav' else ''}\n"
            for original, target in downloads) + "\n"
    claims = _claims(out) if not _SEEN.get(str(out) + "#claims") else []
    if claims:
        from asperity_docs import claims_table_lines

        _SEEN[str(out) + "#claims"] = {"shown"}
        rst += ("\n\n.. rubric:: The claims of this quick run\n\n"
                "Few seeds and small scenes: a verdict here is a smoke test, not a result. The "
                "full-size verdicts are in :doc:`/studies/index`.\n\n"
                + "\n".join(claims_table_lines(claims)) + "\n")
    return rst


def _claims(out: Path) -> list[dict]:
    """The claim records the script wrote (its summary.json)."""
    import json

    found = []
    for path in [out / "summary.json"]:
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            continue
        if isinstance(data, dict) and isinstance(data.get("claims"), list):
            found += data["claims"]
    return found


def _caption(image: Path, new: list[Path], images: list[Path]) -> str:
    """The name of the file the script wrote (the alt text of its picture)."""
    originals = [p for p in new if p.suffix.lower() in IMAGES]
    return originals[images.index(image)].name


def notebook_first_cells(app) -> None:
    """Each notebook's first cell made its own: the scene script's name in place of ``SCRIPT``,
    and none for the tutorial (the cell sets a scene script's command-line options). Runs after
    sphinx-gallery has written the notebooks; a notebook already done is left as it is."""
    import json

    src = Path(app.srcdir)
    for path in [*(src / "auto_scenes").rglob("*.ipynb"), *(src / "tutorial").glob("*.ipynb")]:
        notebook = json.loads(path.read_text(encoding="utf-8"))
        cells = notebook.get("cells", [])
        if not cells or "".join(cells[0].get("source", "")).strip() != FIRST_NOTEBOOK_CELL.strip():
            continue
        if path.parent.name == "tutorial":
            notebook["cells"] = cells[1:]
        else:
            cells[0]["source"] = first_cell(path.stem)
        path.write_text(json.dumps(notebook, indent=1, ensure_ascii=False), encoding="utf-8")


def setup(app):
    app.connect("builder-inited", notebook_first_cells, priority=900)  # after sphinx-gallery (500)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
