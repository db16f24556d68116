"""Seed 000 Table 1 (issue 4, first part): the seven spalling decks against the paper."""

from __future__ import annotations

import importlib.util
import json

import pytest

from tests.helpers import EXAMPLES, cli

_spec = importlib.util.spec_from_file_location(
    "make_table", EXAMPLES / "spalling" / "make_table.py"
)
make_table = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(make_table)


@pytest.fixture(scope="module")
def rows(tmp_path_factory) -> dict[int, dict]:
    tmp = tmp_path_factory.mktemp("spalling")
    return {n: make_table.run_case(n, tmp / f"case{n}") for n in make_table.PAPER}


@pytest.mark.parametrize("case", range(1, 8))
def test_table1_case_matches_the_paper(rows, case: int) -> None:
    r = rows[case]
    assert r["x_F_ok"], r  # x_F within the paper's range +/- 2 dx
    assert abs(r["t_F_error"]) < 0.01, r  # t_F within 1 % (measured <= 0.14 %)


def test_table1_trends(rows) -> None:
    base, longer, stronger = rows[1], rows[6], rows[7]
    # a longer pulse moves the spall away from the free end (x = 1 m)
    assert max(longer["x_F_m"]) < min(base["x_F_m"])
    # a stronger pulse moves it closer to the free end, and earlier
    assert min(stronger["x_F_m"]) > max(base["x_F_m"])
    assert stronger["t_F_ms"] < base["t_F_ms"]


def test_contract_through_the_cli(tmp_path) -> None:
    out = tmp_path / "c1"
    cli(
        "run",
        str(EXAMPLES / "spalling" / "table1_case1.yaml"),
        "--out",
        str(out),
        "--quiet",
        check=True,
    )
    r = json.loads((out / "summary.json").read_text())["results"]
    assert len(r["fracture_position_m"]) == 2
    assert r["fracture_position_m"][0] <= r["fracture_position_m"][1]
    assert r["fracture_time_s"] == pytest.approx(0.4395e-3, rel=0.01)
    assert max(r["damage_at_fracture"]) >= 0.3
