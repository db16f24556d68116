"""Two measured ideas for the PMB force pass, side by side with the package's kernel in
one process: points reordered along a space-filling curve, and each bond pair once.

Run from the repository root::

    python benchmarks/locality.py                       # 3-D 60^3, 2-D 700^2
    python benchmarks/locality.py --cases 3:100,2:1000 --rounds 7 --json out.json

Cases, each on a grid (dx = 1 mm, delta = 3.015 dx, PMB, no breaking) with a small
random displacement; the force pass alone (``peridynamics.kernels.bond_based``), best of
``--rounds``:

* ``lexicographic``: the generator's order (x fastest), the package's order today;
* ``morton``: the same points sorted by their Morton (Z-order) code of the grid indices
  before the bonds are built: neighbours in space are neighbours in memory, so the
  gathers of x[j] and u[j] hit the cache;
* ``pairs`` (3-D): the prototype pair pass of :mod:`_pair_pass` (each pair once, forces
  scattered to both ends, race-free by blocks of rows) on the lexicographic and the
  Morton order.

Reported per case: directed bonds per second, the median index distance |j - i| of a
bond, and the largest relative force difference against the package's kernel (the
pair pass sums in another order).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
import time
from pathlib import Path

import numba
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _pair_pass as pp  # noqa: E402
from _machine import cpu_model  # noqa: E402

from peridynamics.bonds import build_bonds  # noqa: E402
from peridynamics.damage.critical_stretch import NO_DAMAGE  # noqa: E402
from peridynamics.evaluation import Evaluator  # noqa: E402
from peridynamics.families.pmb import BondBasedMaterial  # noqa: E402
from peridynamics.geometry import box, rectangle  # noqa: E402
from peridynamics.kernels import bond_based  # noqa: E402

DX = 1.0e-3


def morton_order(x: np.ndarray, dx: float) -> np.ndarray:
    """Permutation (n,) sorting grid points by the Morton code of their indices."""
    ix = np.rint((x - x.min(axis=0)) / dx).astype(np.uint64)
    code = np.zeros(len(x), dtype=np.uint64)
    dim = x.shape[1]
    for bit in range(21):
        for c in range(dim):
            code |= ((ix[:, c] >> np.uint64(bit)) & np.uint64(1)) << np.uint64(dim * bit + c)
    return np.argsort(code, kind="stable")


def model(dim: int, side: int, order: str) -> Evaluator:
    """The benchmark body of ``peridynamics bench``, in the generator's or Morton order."""
    if dim == 2:
        cloud = rectangle((side * DX, side * DX), DX, thickness=1e-3)
    else:
        cloud = box((side * DX,) * 3, DX)
    if order == "morton":
        perm = morton_order(cloud.x, DX)
        cloud = dataclasses.replace(
            cloud, x=np.ascontiguousarray(cloud.x[perm]), volume=cloud.volume[perm]
        )
    bonds = build_bonds(cloud, 3.015 * DX)
    return Evaluator(
        cloud, bonds, BondBasedMaterial(youngs_modulus=70e9, density=2500.0), NO_DAMAGE
    )


def best(fn, args: tuple, rounds: int) -> float:  # type: ignore[no-untyped-def]
    """Shortest of ``rounds`` calls of ``fn(*args)`` after one call (compile or load)."""
    fn(*args)
    times = []
    for _ in range(rounds):
        t0 = time.perf_counter()
        fn(*args)
        times.append(time.perf_counter() - t0)
    return min(times)


def run_case(dim: int, side: int, rounds: int) -> list[dict]:
    out = []
    for order in ("lexicographic", "morton"):
        m = model(dim, side, order)
        fm, b, x = m.force_model, m.bonds, m.cloud.x
        n = len(x)
        u = np.random.default_rng(0).normal(scale=1e-7, size=x.shape)
        never, nb = np.full(n, np.inf), np.zeros(n, dtype=np.int64)
        intact = np.ones(b.n_bonds, dtype=np.uint8)
        f_ref = np.zeros_like(x)
        kern = bond_based.FORCE_KERNELS[dim]
        args = (x, u, b.offsets, b.bond_j, fm.stiffness, intact, never, never, f_ref, nb)
        t = best(kern, args, rounds)
        gap = float(np.median(np.abs(b.bond_j.astype(np.int64) - b.bond_i)))
        row = {"dim": dim, "side": side, "points": n, "bonds": b.n_bonds, "order": order}
        out.append({**row, "pass": "directed", "bonds_per_s": b.n_bonds / t,
                    "median_gap": gap, "max_rel_diff": 0.0})  # fmt: skip
        if dim != 3:
            continue
        hs = pp.half_starts(b.offsets, b.bond_j)
        tail = b.offsets[1:] - hs
        pair_of = np.concatenate([[0], np.cumsum(tail)[:-1]]) - hs
        upper = b.bond_j > b.bond_i
        k_ij = np.ascontiguousarray(fm.stiffness[upper])
        k_ji = np.ascontiguousarray(fm.stiffness[b.reverse_index()[upper]])
        blocks = pp.row_blocks(b.offsets, hs, b.bond_j)
        f = np.zeros_like(x)
        pargs = (x, u, b.offsets, hs, pair_of, b.bond_j, k_ij, k_ji, intact, never, never,
                 blocks, f, nb)  # fmt: skip
        t = best(pp.pair_force_3d, pargs, rounds)
        diff = float(np.abs(f - f_ref).max() / np.abs(f_ref).max())
        rate = b.n_bonds / t
        out.append({**row, "pass": "pairs", "bonds_per_s": rate, "median_gap": gap,
                    "max_rel_diff": diff, "blocks": len(blocks) - 1})  # fmt: skip
    return out


def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--cases", default="3:60,2:700", help="dim:side,... (default 3:60,2:700)")
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--json", type=Path, help="also write the rows as JSON")
    a = p.parse_args(argv)
    rows = []
    print(f"{cpu_model()}, {numba.get_num_threads()} Numba threads")
    for case in a.cases.split(","):
        dim, side = (int(v) for v in case.split(":"))
        for r in run_case(dim, side, a.rounds):
            rows.append(r)
            print(f"{r['dim']}-D {r['side']}: {r['order']:>13} {r['pass']:>8} "
                  f"{r['bonds_per_s']:.3e} bonds/s  median |j-i| {r['median_gap']:.0f}  "
                  f"max rel diff {r['max_rel_diff']:.1e}")  # fmt: skip
    if a.json:
        a.json.write_text(json.dumps({"cpu": cpu_model(), "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
