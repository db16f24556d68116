"""Sparse direct and iterative solvers on the free-free tangent of the static solver at
paper size: the micropolar L-panel (``examples/micropolar/l_panel.yaml`` as shipped:
dx = 2.5 mm, delta = 5.015 dx, about 30 500 points and 90 000 free dofs).

Usage::

    python benchmarks/static_solvers.py                       # every candidate installed
    python benchmarks/static_solvers.py --only superlu-mmd,pardiso
    python benchmarks/static_solvers.py --spacing 5e-3        # a smaller panel
    python benchmarks/static_solvers.py --matrix k.npz        # cache K_ff (and reuse it)

The tangent is built through the package (``Simulation.from_deck`` -> the static
solver's model -> ``model.tangent`` at u = 0, free dofs as
:class:`peridynamics.solvers.tangent_system.TangentSystem` takes them) and scaled by its
diagonal as :mod:`peridynamics.solvers.linear` does. For each candidate it prints (and
writes as JSON with ``--json``): the ordering/analysis + factorisation time, the time of
one solve (one right-hand side), of a block of 8 right-hand sides, the entries of the
factors, the peak resident memory of the process after the candidate, and the relative
residual ||A x - b|| / ||b||. Candidates:

* ``superlu-mmd``: ``splu`` with MMD_AT_PLUS_A, symmetric mode (the solver before);
* ``superlu-colamd``: ``splu`` with COLAMD, partial pivoting (its default);
* ``superlu-rcm``: reverse Cuthill-McKee of the point graph, then ``splu`` NATURAL;
* ``cholmod``: CHOLMOD through ``cholespy`` (if installed);
* ``pardiso``: MKL PARDISO, Cholesky with METIS (:mod:`peridynamics.solvers.pardiso`,
  if the ``mkl`` wheel is installed);
* ``amg``: pyamg smoothed aggregation + CG to 1e-10 (setup, one solve).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

DECK = Path(__file__).resolve().parents[1] / "examples" / "micropolar" / "l_panel.yaml"
CANDIDATES = (
    "superlu-mmd",
    "superlu-colamd",
    "superlu-rcm",
    "cholmod",
    "pardiso",
    "amg",
)


def _cpu() -> str:
    from _machine import cpu_model  # benchmarks/ is on sys.path when run as a script

    return cpu_model()


def _rss_mib() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def tangent(spacing: float | None, horizon: float | None) -> dict[str, Any]:
    """K_ff (scaled by its diagonal), the free dofs' point of origin, the coordinates."""
    from peridynamics.app.run import Simulation
    from peridynamics.deck import load_deck
    from peridynamics.solvers import linear as lin

    sets = ["output.crack_paths=[]", "output.plot=none"]
    if spacing is not None:
        sets.append(f"discretisation.spacing={spacing}")
    if horizon is not None:
        sets.append(f"discretisation.horizon_factor={horizon}")
    t0 = time.perf_counter()
    sim = Simulation.from_deck(load_deck(DECK, overrides=sets))
    solver: Any = sim.solver
    s = solver.init()
    k = sp.csr_matrix(solver.model.tangent(s))
    free = np.flatnonzero(~solver.fixed & (k.diagonal() > 0))
    k_ff = k[free][:, free].tocsr()
    d = lin._scaling(k_ff)
    a = lin._scaled(k_ff, d)
    return {
        "a": a,
        "point": free // solver.width,
        "free": free,
        "width": int(solver.width),
        "x": np.asarray(solver.model.cloud.x),
        "build_s": time.perf_counter() - t0,
        "points": int(solver.model.n_points),
        "d": d,
    }


def _time(fn: Callable[[], Any]) -> tuple[Any, float]:
    t0 = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t0


def _superlu(a: sp.csr_matrix, perm: np.ndarray | None, spec: str, sym: bool) -> Any:
    if perm is not None:
        a = a[perm][:, perm]
    opts: dict[str, Any] = {"SymmetricMode": True} if sym else {}
    lu = spla.splu(
        sp.csc_matrix(a), permc_spec=spec, diag_pivot_thresh=0.0 if sym else 1.0, options=opts
    )
    fill = int(lu.L.nnz + lu.U.nnz)
    if perm is None:
        return lu.solve, fill
    inv = np.empty_like(perm)
    inv[perm] = np.arange(len(perm))

    def solve(b: np.ndarray) -> np.ndarray:
        return lu.solve(np.ascontiguousarray(b[perm]))[inv]

    return solve, fill


def _point_graph(a: sp.csr_matrix, point: np.ndarray) -> sp.csr_matrix:
    n = int(point.max()) + 1
    c = a.tocoo()
    g = sp.csr_matrix((np.ones(c.nnz), (point[c.row], point[c.col])), shape=(n, n))
    return g


def _expand(order: np.ndarray, point: np.ndarray) -> np.ndarray:
    """A point order -> the dof order (the dofs of a point stay together)."""
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    return np.lexsort((np.arange(len(point)), rank[point]))


