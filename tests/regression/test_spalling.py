"""Lu & Wang (2016), Table 1 (issue 4, first part): the seven spalling decks against the paper."""

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
    r = _run_results(tmp_path, "table1_case1")
    assert len(r["fracture_position_m"]) == 2
    assert r["fracture_position_m"][0] <= r["fracture_position_m"][1]
    assert r["fracture_time_s"] == pytest.approx(0.4395e-3, rel=0.01)
    assert max(r["damage_at_fracture"]) >= 0.3


def _run_results(tmp_path, stem: str) -> dict:
    """Run ``examples/spalling/<stem>.yaml`` through the CLI; its summary's results."""
    out = tmp_path / stem
    cli(
        "run", str(EXAMPLES / "spalling" / f"{stem}.yaml"), "--out", str(out), "--quiet", check=True
    )
    return json.loads((out / "summary.json").read_text())["results"]


def _probe(results: dict, name: str = "stress_at_0_5m"):
    import numpy as np

    r = results["probes"][name]
    return np.array(r["time_s"]), np.array(r["values"])


def test_fig7a_wave_test_fdm_equals_pd1_and_dispersion_grows_with_m(tmp_path) -> None:
    import numpy as np

    runs = {
        k: _probe(_run_results(tmp_path, f"wave_{k}"))
        for k in ("fdm", "pd_m1", "pd_m2", "pd_m4", "pd_m8")
    }
    t, fdm = runs["fdm"]
    _, pd1 = runs["pd_m1"]
    assert np.abs(fdm - pd1).max() <= 1e-10 * np.abs(fdm).max()  # measured 3e-12
    assert fdm.min() < -8e6  # the 8.9 MPa compressive pulse passed x = 0.5 m
    # larger horizons delay the peak (slower short waves) and leave a tensile tail
    arrival = [t[np.argmin(runs[k][1])] for k in ("pd_m1", "pd_m2", "pd_m4", "pd_m8")]
    assert np.all(np.diff(arrival) > 0)
    assert runs["pd_m8"][1].max() > 3 * runs["pd_m1"][1].max()


def test_table2_test_bar_schemes(tmp_path) -> None:
    res = {k: _run_results(tmp_path, f"test_bar_{k}") for k in ("pd3", "pd1_pd3", "fdm_pd3")}
    for kind in ("pd1_pd3", "fdm_pd3"):
        r = res[kind]
        assert r["switched"] and r["switch_time_s"] < r["fracture_time_s"]
    # with the synthetic pulse (examples/spalling/README.md) the hybrids spall at 0.80-0.81 m,
    # the PD3 run at 0.84-0.86 m, 8 us earlier: recorded, not the paper's claim of one position
    assert res["fdm_pd3"]["fracture_position_m"] == res["pd1_pd3"]["fracture_position_m"]
    assert res["pd3"]["fracture_time_s"] < res["fdm_pd3"]["fracture_time_s"]
    for r in res.values():
        assert 0.78 <= r["fracture_position_m"][0] <= r["fracture_position_m"][1] <= 0.87


def test_spalling_figures(tmp_path) -> None:
    spec = importlib.util.spec_from_file_location(
        "spalling_figures", EXAMPLES / "spalling" / "make_figures.py"
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    paths = mod.make_figures(tmp_path)
    assert [p.name for p in paths] == [
        "seed000_fig7a.png",
        "seed000_fig7b.png",
        "seed000_fig8a.png",
        "seed000_fig8b.png",
    ]
    for p in paths:
        assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and p.stat().st_size > 5000


def test_table2_timing_script_on_a_refined_bar() -> None:
    """time_table2 at dx = 1 mm: every scheme fractures, all at the observed 0.79-0.80 m
    (refinement removes the PD3 offset), the hybrids after switching. No wall-time
    assertion: speed is measured by the script, not by a unit test."""
    spec = importlib.util.spec_from_file_location(
        "time_table2", EXAMPLES / "spalling" / "time_table2.py"
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    rows = {k: mod.time_scheme(k, 0.001, 1) for k in mod.SCHEMES}
    for k, r in rows.items():
        lo, hi = r["fracture_position_m"]
        assert 0.785 <= lo <= hi <= 0.805, (k, lo, hi)
        assert r["fracture_time_ms"] == pytest.approx(0.465, abs=0.002)
        assert r["wall_s"] > 0
    for k in ("pd1_pd3", "fdm_pd3"):
        assert rows[k]["switch_ms"] is not None
        assert 0.3 < rows[k]["switch_ms"] < rows[k]["fracture_time_ms"]
