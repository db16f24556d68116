"""The ``max_stretch`` probe reports the largest stretch of an intact bond at each
record for every model family (the PMB force pass does not track it: before this test
the probe of a PMB run read zeros), checked against a NumPy computation from the final
state; the same under MPI is in the decomposed runs' tests."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import yaml

from peridynamics.app.run import Simulation
from peridynamics.deck import apply_overrides, parse_deck

DECK = """
name: ms
geometry: {type: rectangle, size: [0.02, 0.01], thickness: 1.0e-3, plane: stress}
discretisation: {spacing: 5.0e-4, horizon_factor: 3.015}
material: {model: pmb, youngs_modulus: 70.0e9, density: 2700.0, poisson_ratio: 0.25}
damage: {model: critical_stretch, critical_stretch: 4.0e-3}
node_sets:
  left: {edge: {normal: [-1.0, 0.0]}}
  right: {edge: {normal: [1.0, 0.0]}}
boundary_conditions:
  - {type: velocity, set: right, components: {x: 5.0}}
  - {type: velocity, set: left, components: {x: -5.0}}
solver: {type: explicit, steps: 100}
output:
  history_every: 20
  plot: none
  vtk_every: 0
  probes:
    - {name: s, quantity: max_stretch, set: right}
"""


@pytest.mark.parametrize("model", ["pmb", "lps"])
def test_probe_is_the_largest_intact_stretch(tmp_path: Path, model: str) -> None:
    raw = apply_overrides(yaml.safe_load(DECK), [f"material.model={model}"])
    if model == "pmb":
        del raw["material"]["poisson_ratio"]
    sim = Simulation.from_deck(parse_deck(raw))
    sim.run(tmp_path, quiet=True)
    values = json.loads((tmp_path / "summary.json").read_text())["results"]["probes"]["s"]
    final = np.load(tmp_path / "final_state.npz")
    b, x = sim.model.bonds, sim.model.cloud.x
    i = np.repeat(np.arange(len(x)), np.diff(b.offsets))
    j = b.bond_j
    e = (x[j] - x[i]) + (final["u"][j] - final["u"][i])
    stretch = np.linalg.norm(e, axis=1) / np.linalg.norm(x[j] - x[i], axis=1) - 1.0
    stretch[final["intact"] == 0] = 0.0
    right = sim.model.cloud.node_set("right")
    expect = max(0.0, float(np.max(stretch[np.isin(i, right)])))
    assert expect > 1e-3  # the bar is pulled: its end bonds stretch
    assert values["values"][-1] == pytest.approx(expect, rel=1e-12)
