"""The thermal-shock benchmark ``examples/thermal/jiang_quench.py``: its crack
post-processing on a synthetic damage field with known cracks (quick), and the deck
itself at a small size (``long``): edge cracks start at the cooled long edges, and
the hotter quench gives more of them."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.helpers import load_script

SCRIPT = Path(__file__).parents[2] / "examples" / "thermal" / "jiang_quench.py"
DX = 2.5e-4


@pytest.fixture(scope="module")
def jq():
    return load_script(SCRIPT, "jiang_quench")


def _plate(nx: int = 80, ny: int = 40) -> tuple[np.ndarray, np.ndarray]:
    """Cell-centred points of a nx x ny grid (spacing DX) and their damage: cracks
    from the bottom edge at columns 20 (10 rows deep), 40 (4 rows) and 60 (10 rows,
    leaning one column every 3 rows), one from the top edge at column 30 (3 rows)."""
    i, j = np.meshgrid(np.arange(nx), np.arange(ny))
    x = np.column_stack([(i.ravel() + 0.5) * DX, (j.ravel() + 0.5) * DX])
    img = np.zeros((ny, nx))
    img[:10, 20] = 0.5
    img[:10, 19] = 0.2  # a crack face neighbour: below the threshold
    img[:4, 40] = 0.45
    for r in range(10):
        img[r, 60 + r // 3] = 0.6
    img[ny - 3 :, 30] = 0.4
    return x, img.ravel()


def test_edge_cracks_found_and_measured(jq):
    """Positions and lengths of the synthetic cracks are recovered exactly."""
    x, damage = _plate()
    cracks = jq.edge_cracks(x, damage, DX, margin=1e-3)
    bottom = [(round(c["x_m"] / DX), round(c["length_m"] / DX)) for c in cracks["bottom"]]
    assert bottom == [(20, 10), (40, 4), (60, 10)]
    top = [(round(c["x_m"] / DX), round(c["length_m"] / DX)) for c in cracks["top"]]
    assert top == [(30, 3)]


def test_length_classes_split_at_gaps(jq):
    """Lengths 10, 10, 4, 3 spacings: two classes (10 > 1.4 x 4 and 6 spacings apart);
    4 and 3 stay one class (ratio 1.33)."""
    classes = jq.length_classes([10 * DX, 4 * DX, 10 * DX, 3 * DX], DX)
    assert [len(c) for c in classes] == [2, 2]
    assert jq.length_classes([3 * DX, 2 * DX], DX) == [[3 * DX, 2 * DX]]  # 1 spacing apart


def test_summary_counts(jq):
    """Counts per edge, cracks per mm of the searched edges and the spacing."""
    x, damage = _plate()
    s = jq.analyse(x, damage, DX)
    assert (s["cracks_bottom"], s["cracks_top"]) == (3, 1)
    span_mm = (80 * DX - 2 * jq.MARGIN) * 1e3
    assert s["cracks_per_mm"] == pytest.approx(4 / (2 * span_mm))
    assert s["mean_spacing_mm"] == pytest.approx(20 * DX * 1e3)
    assert s["longest_mm"] == pytest.approx(10 * DX * 1e3)


def test_no_damage_no_cracks(jq):
    x, damage = _plate()
    s = jq.analyse(x, np.zeros_like(damage), DX)
    assert s["cracks_top"] == s["cracks_bottom"] == 0 and s["n_classes"] == 0


@pytest.mark.long
def test_small_plate_quench(jq, tmp_path):
    """A 20 x 10 mm plate (the deck's dx = 0.25 mm), 0.05 s of cooling from 300 C and
    600 C (22 s): the cracks start at the cooled long edges (each reaches the edge; the
    centre row is undamaged away from the short edges), there are some, and 600 C gives
    more than 300 C."""
    over = ["geometry.size=[0.02, 0.01]", "solver.end_time=0.05", "output.probes=[]"]
    counts = {}
    for t0 in (300.0, 600.0):
        r = jq.run(t0, tmp_path / f"T0_{t0:.0f}", over)
        s = jq.analyse(r["x"], r["damage"], r["dx"])
        counts[t0] = s["cracks_top"] + s["cracks_bottom"]
        img = jq.damage_image(r["x"], r["damage"], r["dx"])
        ends = int(round(4e-3 / r["dx"]))  # the cracks from the short edges reach 4 mm
        assert img[img.shape[0] // 2, ends:-ends].max() < jq.THRESHOLD  # centre intact
        for c in s["cracks"]["top"] + s["cracks"]["bottom"]:
            assert c["length_m"] >= (jq.PROBE_ROWS + 1) * r["dx"]  # reaches the edge
    assert counts[300.0] > 0
    assert counts[600.0] > counts[300.0]
