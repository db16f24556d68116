"""Horizon search: all point pairs closer than a radius, as a directed CSR list."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree


def find_pairs(x: NDArray[np.float64], radius: float) -> NDArray[np.int64]:
    """Unordered pairs ``(i, j)``, ``i < j``, with ``|x_j - x_i| <= radius``; shape (n, 2)."""
    tree = cKDTree(x)
    pairs = tree.query_pairs(radius, output_type="ndarray")
    return np.asarray(pairs, dtype=np.int64).reshape(-1, 2)


def directed_csr(
    pairs: NDArray[np.int64], n_points: int
) -> tuple[NDArray[np.int64], NDArray[np.int32], NDArray[np.int32]]:
    """Turn unordered pairs into a full directed list sorted by (i, j).

    Returns
    -------
    offsets : (n_points + 1,) int64, bonds of point i are ``offsets[i]:offsets[i+1]``.
    bond_i, bond_j : (2 * n_pairs,) int32.
    """
    if n_points >= 2**31 - 1:
        raise ValueError("more than 2**31 points are not supported (int32 indices)")
    i = np.concatenate([pairs[:, 0], pairs[:, 1]])
    j = np.concatenate([pairs[:, 1], pairs[:, 0]])
    order = np.argsort(i * np.int64(n_points) + j, kind="stable")
    bond_i = i[order].astype(np.int32)
    bond_j = j[order].astype(np.int32)
    offsets = np.zeros(n_points + 1, dtype=np.int64)
    np.cumsum(np.bincount(bond_i, minlength=n_points), out=offsets[1:])
    return offsets, bond_i, bond_j


def brute_force_pairs(x: NDArray[np.float64], radius: float) -> NDArray[np.int64]:
    """O(n^2) reference for tests: all pairs i < j within ``radius``."""
    d2 = np.sum((x[:, None, :] - x[None, :, :]) ** 2, axis=-1)
    i, j = np.nonzero(np.triu(d2 <= radius * radius, k=1))
    return np.column_stack([i, j]).astype(np.int64)
