"""The decks of ``examples/geometry`` (an STL tube, a Gmsh plate with a hole, an
image-based concrete mesostructure) run through the CLI at a small size, and the
figure script at a coarse one (``long``). The checks are the geometry the decks
describe (volumes, node sets) and the sign and size of the loads."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from tests.helpers import EXAMPLES, load_script

HERE = EXAMPLES / "geometry"


def _summary(example_run, deck: str, *sets: str) -> tuple[dict, Path]:
    out = example_run("geometry", deck, *sets)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "completed"
    return summary, out


def test_tube_from_stl_runs(example_run) -> None:
    """dx = 2 mm (2.5 cells across the wall): the filled tube holds its STL volume to
    10 % (1.004 at the shipped 1 mm), the held bottom pulls back (a negative reaction)."""
    pytest.importorskip("trimesh")
    s, out = _summary(example_run, "tube.yaml", "discretisation.spacing=2e-3")
    x = np.load(out / "final_state.npz")["x"]
    rho = np.hypot(x[:, 0], x[:, 1])
    assert rho.min() > 0.005 and rho.max() < 0.010
    stl = 24 * math.sin(2 * math.pi / 48) * (0.01**2 - 0.005**2) * 0.03
    assert len(x) * 8e-9 == pytest.approx(stl, rel=0.1)
    assert s["results"]["probes"]["reaction"]["peak"] < 0


def test_part_from_gmsh_runs(example_run) -> None:
    """dx = 2 mm: the groups of part.geo hold the ends, the volume is the CAD one."""
    pytest.importorskip("gmsh")
    from peridynamics.build.cloud import build_cloud
    from peridynamics.deck import load_deck

    s, _ = _summary(example_run, "part.yaml", "discretisation.spacing=2e-3")
    cloud = build_cloud(load_deck(HERE / "part.yaml", ["discretisation.spacing=2e-3"]))
    cad = (40 * 20 * 10 - math.pi * 5**2 * 10) * 1e-9
    assert cloud.volume.sum() == pytest.approx(cad, rel=0.01)
    assert cloud.n_points == s["results"]["n_points"]
    assert {"left", "right", "part"} <= set(cloud.node_sets)
    assert s["results"]["probes"]["reaction"]["peak"] < 0
    assert s["results"]["probes"]["pull"]["values"][-1] > 0


def test_concrete_from_png_runs_in_one_command(example_run) -> None:
    """dx = 1 mm (one point per 5 x 5 pixels): the pores are gone, the aggregates are a
    body of their own, the plate breaks at a mean stress between the interface's
    strength (E s_i = 2.5 MPa for the mortar) halved and the mortar's (5 MPa)."""
    s, out = _summary(example_run, "concrete.yaml", "discretisation.spacing=1e-3")
    r = s["results"]
    assert r["n_points"] < 800  # 40 x 20 cells less the pores
    assert r["max_damage"] > 0.9
    peak = abs(r["probes"]["reaction"]["peak"]) / (0.02 * 0.01)
    assert 1.25e6 < peak < 5e6


@pytest.mark.long
def test_make_figures_coarse(tmp_path: Path) -> None:
    pytest.importorskip("trimesh")
    pytest.importorskip("gmsh")
    script = load_script(HERE / "make_figures.py", "geometry_make_figures")
    assert script.main(["--out", str(tmp_path), "--spacing-factor", "2.5"]) == 0
    numbers = json.loads((tmp_path / "geometry.json").read_text())
    assert set(numbers) == {"tube", "part", "concrete"}
    assert (tmp_path / "geometry.png").stat().st_size > 10_000
