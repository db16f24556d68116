"""Cost of one force evaluation with commit (the work of an explicit step) of the
elastic and the elastic-plastic correspondence model on a 3-D box (AMD EPYC, 2 cores,
shared). Usage: python examples/plasticity/cost_per_step.py [n_per_side]"""

import copy
import sys
import time

import numpy as np

from peridynamics.app.run import Simulation
from peridynamics.deck import parse_deck

n = int(sys.argv[1]) if len(sys.argv) > 1 else 16
dx = 1e-3
base = {
    "name": "cost",
    "geometry": {"type": "box", "size": [n * dx] * 3},
    "discretisation": {"spacing": dx, "horizon_factor": 3.015},
    "material": {
        "model": "correspondence",
        "youngs_modulus": 200e9,
        "poisson_ratio": 0.3,
        "density": 7800.0,
    },
    "solver": {"steps": 10},
    "output": {"plot": "none", "vtk_every": 0},
}
variants = {
    "elastic (linear_elastic)": {"law": "linear_elastic"},
    "elastic (st_venant_kirchhoff)": {},
    "j2": {
        "plasticity": {
            "type": "j2",
            "yield_stress": 200e6,
            "hardening_modulus": 2e9,
            "kinematic_modulus": 2e9,
        }
    },
    "drucker_prager": {
        "plasticity": {
            "type": "drucker_prager",
            "cohesion": 40e6,
            "friction_angle": 30.0,
            "dilation_angle": 10.0,
        }
    },
}
for strain in (5e-4, 4e-3):
    for name, extra in variants.items():
        d = copy.deepcopy(base)
        d["material"].update(extra)
        model = Simulation.from_deck(parse_deck(d)).model
        s = model.new_state()
        s.u[...] = model.cloud.x @ np.diag([strain, -0.3 * strain, -0.3 * strain])
        model.evaluate(s, commit=True)  # compile / warm
        reps = 20
        t0 = time.perf_counter()
        for _ in range(reps):
            model.evaluate(s, commit=True)
        dt = (time.perf_counter() - t0) / reps
        tag = (
            "plastic"
            if "plastic_history" in s and np.abs(s["plastic_history"]).max() > 0
            else "elastic"
        )
        pts, nb = model.cloud.n_points, model.bonds.n_bonds
        print(
            f"points {pts} bonds {nb} strain {strain:g} {name:32s} "
            f"{1e3 * dt:8.2f} ms/evaluation ({tag} state)",
            flush=True,
        )
