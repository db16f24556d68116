"""The lower layers as a script meets them: a reference state of a built model has every
field its force model reads (the evaluator is accepted, a micropolar model gets its
rotations)."""

from __future__ import annotations

import numpy as np

import peridynamics as pd
from peridynamics.solvers.linear_static import reference_state


def test_reference_state_of_a_built_micropolar_model_has_its_rotations():
    sim = pd.Simulation(pd.Deck.example("micropolar/dcb"))
    state = reference_state(sim.model)  # the evaluator, not its force model
    n = sim.n_points
    for name in ("theta", "omega", "moment", "body_moment"):
        assert state[name].shape == (n, 1), name
    fm = sim.model.force_model
    fm.prepass(state)
    fm.force(state)  # no KeyError, no typing error: zero displacement, zero force
    assert np.all(state.force == 0.0) and np.all(state["moment"] == 0.0)
