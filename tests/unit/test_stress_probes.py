"""Probes of the point stress (``quantity: stress | strain | von_mises | pressure |
principal_stress``): the recorded value is the reduction of the point field over the
node set at that record, and the deck refuses a tensor component on a vector."""

from __future__ import annotations

import numpy as np
import pytest

import peridynamics as pd
from peridynamics.deck import DeckError

DECK = {
    "name": "stress_probes",
    "geometry": {"type": "rectangle", "size": [0.02, 0.01], "thickness": 1e-3},
    "discretisation": {"spacing": 1e-3, "horizon_factor": 3.015},
    "material": {"model": "lps", "youngs_modulus": 70e9, "density": 2700.0,
                 "poisson_ratio": 0.3},
    "node_sets": {"right": {"edge": {"normal": [1.0, 0.0]}},
                  "left": {"edge": {"normal": [-1.0, 0.0]}},
                  "middle": {"box": {"min": [0.008, 0.003], "max": [0.012, 0.007]}}},
    "boundary_conditions": [
        {"type": "velocity", "set": "right", "components": {"x": 1.0}},
        {"type": "velocity", "set": "left", "components": {"x": -1.0}},
    ],
    "solver": {"type": "explicit", "steps": 40},
    "output": {"history_every": 40, "plot": "none", "probes": [
        {"name": "sxx", "quantity": "stress", "set": "middle", "component": "xx"},
        {"name": "eyy", "quantity": "strain", "set": "middle", "component": "y"},
        {"name": "vm", "quantity": "von_mises", "set": "middle", "reduce": "max"},
        {"name": "p", "quantity": "pressure", "set": "middle", "reduce": "min"},
        {"name": "s1", "quantity": "principal_stress", "set": "middle"},
    ]},
}  # fmt: skip


def test_stress_probes_reduce_the_point_fields(tmp_path) -> None:
    sim = pd.Simulation(pd.Deck.from_dict(DECK), out=tmp_path / "run")
    result = sim.run()
    nodes = sim.model.cloud.node_set("middle")
    last = {k: v["values"][-1] if isinstance(v, dict) else v[-1]
            for k, v in result.summary["results"]["probes"].items()}  # fmt: skip
    stress, strain = sim.field("stress")[nodes], sim.field("strain")[nodes]
    assert last["sxx"] == pytest.approx(float(np.mean(stress[:, 0, 0])), rel=1e-12)
    assert last["eyy"] == pytest.approx(float(np.mean(strain[:, 1, 1])), rel=1e-12)
    assert last["vm"] == pytest.approx(float(np.max(sim.field("von_mises")[nodes])), rel=1e-12)
    assert last["p"] == pytest.approx(float(np.min(sim.field("pressure")[nodes])), rel=1e-12)
    s1 = sim.field("principal_stress")[nodes, 0]
    assert last["s1"] == pytest.approx(float(np.mean(s1)), rel=1e-12)
    assert last["sxx"] > 0 and last["eyy"] < 0  # pulled along x, contracting along y


@pytest.mark.parametrize(
    ("probe", "why"),
    [
        ({"quantity": "displacement", "component": "xy"}, "tensor component"),
        ({"quantity": "stress", "component": "magnitude"}, "von_mises"),
    ],
)
def test_components_that_do_not_fit_are_refused(probe: dict, why: str) -> None:
    deck = {**DECK, "output": {"probes": [{"name": "bad", "set": "middle", **probe}]}}
    with pytest.raises(DeckError, match=why):
        pd.Deck.from_dict(deck)
