"""The bonds broken during a run, for the crack outputs: bond flags in crack-meter
order, the crack meter of a model, the broken pairs; and the same measures of a
decomposed run, computed by every rank on its own bonds and reduced (run on every rank
through :meth:`peridynamics.parallel.session.Session.call`)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.analysis.crack_length import CrackMeter
from peridynamics.analysis.crack_orientation import (
    family_first_moment,
    orientation_table,
    pick_interior,
)
from peridynamics.state import State

if TYPE_CHECKING:
    from peridynamics.evaluation import Evaluator


def _interfaces(model: Evaluator) -> tuple[Any, ...]:
    """Bonded interfaces of a model with several bodies (their own bond lists)."""
    return tuple(getattr(model.force_model, "interfaces", ()) or ())


def all_intact(model: Evaluator, s: State) -> NDArray[np.uint8]:
    """Bond flags of ``s`` in the order of :meth:`CrackMeter.from_bonds` with the
    model's interfaces: the bonds, then the interface bonds (n_bonds,)."""
    if _interfaces(model) and "interface_intact" in s:
        return np.concatenate([s.intact, s["interface_intact"]])
    return s.intact


def build_meter(model: Evaluator, table: NDArray[np.float64] | None = None) -> CrackMeter:
    """The crack meter of a model (its bonds and those of its bonded interfaces);
    ``table``: its orientation table when made elsewhere (a decomposed run)."""
    extra = [f.bonds for f in _interfaces(model)]
    return CrackMeter.from_bonds(model.cloud, model.bonds, extra, table)


def broken_pairs(
    model: Evaluator, s: State, session: Any = None
) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """End points (i, j) of the directed bonds broken during the run (pre-cracks
    excluded), interface bonds included; the owned families' bonds on a rank of a
    decomposed run (local indices). With the ``session`` of a decomposed run (rank 0):
    the whole body's, in global ids."""
    if session is not None:  # the whole body's view of a decomposed run (global ids)
        got = session.call("call", _broken_pairs_on_ranks)
        assert got is not None
        return got
    b, end = model.bonds, model.owned_bonds
    k = np.flatnonzero(b.bond_intact[:end].astype(bool) & (s.intact[:end] == 0))
    ii, jj = [b.bond_i[k]], [b.bond_j[k]]
    if _interfaces(model) and "interface_intact" in s:
        start = 0
        for f in _interfaces(model):  # over interfaces (a handful)
            now = s["interface_intact"][start : start + f.n_bonds]
            g = np.flatnonzero(f.bonds.bond_intact.astype(bool) & (now == 0))
            ii.append(f.bonds.bond_i[g])
            jj.append(f.bonds.bond_j[g])
            start += f.n_bonds
    return np.concatenate(ii).astype(np.intp), np.concatenate(jj).astype(np.intp)


# -- a decomposed run: every rank measures its owned bonds ---------------------------------
def crack_measure(session: Any, separating: bool = True) -> float:
    """Rank 0 of a decomposed run: the broken-bond crack length (area) of the whole
    body."""
    return session.call("call", _crack_on_ranks, "measure", separating)


def crack_weights(session: Any) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Rank 0 of a decomposed run: midpoints (k, dim) and weights (k,) of every counted
    broken bond of the whole body."""
    return session.call("call", _crack_on_ranks, "weights", True)


def _crack_on_ranks(session: Any, what: str, separating: bool) -> Any:
    """Every rank: crack measures of the owned bonds: the sum ("measure") or, on rank
    0, the weights and midpoints of every counted bond ("weights")."""
    m, s, comm = session.model, session.state, session.comm
    meter = session.cache.get("crack_meter")
    if meter is None:
        meter = session.cache["crack_meter"] = build_meter(m, _orientation_table(session))
    flags = all_intact(m, s)
    idx, w = meter.weights(flags, separating=separating, exchange=comm.exchange)
    keep = idx < m.owned_bonds
    idx, w = idx[keep], w[keep]
    if what == "measure":
        return comm.sum(float(w.sum()))
    parts = comm.gather_root((meter.midpoints(idx), w))
    if not session.root:
        return None
    mids = np.concatenate([p[0] for p in parts]).reshape(-1, m.dim)
    return mids, np.concatenate([p[1] for p in parts])


def _orientation_table(session: Any) -> NDArray[np.float64]:
    """The crack meter's orientation table from the whole body's interior families,
    as a serial run makes it (the same sample, the same bond order)."""
    m, comm = session.model, session.comm
    b, dim, n_own = m.bonds, m.dim, comm.n_owned
    s = np.bincount(b.bond_i, weights=b.bond_length, minlength=b.n_points)
    lop = family_first_moment(b, s, dim)
    whole = [comm.gather_points_root(a) for a in (s, lop, b.family_size)]
    pts = None
    if session.root:
        pts = pick_interior(whole[0], whole[1], whole[2], dim)  # type: ignore[arg-type]
    pts = comm.comm.bcast(pts, root=0)
    gid = m.cloud.global_ids
    chosen = np.zeros(b.n_points, dtype=bool)
    chosen[:n_own] = np.isin(gid[:n_own], pts)
    k = np.flatnonzero(chosen[b.bond_i])
    parts = comm.gather_root((gid[b.bond_i[k]], b.bond_xi[k]))
    table = None
    if session.root:
        owner = np.concatenate([p[0] for p in parts])
        xi = np.concatenate([p[1] for p in parts]).reshape(-1, dim)
        order = np.argsort(owner, kind="stable")  # families in global order
        table = orientation_table(xi[order], m.cloud.spacing, dim)
    return comm.comm.bcast(table, root=0)


def _broken_pairs_on_ranks(session: Any) -> tuple[NDArray[np.intp], NDArray[np.intp]] | None:
    """Every rank: its owned bonds broken during the run, in global ids, on rank 0."""
    i, j = broken_pairs(session.model, session.state)
    gid = session.model.cloud.global_ids
    parts = session.comm.gather_root((gid[i], gid[j]))
    if not session.root:
        return None
    return (
        np.concatenate([p[0] for p in parts]).astype(np.intp),
        np.concatenate([p[1] for p in parts]).astype(np.intp),
    )
