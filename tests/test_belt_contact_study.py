"""scenes/belt_contact.py --quick: contacts that open, the minimal model's regimes and squeal (issue 26).

The script's claims are judged inside it against criteria fixed in its code; here the quick run must
produce them with the numbers that decide them, and those numbers must be the closed forms'."""

import math

import numpy as np
import pytest
from scipy.io import wavfile

from scene_scripts import run_script

from asperity2d.belt.contact.minimal import MinimalModel


def test_belt_contact_script_quick(tmp_path, capsys):
    s = run_script("belt_contact", tmp_path, capsys)
    mm = MinimalModel(eta=300.0)
    assert s["model"]["mu_crit_damped"] == pytest.approx(mm.mu_crit_damped(), rel=1e-12)
    verdicts = {c["claim"]: c["verdict"] for c in s["claims"]}
    assert len(verdicts) == 6 and set(verdicts.values()) <= {"holds", "does not hold"}
    # the regime map: every grid point classified, steady sliding exactly on the stable side of the closed form
    rm = s["regime_map"]
    assert sum(rm["counts"].values()) == len(rm["mu"]) * len(rm["v_belt_m_s"]) and rm["counts"]["failed"] == 0
    for mu, row in zip(rm["mu"], rm["labels"]):
        assert all(label == "steady sliding" for label in row) == (mu < mm.mu_crit_damped())
    # the squeal: a separation cycle whose Floquet product is Liouville's, heard in real time
    cyc = s["separation_cycle"]
    assert cyc["periodic"] and cyc["energy_balance_error"] <= 1e-9
    fl = cyc["floquet"]
    assert fl["product"] == pytest.approx(math.exp(-2 * 300.0 * cyc["period_s"]), rel=1e-6)
    rate, pcm = wavfile.read(tmp_path / "minimal_squeal.wav")
    assert rate == 44_100 and pcm.dtype == np.int16 and pcm.size == s["sounds"]["squeal"]["samples"]
    assert s["sounds"]["squeal"]["time_scale"] == 1.0
    # what is heard (the normal acceleration) peaks at the cycle's fundamental, 1/T
    assert s["spectra"]["squeal"]["dominant_hz"] == pytest.approx(cyc["frequency_hz"], rel=0.02)
    # the three-state table: fractions of each row add up to one
    for row in s["states_table"]:
        assert row["separated"] + row["sliding"] + row["sticking"] == pytest.approx(1.0, abs=1e-12)
    assert s["without_coupling"]["openings"] == 0
