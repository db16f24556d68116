"""Instruction-mix ceiling of the PMB bond on this machine, next to the package's step.

Run from the repository root::

    python benchmarks/bond_ceiling.py                     # 2-D 1000^2 and 3-D 100^3
    python benchmarks/bond_ceiling.py --cases 2:1000,3:80 --rounds 5 --json out.json

Each ceiling kernel is ``@njit(parallel=True, fastmath=True, error_model="numpy")`` with
``prange`` over points and an inner loop over the point's family in the package's own
directed CSR list (``offsets`` int64, ``bond_j`` int32, per-bond float64 ``stiffness``
and ``inv_length`` of the PMB model), and stores nothing per bond: only the per-point
result. Variants (every one does the float64 arithmetic of the package's bond unless
named f32):

(a) ``mix``        the bond: gather x[j] and u[j], bond vector, square root, division
                   (1/r), g = c (1/L - 1/r), multiply-adds into the point's force.
                   Vectorised by LLVM (AVX-512 gathers for x[j], u[j]); indices are
                   unsigned so that the contiguous per-bond streams are plain loads.
    ``mix_signed`` the same with signed indices, as the package writes them: Numba's
                   negative-index wraparound makes LLVM gather every stream.
    ``mix_scalar`` the same source with fast-math minus ``reassoc``: the family sum
                   may not be reordered, so the loop stays scalar (no gathers).
(a') ``mixflag``   the package's family loop exactly (``_family_2d/3d``): ``mix`` plus
                   the uint8 intact flag and the largest stretch. LLVM keeps it scalar.
(a'') ``lean``     ``mix`` with |xi| recomputed from the gathered x[j] instead of a
                   stored 1/|xi| (one more square root and division, one stream less):
                   the mix of the package's kernel since the lean bond store.
(b) ``nogather``   ``mix`` with j = i + (k - offsets[i]) + 1 computed, not loaded, and
                   x, u as unit-stride columns: plain vector loads, no ``bond_j``
                   stream; stiffness and 1/L are still streamed per bond.
(b') ``alu``       no per-bond memory traffic: the bond vector is made from a per-point
                   base and the bond counter, stiffness and 1/L are per-point constants.
                   Square root, division and multiply-adds only.
(c) ``mix32``      ``mix`` with x, u, stiffness, 1/L and the sums in float32 (fast-math
                   turns 1/sqrt into vrsqrt14ps + a Newton step); ``mix32_scalar`` as
                   ``mix_scalar``. Only the speed matters here: with x ~ 0.1 m and u ~
                   1e-10 m float32 cannot resolve the displacement.

The ceiling of the float64 mix is the fastest of the three builds of (a).

In the same rounds it times the package: ``pkg step`` is ``ExplicitSolver.run`` (what
``peridynamics bench`` times: bond forces with the breaking pass + velocity Verlet +
the periodic check) and ``pkg force`` is the PMB force kernel alone
(``PMBForceModel.force``, a pass with no bond breaking). The lattice, horizon (3.015 dx)
and material are those of ``peridynamics bench`` (:func:`peridynamics.app.bench._model`).
Rounds interleave all kernels so that a change of load hits them alike; a window in
which other processes used more than 0.25 cores is timed again (see ``--quiet-wait``).

Directed bond updates per second = directed bonds / seconds per pass (or per step).
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from numba import get_num_threads, njit, prange

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _load import LoadMeter, best_median, loadavg, peak_rss_gib, timed_clean  # noqa: E402
from _machine import cpu_model  # noqa: E402

_ceil = njit(parallel=True, fastmath=True, error_model="numpy")


# --------------------------------------------------------------------------- 2-D kernels
# Indexing: Numba wraps negative indices (i < 0 -> i + n) for signed integers; that
# select makes LLVM gather even the contiguous per-bond streams. The ceiling kernels
# index with unsigned integers (``q``, ``j``) so only x[j] and u[j] are gathered;
# ``mix_signed_*`` and ``mixflag_*`` index as the package does (signed).
@_ceil
def mix_2d(x, u, offsets, bond_j, inv_length, stiffness, out):
    n = offsets.shape[0] - 1
    for i in prange(n):
        x0, x1, u0, u1 = x[i, 0], x[i, 1], u[i, 0], u[i, 1]
        f0 = 0.0
        f1 = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            q = np.uint64(k)
            j = np.uint64(bond_j[q])
            e0 = (x[j, 0] - x0) + (u[j, 0] - u0)
            e1 = (x[j, 1] - x1) + (u[j, 1] - u1)
            r = np.sqrt(e0 * e0 + e1 * e1)
            g = stiffness[q] * (inv_length[q] - 1.0 / r)
            f0 += g * e0
            f1 += g * e1
        out[i, 0] = f0
        out[i, 1] = f1


@_ceil
def mix_signed_2d(x, u, offsets, bond_j, inv_length, stiffness, out):
    n = offsets.shape[0] - 1
    for i in prange(n):
        x0, x1, u0, u1 = x[i, 0], x[i, 1], u[i, 0], u[i, 1]
        f0 = 0.0
        f1 = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            j = bond_j[k]
            e0 = (x[j, 0] - x0) + (u[j, 0] - u0)
            e1 = (x[j, 1] - x1) + (u[j, 1] - u1)
            r = np.sqrt(e0 * e0 + e1 * e1)
            g = stiffness[k] * (inv_length[k] - 1.0 / r)
            f0 += g * e0
            f1 += g * e1
        out[i, 0] = f0
        out[i, 1] = f1


@_ceil
def mixflag_2d(x, u, offsets, bond_j, inv_length, stiffness, intact, out, smax_out):
    n = offsets.shape[0] - 1
    for i in prange(n):
        x0, x1, u0, u1 = x[i, 0], x[i, 1], u[i, 0], u[i, 1]
        f0 = 0.0
        f1 = 0.0
        smax = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            j = bond_j[k]
            e0 = (x[j, 0] - x0) + (u[j, 0] - u0)
            e1 = (x[j, 1] - x1) + (u[j, 1] - u1)
            r = np.sqrt(e0 * e0 + e1 * e1)
            m = intact[k]
            g = stiffness[k] * m * (inv_length[k] - 1.0 / r)
            f0 += g * e0
            f1 += g * e1
            smax = max(smax, (r * inv_length[k] - 1.0) * m)
        out[i, 0] = f0
        out[i, 1] = f1
        smax_out[i] = smax


@_ceil
def nogather_2d(xa, xb, ua, ub, offsets, inv_length, stiffness, out):
    n = offsets.shape[0] - 1
    for i in prange(n):
        x0, x1, u0, u1 = xa[i], xb[i], ua[i], ub[i]
        f0 = 0.0
        f1 = 0.0
        start = offsets[i]
        for k in range(start, offsets[i + 1]):
            q = np.uint64(k)
            j = np.uint64(i + (k - start) + 1)  # consecutive rows: unit-stride loads
            e0 = (xa[j] - x0) + (ua[j] - u0)
            e1 = (xb[j] - x1) + (ub[j] - u1)
            r = np.sqrt(e0 * e0 + e1 * e1)
            g = stiffness[q] * (inv_length[q] - 1.0 / r)
            f0 += g * e0
            f1 += g * e1
        out[i, 0] = f0
        out[i, 1] = f1


@_ceil
def alu_2d(x, u, offsets, inv_length, stiffness, out):
    n = offsets.shape[0] - 1
    for i in prange(n):
        a0 = x[i, 0] + u[i, 0] + 1e-3
        a1 = x[i, 1] + u[i, 1] + 2e-3
        c = stiffness[offsets[i]]
        il = inv_length[offsets[i]]
        h = 1e-4
        f0 = 0.0
        f1 = 0.0
        start = offsets[i]
        for k in range(start, offsets[i + 1]):
            t = h * (k - start)
            e0 = a0 + t
            e1 = a1 - t
            r = np.sqrt(e0 * e0 + e1 * e1)
            g = c * (il - 1.0 / r)
            f0 += g * e0
            f1 += g * e1
        out[i, 0] = f0
        out[i, 1] = f1


@_ceil
def mix32_2d(x, u, offsets, bond_j, inv_length, stiffness, out):
    n = offsets.shape[0] - 1
    one = np.float32(1.0)
    for i in prange(n):
        x0, x1, u0, u1 = x[i, 0], x[i, 1], u[i, 0], u[i, 1]
        f0 = np.float32(0.0)
        f1 = np.float32(0.0)
        for k in range(offsets[i], offsets[i + 1]):
            q = np.uint64(k)
            j = np.uint64(bond_j[q])
            e0 = (x[j, 0] - x0) + (u[j, 0] - u0)
            e1 = (x[j, 1] - x1) + (u[j, 1] - u1)
            r = np.sqrt(e0 * e0 + e1 * e1)
            g = stiffness[q] * (inv_length[q] - one / r)
            f0 += g * e0
            f1 += g * e1
        out[i, 0] = f0
        out[i, 1] = f1


# --------------------------------------------------------------------------- 3-D kernels
@_ceil
def mix_3d(x, u, offsets, bond_j, inv_length, stiffness, out):
    n = offsets.shape[0] - 1
    for i in prange(n):
        x0, x1, x2 = x[i, 0], x[i, 1], x[i, 2]
        u0, u1, u2 = u[i, 0], u[i, 1], u[i, 2]
        f0 = 0.0
        f1 = 0.0
        f2 = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            q = np.uint64(k)
            j = np.uint64(bond_j[q])
            e0 = (x[j, 0] - x0) + (u[j, 0] - u0)
            e1 = (x[j, 1] - x1) + (u[j, 1] - u1)
            e2 = (x[j, 2] - x2) + (u[j, 2] - u2)
            r = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
            g = stiffness[q] * (inv_length[q] - 1.0 / r)
            f0 += g * e0
            f1 += g * e1
            f2 += g * e2
        out[i, 0] = f0
        out[i, 1] = f1
        out[i, 2] = f2


@_ceil
def mix_signed_3d(x, u, offsets, bond_j, inv_length, stiffness, out):
    n = offsets.shape[0] - 1
    for i in prange(n):
        x0, x1, x2 = x[i, 0], x[i, 1], x[i, 2]
        u0, u1, u2 = u[i, 0], u[i, 1], u[i, 2]
        f0 = 0.0
        f1 = 0.0
        f2 = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            j = bond_j[k]
            e0 = (x[j, 0] - x0) + (u[j, 0] - u0)
            e1 = (x[j, 1] - x1) + (u[j, 1] - u1)
            e2 = (x[j, 2] - x2) + (u[j, 2] - u2)
            r = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
            g = stiffness[k] * (inv_length[k] - 1.0 / r)
            f0 += g * e0
            f1 += g * e1
            f2 += g * e2
        out[i, 0] = f0
        out[i, 1] = f1
        out[i, 2] = f2


@_ceil
def mixflag_3d(x, u, offsets, bond_j, inv_length, stiffness, intact, out, smax_out):
    n = offsets.shape[0] - 1
    for i in prange(n):
        x0, x1, x2 = x[i, 0], x[i, 1], x[i, 2]
        u0, u1, u2 = u[i, 0], u[i, 1], u[i, 2]
        f0 = 0.0
        f1 = 0.0
        f2 = 0.0
        smax = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            j = bond_j[k]
            e0 = (x[j, 0] - x0) + (u[j, 0] - u0)
            e1 = (x[j, 1] - x1) + (u[j, 1] - u1)
            e2 = (x[j, 2] - x2) + (u[j, 2] - u2)
            r = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
            m = intact[k]
            g = stiffness[k] * m * (inv_length[k] - 1.0 / r)
            f0 += g * e0
            f1 += g * e1
            f2 += g * e2
            smax = max(smax, (r * inv_length[k] - 1.0) * m)
        out[i, 0] = f0
        out[i, 1] = f1
        out[i, 2] = f2
        smax_out[i] = smax


@_ceil
def nogather_3d(xa, xb, xc, ua, ub, uc, offsets, inv_length, stiffness, out):
    n = offsets.shape[0] - 1
    for i in prange(n):
        x0, x1, x2 = xa[i], xb[i], xc[i]
        u0, u1, u2 = ua[i], ub[i], uc[i]
        f0 = 0.0
        f1 = 0.0
        f2 = 0.0
        start = offsets[i]
        for k in range(start, offsets[i + 1]):
            q = np.uint64(k)
            j = np.uint64(i + (k - start) + 1)  # consecutive rows: unit-stride loads
            e0 = (xa[j] - x0) + (ua[j] - u0)
            e1 = (xb[j] - x1) + (ub[j] - u1)
            e2 = (xc[j] - x2) + (uc[j] - u2)
            r = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
            g = stiffness[q] * (inv_length[q] - 1.0 / r)
            f0 += g * e0
            f1 += g * e1
            f2 += g * e2
        out[i, 0] = f0
        out[i, 1] = f1
        out[i, 2] = f2


@_ceil
def alu_3d(x, u, offsets, inv_length, stiffness, out):
    n = offsets.shape[0] - 1
    for i in prange(n):
        a0 = x[i, 0] + u[i, 0] + 1e-3
        a1 = x[i, 1] + u[i, 1] + 2e-3
        a2 = x[i, 2] + u[i, 2] + 3e-3
        c = stiffness[offsets[i]]
        il = inv_length[offsets[i]]
        h = 1e-4
        f0 = 0.0
        f1 = 0.0
        f2 = 0.0
        start = offsets[i]
        for k in range(start, offsets[i + 1]):
            t = h * (k - start)
            e0 = a0 + t
            e1 = a1 - t
            e2 = a2 + 0.5 * t
            r = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
            g = c * (il - 1.0 / r)
            f0 += g * e0
            f1 += g * e1
            f2 += g * e2
        out[i, 0] = f0
        out[i, 1] = f1
        out[i, 2] = f2


@_ceil
def mix32_3d(x, u, offsets, bond_j, inv_length, stiffness, out):
    n = offsets.shape[0] - 1
    one = np.float32(1.0)
    for i in prange(n):
        x0, x1, x2 = x[i, 0], x[i, 1], x[i, 2]
        u0, u1, u2 = u[i, 0], u[i, 1], u[i, 2]
        f0 = np.float32(0.0)
        f1 = np.float32(0.0)
        f2 = np.float32(0.0)
        for k in range(offsets[i], offsets[i + 1]):
            q = np.uint64(k)
            j = np.uint64(bond_j[q])
            e0 = (x[j, 0] - x0) + (u[j, 0] - u0)
            e1 = (x[j, 1] - x1) + (u[j, 1] - u1)
            e2 = (x[j, 2] - x2) + (u[j, 2] - u2)
            r = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
            g = stiffness[q] * (inv_length[q] - one / r)
            f0 += g * e0
            f1 += g * e1
            f2 += g * e2
        out[i, 0] = f0
        out[i, 1] = f1
        out[i, 2] = f2


#: fast-math without ``reassoc``: the family sum may not be reordered, so LLVM keeps the
#: inner loop scalar (no gathers); everything else as in ``_ceil``
_scalar = njit(
    parallel=True, fastmath={"nnan", "ninf", "nsz", "arcp", "contract", "afn"},
    error_model="numpy",
)  # fmt: skip


@_ceil
def lean_2d(x, u, offsets, bond_j, stiffness, out):
    """(a) with |xi| recomputed from x (the lean store: no 1/|xi| stream; one more
    square root and division per bond)."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        x0, x1, u0, u1 = x[i, 0], x[i, 1], u[i, 0], u[i, 1]
        f0 = 0.0
        f1 = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            q = np.uint64(k)
            j = np.uint64(bond_j[q])
            d0 = x[j, 0] - x0
            d1 = x[j, 1] - x1
            e0 = d0 + (u[j, 0] - u0)
            e1 = d1 + (u[j, 1] - u1)
            r = np.sqrt(e0 * e0 + e1 * e1)
            g = stiffness[q] * (1.0 / np.sqrt(d0 * d0 + d1 * d1) - 1.0 / r)
            f0 += g * e0
            f1 += g * e1
        out[i, 0] = f0
        out[i, 1] = f1


