"""``bonds.npz``: the bond list of a run (each bond once, its reference length and final
status) and :func:`read_bonds`, which reads it back (a decomposed run's per-rank files
joined)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.io.atomic import save_npz
from peridynamics.io.observers.base import Observer, RunContext
from peridynamics.state import State

if TYPE_CHECKING:
    from peridynamics.evaluation import Evaluator


class BondList(Observer):
    """``bonds.npz``: the bond list of the run, each bond once (i < j), with its
    reference length and final status, and the reference points (see docs/output.md)."""

    def __init__(self, model: Evaluator) -> None:
        self.model = model

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        if ctx.session is not None:  # every rank writes its owned bonds (global ids)
            return ctx.session.call("call", _write_rank_bonds, str(ctx.out))
        path = ctx.out / "bonds.npz"
        _save_bonds(path, half_bonds(self.model.bonds, s.intact), self.model)
        return [path.name]


def _save_bonds(
    path: Path, table: dict[str, NDArray], model: Any, points: dict[str, NDArray] | None = None
) -> None:
    """``bonds.npz`` of a bond table (:func:`half_bonds`) with the points of the model's
    cloud, or ``points`` (a rank's owned points: ``x_m``, ``volume_m3``, ``point_ids``)."""
    if points is None:
        points = {"x_m": model.cloud.x, "volume_m3": model.cloud.volume}
    save_npz(
        path,
        i=table["i"].astype(np.int32),
        j=table["j"].astype(np.int32),
        length_m=table["length_m"].astype(np.float64),
        intact=table["intact"].astype(np.uint8),
        initially_intact=table["ini"].astype(np.uint8),
        horizon_m=np.float64(model.bonds.horizon),
        **points,
    )


def read_bonds(folder: str | Path) -> dict[str, NDArray]:
    """The bond table of a run folder (``bonds.npz``; under MPI the per-rank files
    ``ranks/rankNNNN/bonds.npz`` joined), each bond once, sorted by (i, j): the same
    arrays whichever way the run was made."""
    folder = Path(folder)
    if (folder / "bonds.npz").exists():
        with np.load(folder / "bonds.npz") as f:
            return {k: f[k] for k in f.files}
    files = sorted(folder.glob("ranks/rank*/bonds.npz"))
    if not files:
        raise FileNotFoundError(f"no bonds.npz in {str(folder)!r} (output.bonds off?)")
    parts = []
    for p in files:
        with np.load(p) as f:
            parts.append({k: f[k] for k in f.files})
    keys = ("i", "j", "length_m", "intact", "initially_intact")
    out = {k: np.concatenate([p[k] for p in parts]) for k in keys}
    order = np.lexsort((out["j"], out["i"]))
    out = {k: v[order] for k, v in out.items()}
    out["horizon_m"] = parts[0]["horizon_m"]
    if "point_ids" not in parts[0]:  # files of 0.3.0: every rank stored the whole body
        out["x_m"], out["volume_m3"] = parts[0]["x_m"], parts[0]["volume_m3"]
        return out
    ids = np.concatenate([p["point_ids"] for p in parts])
    for k in ("x_m", "volume_m3"):
        rows = np.concatenate([p[k] for p in parts])
        out[k] = np.empty_like(rows)
        out[k][ids] = rows
    return out


def half_bonds(
    b: Any, intact: NDArray, end: int | None = None, gid: NDArray | None = None
) -> dict[str, NDArray]:
    """Each bond of the families ``0:end`` once (i < j, by ``gid`` when given): end
    points, reference length, current and initial status."""
    from peridynamics.bonds.bonds import setup_chunk_bonds
    from peridynamics.bonds.search import bond_chunks

    end = int(b.offsets[-1]) if end is None else end
    parts: dict[str, list[NDArray]] = {k: [] for k in ("i", "j", "length_m", "intact", "ini")}
    for a, z in bond_chunks(b.offsets, setup_chunk_bonds(b.x.shape[1])):  # derived by range
        z = min(z, end)
        if a >= z:
            break
        bi, bj = b.bond_range("bond_i", a, z), b.bond_j[a:z]
        if gid is not None:
            bi, bj = gid[bi], gid[bj]
        half = bi < bj
        parts["i"].append(bi[half])
        parts["j"].append(bj[half])
        parts["length_m"].append(b.bond_range("bond_length", a, z)[half])
        parts["intact"].append(intact[a:z][half])
        parts["ini"].append(b.bond_intact[a:z][half])
    return {k: np.concatenate(v) if v else np.zeros(0) for k, v in parts.items()}


def _write_rank_bonds(session: Any, out: str) -> list[str]:
    """Every rank: ``ranks/rankNNNN/bonds.npz`` of its owned bonds, each once, and its
    owned points, in global ids (:func:`read_bonds` joins them); the names."""
    from peridynamics.parallel.session import rank_dir

    m, s, comm = session.model, session.state, session.comm
    end = m.owned_bonds
    folder = rank_dir(Path(out), comm.rank)
    folder.mkdir(parents=True, exist_ok=True)
    table = half_bonds(m.bonds, s.intact, end, m.cloud.global_ids)
    own = slice(0, comm.n_owned)
    points = {
        "x_m": m.cloud.x[own],
        "volume_m3": m.cloud.volume[own],
        "point_ids": np.asarray(m.cloud.global_ids)[own].astype(np.int64),
    }
    _save_bonds(folder / "bonds.npz", table, m, points)
    names = comm.gather_objects(str((folder / "bonds.npz").relative_to(out)))
    return names if session.root else []
