"""Crack length (2-D) and area (3-D) from broken bonds (analysis/crack_length.py), its
attribution to tracked cracks, the threshold warning of the crack trackers, and the
summary.json keys of a small run (io/observers/cracks.py, crack_threshold.py)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from peridynamics.analysis.crack_attribution import attribute_to_polylines
from peridynamics.analysis.crack_length import CrackMeter, broken_bond_crack_length
from peridynamics.analysis.crack_orientation import ORIENTATION_AVERAGE, orientation_factor
from peridynamics.app.run import Simulation
from peridynamics.bonds.bonds import Bonds, build_bonds
from peridynamics.bonds.precrack import RectangleCrack, SegmentCrack, crossing_bonds
from peridynamics.deck import parse_deck
from peridynamics.geometry.cloud import PointCloud
from peridynamics.geometry.generators import box, rectangle
from peridynamics.io.observers.crack_threshold import (
    CrackThresholdWarning,
    ridge_mask,
    threshold_check,
)

DX = 1.0  # grid spacing (m): lengths below are in spacings


def _plate(m: int, n: int = 60, jitter: float = 0.0) -> tuple[PointCloud, Bonds]:
    cloud = rectangle((n * DX, n * DX), DX, jitter=jitter, seed=3)
    return cloud, build_bonds(cloud, m * DX, "extended" if jitter else "truncated")


def _cut(cloud: PointCloud, bonds: Bonds, *segments: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """Bond flags (uint8) with every bond crossing the segments broken (and the
    pre-cracked ones)."""
    cracks = [SegmentCrack(tuple(a), tuple(b)) for a, b in segments]
    hit = crossing_bonds(cloud.x, bonds.bond_i, bonds.bond_j, cracks)
    return (bonds.bond_intact.astype(bool) & ~hit).astype(np.uint8)


def _segment(centre: tuple[float, float], angle_deg: float, length: float):
    d = np.array([math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))])
    c = np.asarray(centre, dtype=float)
    return c - 0.5 * length * d, c + 0.5 * length * d


def _damage(bonds: Bonds, intact: np.ndarray) -> np.ndarray:
    """Point damage: broken share of the family's partial volumes."""
    n = bonds.n_points
    total = np.bincount(bonds.bond_i, weights=bonds.bond_volume, minlength=n)
    gone = np.bincount(bonds.bond_i, weights=bonds.bond_volume * (intact == 0), minlength=n)
    return gone / total


# measured spread over 8 random offsets of a 30-spacing segment (docs/output.md): mean
# error within 0.7 %, standard deviation up to 0.94 % (45 deg, m = 2); 3 % is > 2.5 sigma
@pytest.mark.parametrize("m", [2, 3, 4])
@pytest.mark.parametrize("angle", [0.0, 30.0, 45.0])
def test_a_cut_segment_of_known_length_is_recovered(m: int, angle: float) -> None:
    cloud, bonds = _plate(m)
    length = 24.0 * DX
    intact = _cut(cloud, bonds, _segment((30.3, 29.8), angle, length))
    assert broken_bond_crack_length(cloud, bonds, intact) == pytest.approx(length, rel=0.03)


def test_the_orientation_average_alone_misses_a_grid_aligned_crack_at_m2() -> None:
    cloud, bonds = _plate(2)
    meter = CrackMeter.from_bonds(cloud, bonds)
    intact = _cut(cloud, bonds, _segment((30.3, 30.0), 0.0, 24.0))
    # sum |xi . n| of the m = 2 family for n along a grid axis is 11.0 % below 2/pi sum|xi|
    assert meter.measure(intact, "average") == pytest.approx(24.0 * (1 - 0.110), rel=0.005)
    assert meter.measure(intact) == pytest.approx(24.0, rel=0.01)
    assert meter.weights(intact, normal=[0.0, 1.0])[1].sum() == pytest.approx(24.0, rel=1e-3)