@_ceil
def lean_3d(x, u, offsets, bond_j, stiffness, out):
    """:func:`lean_2d` in 3-D."""
    n = offsets.shape[0] - 1
    for i in prange(n):
        x0, x1, x2 = x[i, 0], x[i, 1], x[i, 2]
        u0, u1, u2 = u[i, 0], u[i, 1], u[i, 2]
        f0 = 0.0
        f1 = 0.0
        f2 = 0.0
        for k in range(offsets[i], offsets[i + 1]):
            q = np.uint64(k)
            j = np.uint64(bond_j[q])
            d0 = x[j, 0] - x0
            d1 = x[j, 1] - x1
            d2 = x[j, 2] - x2
            e0 = d0 + (u[j, 0] - u0)
            e1 = d1 + (u[j, 1] - u1)
            e2 = d2 + (u[j, 2] - u2)
            r = np.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
            g = stiffness[q] * (1.0 / np.sqrt(d0 * d0 + d1 * d1 + d2 * d2) - 1.0 / r)
            f0 += g * e0
            f1 += g * e1
            f2 += g * e2
        out[i, 0] = f0
        out[i, 1] = f1
        out[i, 2] = f2


KERNELS = {
    2: dict(
        mix=mix_2d, mix_signed=mix_signed_2d, mix_scalar=_scalar(mix_2d.py_func),
        mixflag=mixflag_2d, lean=lean_2d,
        nogather=nogather_2d, alu=alu_2d, mix32=mix32_2d,
        mix32_scalar=_scalar(mix32_2d.py_func),
    ),
    3: dict(
        mix=mix_3d, mix_signed=mix_signed_3d, mix_scalar=_scalar(mix_3d.py_func),
        mixflag=mixflag_3d, lean=lean_3d,
        nogather=nogather_3d, alu=alu_3d, mix32=mix32_3d,
        mix32_scalar=_scalar(mix32_3d.py_func),
    ),
}  # fmt: skip
LABELS = {
    "pkg_step": "pkg step (force+break+Verlet)",
    "pkg_force": "pkg force kernel",
    "mix": "(a) mix, vectorised",
    "mix_signed": "(a) mix, vectorised, signed idx",
    "mix_scalar": "(a) mix, scalar",
    "mixflag": "(a') mix+flag",
    "lean": "(a'') mix, |xi| from x",
    "nogather": "(b) no gather, vectorised",
    "alu": "(b') alu only",
    "mix32": "(c) mix f32, vectorised",
    "mix32_scalar": "(c) mix f32, scalar",
}


