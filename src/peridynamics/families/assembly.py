"""Sparse assembly of bond-wise tangent blocks (no Python loop over bonds or points).

A force model whose point i interacts with its family only through bonds (bond-based
PMB, micropolar) has a tangent K = d^2 E / dq dq with one c x c block per directed bond
(i, j) (c degrees of freedom per point) and a diagonal block per point. In a directed
CSR bond list the off-diagonal block structure *is* the bond list, so the matrix is
built directly in block-CSR form: row i holds its diagonal block and then the blocks of
its kept bonds in the order of the list (no duplicates to sum, 8 c^2 bytes per bond).

Two assemblies of the same matrix are provided, and the tests check they agree:

* **pair assembly** (:func:`block_csr`, production): the block (i, j) of the pair
  stiffness k_ij, whole, from the directed bond (i, j); the diagonal block (i, i) as the
  family sum of the (i, i) parts;
* **element assembly** (:func:`element_assembly`, reference): the "nonlocal element"
  of point i (Zhou, Zhu & Li (n.d.), section 3.2: the point and its family) carries
  E_i = W_i V_i = sum_j 1/2 w_ij V_i V_j, so its matrix is sum_j 1/2 k_ij scattered
  into the blocks (i, i), (i, j), (j, i), (j, j); the sum over all elements, with
  duplicates added, is the global K.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray


def block_csr(
    offsets: NDArray[np.int64],
    bond_j: NDArray[np.integer],
    diag: NDArray[np.float64],
    off: NDArray[np.float64],
    keep: NDArray[np.bool_],
    n_points: int,
) -> sp.csr_matrix:
    """Global matrix from diagonal and per-bond blocks.

    Parameters
    ----------
    offsets : (n_own + 1,) CSR offsets of the directed bond list.
    bond_j : (n_bonds,) neighbour of each bond.
    diag : (n_own, c, c) diagonal blocks.
    off : (n_bonds, c, c) block (i, j) of each bond (ignored where not ``keep``).
    keep : (n_bonds,) bool, bonds that carry stiffness.
    n_points : int, number of block rows/columns (>= n_own).

    Returns
    -------
    scipy.sparse.csr_matrix, shape (n_points c, n_points c), sorted indices.
    """
    n_own = len(offsets) - 1
    c = diag.shape[1]
    keep_i = keep.astype(np.int64)
    cum = np.concatenate([[0], np.cumsum(keep_i)])  # kept bonds before each bond
    per_row = cum[offsets[1:]] - cum[offsets[:-1]]
    indptr = np.zeros(n_points + 1, dtype=np.int64)
    indptr[1 : n_own + 1] = np.cumsum(per_row + 1)
    indptr[n_own + 1 :] = indptr[n_own]
    nblocks = int(indptr[-1])
    indices = np.empty(nblocks, dtype=np.int32)
    data = np.empty((nblocks, c, c))
    first = indptr[:n_own]
    indices[first] = np.arange(n_own, dtype=np.int32)
    data[first] = diag
    kept = np.flatnonzero(keep)
    row = np.repeat(np.arange(n_own), np.diff(offsets))[kept]
    pos = first[row] + 1 + (cum[kept] - cum[offsets[row]])
    indices[pos] = bond_j[kept]
    data[pos] = off[kept]
    size = n_points * c
    mat = sp.bsr_matrix((data, indices, indptr), shape=(size, size)).tocsr()
    mat.sort_indices()
    return mat


def family_sum(offsets: NDArray[np.int64], blocks: NDArray[np.float64]) -> NDArray[np.float64]:
    """Sum of per-bond blocks over each family, shape (n_own,) + blocks.shape[1:]."""
    n_own = len(offsets) - 1
    out = np.zeros((n_own,) + blocks.shape[1:])
    nonempty = np.flatnonzero(np.diff(offsets) > 0)
    if len(nonempty):
        out[nonempty] = np.add.reduceat(blocks, offsets[:-1][nonempty], axis=0)
    return out


def element_assembly(
    bond_i: NDArray[np.integer],
    bond_j: NDArray[np.integer],
    pair: NDArray[np.float64],
    n_points: int,
) -> sp.csr_matrix:
    """Sum of the nonlocal element matrices (reference assembly, module docstring).

    Parameters
    ----------
    bond_i, bond_j : (n_bonds,) the directed bonds.
    pair : (n_bonds, 2c, 2c) the pair stiffness k_ij of each directed bond in the dof
        order [q_i, q_j] (N/m).
    n_points : int

    Returns
    -------
    scipy.sparse.csr_matrix (n_points c, n_points c): sum_elements sum_j 1/2 k_ij.
    """
    nb, two_c, _ = pair.shape
    c = two_c // 2
    comp = np.arange(c)
    dofs = np.concatenate([bond_i[:, None] * c + comp, bond_j[:, None] * c + comp], axis=1).astype(
        np.int64
    )  # (nb, 2c)
    rows = np.broadcast_to(dofs[:, :, None], pair.shape).ravel()
    cols = np.broadcast_to(dofs[:, None, :], pair.shape).ravel()
    size = n_points * c
    coo = sp.coo_matrix((0.5 * pair.ravel(), (rows, cols)), shape=(size, size))
    return sp.csr_matrix(coo)