@pytest.mark.parametrize(
    ("m", "expected"),  # g(n) / (2/pi) - 1 for cracks at 0, 30, 45 degrees (measured)
    [
        (2, (-0.1104, 0.0373, 0.0065)),
        (3, (-0.0393, 0.0065, -0.0187)),
        (4, (-0.0259, 0.0028, -0.0012)),
    ],
)
def test_orientation_table_of_the_square_lattice(m: int, expected: tuple) -> None:
    cloud, bonds = _plate(m, n=20)
    meter = CrackMeter.from_bonds(cloud, bonds)
    normals = np.array([[-math.sin(a), math.cos(a)] for a in np.radians([0.0, 30.0, 45.0])])
    got = meter.g(normals) / ORIENTATION_AVERAGE[2] - 1
    np.testing.assert_allclose(got, expected, atol=3e-4)
    # the table is that of one interior family
    inner = int(np.argmin(np.linalg.norm(cloud.x - 10.0, axis=1)))
    fam = slice(bonds.offsets[inner], bonds.offsets[inner + 1])
    np.testing.assert_allclose(orientation_factor(bonds.bond_xi[fam], normals), meter.g(normals))


def test_jittered_cloud_with_voronoi_volumes() -> None:
    cloud, bonds = _plate(3, jitter=0.25)
    for angle in (0.0, 30.0):  # measured -0.4 % ... +0.3 %
        intact = _cut(cloud, bonds, _segment((30.0, 30.2), angle, 30.0))
        assert broken_bond_crack_length(cloud, bonds, intact) == pytest.approx(30.0, rel=0.03)


def test_a_crack_ending_at_a_free_edge() -> None:
    cloud, bonds = _plate(4)
    start = np.array([-1e-9, 20.3])
    intact = _cut(cloud, bonds, (start, start + [30.0, 0.0]))  # measured +0.7 %
    assert broken_bond_crack_length(cloud, bonds, intact) == pytest.approx(30.0, rel=0.02)


def test_pre_cracked_bonds_are_not_counted() -> None:
    cloud = rectangle((60.0, 60.0), DX)
    pre = SegmentCrack((0.0, 30.2), (20.0, 30.2))
    bonds = build_bonds(cloud, 3 * DX, cracks=[pre])
    meter = CrackMeter.from_bonds(cloud, bonds)
    assert meter.measure(bonds.bond_intact) == 0.0
    # growing it by 15 spacings along its line counts the 15 spacings only
    intact = _cut(cloud, bonds, (np.array([20.0, 30.2]), np.array([35.0, 30.2])))
    assert meter.measure(intact) == pytest.approx(15.0, rel=0.02)


def test_bonds_broken_beside_the_crack_are_not_crack() -> None:
    cloud, bonds = _plate(3)
    intact = _cut(cloud, bonds, _segment((30.3, 30.0), 0.0, 24.0))
    meter = CrackMeter.from_bonds(cloud, bonds)
    clean = meter.measure(intact)
    # a wider band: also break the bonds between the first and second rows above the
    # crack (they do not cross it), as a running crack does at m = 4
    y = cloud.x[:, 1]
    xi, xj = cloud.x[bonds.bond_i], cloud.x[bonds.bond_j]
    beside = (
        (np.minimum(y[bonds.bond_i], y[bonds.bond_j]) > 30.0)
        & (np.maximum(y[bonds.bond_i], y[bonds.bond_j]) < 32.0)
        & (np.abs(xi[:, 1] - xj[:, 1]) > 0.5)
        & (np.minimum(xi[:, 0], xj[:, 0]) > 20.0)
        & (np.maximum(xi[:, 0], xj[:, 0]) < 40.0)
    )
    wider = intact.copy()
    wider[beside] = 0
    assert meter.measure(wider, separating=False) > 1.1 * clean
    assert meter.measure(wider) == pytest.approx(clean, rel=0.01)


@pytest.mark.parametrize("inclined", [False, True])
def test_planar_crack_area_in_3d(inclined: bool) -> None:
    cloud = box((24.0, 24.0, 24.0), DX)
    bonds = build_bonds(cloud, 3 * DX)
    side = 12.0
    if inclined:  # 45 deg about x
        c = (6.2, 8.1, 8.3), (side, 0, 0), (0, side / math.sqrt(2), side / math.sqrt(2))
    else:
        c = (6.2, 6.1, 12.3), (side, 0, 0), (0, side, 0)
    hit = crossing_bonds(cloud.x, bonds.bond_i, bonds.bond_j, [RectangleCrack(*c)])
    area = broken_bond_crack_length(cloud, bonds, (~hit).astype(np.uint8))
    # measured -0.03 % (on a grid plane) and +1.7 % (45 deg; the edges of a crack only
    # 4 horizons wide weigh in); the orientation average is -0.7 % and -0.5 %
    assert area == pytest.approx(side * side, rel=0.03)


