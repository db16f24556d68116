"""``peridynamics band``: percentiles of a history curve over run folders (made here by
hand: history.csv and summary.json), the common and the extended range, the files and
bad input (exit 2)."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from peridynamics.app.prediction_band import band, run_folders
from peridynamics.cli import main


def _runs(root, slopes, ends, status="completed"):
    for k, (a, end) in enumerate(zip(slopes, ends, strict=True)):
        folder = root / f"seed_{k}"
        folder.mkdir(parents=True)
        x = np.linspace(0.0, end, 11)
        rows = ["time [s],strain [-],stress [Pa]"]
        rows += [f"{i},{float(xi)!r},{float(a * xi)!r}" for i, xi in enumerate(x)]
        (folder / "history.csv").write_text("\n".join(rows) + "\n")
        (folder / "summary.json").write_text(json.dumps({"status": status}))


def test_percentiles_of_linear_curves(tmp_path, capsys):
    slopes = [1.0, 2.0, 3.0, 4.0, 5.0]
    _runs(tmp_path, slopes, [1.0, 1.0, 1.0, 1.0, 2.0])
    _runs(tmp_path / "failed", [9.0], [1.0], status="unstable")
    assert len(run_folders(tmp_path)) == 5
    assert main(["band", str(tmp_path), "--x", "strain", "--y", "stress", "--points", "5",
                 "--quiet"]) == 0  # fmt: skip
    with (tmp_path / "band.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 5 and float(rows[-1]["x (strain)"]) == 1.0  # the common range
    x = float(rows[2]["x (strain)"])
    for q in (5, 50, 95):
        assert float(rows[2][f"p{q}"]) == pytest.approx(np.percentile(slopes, q) * x)
    info = json.loads((tmp_path / "band.json").read_text())
    assert info["n_runs"] == 5 and (tmp_path / "band.png").is_file()


def test_extended_range_counts_the_runs_that_reach():
    c1 = (np.array([0.0, 1.0]), np.array([0.0, 1.0]))
    c2 = (np.array([0.0, 2.0]), np.array([0.0, 4.0]))
    res = band([c1, c2], points=3, extend=True)
    assert res["x"].tolist() == [0.0, 1.0, 2.0]
    assert res["count"].tolist() == [2, 2, 1] and res["p50"][-1] == pytest.approx(4.0)


def test_bad_input_exits_2(tmp_path, capsys):
    assert main(["band", str(tmp_path / "none"), "--x", "a", "--y", "b"]) == 2
    assert "no folder" in capsys.readouterr().err
    _runs(tmp_path, [1.0], [1.0])
    assert main(["band", str(tmp_path), "--x", "strain", "--y", "sress"]) == 2
    assert "no column 'sress'" in capsys.readouterr().err
