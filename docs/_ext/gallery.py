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
#: Where the scripts write during the build (outside the source tree's committed files).
OUTPUTS = DOCS / "_build" / "scene_outputs"
#: File kinds shown as images, and offered as downloads.
IMAGES = (".gif", ".png", ".svg")
DOWNLOADS = (".html", ".wav")
#: Scripts whose quick run writes no plots unless asked (the belt chain studies of the multi-DOF
#: belt thesis: their tests run without plots).
WANTS_PLOTS = ("belt_2dof", "belt_3dof", "belt_parameters", "belt_damping", "belt_friction",
               "belt_mass", "belt_speed", "belt_stiffness", "belt_regime_map")


def output_dir(src_file) -> Path:
    """The directory the gallery run of ``src_file`` writes to."""
    return OUTPUTS / Path(src_file).stem


def arguments(gallery_conf, script_vars) -> list[str]:
    """``sys.argv[1:]`` for a scene script: quick settings, its own output directory.

    sphinx-gallery does not define ``__file__`` for an example; the scripts use it to find their
    data and default output folder, so it is set here (the example's globals exist by now).
    """
    src = Path(script_vars["src_file"])
    script_vars["example_globals"]["__file__"] = str(src)
    text = src.read_text(encoding="utf-8")
    argv = ["--quick", "-o", str(output_dir(src))]
    if "--workers" in text or "study_args(" in text:
        argv += ["--workers", "1"]
    if src.stem in WANTS_PLOTS:
        argv.append("--plots")
    return argv


def reset(gallery_conf, fname, when=None) -> None:
    """Before each script: an empty output directory, no open matplotlib figures."""
    import matplotlib.pyplot as plt

    plt.close("all")
    if when in (None, "before"):
        out = output_dir(fname)
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
    from sphinx_gallery.scrapers import figure_rst

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
    """The claim records the script wrote (its summary.json, or a belt study's <name>.json)."""
    import json

    paths = [out / "summary.json"] if (out / "summary.json").exists() else sorted(out.glob("*.json"))
    found = []
    for path in paths:
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
