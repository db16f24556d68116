"""Point fields that a frame computes from the model and the state (stress, strain and
what derives from them), by the names of ``output.fields``.

:data:`POINT_FIELDS` is the registry: a frame field name to the function that makes it
from the model and the state. A field a frame stores in the State (displacement,
damage) is not here: :func:`~peridynamics.io.observers.frame_pieces.frame_fields`
reads those. The stress and strain (:mod:`peridynamics.evaluation.stress`) of a point
need only its own bonds and the displacement of its neighbours, which every rank of a
decomposed run holds for its owned points: each rank computes its own piece.

Fields (rows: the points that own a family):

* ``stress``: the stress tensor (n, 9) (Pa), row-major 3 x 3 (ParaView's tensor);
* ``strain``: the small-strain tensor of the nonlocal F (n, 9);
* ``von_mises``, ``pressure`` (n,) (Pa);
* ``principal_stress``: the principal stresses, largest first (n, 3) (Pa);
* ``principal_direction``: the unit direction of the largest principal stress (n, 3).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.evaluation import stress
from peridynamics.state import State

F = NDArray[np.float64]


def _stress(model: Any, s: State, cache: dict[str, F]) -> F:
    if "stress" not in cache:
        cache["stress"] = stress.point_stress(model, s)
    return cache["stress"]


def _principal(model: Any, s: State, cache: dict[str, F]) -> tuple[F, F]:
    if "principal" not in cache:
        w, v = stress.principal_stresses(_stress(model, s, cache))
        cache["principal"], cache["directions"] = w, v
    return cache["principal"], cache["directions"]


#: frame field name -> function of (model, state, cache) giving its point values
POINT_FIELDS: dict[str, Callable[[Any, State, dict[str, F]], F]] = {
    "stress": lambda m, s, c: _stress(m, s, c).reshape(-1, 9),
    "strain": lambda m, s, c: stress.point_strain(m, s).reshape(-1, 9),
    "von_mises": lambda m, s, c: stress.von_mises(_stress(m, s, c)),
    "pressure": lambda m, s, c: stress.pressure(_stress(m, s, c)),
    "principal_stress": lambda m, s, c: _principal(m, s, c)[0],
    "principal_direction": lambda m, s, c: _principal(m, s, c)[1][:, :, 0],
}


def point_fields(names: list[str], model: Any, s: State) -> dict[str, F]:
    """The fields of :data:`POINT_FIELDS` among ``names`` at state ``s`` (the stress
    computed once for all of them)."""
    cache: dict[str, F] = {}
    return {name: POINT_FIELDS[name](model, s, cache) for name in names if name in POINT_FIELDS}


__all__ = ["POINT_FIELDS", "point_fields"]


def point_field(name: str, model: Any, s: State) -> F:
    """One field of :data:`POINT_FIELDS` at state ``s``, every local point (a probe's
    rows; module level, so a decomposed run's ranks can be asked for it)."""
    return point_fields([name], model, s)[name]
