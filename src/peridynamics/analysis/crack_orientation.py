"""The orientation factor g(n) = sum_j |xi_ij . n| / sum_j |xi_ij| of bond families and its
table over crack normals, for :class:`peridynamics.analysis.crack_length.CrackMeter`
(that module's docstring: the derivation and the measured lattice dependence). The
table is made from the families of interior points (full, balanced families).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from peridynamics.bonds.bonds import Bonds

__all__ = [
    "ORIENTATION_AVERAGE",
    "STEP_2D",
    "STEP_3D",
    "family_first_moment",
    "interior_sample",
    "orientation_factor",
    "orientation_table",
    "pick_interior",
]

#: orientation average of |cos| between a bond and the crack normal: 2/pi in 2-D, 1/2 in 3-D
ORIENTATION_AVERAGE: dict[int, float] = {2: 2.0 / math.pi, 3: 0.5}

STEP_2D = math.radians(0.5)  # table step of g(theta), 2-D
STEP_3D = math.radians(3.0)  # table step of g(polar, azimuth), 3-D
_MAX_TABLE_BONDS = {2: 50_000, 3: 15_000}  # bond vectors sampled for the table


def orientation_factor(
    xi: ArrayLike, normals: ArrayLike, counts: ArrayLike | None = None
) -> NDArray[np.float64]:
    """Orientation factor g(n) = sum_k |xi_k . n| / sum_k |xi_k| of a set of bonds.

    Parameters
    ----------
    xi : array_like, shape (k, dim)
        Bond vectors (m), e.g. the family of one point.
    normals : array_like, shape (q, dim)
        Unit crack normals.
    counts : array_like, shape (k,), optional
        How many times each bond vector occurs (default once).

    Returns
    -------
    ndarray, shape (q,)
        g for each normal (dimensionless); averaged over orientations it is 2/pi in 2-D
        and 1/2 in 3-D for any isotropic set of bonds.
    """
    v = np.asarray(xi, dtype=np.float64)
    n = np.asarray(normals, dtype=np.float64)
    c = np.ones(v.shape[0]) if counts is None else np.asarray(counts, dtype=np.float64)
    total = float(c @ np.sqrt(np.einsum("ij,ij->i", v, v)))
    out = np.zeros(n.shape[0])
    chunk = max(1, 4_000_000 // max(v.shape[0], 1))
    for a in range(0, n.shape[0], chunk):  # over blocks of directions (memory bound)
        out[a : a + chunk] = c @ np.abs(v @ n[a : a + chunk].T)
    return out / total if total > 0 else out


def _table_normals(dim: int) -> tuple[NDArray[np.float64], tuple[int, ...]]:
    """Unit normals of the table (q, dim) and the table's shape."""
    if dim == 2:
        k = round(math.pi / STEP_2D)
        t = np.arange(k) * STEP_2D  # angle of the normal in [0, pi)
        return np.column_stack([np.cos(t), np.sin(t)]), (k,)
    kp = round(0.5 * math.pi / STEP_3D) + 1  # polar angle 0 .. pi/2 (upper hemisphere)
    ka = round(2.0 * math.pi / STEP_3D)  # azimuth 0 .. 2 pi
    p, a = np.meshgrid(np.arange(kp) * STEP_3D, np.arange(ka) * STEP_3D, indexing="ij")
    n = np.column_stack(
        [(np.sin(p) * np.cos(a)).ravel(), (np.sin(p) * np.sin(a)).ravel(), np.cos(p).ravel()]
    )
    return n, (kp, ka)


def family_first_moment(bonds: Bonds, s: NDArray, dim: int) -> NDArray[np.float64]:
    """The norm of sum_j xi_ij of every point's family, shape (len(s),) (m): 0 for a balanced
    family, large for a point near a free surface."""
    first = np.stack(
        [
            np.bincount(bonds.bond_i, weights=bonds.bond_xi[:, k], minlength=len(s))
            for k in range(dim)
        ],
        axis=1,
    )
    return np.sqrt(np.einsum("ij,ij->i", first, first))


def pick_interior(
    s: NDArray, lopsided: NDArray, family_size: NDArray, dim: int
) -> NDArray[np.intp]:
    """Points with a full, balanced family (a sample of them): the largest families
    (>= 97 % of the 90th percentile of S_i) whose first moment |sum xi| is under 5 % of
    S_i (points near a free surface have a lopsided family)."""
    full = (s >= 0.97 * np.percentile(s, 90.0)) & (lopsided <= 0.05 * s)
    pts = np.flatnonzero(full)
    if pts.size == 0:
        pts = np.array([int(np.argmax(s))])
    per = max(1.0, float(np.median(family_size[pts])))
    take = max(1, int(_MAX_TABLE_BONDS[dim] / per))
    if pts.size > take:
        pts = pts[np.linspace(0, pts.size - 1, take).astype(np.intp)]
    return pts


def interior_sample(bonds: Bonds, s: NDArray, dim: int) -> NDArray[np.intp]:
    """:func:`pick_interior` of a bond list."""
    return pick_interior(s, family_first_moment(bonds, s, dim), bonds.family_size, dim)


def orientation_table(xi: NDArray[np.float64], spacing: float, dim: int) -> NDArray[np.float64]:
    """The orientation factor table of interior families whose bond vectors are ``xi``
    (k, dim), each distinct vector once with its count."""
    key = np.rint(xi / (1e-6 * spacing)).astype(np.int64)
    _, first, counts = np.unique(key, axis=0, return_index=True, return_counts=True)
    normals, shape = _table_normals(dim)
    return orientation_factor(xi[first], normals, counts).reshape(shape)