def test_attribution_to_two_separate_cracks() -> None:
    cloud, bonds = _plate(3)
    a = (np.array([5.0, 15.2]), np.array([25.0, 15.2]))  # 20 long
    b = _segment((40.0, 42.0), 30.0, 16.0)  # 16 long
    stray = (np.array([50.0, 5.2]), np.array([56.0, 5.2]))  # 6 long, not tracked
    intact = _cut(cloud, bonds, a, b, stray)
    meter = CrackMeter.from_bonds(cloud, bonds)
    idx, w = meter.weights(intact)
    lines = {"a": [np.array(a)], "b": [np.array(b)]}
    share, rest = attribute_to_polylines(meter.midpoints(idx), w, lines, radius=2 * 3 * DX)
    assert share["a"] == pytest.approx(20.0, rel=0.03)
    assert share["b"] == pytest.approx(16.0, rel=0.03)
    assert rest == pytest.approx(6.0, rel=0.05)
    assert sum(share.values()) + rest == pytest.approx(float(w.sum()), rel=1e-12)


@pytest.mark.parametrize(
    ("m", "crest", "at", "above", "clear"),
    [
        (2, 0.350, (0.35, 0.36), (0.4, 0.5), (0.2, 0.25, 0.3)),
        # m = 3: the second row (0.196) sits at 0.2, but the first (0.399) shows the crack
        (3, 0.399, (0.4,), (0.45, 0.5), (0.2, 0.25, 0.3, 0.35)),
    ],
)
def test_threshold_rule_on_a_straight_crack(m, crest, at, above, clear) -> None:
    cloud, bonds = _plate(m)
    intact = _cut(cloud, bonds, _segment((30.0, 30.0), 0.0, 30.0))  # between grid rows
    phi = _damage(bonds, intact)
    gone = np.flatnonzero(bonds.bond_intact.astype(bool) & (intact == 0))
    ridge = ridge_mask(bonds.bond_i[gone], bonds.bond_j[gone], phi)
    assert np.median(phi[ridge]) == pytest.approx(crest, abs=5e-4)
    assert np.all(phi[ridge] > 0.3)  # the rows farther out are not on the ridge
    for thr in at:
        assert threshold_check(phi, ridge, thr)[0] == "at"
    for thr in above:
        assert threshold_check(phi, ridge, thr)[0] == "above"
    for thr in clear:
        assert threshold_check(phi, ridge, thr)[0] is None


# ---------------------------------------------------------------- through a deck
def _strip_deck(thresholds: tuple[float, float, float], dim: int = 2) -> dict:
    """A glass strip 50 x 20 mm with a 15 mm edge pre-crack at mid-height, pulled apart
    by 8 MPa on its long edges; delta = 1 mm, m = 2: a straight mode-I crack grows
    23 mm in 30 us (docs/output.md)."""
    tip, paths_a, paths_b = thresholds
    return {
        "name": "strip",
        "geometry": {"type": "rectangle", "size": [0.05, 0.02], "thickness": 1e-3},
        "discretisation": {"spacing": 5e-4, "horizon": 1e-3, "surface_correction": False},
        "material": {"model": "pmb", "youngs_modulus": 65e9, "density": 2235.0},
        "damage": {"model": "critical_stretch", "fracture_energy": 204.0},
        "node_sets": {
            "top": {"edge": {"normal": [0.0, 1.0], "layers": 1}},
            "bottom": {"edge": {"normal": [0.0, -1.0], "layers": 1}},
        },
        "precracks": [{"points": [[0.0, 0.01], [0.015, 0.01]]}],
        "boundary_conditions": [
            {"type": "traction", "set": "top", "value": [0.0, 8e6]},
            {"type": "traction", "set": "bottom", "value": [0.0, -8e6]},
        ],
        "solver": {"safety_factor": 0.8, "end_time": 30e-6},
        "output": {
            "history_every": 20,
            "plot": "none",
            "bonds": False,
            "crack_tip": {"origin": [0.015, 0.01], "direction": [1.0, 0.0],
                          "damage_threshold": tip},
            "crack_paths": [
                {"name": "at", "seed": [0.015, 0.01], "damage_threshold": paths_a},
                {"name": "below", "seed": [0.015, 0.01], "damage_threshold": paths_b},
            ],
        },
    }  # fmt: skip


