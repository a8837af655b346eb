"""The tutorial ("Your first study", docs/tutorial_src/first_study.py) runs block by block, in
order, and writes and reads back what it says: the run, the comparison, the plot, the .mat file.

Its downloaded notebook is executed by tests/test_notebooks.py (needs the docs extra)."""

import runpy
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent
TUTORIAL = ROOT / "docs" / "tutorial_src" / "first_study.py"
VERDICTS = ("holds", "no effect", "does not hold", "undecided", "not testable")


def test_tutorial_runs_in_order_and_its_files_read_back(tmp_path, monkeypatch, capsys):
    pytest.importorskip("matplotlib")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.setenv("TQDM_DISABLE", "1")
    names = runpy.run_path(str(TUTORIAL), run_name="__main__")
    import matplotlib.pyplot as plt

    plt.close("all")
    out = capsys.readouterr().out
    verdict = next(line for line in out.splitlines() if line.startswith("Random spacing lowers"))
    assert verdict.split(": ", 1)[1].startswith(VERDICTS), verdict
    # the verdict printed is the rule applied to the numbers printed beside it
    assert (verdict.endswith("holds")) == (names["test"]["p_wilcoxon"] < 0.01
                                            and names["effect"]["ratio"] <= 0.99 and names["n"] >= 7)
    folder = tmp_path / "first_study"
    for name in ("run.npz", "run.mat", "critical.json", "first_study.png"):
        assert (folder / name).stat().st_size > 0, name
    from scipy.io import loadmat

    import asperity2d as a

    again = a.load(folder / "run.npz")
    assert np.array_equal(again.drive_force, names["result"].drive_force)
    assert np.array_equal(loadmat(folder / "run.mat")["drive_force"].ravel(), names["result"].drive_force)
