"""Benchmark of the explicit PMB step (force + velocity Verlet) against plain NumPy.

Bond updates per second count directed bonds (entries of the full list) per step, so
the Numba and NumPy figures are comparable: the NumPy baseline (half list, bincount
scatter; PERFORMANCE.md's best NumPy variant) processes the same physical bonds.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from peridynamics.bonds import build_bonds
from peridynamics.damage.critical_stretch import NO_DAMAGE
from peridynamics.evaluation import Evaluator
from peridynamics.families.pmb import BondBasedMaterial
from peridynamics.geometry import bar, box, rectangle
from peridynamics.kernels import reference
from peridynamics.solvers import ExplicitSolver
from peridynamics.state import State

CASES = {
    # name: (dim, points per side)
    "quick": {1: 100_000, 2: 200, 3: 30},
    "default": {1: 1_000_000, 2: 1000, 3: 60},
    "full": {1: 1_000_000, 2: 1000, 3: 100},
    "huge": {1: 8_000_000, 2: 2000, 3: 200},
}
#: sizes whose NumPy baseline is skipped (its half list and temporaries need about four
#: times the memory of the package's bond store: 200^3 would not fit in 24 GiB)
NO_NUMPY_BASELINE = ("huge",)


def peak_rss_bytes() -> int:
    """Peak resident set size of this process so far (bytes; Linux/macOS)."""
    import resource
    import sys

    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return int(peak if sys.platform == "darwin" else peak * 1024)


@dataclass
class BenchResult:
    """One benchmark case."""

    dim: int
    points: int
    bonds: int
    seconds_per_step: float
    bonds_per_second: float
    numpy_seconds_per_step: float
    numpy_bonds_per_second: float
    speedup: float
    bytes_per_bond: float
    setup_s: float
    peak_rss_gib: float
    held_arrays: tuple[str, ...]

    def as_dict(self) -> dict:
        """JSON-ready mapping."""
        return dict(self.__dict__)


def _model(dim: int, n_side: int, damage: Any = NO_DAMAGE) -> Evaluator:
    """The benchmark body: a bar, square or cube of points on a grid (dx = 1 mm,
    delta = 3.015 dx), PMB, ``damage`` (none by default)."""
    dx = 1.0e-3
    if dim == 1:
        cloud = bar(n_side * dx, dx, area=1e-4)
    elif dim == 2:
        cloud = rectangle((n_side * dx, n_side * dx), dx, thickness=1e-3)
    else:
        cloud = box((n_side * dx,) * 3, dx)
    bonds = build_bonds(cloud, 3.015 * dx)
    return Evaluator(cloud, bonds, BondBasedMaterial(youngs_modulus=70e9, density=2500.0), damage)


def run_case(
    dim: int, n_side: int, steps: int = 20, numpy_steps: int = 3, seed: int = 0
) -> BenchResult:
    """Time ``steps`` explicit steps with the Numba kernels and NumPy in one process."""
    t0 = time.perf_counter()
    model = _model(dim, n_side)
    solver = ExplicitSolver(model)
    state = solver.init()
    rng = np.random.default_rng(seed)
    state.v[:] = rng.normal(scale=1e-3, size=state.v.shape)
    solver.run(state, 2)  # warm-up (JIT compile or cache load)
    setup = time.perf_counter() - t0
    t0 = time.perf_counter()
    solver.run(state, steps)
    numba_s = (time.perf_counter() - t0) / steps
    b = model.bonds
    # what the step holds per directed bond: the bond list's arrays (neighbour index,
    # as-built flag and whatever was derived so far), the stiffness, the State's flags
    held = b.nbytes + model.stiffness.nbytes + state.intact.nbytes
    held_arrays = b.held
    peak = peak_rss_bytes()
    numpy_s = _numpy_seconds_per_step(model, solver, state, numpy_steps)
    return BenchResult(
        dim=dim,
        points=model.n_points,
        bonds=b.n_bonds,
        seconds_per_step=numba_s,
        bonds_per_second=b.n_bonds / numba_s,
        numpy_seconds_per_step=numpy_s,
        numpy_bonds_per_second=b.n_bonds / numpy_s,
        speedup=numpy_s / numba_s,
        bytes_per_bond=held / b.n_bonds,
        setup_s=setup,
        peak_rss_gib=peak / 2**30,
        held_arrays=held_arrays,
    )


def _numpy_seconds_per_step(
    model: Evaluator, solver: ExplicitSolver, state: State, numpy_steps: int
) -> float:
    """Seconds per step of the plain-NumPy baseline from ``state`` (NaN when
    ``numpy_steps`` < 1: its half list would make every derived bond array)."""
    if numpy_steps < 1:
        return float("nan")
    b = model.bonds
    half = b.bond_i < b.bond_j
    pi, pj = b.bond_i[half].astype(np.intp), b.bond_j[half].astype(np.intp)
    length = b.bond_length[half]
    k_ij = model.stiffness[half]
    k_ji = model.stiffness[b.reverse_index()[half]]
    x = model.cloud.x
    u, v = state.u.copy(), state.v.copy()
    inv_rho = 1.0 / model.density[:, None]
    dt = solver.dt
    f = reference.force_half_list(x, u, pi, pj, length, k_ij, k_ji)
    t0 = time.perf_counter()
    for _ in range(numpy_steps):  # the baseline's time loop
        v += 0.5 * dt * f * inv_rho
        u += dt * v
        f = reference.force_half_list(x, u, pi, pj, length, k_ij, k_ji)
        v += 0.5 * dt * f * inv_rho
    return (time.perf_counter() - t0) / numpy_steps


def run_benchmarks(
    size: str = "default", dims: tuple[int, ...] = (1, 2, 3), steps: int = 20
) -> list[BenchResult]:
    """Run the benchmark cases of ``size`` ("quick", "default", "full", "huge"); "huge"
    skips the NumPy baseline. Peak RSS is that of the whole process so far: run one
    dimension per process to read it per case."""
    numpy_steps = 0 if size in NO_NUMPY_BASELINE else 3
    return [run_case(d, CASES[size][d], steps=steps, numpy_steps=numpy_steps) for d in dims]
