"""The issue-15 scene scripts run on their quick settings and write what they promise.

Cost: about 10 s in the default run (belt_basins and belt_spectra, --quick, in-process);
asperity_spectrum --quick (pymunk runs) is marked slow.
"""

from pathlib import Path

import pytest
from scipy.io import wavfile

from scene_scripts import run_script


def check_wav(path):
    rate, data = wavfile.read(path)
    assert rate == 44_100 and data.size > 1000
    assert Path(path).with_name(Path(path).stem + ".spectrogram.png").exists()


def test_belt_basins_script(tmp_path, capsys):
    s = run_script("belt_basins", tmp_path, capsys, "--workers", "1")
    assert s["base"]["shape"] == [3, 3] and sum(s["base"]["counts"].values()) == 9
    assert (tmp_path / "basins_base.png").stat().st_size > 0
    fl = s["floquet_contrast_eq312"]
    assert fl["multiplicity"] >= 1 and abs(fl["trivial"][0] - 1) < 1e-6  # the orbit's own direction
    check_wav(s["sound"]["path"])


def test_belt_spectra_script(tmp_path, capsys):
    s = run_script("belt_spectra", tmp_path, capsys)
    rows = s["chains"]["base"]
    assert [r["v_belt"] for r in rows] == [0.1, 0.7]
    # the undamped chain's lowest normal mode, sqrt(k (2 - sqrt 2) / m) / 2π, leads its steady spectrum
    assert rows[-1]["steady"]["dominant_hz"] == pytest.approx(s["modes_hz"][0],
                                                              abs=rows[-1]["steady"]["resolution_hz"])
    for sound in s["sounds"].values():
        check_wav(sound["path"])


@pytest.mark.slow  # pymunk runs: about 15 s of CPU
def test_asperity_spectrum_script(tmp_path, capsys):
    s = run_script("asperity_spectrum", tmp_path, capsys, "--workers", "1")
    assert set(s["runs"]) == {"regular_stiff", "random_stiff"}
    assert len(s["preload_scan"]["classes"]) == 2
    check_wav(s["sound"]["path"])