def _mem_available_gib() -> float:
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) / 2**20
    except OSError:
        pass
    return float("nan")


def _git_state() -> str:
    root = Path(__file__).resolve().parent.parent
    try:
        head = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"], cwd=root, capture_output=True, text=True
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--", "src"], cwd=root, capture_output=True,
            text=True,
        ).stdout.strip()  # fmt: skip
        return head + (" (src/ modified)" if dirty else "")
    except OSError:
        return "unknown"


def vector_ops(dispatcher) -> dict:
    """Counts of a few instructions in the compiled kernel (is the inner loop
    vectorised? does it gather?)."""
    import re

    asm = dispatcher.inspect_asm(dispatcher.signatures[0])
    keys = (
        "vsqrtpd", "vsqrtsd", "vdivpd", "vdivsd", "vgatherqpd", "vrsqrt14ps", "vsqrtss",
        "vrsqrtss", "vrsqrt14ss", "vgatherqps",
    )  # fmt: skip
    return {k: len(re.findall(rf"\b{k}\b", asm)) for k in keys}


def run_case(
    dim: int, n_side: int, rounds: int, steps: int, passes: int, quiet: tuple[float, float]
) -> dict:
    """Time the package and every ceiling variant on one lattice, interleaved."""
    from peridynamics.app.bench import _model
    from peridynamics.kernels import bond_based
    from peridynamics.solvers import ExplicitSolver

    t0 = time.perf_counter()
    model = _model(dim, n_side)
    solver = ExplicitSolver(model)
    state = solver.init()
    rng = np.random.default_rng(0)
    state.v[:] = rng.normal(scale=1e-3, size=state.v.shape)
    solver.run(state, 2)  # warm-up: JIT compile / cache load
    setup_s = time.perf_counter() - t0

    b = model.bonds
    fm = model.force_model
    n, nb = model.n_points, b.n_bonds
    x, u = model.cloud.x, state.u
    offsets, bond_j = b.offsets, b.bond_j
    inv_length, stiffness = model.inv_length, model.stiffness
    intact = state.intact
    fam = int(np.diff(offsets).max())
    # no-gather pattern: unit-stride columns padded so that j = i + m stays in range
    cols = []
    for arr in (x, u):
        for c in range(dim):
            col = np.empty(n + fam + 2)
            col[:n] = arr[:, c]
            col[n:] = arr[-1, c] + np.arange(1, fam + 3) * 1e-3 * (arr is x)
            cols.append(col)
    x32, u32 = x.astype(np.float32), u.astype(np.float32)
    il32, c32 = inv_length.astype(np.float32), stiffness.astype(np.float32)
    out = np.empty((n, dim))
    out32 = np.empty((n, dim), dtype=np.float32)
    smax = np.empty(n)
    k = KERNELS[dim]
    calls = {
        "pkg_force": lambda: fm.force(state),
        "mix": lambda: k["mix"](x, u, offsets, bond_j, inv_length, stiffness, out),
        "mix_signed": lambda: k["mix_signed"](x, u, offsets, bond_j, inv_length, stiffness, out),
        "mix_scalar": lambda: k["mix_scalar"](x, u, offsets, bond_j, inv_length, stiffness, out),
        "mixflag": lambda: k["mixflag"](
            x, u, offsets, bond_j, inv_length, stiffness, intact, out, smax
        ),
        "lean": lambda: k["lean"](x, u, offsets, bond_j, stiffness, out),
        "nogather": lambda: k["nogather"](*cols, offsets, inv_length, stiffness, out),
        "alu": lambda: k["alu"](x, u, offsets, inv_length, stiffness, out),
        "mix32": lambda: k["mix32"](x32, u32, offsets, bond_j, il32, c32, out32),
        "mix32_scalar": lambda: k["mix32_scalar"](x32, u32, offsets, bond_j, il32, c32, out32),
    }
    # warm-up (compile) and check that the ceiling does the package's arithmetic
    t_c = time.perf_counter()
    for f in calls.values():
        f()
    compile_s = time.perf_counter() - t_c
    fm.force(state)
    ref = state.force.copy()
    scale = np.abs(ref).max()
    check = {}
    for key in ("mixflag", "mix", "mix_signed", "mix_scalar", "lean"):
        calls[key]()
        check[f"{key} vs pkg force"] = float(np.abs(out - ref).max() / scale)
    asm = {key: vector_ops(k[key]) for key in k}
    # the package's kernel is loaded from Numba's cache, which cannot be inspected: compile
    # its Python source once more with the same options, only to count instructions
    fresh = njit(parallel=True, fastmath=True, error_model="numpy")(
        bond_based.FORCE_KERNELS[dim].py_func
    )
    fresh(x[:2], u[:2], offsets[:2] * 0, bond_j[:1], stiffness[:1], intact[:1],
          np.full(1, np.inf), np.full(1, np.inf), out[:1], np.zeros(1, np.int64))  # fmt: skip
    asm["pkg_force"] = vector_ops(fresh)

    # the package's step as ``peridynamics bench`` times it: ``steps`` steps in one run
    calls = {"pkg_step": lambda: solver.run(state, steps), **calls}
    reps = {key: 1 if key == "pkg_step" else passes for key in calls}
    per = {key: steps if key == "pkg_step" else 1 for key in calls}
    times: dict[str, list[float]] = {key: [] for key in calls}
    loads: dict[str, list[float]] = {key: [] for key in calls}
    meter = LoadMeter()
    dropped = 0
    for _ in range(rounds):
        for key, f in calls.items():
            s, load, drop = timed_clean(f, reps[key], meter, quiet)
            times[key].append(s / per[key])
            loads[key].append(round(load, 3))
            dropped += drop
    rows = {}
    for key, ts in times.items():
        best, med = best_median(ts)
        rows[key] = {
            "s_best": best,
            "s_median": med,
            "rate_best": nb / best,
            "rate_median": nb / med,
            "s_all": ts,
            "other_load_cores": loads[key],
        }
    # the ceiling of the float64 mix: the faster of its vectorised and scalar builds
    ceil_key = max(("mix", "mix_signed", "mix_scalar"), key=lambda q: rows[q]["rate_best"])
    # and of the lean store's mix (|xi| from x): the package's kernel since issue 14
    ratios = {
        f"{a} / {c}": {
            "best": rows[c]["s_best"] / rows[a]["s_best"],
            "median": rows[c]["s_median"] / rows[a]["s_median"],
        }
        for a in ("pkg_step", "pkg_force")
        for c in (ceil_key, "mixflag", "lean")
    }
    return {
        "dim": dim,
        "n_side": n_side,
        "points": n,
        "directed_bonds": nb,
        "bonds_per_point_max": fam,
        "rounds": rounds,
        "steps_per_round": steps,
        "passes_per_round": passes,
        "setup_s": setup_s,
        "compile_s": compile_s,
        "ceiling_kernel": ceil_key,
        "check_rel_max_diff": check,
        "instructions": asm,
        "results": rows,
        "ratios": ratios,
        "windows_dropped_for_load": dropped,
        "peak_rss_gib": peak_rss_gib(),
        **meter.summary(),
    }


