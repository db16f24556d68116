"""Build one rank's part of a decomposed run from a deck (``mpiexec -n N peridynamics run``).

A body that is a grid, jittered or not, is made by every rank without the global point
cloud: each makes only its owned points and ghosts (:mod:`peridynamics.build.windowed`).
Other bodies (mesh geometries, several bodies) are built whole on every
rank, which then cuts out its points and ghosts (:mod:`peridynamics.parallel.local`;
with several bodies each rank owns points of one body,
:mod:`peridynamics.parallel.bodies`).
Either way a rank builds the bonds of its owned points and of the first ghost layer on
that local cloud, then the model, loads and solver exactly as a serial run does, with
the MPI communicator active (:func:`~peridynamics.communicator.using`).
What a decomposed run cannot do yet is refused here with the key that asks for it.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics import deck as dk
from peridynamics.bonds.partial_volume import search_radius
from peridynamics.build.bodies import (
    attach_rigid_bodies,
    body_layout,
    build_deck_model,
    has_bodies,
)
from peridynamics.build.cloud import build_bonds_for, build_cloud
from peridynamics.build.errors import SetupError
from peridynamics.build.loads import build_conditions
from peridynamics.build.plausibility import warn_horizon
from peridynamics.build.solvers import build_solver
from peridynamics.build.windowed import agreed, cloud_meta, conditions, deck_lattice
from peridynamics.build.windowed import local_cloud as windowed_cloud
from peridynamics.communicator import using
from peridynamics.geometry.cloud import PointCloud
from peridynamics.geometry.lattice import Lattice
from peridynamics.parallel.bodies import decompose_bodies
from peridynamics.parallel.local import (
    decompose,
    local_cloud,
    localize_condition,
    own_families,
)
from peridynamics.parallel.mpi import MPICommunicator
from peridynamics.parallel.windowed import windowed_layout


def _refuse(deck: dk.Deck, size: int) -> None:
    """SetupError for what a decomposed run does not support."""
    how = f"run it on one rank (without mpiexec -n {size}), or as an ensemble/sweep member"
    s = deck.solver
    if s.type == "fatigue":
        raise SetupError("solver.type", f"the fatigue solver is not distributed; {how}")
    if isinstance(s, dk.Solver) and (s.hybrid is not None or s.method == "fdm"):
        key = "solver.hybrid" if s.hybrid is not None else "solver.method"
        raise SetupError(key, f"hybrid and finite-difference runs are 1-D and serial; {how}")
    if getattr(deck.material, "plasticity", None) is not None:
        raise SetupError("material.plasticity", f"plastic history is not distributed yet; {how}")
    if getattr(deck.material, "viscoelastic", None) is not None:
        raise SetupError(
            "material.viscoelastic", f"the viscoelastic bond history is not distributed; {how}"
        )


def ghost_families(deck: dk.Deck, cloud: Any) -> bool:
    """Whether the first ghost layer needs its bond families on the rank: for every
    model whose force pass reads, at the far end of a bond, a quantity made from that
    point's own family (LPS dilatation, correspondence force state, SED levels, the
    moment surface correction of irregular clouds); not for plain bond-based PMB, which
    reads only u and v there (one layer, no redundant work)."""
    plain = deck.material.model in ("pmb", "bond_based") and deck.damage.bond_law == "brittle"
    irregular = bool(cloud.irregular)  # a PointCloud or a Lattice (jittered: irregular)
    return not plain or deck.damage.sed_softening is not None or irregular


def build_distributed(deck: dk.Deck, comm: Any) -> dict[str, Any]:
    """The objects of this rank: ``cloud`` (local), ``global_cloud`` (the whole cloud,
    or a :class:`~peridynamics.parallel.global_cloud.CloudMeta` when no rank made it),
    ``model``, ``solver``, ``communicator`` (a :class:`MPICommunicator`), ``n_family``
    (points with a bond family: owned and first ghost layer) and ``set_up`` (how:
    ``"windowed"`` or ``"replicated"``, with the replicated bytes per rank)."""
    if deck.geometry.type != "bar":
        _refuse(deck, int(comm.Get_size()))
        lattice = deck_lattice(deck)
        if lattice is not None:
            return _build_windowed(deck, comm, lattice)
    return _build_replicated(deck, comm)


def _radii(deck: dk.Deck, spacing: float, families: bool) -> tuple[float, float]:
    """(bond search radius, ghost radius) (m)."""
    d = deck.discretisation
    radius = search_radius(d.delta, spacing, d.partial_volume)
    ghost_radius = (2.0 if families else 1.0) * radius
    if deck.contact is not None:  # points that may touch an owned point
        ghost_radius += deck.contact.distance_factor * spacing
    return radius, ghost_radius


def _build_windowed(deck: dk.Deck, comm: Any, lattice: Lattice) -> dict[str, Any]:
    """:func:`build_distributed` of a lattice body (:mod:`peridynamics.build.windowed`)."""
    families = ghost_families(deck, lattice)
    radius, ghost_radius = _radii(deck, lattice.spacing, families)
    part = agreed(comm, lambda: _windowed(comm, lattice, radius, ghost_radius, families))
    lay = part.layout
    cloud = windowed_cloud(deck, lattice, part, comm)
    meta = cloud_meta(lattice, cloud, lay.n_owned, comm, lay.n_global)
    if comm.Get_rank() == 0:
        warn_horizon(deck, meta.lo, meta.hi, meta.n_points, meta.spacing)
    body, kin, init = conditions(deck, cloud, lay.n_owned, comm)
    parts = _rank_model(
        deck, cloud, MPICommunicator(comm, lay), part.n_family, (meta.lo, meta.hi), body, kin, init
    )
    set_up = {"how": "windowed", "replicated_bytes": part.replicated_bytes}
    return {**parts, "global_cloud": meta, "set_up": set_up}


def _rank_model(
    deck: dk.Deck,
    cloud: PointCloud,
    mpi: MPICommunicator,
    n_family: int | NDArray[np.bool_],
    bounds: tuple[Any, Any],
    body: list,
    kin: list,
    init: list,
) -> dict[str, Any]:
    """A rank's bonds (owned and first-layer families: the first ``n_family`` points,
    or a mask of them), model, rigid bodies and solver, built with its communicator
    active (``bounds``: the whole body's corners, m)."""
    with using(mpi):
        bonds = own_families(build_bonds_for(deck, cloud, bounds), cloud, n_family)
        model = build_deck_model(deck, cloud, bonds, body)
        attach_rigid_bodies(deck, cloud, model, bonds)
        solver = build_solver(deck, cloud, model, body, kin, init)
    return {
        "cloud": cloud,
        "model": model,
        "solver": solver,
        "communicator": mpi,
        "n_family": n_family,
    }


def _windowed(comm: Any, lattice: Lattice, radius: float, ghost: float, families: bool) -> Any:
    try:
        return windowed_layout(comm, lattice, radius, ghost, families)
    except ValueError as exc:
        raise SetupError("geometry", str(exc)) from None


def _build_replicated(deck: dk.Deck, comm: Any) -> dict[str, Any]:
    """:func:`build_distributed` of a body every rank builds whole."""
    size = int(comm.Get_size())
    global_cloud = build_cloud(deck)
    if global_cloud.dim == 1:
        raise SetupError(
            "geometry", f"1-D runs are not decomposed; run it on one rank (not mpiexec -n {size})"
        )
    _refuse(deck, size)
    families = ghost_families(deck, global_cloud)
    radius, ghost_radius = _radii(deck, global_cloud.spacing, families)
    n_family: int | NDArray[np.bool_]
    if has_bodies(deck):  # each rank owns points of one body (parallel/bodies.py)
        owner = body_layout(deck, global_cloud).body_of_points()
        # the first ghost layer always has its families: each body's model is set up
        # from the points held here, with no exchange (build/bodies.py)
        radius, ghost_radius = _radii(deck, global_cloud.spacing, True)
        try:
            layout, n_family = decompose_bodies(comm, global_cloud, owner, radius, ghost_radius)
        except ValueError as exc:
            raise SetupError("bodies", str(exc)) from None
    else:
        layout, n_family = decompose(comm, global_cloud, radius, ghost_radius, families)
    cloud = local_cloud(global_cloud, layout)
    # on the global cloud (a traction's layer thickness is that of the whole node set)
    body, kin, init = (
        [localize_condition(c, layout.owned_ids) for c in group]
        for group in build_conditions(deck, global_cloud)
    )
    parts = _rank_model(
        deck, cloud, MPICommunicator(comm, layout), n_family, global_cloud.bounds, body, kin, init
    )
    set_up = {"how": "replicated", "replicated_bytes": int(global_cloud.x.nbytes)}
    return {**parts, "global_cloud": global_cloud, "set_up": set_up}
