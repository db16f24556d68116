"""The micropolar examples (cantilever, DCB, L-panel) through their figure script at a
small size; the paper-scale runs are ``slow``.

Tolerances are set from the measured coarse-grid values (in the comments) with margin.
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pytest

from tests.helpers import EXAMPLES

HERE = EXAMPLES / "micropolar"


def _figures():
    spec = importlib.util.spec_from_file_location("mp_figures", HERE / "make_figures.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _run(tmp_path: Path, case: str, *sets: str) -> dict:
    args = [case, "--out", str(tmp_path)] + [a for s in sets for a in ("--set", s)]
    assert _figures().main(args) == 0
    res = json.loads((tmp_path / case / f"{case}.json").read_text())
    assert (tmp_path / case / f"{case}.png").stat().st_size > 1000
    return res


@pytest.mark.long
def test_cantilever_small(tmp_path: Path) -> None:
    pytest.importorskip("skfem")
    res = _run(
        tmp_path,
        "cantilever",
        "discretisation.spacing=0.02",
        "geometry.size=[1.06,0.3]",
        "geometry.origin=[-0.06,0.0]",
    )
    # dx = 0.02 (15 rows): measured 0.97 (u_x) and 0.98 (u_y) of the FEM values
    assert 0.93 < res["ux_ratio_pd_to_fem"] < 1.03
    assert 0.95 < res["uy_ratio_pd_to_fem"] < 1.03
    assert 0.95 < res["tip_ratio_pd_to_tg"] < 1.03


@pytest.mark.long
def test_dcb_small(tmp_path: Path) -> None:
    res = _run(
        tmp_path,
        "dcb",
        # dx = 1 mm (20 points per arm; at 2 mm the crack turns at the tip and cuts the
        # arms: too coarse), the opening stopped at 1.0 mm to keep the test short
        "discretisation.spacing=1.0e-3",
        "geometry.size=[0.203,0.04]",
        "boundary_conditions.1.components.y=0.5e-3",
        "boundary_conditions.2.components.y=-0.5e-3",
        "solver.load_steps=5",
    )
    # measured at dx = 1 mm (the deck's corrected_critical_stretch: true): compliance
    # 1.046 x corrected beam theory, 17 events at 1.096 +- 0.053 x LEFM (0.954-1.137),
    # the first at 0.954, the path on the mid-line (offset dx / 2); without the option
    # the events of the full run sit at 1.245 +- 0.041 (README)
    assert 0.97 < res["compliance_ratio_pd_to_cbt"] < 1.10
    assert res["events"] > 5
    assert res["crack_growth_m"] > 0.005
    assert res["max_path_offset_from_midline_m"] <= 1.0e-3
    assert res["p_over_p_lefm_mean"] is not None
    assert 1.0 < res["p_over_p_lefm_mean"] < 1.15  # the band of issue 35
    assert 0.90 < res["first_event_p_over_p_lefm"] < 1.05


@pytest.mark.long
def test_l_panel_small(tmp_path: Path) -> None:
    res = _run(
        tmp_path,
        "l_panel",
        "discretisation.spacing=1.0e-2",
        "discretisation.horizon_factor=3.015",
        "geometry.size=[0.5,0.53]",
        "geometry.origin=[0.0,-0.03]",
        "node_sets.load.box.max=[0.48,0.26]",
        "solver.load_steps=10",
        "boundary_conditions.1.components.y=0.6e-3",
    )
    # measured at dx = 10 mm: first break 6 mm from the corner, the path heads left at
    # about 15 deg upward, stiffness 64 kN/mm, peak 14.3 kN (twice the experiment's 7.2:
    # l_c from G_c makes MPPD far stronger than concrete's tensile strength)
    assert res["broken_pairs"] > 0
    assert res["first_break_distance_from_corner_m"] < 0.02
    assert res["crack_end_m"][0] < 0.1  # the crack runs from the corner to the left
    assert 5.0 < res["crack_angle_first_25mm_deg"] < 45.0
    assert 40.0 < res["initial_stiffness_kN_per_mm"] < 90.0
    assert 10.0 < res["peak_load_kN"] < 20.0


@pytest.mark.long
def test_cantilever_paper_resolution(tmp_path: Path) -> None:
    """The paper's cantilever (dx = 0.01 m, 100 x 30): measured u_y 0.994 and u_x 0.984
    of the FEM reference at the same points (the paper claims < 1 % for both: u_x misses
    it by 0.6 %), the tip 0.991 of Timoshenko-Goodier."""
    pytest.importorskip("skfem")
    res = _run(tmp_path, "cantilever")
    assert 0.99 < res["uy_ratio_pd_to_fem"] < 1.0
    assert 0.98 < res["ux_ratio_pd_to_fem"] < 1.0
    assert 0.985 < res["tip_ratio_pd_to_tg"] < 1.0


@pytest.mark.slow
def test_dcb_paper_resolution(tmp_path: Path) -> None:
    """dx = 0.5 mm (about 9 min), the deck as shipped (corrected_critical_stretch: true):
    measured compliance 1.029 x corrected beam theory, first event 0.902 x LEFM, 85
    events on the straight part at 1.165 +- 0.050 x LEFM (without the option: 1.009 and
    1.30 +- 0.06)."""
    res = _run(tmp_path, "dcb")
    assert 0.97 < res["compliance_ratio_pd_to_cbt"] < 1.03
    assert 0.85 < res["first_event_p_over_p_lefm"] < 1.0
    assert 1.12 < res["p_over_p_lefm_mean"] < 1.21
    assert res["max_path_offset_from_midline_m"] <= 5.0e-4


@pytest.mark.slow
def test_l_panel_paper_resolution(tmp_path: Path) -> None:
    """dx = 2.5 mm, 80 neighbours (about 25 min): measured first break 4.5 mm from the
    corner, 22.8 deg over the first 25 mm, the path 19 mm short of the left edge at
    1 mm, peak 13.9 kN."""
    res = _run(tmp_path, "l_panel")
    assert res["first_break_distance_from_corner_m"] < 0.01
    assert 15.0 < res["crack_angle_first_25mm_deg"] < 30.0
    assert res["crack_end_m"][0] < 0.05
    assert 12.0 < res["peak_load_kN"] < 16.0