def _print_case(c: dict) -> None:
    print(
        f"\n{c['dim']}-D {c['n_side']}^{c['dim']}: {c['points']} points, "
        f"{c['directed_bonds']} directed bonds, {c['rounds']} rounds; other load mean "
        f"{c['other_load_mean_cores']} max {c['other_load_max_cores']} cores; peak RSS "
        f"{c['peak_rss_gib']:.2f} GiB; {c['windows_dropped_for_load']} loaded windows re-timed"
    )
    print(f"  {'kernel':32s} {'best /s':>10s} {'median /s':>10s} {'s/pass best':>12s}")
    for key, r in c["results"].items():
        print(
            f"  {LABELS[key]:32s} {r['rate_best']:10.3e} {r['rate_median']:10.3e} "
            f"{r['s_best']:12.5f}"
        )
    for key, r in c["ratios"].items():
        print(f"  ratio {key:30s} best {r['best']:.3f}  median {r['median']:.3f}")
    for key, v in c["check_rel_max_diff"].items():
        print(f"  check {key}: max |diff| / max |f| = {v:.2e}")
    for key, v in c["instructions"].items():
        ops = {q: w for q, w in v.items() if w}
        print(f"  asm {key:14s} {ops}")


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--cases", default="2:1000,3:100", help="dim:points_per_side,...")
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--steps", type=int, default=10, help="package steps per round")
    p.add_argument("--passes", type=int, default=10, help="kernel passes per round")
    p.add_argument("--json", type=Path, help="write the results here")
    p.add_argument(
        "--quiet-wait", type=float, default=30.0,
        help="before each timing window wait up to this many seconds for the other load "
        "to drop below --quiet-threshold; a window that still saw more than 0.25 cores of "
        "other load is timed again (twice at most)",
    )  # fmt: skip
    p.add_argument("--quiet-threshold", type=float, default=0.15, help="cores")
    p.add_argument(
        "--min-free-gib", type=float, default=1.0,
        help="skip a case whose estimated memory leaves less than this free",
    )  # fmt: skip
    a = p.parse_args(argv)
    meta = {
        "date": _dt.datetime.now().isoformat(timespec="seconds"),
        "cpu": cpu_model(),
        "numba_threads": get_num_threads(),
        "commit": _git_state(),
        "loadavg_before": loadavg(),
    }
    print(json.dumps(meta))
    cases = []
    for spec in a.cases.split(","):
        d, s = (int(v) for v in spec.split(":"))
        # bonds ~ n * (28 | 122); ~95 B/bond at peak (store, float32 copies, build)
        est = s**d * {2: 28, 3: 122}[d] * 95 / 2**30
        free = _mem_available_gib()
        if est > free - a.min_free_gib:
            print(f"skip {d}-D {s}: needs ~{est:.1f} GiB, {free:.1f} GiB available")
            cases.append({"dim": d, "n_side": s, "skipped": f"needs ~{est:.1f} GiB"})
            continue
        c = run_case(d, s, a.rounds, a.steps, a.passes, (a.quiet_wait, a.quiet_threshold))
        c["mem_available_before_gib"] = free
        _print_case(c)
        cases.append(c)
    meta["loadavg_after"] = loadavg()
    if a.json:
        a.json.write_text(json.dumps({"meta": meta, "cases": cases}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