def candidate(name: str, m: dict[str, Any]) -> dict[str, Any]:
    """Factor and solve with one candidate; returns its measurements."""
    a: sp.csr_matrix = m["a"]
    n = a.shape[0]
    rng = np.random.default_rng(0)
    b = rng.standard_normal(n)
    block = rng.standard_normal((n, 8))
    extra: dict[str, Any] = {}
    fill: int | None = None
    if name == "superlu-mmd":
        (solve, fill), t_f = _time(lambda: _superlu(a, None, "MMD_AT_PLUS_A", True))
    elif name == "superlu-colamd":
        (solve, fill), t_f = _time(lambda: _superlu(a, None, "COLAMD", False))
    elif name == "superlu-rcm":
        t0 = time.perf_counter()
        g = _point_graph(a, m["point"])
        from scipy.sparse.csgraph import reverse_cuthill_mckee

        order = np.asarray(reverse_cuthill_mckee(g, symmetric_mode=True))
        perm = _expand(order, m["point"])
        extra["ordering_s"] = time.perf_counter() - t0
        (solve, fill), t_f = _time(lambda: _superlu(a, perm, "NATURAL", True))
        t_f += extra["ordering_s"]
    elif name == "cholmod":
        import cholespy

        def build() -> Any:
            c = sp.csc_matrix(a)
            f = cholespy.CholeskySolverD(
                n, c.indptr.astype(np.int32), c.indices.astype(np.int32), c.data,
                cholespy.MatrixType.CSC,
            )  # fmt: skip

            def solve(rhs: np.ndarray) -> np.ndarray:
                rhs = np.ascontiguousarray(rhs)
                out = np.zeros_like(rhs)
                f.solve(rhs, out)
                return out

            return solve

        solve, t_f = _time(build)
    elif name == "pardiso":
        from peridynamics.solvers.pardiso import PardisoCholesky

        fac, t_f = _time(lambda: PardisoCholesky(a))
        solve, fill = fac.solve, fac.fill
    elif name == "amg":
        import pyamg

        from peridynamics.solvers.linear import rigid_modes

        def build_a() -> Any:
            # as peridynamics.solvers.linear.AMGSolver: the modes of the scaled system
            bnull = rigid_modes(m["x"], m["width"])[m["free"]] / m["d"][:, None]
            bnull /= np.linalg.norm(bnull, axis=0)
            ml = pyamg.smoothed_aggregation_solver(a, B=bnull, symmetry="hermitian")
            pre = ml.aspreconditioner(cycle="V")
            its = [0]

            def solve(rhs: np.ndarray) -> np.ndarray:
                cols = rhs.reshape(n, -1)
                out = np.empty_like(cols)
                its[0] = 0

                def tick(_x: np.ndarray) -> None:
                    its[0] += 1

                for j in range(cols.shape[1]):
                    out[:, j], _ = spla.cg(
                        a, cols[:, j], rtol=1e-10, maxiter=5000, M=pre, callback=tick
                    )
                its[0] //= cols.shape[1]
                return out.reshape(rhs.shape)

            return solve, its

        (solve, its), t_f = _time(build_a)
    else:
        raise ValueError(name)
    x, t_1 = _time(lambda: solve(b))
    _, t_1b = _time(lambda: solve(b))
    xb, t_8 = _time(lambda: solve(block))
    if name == "amg":
        extra["cg_iterations"] = its[0]
    res = float(np.linalg.norm(a @ x - b) / np.linalg.norm(b))
    res8 = float(np.linalg.norm(a @ xb - block) / np.linalg.norm(block))
    return {
        "candidate": name,
        "factor_s": t_f,
        "solve_1_s": min(t_1, t_1b),
        "solve_8_s": t_8,
        "factor_entries": fill,
        "peak_rss_mib": _rss_mib(),
        "residual": max(res, res8),
        **extra,
    }


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--spacing", type=float, default=None, help="default: the deck's 2.5 mm")
    ap.add_argument("--horizon", type=float, default=None, help="default: the deck's 5.015")
    ap.add_argument("--only", default=",".join(CANDIDATES))
    ap.add_argument("--matrix", type=Path, default=None, help="npz cache of K_ff")
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args()
    if args.matrix is not None and args.matrix.exists():
        z = np.load(args.matrix)
        m = {
            "a": sp.csr_matrix((z["data"], z["indices"], z["indptr"]), shape=tuple(z["shape"])),
            "point": z["point"], "x": z["x"], "build_s": None, "points": int(z["points"]),
            "free": z["free"], "width": int(z["width"]), "d": z["scale"],
        }  # fmt: skip
    else:
        m = tangent(args.spacing, args.horizon)
        if args.matrix is not None:
            a = m["a"]
            np.savez(
                args.matrix, data=a.data, indices=a.indices, indptr=a.indptr, shape=a.shape,
                point=m["point"], x=m["x"], points=m["points"], free=m["free"],
                width=m["width"], scale=m["d"],
            )  # fmt: skip
    a = m["a"]
    print(f"K_ff: {a.shape[0]} dofs, {a.nnz} entries, {m['points']} points", flush=True)
    rows = []
    for name in args.only.split(","):
        try:
            r = candidate(name, m)
        except ImportError as exc:
            r = {"candidate": name, "skipped": str(exc)}
        print(json.dumps(r), flush=True)
        rows.append(r)
    out = {
        "machine": f"{_cpu()}, {os.cpu_count()} cores",
        "dofs": int(a.shape[0]),
        "nnz": int(a.nnz),
        "points": m["points"],
        "build_s": m["build_s"],
        "candidates": rows,
    }
    if args.json:
        args.json.write_text(json.dumps(out, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
