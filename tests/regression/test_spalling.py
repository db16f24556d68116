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


#: Lu & Wang (2016), Table 1, copied here so that the test does not take the paper's
#: numbers (or the verdict) from the script it checks:
#: case -> (dx (m), x_F range (m), t_F (ms))
PAPER_TABLE1 = {
    1: (0.0010, (0.906, 0.909), 0.4395),
    2: (0.0010, (0.901, 0.908), 0.4399),
    3: (0.0010, (0.900, 0.910), 0.4407),
    4: (0.0005, (0.905, 0.907), 0.4389),
    5: (0.0005, (0.904, 0.908), 0.4392),
    6: (0.0010, (0.811, 0.816), 0.5126),
    7: (0.0010, (0.924, 0.928), 0.4327),
}

#: Our x_F (m) and t_F (ms), measured: the same in every digit with default threads (2),
#: NUMBA_NUM_THREADS=1 and NUMBA_CPU_NAME=generic (another vectorisation of the fast-math
#: sums). x_F are node positions (x_i = i dx) and t_F a step count times dt, so they can
#: only move by whole nodes or steps; asserted to 1e-9 (the floor for such numbers).
OURS_TABLE1 = {
    1: ((0.906, 0.909), 0.4398),
    2: ((0.903, 0.906), 0.4401),
    3: ((0.900, 0.910), 0.4412),
    4: ((0.904, 0.9065), 0.4393),
    5: ((0.9045, 0.908), 0.43955),
    6: ((0.811, 0.816), 0.5133),
    7: ((0.924, 0.927), 0.4331),
}


@pytest.fixture(scope="module")
def rows(tmp_path_factory) -> dict[int, dict]:
    tmp = tmp_path_factory.mktemp("spalling")
    return {n: make_table.run_case(n, tmp / f"case{n}") for n in PAPER_TABLE1}


@pytest.mark.long
@pytest.mark.parametrize("case", range(1, 8))
def test_table1_case_matches_the_paper(rows, case: int) -> None:
    dx, (lo, hi), t_paper = PAPER_TABLE1[case]
    r = rows[case]
    x_lo, x_hi = r["x_F_m"]
    t_ms = r["t_F_ms"]
    # against the paper (examples/spalling/README.md): x_F within the paper's range
    # +/- 2 dx (case 4 needs the 2 dx: 0.904 against 0.905, dx = 0.5 mm; the others lie
    # inside the paper's range) and t_F within 1 % (measured +0.05 ... +0.14 %)
    assert lo - 2 * dx - 1e-12 <= x_lo <= x_hi <= hi + 2 * dx + 1e-12, (case, r["x_F_m"])
    assert t_ms == pytest.approx(t_paper, rel=0.01), (case, t_ms)
    # against our measured numbers (regressions; identical over threads and CPU builds,
    # one grid spacing and 0.2 % of the time left for a bond decision that flips on
    # other hardware)
    (o_lo, o_hi), o_t = OURS_TABLE1[case]
    assert [x_lo, x_hi] == pytest.approx([o_lo, o_hi], abs=dx + 1e-9), (case, r["x_F_m"])
    assert t_ms == pytest.approx(o_t, rel=2e-3), (case, t_ms)
    # the script that writes the README table uses the paper's numbers and the same
    # verdict and error
    _m, dx_s, _pm, _t0, _dt, rng, t_s = make_table.PAPER[case]
    assert (dx_s, tuple(rng), t_s) == (dx, (lo, hi), t_paper)
    assert r["x_F_ok"] is True
    assert r["t_F_error"] == pytest.approx(t_ms / t_paper - 1.0, abs=1e-12)


@pytest.mark.long
def test_table1_trends(rows) -> None:
    base, longer, stronger = rows[1], rows[6], rows[7]
    # a longer pulse moves the spall away from the free end (x = 1 m)
    assert max(longer["x_F_m"]) < min(base["x_F_m"])
    # a stronger pulse moves it closer to the free end, and earlier
    assert min(stronger["x_F_m"]) > max(base["x_F_m"])
    assert stronger["t_F_ms"] < base["t_F_ms"]


@pytest.mark.long
def test_contract_through_the_cli(tmp_path) -> None:
    r = _run_results(tmp_path, "table1_case1")
    assert len(r["fracture_position_m"]) == 2
    assert r["fracture_position_m"][0] <= r["fracture_position_m"][1]
    assert r["fracture_time_s"] == pytest.approx(0.4395e-3, rel=0.01)  # the paper's
    # through the CLI, the numbers of the in-process run (OURS_TABLE1, case 1)
    assert r["fracture_position_m"] == pytest.approx(list(OURS_TABLE1[1][0]), abs=1e-3)
    assert r["fracture_time_s"] == pytest.approx(OURS_TABLE1[1][1] * 1e-3, rel=2e-3)
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


@pytest.mark.long
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


@pytest.mark.long
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


@pytest.mark.long
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


@pytest.mark.long
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
