"""Cost of one explicit step of the elastic and the viscoelastic LPS on a 3-D box
(docs/theory_viscoelasticity.md, "Cost"). Usage:
NUMBA_NUM_THREADS=2 python examples/viscoelastic/cost_per_step.py [n_per_side] [steps]"""

import copy
import sys
import time

import numpy as np

from peridynamics.app.run import Simulation
from peridynamics.deck import parse_deck

n = int(sys.argv[1]) if len(sys.argv) > 1 else 20
steps = int(sys.argv[2]) if len(sys.argv) > 2 else 100
dx = 1e-3
base = {
    "name": "cost",
    "geometry": {"type": "box", "size": [n * dx] * 3},
    "discretisation": {"spacing": dx, "horizon_factor": 3.015},
    "material": {"model": "lps", "youngs_modulus": 1e9, "poisson_ratio": 0.3, "density": 1000.0},
    "solver": {"type": "explicit", "steps": 10},
    "output": {"plot": "none", "vtk_every": 0},
}
times: dict[str, list[float]] = {}
for name in ("elastic", "viscoelastic") * 3:  # alternating: a shared machine drifts
    d = copy.deepcopy(base)
    if name == "viscoelastic":
        d["material"]["viscoelastic"] = {"fraction": 0.5, "relaxation_time": 1e-5}
    sim = Simulation.from_deck(parse_deck(d))
    s = sim.solver.init()
    s.u[...] = 1e-6 * np.random.default_rng(0).standard_normal(s.u.shape)
    for _ in range(5):  # compile and warm up
        sim.solver.step(s)
    t0 = time.perf_counter()
    for _ in range(steps):
        sim.solver.step(s)
    per = (time.perf_counter() - t0) / steps
    times.setdefault(name, []).append(per)
    print(f"{name}: {sim.model.cloud.n_points} points, {sim.model.bonds.n_bonds} bonds, "
          f"{per * 1e3:.2f} ms/step", flush=True)  # fmt: skip
ratio = min(times["viscoelastic"]) / min(times["elastic"])
print(f"best of three: viscoelastic / elastic = {ratio:.2f}")
