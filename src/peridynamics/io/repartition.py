"""Resuming a decomposed run on another number of ranks: the new ranks' States made
from the old ranks' checkpoint files.

Every rank's checkpoint carries its partition (:func:`partition_arrays`, stored as the
``extra_*`` arrays of :func:`~peridynamics.io.checkpoint.write_checkpoint`): the global
ids of its local rows (owned, then ghosts), how many rows it owns, the CSR offsets of
its owned families and their bonds' far ends (local rows, so global ids through the
first array). The marker names each rank's owned bounding box (:func:`owned_boxes`).

A new rank builds its model on the new partition as usual, reads the files of the old
ranks whose owned box holds one of its local points (:func:`needed_ranks`; rank 0 also
old rank 0's, which holds the records), and fills a State of the new layout
(:func:`rebuild_state`): each per-point field row from the old rank that owned that
global id, each per-bond field entry from the old owner of the bond's near end,
looked up by the key ``(global i) * n_points + (global j)`` in the sorted keys of the
old owned bonds (``np.searchsorted``; no loop over points or bonds). The kind of every
field comes from the State's registry below and the force model's
:meth:`~peridynamics.families.base.ForceModel.state_fields` (``FieldSpec.where``); a
field of any other kind (the interface bonds of several bodies) cannot be repartitioned
and is refused (:func:`field_kinds`); the rigid bodies' fields, the same on every rank,
are taken from any old rank.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.bodies.rigid import RIGID_FIELDS
from peridynamics.io.checkpoint import Checkpoint
from peridynamics.parallel.decompose import find_sorted
from peridynamics.state import State

#: per-point fields of every State (first dimension: the rank's local points)
POINT_FIELDS = ("u", "v", "force", "body", "u_prev", "max_stretch", "sed_level")
#: per-bond fields of every State (first dimension: the rank's directed bonds)
BOND_FIELDS = ("intact",)
#: per-rank partial sums (the run reports their sum over ranks): new rank 0 takes it
SUMMED_FIELDS = ("friction_work",)
#: the partition arrays every rank's checkpoint carries (``extra_<name>``)
PARTITION_KEYS = ("ranks", "rank", "global_ids", "n_owned", "offsets", "bond_j")


class ResumeError(ValueError):
    """The checkpoint of a decomposed run cannot be resumed (the run loop reports it as
    a set-up error of ``--resume``)."""


def partition_arrays(session: Any) -> dict[str, NDArray]:
    """This rank's partition, stored beside its State.

    Returns
    -------
    dict
        ``ranks``, ``rank``, ``n_owned`` (0-d int64); ``global_ids`` (n_local,) int64,
        owned rows first; ``offsets`` (n_owned + 1,) int64, the CSR offsets of the owned
        families; ``bond_j`` (offsets[-1],) the local row of each owned bond's far end.
        Added bytes: 8 per local point, 8 per owned point, 4 per owned bond (int32 rows).
    """
    m, comm = session.model, session.comm
    n_own = int(comm.n_owned)
    offsets = np.asarray(m.bonds.offsets[: n_own + 1], dtype=np.int64)
    return {
        "ranks": np.array(comm.size, dtype=np.int64),
        "rank": np.array(comm.rank, dtype=np.int64),
        "global_ids": np.asarray(m.cloud.global_ids, dtype=np.int64),
        "n_owned": np.array(n_own, dtype=np.int64),
        "offsets": offsets,
        "bond_j": np.asarray(m.bonds.bond_j[: int(offsets[-1])]),
    }


def same_partition(a: dict[str, NDArray], b: dict[str, NDArray]) -> bool:
    """Whether two :func:`partition_arrays` describe the same rows and bonds."""
    keys = ("global_ids", "n_owned", "offsets", "bond_j")
    return all(k in a and k in b and np.array_equal(a[k], b[k]) for k in keys)


def owned_boxes(session: Any) -> list[list[list[float]]]:
    """Every rank's owned bounding box ``[[lo...], [hi...]]`` (m), in rank order, the same
    on every rank (collective the first time: one allgather; then kept in
    ``session.cache``)."""
    boxes = session.cache.get("owned_boxes")
    if boxes is None:
        x = np.asarray(session.model.cloud.x)[: int(session.comm.n_owned)]
        mine = [x.min(axis=0).tolist(), x.max(axis=0).tolist()]
        boxes = session.cache["owned_boxes"] = session.comm.gather_objects(mine)
    return boxes


def needed_ranks(x: NDArray[np.float64], boxes: list[Any], root: bool) -> list[int]:
    """The old ranks whose owned box holds one of the points ``x`` (n_local, dim) of
    this rank (every old owner of a local point among them), plus old rank 0 on the
    new rank 0 (``root``: its file holds the records)."""
    lo_here, hi_here = x.min(axis=0), x.max(axis=0)
    out = []
    for r, (lo, hi) in enumerate(boxes):
        lo, hi = np.asarray(lo, dtype=np.float64), np.asarray(hi, dtype=np.float64)
        if (root and r == 0) or (
            np.all(lo <= hi_here)
            and np.all(hi >= lo_here)
            and np.any(np.all((x >= lo) & (x <= hi), axis=1))
        ):
            out.append(r)
    return out


def field_kinds(model: Any, state: State) -> tuple[dict[str, str], list[str]]:
    """The kind of every field of ``state`` (a new State of ``model``): ``"point"``,
    ``"bond"``, ``"sum"`` or ``"replicated"`` (the rigid bodies' fields, the same on
    every rank), and the names of the fields that cannot be repartitioned (other kinds:
    interface bonds), with their kind."""
    kinds = {name: "point" for name in POINT_FIELDS}
    kinds.update({name: "bond" for name in BOND_FIELDS})
    kinds.update({name: "sum" for name in SUMMED_FIELDS})
    kinds.update({name: "replicated" for name in RIGID_FIELDS})
    fm = model.force_model
    for dof in fm.dofs()[1:]:  # rotations and moments of a micropolar model
        kinds.update({n: "point" for n in (dof.value, dof.rate, dof.force, dof.body)})
    for spec in fm.state_fields():
        kinds[spec.name] = spec.where
    n_local, n_bonds = len(state.u), len(state.intact)
    known: dict[str, str] = {}
    refused: list[str] = []
    for name, a in state.fields.items():
        kind = kinds.get(name, "unknown")
        rows = {"point": n_local, "bond": n_bonds}.get(kind)
        if kind not in ("point", "bond", "sum", "replicated") or (
            rows is not None and len(a) != rows
        ):
            refused.append(f"{name} ({kind})")
        else:
            known[name] = kind
    return known, refused


def _lookup(
    keys: list[NDArray[np.int64]], wanted: NDArray[np.int64], what: str
) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """For each of ``wanted`` (sorted or not), the index of the array of ``keys`` that
    holds it and its position there; ResumeError when one is held by none."""
    flat = np.concatenate(keys) if keys else np.zeros(0, dtype=np.int64)
    src = np.repeat(np.arange(len(keys)), [len(k) for k in keys])
    row = np.concatenate([np.arange(len(k)) for k in keys]) if keys else src
    order = np.argsort(flat, kind="stable")
    pos, hit = find_sorted(flat[order], wanted)
    if not hit.all():
        raise ResumeError(
            f"{int((~hit).sum())} {what} of this rank are in none of the old ranks' files "
            "(the checkpoint does not match this deck's partition)"
        )
    take = order[pos]
    return src[take], row[take]


def _old_keys(ck: Checkpoint, n: np.int64) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """(owned global ids, owned bond keys ``gi * n + gj``) of an old rank's file."""
    e = ck.extra
    gid = np.asarray(e["global_ids"], dtype=np.int64)
    n_own = int(e["n_owned"])
    offsets = np.asarray(e["offsets"], dtype=np.int64)
    bond_j = np.asarray(e["bond_j"], dtype=np.int64)
    if len(gid) != len(ck.state.u) or len(offsets) != n_own + 1 or offsets[-1] != len(bond_j):
        raise ResumeError(f"the partition arrays of {ck.path} do not match its State")
    rows = np.repeat(np.arange(n_own), np.diff(offsets))
    return gid[:n_own], gid[rows] * n + gid[bond_j]


