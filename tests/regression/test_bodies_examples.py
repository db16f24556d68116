"""The multi-body examples of ``examples/bodies`` through their scripts: the notched
three-point bend with softening bonds between rigid rollers and the two-material plate
with bonded interfaces, at a small size; the README's runs are ``slow``.

The checks are physics the runs must satisfy, with bounds from mechanics (strength
bounds of the beam, equilibrium of the rollers, the energy of the ligament) rather than
from the runs' own output.
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.helpers import EXAMPLES

HERE = EXAMPLES / "bodies"

#: the bend at a small size: 10 rows of points (dx = 5 mm, 440 points) and the roller
#: twice as fast, to 0.3 mm
BEND_SMALL = [
    "--spacings", "5.0e-3",
    "--set", "rigid_bodies.0.velocity=[0.0, -0.02]",
    "--set", "solver.end_time=0.0155",
]  # fmt: skip


def _script(name: str) -> Any:
    spec = importlib.util.spec_from_file_location(f"bodies_{name}", HERE / f"{name}.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _bend(tmp_path: Path, *args: str) -> dict:
    assert _script("bend_softening").main(["--out", str(tmp_path), *args]) == 0
    assert (tmp_path / "bend_softening.png").stat().st_size > 1000
    return json.loads((tmp_path / "bend_softening.json").read_text())


def _drop_width(run: dict) -> float:
    """Load-point displacement over which the load falls from the peak before the first
    drop to 40 % of it, over the displacement at that peak."""
    assert run["drop_to_40pct_displacement_m"] is not None, "the load never fell that far"
    return run["drop_to_40pct_displacement_m"] / run["displacement_at_that_peak_m"]


def _crack(folder: Path, dx: float, threshold: float) -> tuple[float, float]:
    """Highest point above the notch tip (y > 25 mm) with damage >= ``threshold`` and the
    largest |x| of those points (0, 0 when there is none)."""
    st = np.load(folder / "final_state.npz")
    x, dmg = st["x"], st["damage"]
    hit = (dmg >= threshold) & (x[:, 1] > 0.025)
    if not hit.any():
        return 0.0, 0.0
    return float(x[hit, 1].max()), float(np.abs(x[hit, 0]).max())


@pytest.mark.long
def test_bend_softening_small(tmp_path: Path) -> None:
    """Bilinear softening bonds, dx = 5 mm: the load peaks between the strength bounds of
    the ligament and below LEFM (size effect), then softens gradually to below half the
    peak with the CMOD growing; the rollers are in equilibrium; the crack runs straight
    up the notch plane; the work of fracture is of the order of G_F times the ligament."""
    res = _bend(tmp_path, *BEND_SMALL, "--laws", "bilinear")
    est, r = res["estimates"], res["runs"]["bilinear dx=5 mm"]
    assert est["P_net_section_elastic_N"] < r["peak_load_N"] < est["P_rigid_plastic_N"]
    assert r["peak_load_N"] < est["P_lefm_N"]
    assert r["final_over_peak"] < 0.5
    assert r["final_displacement_m"] > 2 * r["displacement_at_peak_m"]
    # CMOD grows after the peak (no reversal beyond round-off of the wobble)
    assert r["largest_cmod_decrease_after_peak_m"] < 0.01 * r["final_cmod_m"]
    assert r["final_cmod_m"] > 3 * r["cmod_at_peak_m"]
    # the support reactions balance the loading roller within the dynamic wobble
    assert r["max_reaction_imbalance_over_peak"] < 0.1
    assert r["max_kinetic_to_strain_energy"] < 0.1
    # the run stops before the tail ends: less than the ligament's energy, not far less
    assert 0.5 < r["work_over_GF_ligament"] < 1.2
    # a straight crack up the notch plane, its process zone (softening bonds, partly
    # damaged) ahead of it towards the loading roller
    depth, folder = res["geometry"]["depth_m"], tmp_path / "bilinear_dx5000um"
    top, wide = _crack(folder, 5.0e-3, 0.35)
    assert top > res["geometry"]["notch_m"] and wide <= 5.0e-3
    assert _crack(folder, 5.0e-3, 0.1)[0] > 0.75 * depth
    assert _drop_width(r) > 0.5  # a gradual tail


@pytest.mark.long
def test_bend_brittle_small(tmp_path: Path) -> None:
    """The brittle bond of the same fracture energy, dx = 5 mm: a higher peak, then the
    load collapses within a small fraction of the displacement at the peak (no tail)."""
    res = _bend(tmp_path, *BEND_SMALL, "--laws", "brittle")
    est, r = res["estimates"], res["runs"]["brittle dx=5 mm"]
    assert r["peak_before_first_drop_N"] > est["P_rigid_plastic_N"]
    assert _drop_width(r) < 0.3
    top, wide = _crack(tmp_path / "brittle_dx5000um", 5.0e-3, 0.35)
    assert top > 0.8 * res["geometry"]["depth_m"] and wide <= 5.0e-3  # through, straight


@pytest.mark.long
def test_inclusions_small(tmp_path: Path) -> None:
    """dx = 1 mm (1 600 points), the weak interface: the plate fails (the load falls
    below half its peak), interface bonds break in a larger share than mortar bonds and
    the cracked mortar lies near the aggregates more than the mortar does on average;
    the aggregates stay whole; the nominal strength is below the mortar's E s0."""
    mod = _script("inclusions")
    args = ["weak", "--out", str(tmp_path), "--set", "discretisation.spacing=1.0e-3"]
    assert mod.main(args) == 0
    assert (tmp_path / "inclusions.png").stat().st_size > 1000
    c = json.loads((tmp_path / "inclusions.json").read_text())["cases"]["weak"]
    assert c["final_load_over_peak"] < 0.5
    assert c["interface_broken_share"] > 2 * c["main_broken_share"]
    assert c["interface_enrichment"] > 1.5
    assert c["cracked_mortar_near_aggregate_share"] > c["mortar_near_aggregate_share"]
    assert c["aggregates_broken_share"] < c["main_broken_share"]
    assert c["peak_nominal_stress_Pa"] < 25.0e9 * c["mortar_critical_stretch"]


