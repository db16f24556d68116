"""Cost of one force evaluation with commit (the force work of an explicit step) of
the elastic and the elastic-plastic LPS on a 3-D box
(docs/theory_plasticity.md, "Elastic-plastic LPS"), the plastic model in an elastic
state (homogeneous strain below yield) and in a plastic one (every point yielding).
Usage: NUMBA_NUM_THREADS=2 python examples/plasticity/cost_per_step_lps.py [n] [reps]"""

import copy
import sys
import time

import numpy as np

from peridynamics.app.run import Simulation
from peridynamics.deck import parse_deck

n = int(sys.argv[1]) if len(sys.argv) > 1 else 20
steps = int(sys.argv[2]) if len(sys.argv) > 2 else 20
dx = 1e-3
base = {
    "name": "cost",
    "geometry": {"type": "box", "size": [n * dx] * 3},
    "discretisation": {"spacing": dx, "horizon_factor": 3.015},
    "material": {"model": "lps", "youngs_modulus": 200e9, "poisson_ratio": 0.3,
                 "density": 7800.0},
    "solver": {"type": "explicit", "steps": 10},
    "output": {"plot": "none", "vtk_every": 0},
}  # fmt: skip
cases = {"elastic": None, "plastic, elastic state": 1e12, "plastic, yielding": 1e6}
models = {}
for name, sy in cases.items():
    d = copy.deepcopy(base)
    if sy is not None:
        d["material"]["plasticity"] = {"type": "j2", "yield_stress": sy}
    model = Simulation.from_deck(parse_deck(d)).model
    s = model.new_state()
    s.u[...] = model.cloud.x @ np.diag([1e-3, -3e-4, -3e-4])
    model.evaluate(s, commit=True)  # compile and warm up
    models[name] = (model, s)
times: dict[str, list[float]] = {name: [] for name in cases}
for _ in range(5):  # alternating rounds: a shared machine drifts
    for name, (model, s) in models.items():
        t0 = time.perf_counter()
        for _ in range(steps):
            model.evaluate(s, commit=True)  # the force work of one explicit step
        times[name].append((time.perf_counter() - t0) / steps)
model = models["elastic"][0]
print(f"{model.cloud.n_points} points, {model.bonds.n_bonds} bonds")
for name, t in times.items():
    print(f"{name:24s} ms/evaluation: best {1e3 * min(t):.2f}, median {1e3 * np.median(t):.2f}")
for name in list(cases)[1:]:
    best = min(times[name]) / min(times["elastic"])
    med = np.median(times[name]) / np.median(times["elastic"])
    print(f"{name} / elastic: best {best:.2f}, median {med:.2f}")
