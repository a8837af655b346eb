"""Belt chains run through the same sweep machinery as asperity scenes."""

import numpy as np

from asperity2d.sweep import ResultStore, Study, run_study


def test_belt_chain_study_runs_through_the_sweep(tmp_path):
    study = Study(name="belt", run="asperity2d.studies.mdof_belt:belt_chain_run",
                  grid={"v_belt": [0.1, 0.7]}, seeds=range(2),
                  fixed={"preset_name": "table2-3dof", "ic_spread": 0.02})
    summary = run_study(study, store=tmp_path / "store", workers=1, progress=False)
    assert summary.done == 4 and summary.failed == 0
    table = ResultStore(tmp_path / "store").table()
    assert (table["energy_balance_error"] < 1e-8).all()
    slow, fast = table[table["v_belt"] == 0.1], table[table["v_belt"] == 0.7]
    # the multi-DOF belt thesis: a faster belt sticks less and swings wider
    assert fast["total_stick_s"].mean() < slow["total_stick_s"].mean()
    assert fast["amplitude_m"].mean() > slow["amplitude_m"].mean()
    # seeds perturb the initial conditions: different seeds, different runs
    assert slow["amplitude_m"][0] != slow["amplitude_m"][1]
    again = run_study(study, store=tmp_path / "store", workers=1, progress=False)
    assert again.ran == 0  # everything was already finished
    np.testing.assert_array_equal(ResultStore(tmp_path / "store").table()["amplitude_m"], table["amplitude_m"])