@pytest.mark.slow
def test_bend_readme_runs(tmp_path: Path) -> None:
    """The README's bend at dx = 2.5 mm, bilinear and brittle (about 2 min)."""
    res = _bend(tmp_path, "--laws", "bilinear", "brittle")
    est = res["estimates"]
    soft, brittle = res["runs"]["bilinear dx=2.5 mm"], res["runs"]["brittle dx=2.5 mm"]
    assert est["P_net_section_elastic_N"] < soft["peak_load_N"] < est["P_rigid_plastic_N"]
    assert soft["final_over_peak"] < 0.2
    assert soft["largest_cmod_decrease_after_peak_m"] < 0.01 * soft["final_cmod_m"]
    assert soft["max_reaction_imbalance_over_peak"] < 0.05
    assert 0.6 < soft["work_over_GF_ligament"] < 1.1
    assert brittle["peak_before_first_drop_N"] > 1.5 * soft["peak_load_N"]


@pytest.mark.slow
def test_inclusions_readme_runs(tmp_path: Path) -> None:
    """The README's plate at dx = 0.5 mm, weak and strong interfaces and no aggregates
    (about 90 s): the weak interface breaks more and its cracks keep to the aggregates;
    the aggregates (stiff defects) and the weak interface lower the strength."""
    assert _script("inclusions").main(["--out", str(tmp_path)]) == 0
    res = json.loads((tmp_path / "inclusions.json").read_text())["cases"]
    weak, strong, plain = res["weak"], res["strong"], res["plain"]
    assert weak["interface_enrichment"] > 2 * strong["interface_enrichment"]
    assert weak["peak_load_N"] < strong["peak_load_N"] < plain["peak_load_N"]
    assert plain["peak_nominal_stress_Pa"] < 25.0e9 * plain["mortar_critical_stretch"]
    assert weak["cracked_mortar_near_aggregate_share"] > weak["mortar_near_aggregate_share"]
