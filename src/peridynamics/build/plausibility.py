"""Warnings for admissible but implausible set-ups: a deck that validates and runs, but
almost certainly not as its author meant.

Each warning names the deck key and the reason (:class:`ImplausibleInput`, shown by the
command line as ``warning: ...``):

- a horizon larger than half the body's largest extent (every point bonded to nearly
  every other);
- a separate body (``bodies[k].geometry``) whose points lie on another body's points;
- a pre-crack that cuts no bond (it lies outside the body);
- a large static LPS or correspondence model left to ``linear_solver: auto``, which
  factorises it with the direct solver.

The time step, the damping and the material constants are judged by the solver's set-up
(:mod:`peridynamics.solvers.explicit`); node sets that select nothing are errors.
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from peridynamics import deck as dk

if TYPE_CHECKING:
    from peridynamics.bodies.build import BodyLayout
    from peridynamics.geometry import PointCloud

#: a horizon above this fraction of the body's largest extent is reported
HORIZON_FRACTION = 0.5
#: points of two bodies nearer than this fraction of the spacing overlap
OVERLAP_FRACTION = 0.5
#: points above which a static LPS or correspondence model under ``linear_solver: auto``
#: (direct below 250 000 free dofs) is reported, by dimension: measured on this
#: project's 2-core machine (docs/stress.md, "Plate with a hole"), 2-D LPS at 25 284
#: points direct 63 s and 5.6 GB against iterative 15 s and 1.28 GB, at 101 136 points
#: direct past 20 GB (stopped) against 61 s; 3-D LPS at 4 000 points 34 s and 2.95 GB
#: against 21 s and 1.82 GB
DIRECT_SOLVER_POINTS = {2: 20_000, 3: 4_000}


class ImplausibleInput(UserWarning):
    """An admissible deck value that is almost certainly a mistake."""


def _horizon_key(deck: dk.Deck) -> str:
    d = deck.discretisation
    return "discretisation.horizon" if d.horizon is not None else "discretisation.horizon_factor"


def warn_horizon(
    deck: dk.Deck, lo: NDArray[np.float64], hi: NDArray[np.float64], n_points: int, spacing: float
) -> None:
    """Warn when the horizon exceeds :data:`HORIZON_FRACTION` of the body's largest
    extent (m): ``lo``, ``hi`` are the corners of its bounding box (m)."""
    extent = float(np.max(hi - lo)) if n_points > 1 else 0.0
    delta = deck.discretisation.delta
    if extent <= 0.0 or delta <= HORIZON_FRACTION * extent:
        return
    warnings.warn(
        f"{_horizon_key(deck)}: the horizon {delta:.6g} m is larger than half the body's "
        f"largest extent ({extent:.6g} m): every point is bonded to nearly every other "
        f"and the model is no longer local (the horizon is usually about 3 spacings, "
        f"horizon_factor: 3.015; spacing {spacing:.6g} m)",
        ImplausibleInput,
        stacklevel=2,
    )


def warn_overlapping_bodies(deck: dk.Deck, cloud: PointCloud, layout: BodyLayout) -> None:
    """Warn for every separate body (``bodies[k].geometry``) whose points lie within
    :data:`OVERLAP_FRACTION` of a spacing of another body's points."""
    from scipy.spatial import cKDTree

    owner = layout.body_of_points()
    tol = OVERLAP_FRACTION * cloud.spacing
    for k, spec in enumerate(deck.bodies):
        if spec.geometry is None:
            continue  # a region of the main geometry: its points are not duplicated
        lo, hi = layout.range_of(k + 1)
        others = np.flatnonzero(owner != k + 1)
        if hi <= lo or others.size == 0:
            continue
        dist, near = cKDTree(cloud.x[others]).query(cloud.x[lo:hi], distance_upper_bound=tol)
        hit = np.isfinite(dist)
        if not hit.any():
            continue
        other = layout.names[int(owner[others[near[hit][0]]])]
        warnings.warn(
            f"bodies.{k}.geometry: {int(hit.sum())} of the {hi - lo} points of body "
            f"{spec.name!r} overlap points of body {other!r} (nearer than "
            f"{tol:.3g} m); two bodies in one place double the mass and stiffness there "
            f"- move the body (geometry origin) or make it a region of the main body",
            ImplausibleInput,
            stacklevel=2,
        )


def warn_idle_precracks(
    deck: dk.Deck, x: NDArray[np.float64], hits: list[NDArray[np.bool_]]
) -> None:
    """Warn for every pre-crack that crosses no bond (it lies outside the body);
    ``hits``: the bonds each of ``deck.precracks`` crosses, masks (n_bonds,). On a rank
    of a decomposed run (collective) over the whole body: a pre-crack another rank's
    bonds cross is not idle."""
    from peridynamics.communicator import active_comm

    comm = active_comm()
    for n, (spec, hit) in enumerate(zip(deck.precracks, hits, strict=True)):
        if comm.any(bool(hit.any())):
            continue
        lo = np.array([comm.min(float(v)) for v in x.min(axis=0)])
        hi = np.array([comm.max(float(v)) for v in x.max(axis=0)])
        warnings.warn(
            f"precracks.{n}: the pre-crack {np.asarray(spec.points).tolist()} cuts no "
            f"bond; the points span {lo.tolist()} .. {hi.tolist()} m - check its "
            f"coordinates",
            ImplausibleInput,
            stacklevel=2,
        )


def warn_direct_solver(deck: dk.Deck, n_points: int) -> None:
    """Warn when a static LPS or correspondence model of more than
    :data:`DIRECT_SOLVER_POINTS` points is left to ``solver.linear_solver: auto``: these
    families couple points two horizons apart, so the direct factorisation that ``auto``
    picks (below 250 000 free dofs) fills far faster than for PMB or micropolar models."""
    s = deck.solver
    limit = DIRECT_SOLVER_POINTS.get(deck.dim)
    if s.type != "static" or getattr(s, "linear_solver", "auto") != "auto" or limit is None:
        return
    if deck.bodies or deck.material.model not in ("lps", "correspondence") or n_points <= limit:
        return
    warnings.warn(
        f"solver.linear_solver: auto factorises this {deck.dim}-D {deck.material.model} "
        f"model of {n_points} points with the direct solver, whose fill grows fast for "
        "families that couple points two horizons apart (measured, 2-D LPS: 25 284 points "
        "5.6 GB and 4x the time of the iterative solver, 101 136 points past 20 GB); set "
        "solver.linear_solver: iterative",
        ImplausibleInput,
        stacklevel=2,
    )
