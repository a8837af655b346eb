"""``asperity2d sweep`` CLI, in-process: run / status / report / export and bad input."""

import csv
import json

import numpy as np
import pytest
from scipy import stats

from asperity2d.sweep import ResultStore
from asperity2d.cli.main import build_parser
from asperity2d.cli import main as cli_main
from asperity2d.cli import sweep as sweep_cli


def main(argv):
    """``asperity2d sweep ARGV``."""
    return cli_main(["sweep", *argv])

STUDY_TOML = """\
name = "cli"
run = "sweep_fixtures:flaky_run"
seeds = 5
[grid]
amplitude = [1.0, 2.0]
label = ["a"]
"""


@pytest.fixture
def store_dir(tmp_path, capsys):
    study = tmp_path / "study.toml"
    study.write_text(STUDY_TOML)
    store = tmp_path / "store"
    assert main(["run", str(study), "--store", str(store), "--workers", "1", "--no-progress",
                 "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert (summary["done"], summary["failed"], summary["pending"], summary["ran"]) == (10, 0, 0, 10)
    return store


def test_status_json(store_dir, capsys):
    assert main(["status", str(store_dir), "--json"]) == 0
    status = json.loads(capsys.readouterr().out)
    assert status["study"] == "cli"
    assert {k: status[k] for k in ("done", "failed", "pending", "total")} == {
        "done": 10, "failed": 0, "pending": 0, "total": 10}
    store = ResultStore(store_dir)
    store.run_path(next(iter(store.stored_keys()))).write_text("{")  # half-written
    assert main(["status", str(store_dir), "--json"]) == 0
    out, err = capsys.readouterr()
    assert (json.loads(out)["pending"], json.loads(out)["corrupt"]) == (1, 1)
    assert err.count("\n") == 1 and "warning" in err and "corrupt" in err


def test_export_csv_and_npy(store_dir, tmp_path, capsys):
    assert main(["export", str(store_dir), "-o", str(tmp_path / "runs.csv")]) == 0
    rows = list(csv.DictReader((tmp_path / "runs.csv").open()))
    table = ResultStore(store_dir).table()
    assert len(rows) == 10 and [r["key"] for r in rows] == list(table["key"])
    assert [float(r["peak"]) for r in rows] == list(table["peak"])
    assert main(["export", str(store_dir), "-o", str(tmp_path / "runs.npy")]) == 0
    loaded = np.load(tmp_path / "runs.npy")
    assert loaded.dtype == table.dtype and (loaded == table).all()


def test_report_json_stats_and_figure(store_dir, tmp_path, capsys):
    figure = tmp_path / "summary.png"
    assert main(["report", str(store_dir), "-o", str(figure), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and report["figure"] == str(figure)
    table = ResultStore(store_dir).table()
    peaks = {a: table["peak"][table["amplitude"] == a] for a in (1.0, 2.0)}
    (v1, v2) = report["variants"]
    assert v1["params"] == {"amplitude": 1.0, "label": "a"} and v1["done"] == 5
    assert v1["quantities"]["peak"]["mean"] == pytest.approx(peaks[1.0].mean(), rel=1e-12)
    (cmp_peak,) = [c for c in report["comparisons"] if c["quantity"] == "peak"]
    ref = stats.mannwhitneyu(peaks[1.0], peaks[2.0], alternative="two-sided")
    assert cmp_peak["parameter"] == "amplitude" and cmp_peak["n_a"] == cmp_peak["n_b"] == 5
    assert cmp_peak["p_value"] == pytest.approx(ref.pvalue)
    assert main(["report", str(store_dir)]) == 0  # text form, default figure path
    assert "Mann-Whitney U test p = " in capsys.readouterr().out
    assert (store_dir / "summary.png").is_file()


@pytest.mark.parametrize(
    "argv, needle",
    [
        (["status", "{tmp}/nowhere", "--json"], "`store` does not exist"),
        (["report", "{tmp}", "--json"], "`store` is not a sweep store"),
        (["export", "{store}", "-o", "{tmp}/x.xlsx"], "`--output` must end in .csv, .npy"),
        (["report", "{store}", "-o", "{tmp}/x.gif"], "`--output` must end in .png"),
        (["run", "{tmp}/missing.toml", "--store", "{tmp}/s"], "`study` does not exist"),
        (["run", "{study}", "--store", "{tmp}/s", "--workers", "0"], "argument --workers: must be"),
        (["run", "{study}", "--store", "{tmp}/s", "--workers", "x"], "argument --workers: must be"),
        (["run", "{study}", "--store", "{store}", "--scheduler", "tcp://h:1", "--workers", "2"],
         "`workers` applies only"),
        # refused up front, before Dask is imported (it used to print a traceback, then hang ~60 s)
        (["run", "{study}", "--store", "{tmp}/s", "--scheduler", "notaurl"],
         "`scheduler` must be 'local' or a Dask scheduler address like tcp://host:8786, got 'notaurl'"),
        (["run", "{study}", "--store", "{tmp}/s", "--scheduler", "tcp://host"], "`scheduler` must be 'local'"),
        (["frobnicate"], "invalid choice"),
    ],
)
def test_bad_input_one_line_exit_2(store_dir, tmp_path, capsys, argv, needle):
    bad_study = tmp_path / "bad.toml"
    bad_study.write_text('name = "cli"\nrun = "sweep_fixtures:flaky_run"\nseeds = 1\n')
    fill = {"tmp": str(tmp_path), "store": str(store_dir), "study": str(bad_study)}
    assert main([a.format(**fill) for a in argv]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and needle in err and "Traceback" not in err


def test_the_top_level_cli_runs_sweep_through_its_handler(store_dir, capsys):
    args = build_parser().parse_args(["sweep", "status", str(store_dir), "--json"])
    assert args.handler is sweep_cli.run
    assert sweep_cli.run(args) == 0
    top = json.loads(capsys.readouterr().out)
    assert top["done"] == 10
