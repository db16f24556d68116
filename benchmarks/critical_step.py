"""Measured critical explicit step against the stable step, per family and geometry.

For PMB, LPS and correspondence (LBSCMM), on a 2-D plate (plane stress) and a 3-D box
(delta = 3.015 dx, the deck default surface correction), this prints

* the largest eigenvalue of M^-1 K from a dense eigen-solve of M^-1/2 K M^-1/2 (K the
  family's analytic tangent, else the finite-difference one), and the analytic bound
  (``max_i 2 K_i / rho``) and the Lanczos estimate (:mod:`peridynamics.evaluation.spectral`,
  with its safety factor) over it;
* the critical step dt_c, by bisection (in log dt) for the largest dt at which the real
  explicit solver (velocity Verlet) keeps a body released with random velocities
  bounded (max |v| below 100 times its start) over ``--steps`` steps;
* the stable step the solver uses (``Evaluator.stable_time_step``), analytic and
  Lanczos, over dt_c, and the set-up cost of the estimate.

Usage: ``python benchmarks/critical_step.py [--steps 3000] [--bisections 12]
[--no-dense] [--json out.json]``. Takes a few minutes on two cores (the dense
finite-difference tangent of the 3-D correspondence box is the slow part).
"""

from __future__ import annotations

import argparse
import json
import math
import time
import warnings

import numba
import numpy as np
import scipy.linalg as sla

from peridynamics import BondBasedMaterial, Evaluator, ExplicitSolver, build_bonds
from peridynamics.families.correspondence.material import CorrespondenceMaterial
from peridynamics.families.lps.material import LPSMaterial
from peridynamics.families.tangent import finite_difference_tangent
from peridynamics.geometry import box, rectangle

E, NU, RHO, DX = 70e9, 0.25, 2700.0, 1e-3
FAMILIES = ("pmb", "lps", "correspondence")
GEOMETRIES = {"plate": (2, 20), "box": (3, 8)}  # (dim, points per side)


def build(family: str, dim: int, side: int) -> Evaluator:
    """An Evaluator of ``side`` points per side, surface correction on (deck default)."""
    cloud = rectangle((side * DX,) * 2, DX) if dim == 2 else box((side * DX,) * 3, DX)
    bonds = build_bonds(cloud, 3.015 * DX)
    material = {
        "pmb": lambda: BondBasedMaterial(E, RHO),
        "lps": lambda: LPSMaterial(E, NU, RHO),
        "correspondence": lambda: CorrespondenceMaterial(E, NU, RHO),
    }[family]()
    return Evaluator(cloud, bonds, material, surface_correction=True)


def dense_lambda_max(model: Evaluator) -> float:
    """Largest eigenvalue of M^-1 K (1/s^2) from scipy.linalg.eigh of M^-1/2 K M^-1/2."""
    fm = model.force_model
    st = model.new_state()
    k = fm.tangent(st)
    if k is None:
        k = finite_difference_tangent(fm, st)
    k = k.toarray() if hasattr(k, "toarray") else np.asarray(k)
    m = np.repeat(model.density * model.cloud.volume, model.dim)
    b = 0.5 * (k + k.T) / np.sqrt(np.outer(m, m))
    return float(sla.eigh(b, eigvals_only=True, subset_by_index=[len(m) - 1, len(m) - 1])[0])


def stays_bounded(model: Evaluator, dt: float, steps: int, seed: int = 1) -> bool:
    """``steps`` velocity-Verlet steps of the real solver from random velocities: True
    unless max |v| grows 100-fold (or goes non-finite)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        solver = ExplicitSolver(model, time_step=dt, allow_unstable=True, check_every=10**9)
    s = solver.init()
    s.v[:] = np.random.default_rng(seed).normal(0.0, 1e-3, s.v.shape)
    s.u_prev[:] = s.u - dt * s.v
    v0 = float(np.abs(s.v).max())
    with np.errstate(all="ignore"):
        for k in range(steps):
            solver.step(s)
            if k % 100 == 99 and not np.abs(s.v).max() < 100 * v0:
                return False
        return bool(np.isfinite(s.v).all() and np.abs(s.v).max() < 100 * v0)


def critical_step(model: Evaluator, guess: float, steps: int, bisections: int) -> float:
    """Largest bounded dt (s) by bisection in log dt, bracketed around ``guess``."""
    lo, hi = guess, guess
    while not stays_bounded(model, lo, steps):
        lo /= 1.5
    while stays_bounded(model, hi, steps):
        hi *= 1.5
    for _ in range(bisections):
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if stays_bounded(model, mid, steps) else (lo, mid)
    return lo


def measure(family: str, geometry: str, steps: int, bisections: int, dense: bool) -> dict:
    """One row of the table (see the module docstring)."""
    dim, side = GEOMETRIES[geometry]
    model = build(family, dim, side)
    model.use_spectral_bound = False
    analytic = model.stable_time_step()
    model.use_spectral_bound = True
    t0 = time.perf_counter()
    stable = model.stable_time_step()
    setup = time.perf_counter() - t0
    row: dict = {"family": family, "geometry": geometry, "points": model.n_points}
    row["dt_analytic"], row["dt_stable"], row["setup_s"] = analytic, stable, setup
    if model.spectral_applies:
        est = model.spectral_estimate("mass")
        row["lanczos_ritz"], row["evaluations"] = est.ritz, est.evaluations
    if dense:
        lam = dense_lambda_max(model)
        row["lambda_true"] = lam
        row["analytic_over_true"] = (2.0 / analytic) ** 2 / lam
        row["stable_over_true"] = (2.0 / stable) ** 2 / lam
        if "lanczos_ritz" in row:
            row["ritz_over_true"] = row["lanczos_ritz"] / lam
    crit = critical_step(model, stable, steps, bisections)
    row["dt_critical"] = crit
    row["analytic_over_critical"] = analytic / crit
    row["stable_over_critical"] = stable / crit
    return row


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--steps", type=int, default=3000)
    p.add_argument("--bisections", type=int, default=12)
    p.add_argument("--no-dense", action="store_true", help="skip the dense eigen-solve")
    p.add_argument("--json", help="write the rows to this file")
    args = p.parse_args()
    numba.set_num_threads(1)  # small models: a parallel launch costs more than the work
    rows = []
    head = (
        "family          geom   n    lam_an/true lam_st/true ritz/true  dt_an/dt_c dt_st/dt_c setup"
    )
    print(head)
    for family in FAMILIES:
        for geometry in GEOMETRIES:
            r = measure(family, geometry, args.steps, args.bisections, not args.no_dense)
            rows.append(r)

            def f(key: str, r: dict = r) -> str:
                return f"{r[key]:10.3f}" if key in r else "         -"

            print(
                f"{family:15s} {geometry:5s} {r['points']:4d} {f('analytic_over_true')}  "
                f"{f('stable_over_true')} {f('ritz_over_true')} {f('analytic_over_critical')} "
                f"{f('stable_over_critical')} {r['setup_s']:.2f}s",
                flush=True,
            )
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rows, fh, indent=1)


if __name__ == "__main__":
    main()
