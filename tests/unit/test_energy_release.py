"""The energy of broken bonds and the energy release rate from it
(analysis/energy_release.py, io/observers/cracks.py): the energy a cut removes from a
uniformly stretched plate (the force model's own energy, an independent oracle), the
calibration G = G0 of a straight cut, the slope, and the summary keys of a run."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import peridynamics as pd
from peridynamics.analysis.energy_release import (
    broken_bond_energy,
    energy_release_rate,
    supports_broken_bond_energy,
)
from peridynamics.bonds.bonds import build_bonds
from peridynamics.bonds.precrack import SegmentCrack, crossing_bonds
from peridynamics.damage.critical_stretch import CriticalStretch
from peridynamics.families.lps import LPSMaterial
from peridynamics.families.pmb import BondBasedMaterial
from peridynamics.geometry.generators import rectangle

DX = 1e-3
G0 = 10.0  # J/m^2
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _model(m: int, partial_volume: str = "truncated") -> pd.Evaluator:
    cloud = rectangle((60 * DX, 60 * DX), DX, thickness=2e-3)
    bonds = build_bonds(cloud, (m + 0.015) * DX, partial_volume)  # type: ignore[arg-type]
    material = BondBasedMaterial(70e9, 2500.0)
    s0 = material.critical_stretch(G0, 2, bonds.horizon, cloud.cross_section, cloud.plane)
    return pd.Evaluator(cloud, bonds, material, CriticalStretch(s0))


def _cut(model: pd.Evaluator, angle_deg: float, offset: np.ndarray, length: float):
    d = np.array([math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))])
    c = np.array([30 * DX, 30 * DX]) + offset
    b = model.bonds
    crack = SegmentCrack(tuple(c - 0.5 * length * d), tuple(c + 0.5 * length * d))
    hit = crossing_bonds(model.cloud.x, b.bond_i, b.bond_j, [crack])
    return (b.bond_intact.astype(bool) & ~hit).astype(np.uint8)


def test_supported_models() -> None:
    assert supports_broken_bond_energy(_model(3))
    cloud = rectangle((10 * DX, 10 * DX), DX)
    bonds = build_bonds(cloud, 3.015 * DX)
    lps = pd.Evaluator(cloud, bonds, LPSMaterial(70e9, 0.25, 2500.0), CriticalStretch(0.01))
    assert not supports_broken_bond_energy(lps)


def test_energy_of_a_cut_equals_the_models_energy_drop() -> None:
    """Stretched uniformly by s0 (u = s0 x: every bond at s0), the plate loses exactly
    the broken-bond energy when a cut breaks the bonds crossing it: the force model's
    energy density before and after is the oracle."""
    model = _model(3)
    s0 = float(model.point_s0[0])
    intact = _cut(model, 30.0, np.array([0.3, -0.2]) * DX, 30 * DX)
    u = s0 * model.cloud.x
    state = model.new_state()
    state.u[:] = u
    v = model.cloud.volume
    before = float(np.sum(model.force_model.energy_density(state) * v))
    state.intact[:] = intact
    after = float(np.sum(model.force_model.energy_density(state) * v))
    got = broken_bond_energy(model, intact)
    assert got > 0
    assert got == pytest.approx(before - after, rel=1e-12)


# G of a straight 30-spacing cut over G0, measured (6 random offsets of the segment each,
# standard deviation <= 0.006): truncated 0.814-0.840, extended 1.026-1.058, none
# 0.915-1.056 at m = 3, 4 and angles 0, 30, 45 deg; the bounds below are those +- 0.02
@pytest.mark.parametrize(
    ("partial_volume", "low", "high"),
    [("truncated", 0.79, 0.86), ("extended", 1.00, 1.08), ("none", 0.89, 1.08)],
)
def test_straight_cut_releases_about_g0(partial_volume: str, low: float, high: float) -> None:
    rng = np.random.default_rng(7)
    for m in (3, 4):
        model = _model(m, partial_volume)
        for angle in (0.0, 30.0, 45.0):
            intact = _cut(model, angle, rng.uniform(-0.5, 0.5, 2) * DX, 30 * DX)
            g = broken_bond_energy(model, intact) / (30 * DX * model.cloud.cross_section)
            assert low <= g / G0 <= high, (partial_volume, m, angle, g / G0)


def test_rate_is_the_slope_over_the_growth() -> None:
    a = np.array([0.0, 0.0, 0.001, 0.002, 0.004, 0.008])
    e = 3.0 * a + np.where(a > 0, 1e-4, 0.0)  # an offset at initiation
    assert energy_release_rate(e, a, thickness=1.0) == pytest.approx(3.0, rel=1e-9)
    assert energy_release_rate(2 * 3.0 * a, a, thickness=2.0) == pytest.approx(3.0)
    assert math.isnan(energy_release_rate(np.zeros(3), np.zeros(3)))
    assert math.isnan(energy_release_rate(np.ones(1), np.ones(1)))


def test_a_run_reports_the_energy_and_g(tmp_path: Path) -> None:
    """The crack-branching deck, coarse and short: the history and the summary keys."""
    from peridynamics.cli import main

    out = tmp_path / "run"
    rc = main(
        [
            "run", str(EXAMPLES / "crack_branching_2d" / "deck.yaml"), "-o", str(out),
            "--set", "discretisation.spacing=1e-3", "--set", "discretisation.horizon=3.015e-3",
            "--set", "solver.end_time=30e-6", "--set", "output.vtk_every=0",
            "--set", "output.plot=none", "--quiet",
        ]
    )  # fmt: skip
    assert rc == 0
    summary = json.loads((out / "summary.json").read_text())
    res = summary["results"]
    energy = res["broken_bond_energy_history_J"]
    assert len(energy) == len(res["crack_length_history_m"])
    assert np.all(np.diff(energy) >= 0)  # bonds only break
    assert res["broken_bond_energy_J"] == pytest.approx(energy[-1])
    g = res["energy_release_rate_J_m2"]
    assert g is not None and 0.5 * 204.0 < g < 10 * 204.0