def rebuild_state(
    template: State,
    kinds: dict[str, str],
    model: Any,
    n_points: int,
    old: dict[int, Checkpoint],
) -> State:
    """This rank's State of the new partition filled from the old ranks' files ``old``
    (old rank -> its checkpoint; every old owner of a local point among them).

    Parameters
    ----------
    template : a new State of ``model`` (its fields are filled in place and returned).
    kinds : :func:`field_kinds` of ``template``.
    model : this rank's model: ``cloud.global_ids`` (n_local,), ``bonds.offsets``
        (n_local + 1,) and ``bonds.bond_j`` (n_bonds,) in local rows.
    n_points : points of the whole body.
    old : the old files.

    Returns
    -------
    State
        ``template`` with every per-point and per-bond field filled, ``t``, ``step`` and
        ``phase`` of the old files; ``bonds_broken`` and the summed fields are left to
        the caller (they are sums over every old rank).
    """
    n = np.int64(n_points)
    ranks = sorted(old)
    got = [_old_keys(old[r], n) for r in ranks]
    gid = np.asarray(model.cloud.global_ids, dtype=np.int64)
    offsets = np.asarray(model.bonds.offsets, dtype=np.int64)
    rows = np.repeat(np.arange(len(offsets) - 1), np.diff(offsets))
    bond_keys = gid[rows] * n + gid[np.asarray(model.bonds.bond_j[: len(rows)], np.int64)]
    where = {
        "point": _lookup([g[0] for g in got], gid, "points"),
        "bond": _lookup([g[1] for g in got], bond_keys, "bonds"),
    }
    for name, kind in kinds.items():
        if kind == "replicated":  # any old rank holds them alike
            template[name][...] = old[ranks[0]].state.fields[name]
        if kind in ("sum", "replicated"):
            continue
        src, row = where[kind]
        out = template[name]
        for k, r in enumerate(ranks):
            field = old[r].state.fields.get(name)
            if field is None or field.shape[1:] != out.shape[1:]:
                raise ResumeError(f"{old[r].path} holds no field {name!r} of this shape")
            mask = src == k
            out[mask] = field[row[mask]]
    first = old[ranks[0]].state
    template.t, template.step, template.phase = first.t, first.step, first.phase
    return template
