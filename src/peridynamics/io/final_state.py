"""``final_state.npz``: the fields at the end of a run, and their reader.

A serial run writes one file. A decomposed run (``mpiexec -n N``) writes it by pieces,
so that no rank holds the whole body: every rank writes
``ranks/rankNNNN/final_state.npz`` with the rows of the points it owns (``point_ids``:
their global ids) and the flags of their bonds (``family_size``: bonds per owned point,
each family in the serial order), and rank 0 writes ``final_state.npz`` as the index
(``pieces``: the number of ranks, ``n_points``, ``t``, ``step``). :func:`read_final_state`
returns the serial run's arrays from either, bit for bit: per-point rows put at their
global ids, the bond flags of every point's family in global point order (the serial
CSR order).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from peridynamics.io.atomic import save_npz

#: the arrays of a piece that are not per-point fields
PIECE_KEYS = ("point_ids", "family_size", "intact")


def piece_path(out: Path, rank: int) -> Path:
    """The piece of rank ``rank`` in the run folder ``out``."""
    return Path(out) / "ranks" / f"rank{rank:04d}" / "final_state.npz"


def write_piece(
    out: Path,
    rank: int,
    point_ids: NDArray[np.int64],
    family_size: NDArray[np.int64],
    intact: NDArray,
    **fields: NDArray,
) -> Path:
    """Write one rank's piece.

    Parameters
    ----------
    out : run folder.
    rank : this rank.
    point_ids : (n_owned,) global ids of the owned points, increasing.
    family_size : (n_owned,) bonds of each owned point.
    intact : (sum(family_size),) the flags of the owned points' bonds, family by
        family in the serial order.
    **fields : per-point arrays, first axis the owned points (``u``, ``v``, ``damage``,
        ``x``, ...).
    """
    path = piece_path(out, rank)
    path.parent.mkdir(parents=True, exist_ok=True)
    save_npz(path, point_ids=point_ids, family_size=family_size, intact=intact, **fields)
    return path


def write_index(out: Path, pieces: int, n_points: int, t: float, step: int) -> Path:
    """Rank 0: ``final_state.npz`` of a decomposed run, the index of its pieces."""
    path = Path(out) / "final_state.npz"
    save_npz(path, pieces=np.int64(pieces), n_points=np.int64(n_points), t=t, step=step)
    return path


def read_final_state(folder: str | Path) -> dict[str, NDArray]:
    """The arrays of ``final_state.npz`` in a run folder, the pieces of a decomposed run
    joined into the serial run's arrays (module docstring)."""
    folder = Path(folder)
    path = folder / "final_state.npz"
    if not path.is_file():
        raise FileNotFoundError(f"no final_state.npz in {str(folder)!r}")
    with np.load(path) as data:
        index = {k: data[k] for k in data.files}
    if "pieces" not in index:
        return index
    n = int(index["n_points"])
    parts = []
    for rank in range(int(index["pieces"])):
        piece = piece_path(folder, rank)
        if not piece.is_file():
            raise FileNotFoundError(f"{str(piece)!r}: a piece of final_state.npz is missing")
        with np.load(piece) as data:
            parts.append({k: data[k] for k in data.files})
    ids = np.concatenate([p["point_ids"] for p in parts])
    if ids.size != n or not np.array_equal(np.sort(ids), np.arange(n)):
        raise ValueError(f"the pieces of {str(path)!r} do not hold every point once")
    out: dict[str, NDArray] = {"t": index["t"], "step": index["step"]}
    for key in parts[0]:
        if key in PIECE_KEYS:
            continue
        rows = np.concatenate([p[key] for p in parts])
        out[key] = np.empty_like(rows)
        out[key][ids] = rows
    sizes = np.zeros(n, dtype=np.int64)
    sizes[ids] = np.concatenate([p["family_size"] for p in parts])
    start = np.concatenate([[0], np.cumsum(sizes)])
    flags = np.concatenate([p["intact"] for p in parts])
    out["intact"] = np.empty_like(flags)
    # every piece's flags are its families in point order: move each family as a block
    src = np.concatenate([[0], np.cumsum(np.concatenate([p["family_size"] for p in parts]))])
    order = np.repeat(start[ids] - src[:-1], np.diff(src))
    out["intact"][np.arange(flags.size) + order] = flags
    return out
