"""``quantity: temperature`` probes of the heat solvers record the node set's reduced
temperature at each record, ``final_state.npz`` holds the temperature, and a mechanical
probe on a heat solver (or a temperature probe on a mechanical one) is refused by key."""

from __future__ import annotations

import numpy as np
import pytest

import peridynamics as pd
from peridynamics.deck import DeckError
from peridynamics.io.final_state import read_final_state

PROBES = [
    {"name": "centre_T", "quantity": "temperature", "set": "centre"},
    {"name": "edge_T_min", "quantity": "temperature", "set": "left", "reduce": "min"},
]


def test_temperature_probes_and_final_state(tmp_path) -> None:
    deck = pd.Deck.example(
        "thermal",
        {"discretisation.spacing": 4e-3, "solver.end_time": 0.5, "output.vtk_every": 0,
         "output.probes": PROBES, "output.plot": "none"},
    )  # fmt: skip
    sim = pd.Simulation(deck, out=tmp_path / "run")
    result = sim.run()
    final = read_final_state(tmp_path / "run")
    T = final["temperature"]
    nodes = sim.model.cloud.node_set("centre")
    probes = result.summary["results"]["probes"]
    centre = probes["centre_T"]
    last = centre["values"][-1] if isinstance(centre, dict) else centre[-1]
    assert last == pytest.approx(float(T[nodes].mean()), rel=1e-14)
    assert 293.15 < last < 373.15  # warmed, not yet at the edges' temperature
    edge = probes["edge_T_min"]
    edge_last = edge["values"][-1] if isinstance(edge, dict) else edge[-1]
    assert edge_last == pytest.approx(float(np.min(T[sim.model.cloud.node_set("left")])))


@pytest.mark.parametrize(
    ("example", "probe", "why"),
    [
        ("thermal", {"quantity": "displacement", "set": "centre"}, "records temperature"),
        ("plate_tension_2d", {"quantity": "temperature", "set": "all"}, "heat solver"),
    ],
)
def test_probes_that_do_not_fit_the_solver_are_refused(example, probe, why) -> None:
    with pytest.raises(DeckError, match=why):
        pd.Deck.example(example, {"output.probes": [{"name": "p", **probe}]})
