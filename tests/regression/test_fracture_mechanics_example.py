"""``examples/fracture_mechanics``: the static centre-cracked LPS plate as shipped
(dx = 2 mm, 3 200 points, about 8 s with its Numba compilation on 2 cores), measured by
``make_figures.py``: J on three contours, K_I from the crack opening."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.helpers import EXAMPLES, load_script


@pytest.mark.long
def test_make_figures_measures_j_and_k(tmp_path: Path) -> None:
    """Measured at dx = 2 mm: J/(K^2/E) 1.0576-1.0595 (both tips, three contours),
    K_I/K 1.1065 by extrapolation of K(r), 1.0251 with the tip fitted 0.92 mm ahead;
    the bounds are those numbers with room, not the issue's 5 % (README.md)."""
    script = load_script(EXAMPLES / "fracture_mechanics" / "make_figures.py", "fm_figures")
    assert script.main(["--out", str(tmp_path)]) == 0
    rec = json.loads((tmp_path / "fracture_mechanics.json").read_text())
    j = rec["j_over_k2_e"]["right"] + rec["j_over_k2_e"]["left"]
    assert 1.0 < min(j) and max(j) < 1.08
    assert rec["k_extrapolated_over_k_right"] == pytest.approx(rec["k_extrapolated_over_k_left"])
    assert 1.0 < rec["k_extrapolated_over_k_right"] < 1.13
    assert rec["k_tip_fitted_over_k_right"] == pytest.approx(1.0, abs=0.04)
    assert 0.0 < rec["tip_shift_m_right"] < rec["spacing_m"]
    assert (tmp_path / "fracture_mechanics.png").stat().st_size > 10_000