def test_summary_keys_and_the_warning_in_a_run(tmp_path: Path) -> None:
    sim = Simulation.from_deck(parse_deck(_strip_deck((0.35, 0.35, 0.25))))
    with pytest.warns(CrackThresholdWarning) as caught:
        summary = sim.run(tmp_path, quiet=True, progress=False)
    r = summary["results"]
    # measured 22.98 mm; the damage map (half the crest damage 0.35 at the tip) 23.10 mm
    assert r["crack_length_m"] == pytest.approx(0.0231, rel=0.05)
    assert r["crack_length_all_bonds_m"] >= r["crack_length_m"]
    hist = r["crack_length_history_m"]
    assert len(hist) == len(r["history"]["time_s"]) and hist[0] == 0.0
    assert hist[-1] == r["crack_length_m"] and np.all(np.diff(hist) >= 0)
    # the tracker at 0.35 sees nothing; the broken bonds see the crack
    assert r["crack_tip_position_m"][-1] == 0.0
    assert r["crack_tip_broken_bond_length_m"] == pytest.approx(r["crack_length_m"], rel=1e-9)
    below = r["crack_paths"]["below"]
    assert below["length_m"] == pytest.approx(r["crack_length_m"], rel=0.05)
    assert below["broken_bond_length_m"] == pytest.approx(r["crack_length_m"], rel=1e-9)
    assert r["crack_length_unattributed_m"] == pytest.approx(0.0, abs=1e-12)
    warned = " ".join(r["warnings"])
    assert "output.crack_tip.damage_threshold" in warned
    assert "output.crack_paths[0].damage_threshold" in warned
    assert "output.crack_paths[1]" not in warned
    assert len(caught) == len(r["warnings"]) == 2
    assert "results.crack_length_m" in r["warnings"][0]


def test_no_crack_keys_without_bond_breaking_or_in_1d(tmp_path: Path) -> None:
    d = _strip_deck((0.35, 0.35, 0.25))
    d["damage"] = {"model": "none"}
    d["solver"]["end_time"] = 1e-6
    r = Simulation.from_deck(parse_deck(d)).run(tmp_path / "a", quiet=True, progress=False)
    assert "crack_length_m" not in r["results"] and "warnings" not in r["results"]
    bar = {
        "name": "bar",
        "geometry": {"type": "bar", "length": 0.02, "area": 1e-4},
        "discretisation": {"spacing": 1e-3, "horizon_factor": 3.015},
        "material": {"youngs_modulus": 30e9, "density": 2400.0},
        "damage": {"critical_stretch": 1e-4},
        "solver": {"end_time": 1e-6},
        "output": {"plot": "none"},
    }
    r = Simulation.from_deck(parse_deck(bar)).run(tmp_path / "b", quiet=True, progress=False)
    assert not any(k.startswith("crack_") for k in r["results"])


def test_3d_run_reports_an_area(tmp_path: Path) -> None:
    d = {
        "name": "cube",
        "geometry": {"type": "box", "size": [0.01, 0.01, 0.01]},
        "discretisation": {"spacing": 1e-3, "horizon_factor": 2.0},
        "material": {"youngs_modulus": 65e9, "density": 2235.0},
        "damage": {"fracture_energy": 204.0},
        "precracks": [{"points": [[0.0, 0.0, 0.005], [0.004, 0.0, 0.005], [0.0, 0.01, 0.005]]}],
        "solver": {"end_time": 2e-7},
        "output": {"plot": "none"},
    }
    r = Simulation.from_deck(parse_deck(d)).run(tmp_path, quiet=True, progress=False)["results"]
    assert r["crack_area_m2"] == 0.0  # unloaded: the pre-crack does not count
    assert len(r["crack_area_history_m2"]) == len(r["history"]["time_s"])
    assert "crack_length_m" not in r
