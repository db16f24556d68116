"""Dofs and loads of the static solver (:class:`StaticDofs`, a base of
:class:`peridynamics.solvers.static.StaticSolver`): the eliminated dofs, the flat dof
vector of a State (all dof groups of the force model, ``width`` per point), the
unbalanced force and the loads at a load level."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from peridynamics.evaluation import Evaluator
from peridynamics.families.base import Dof
from peridynamics.loading.conditions import Fixed, Kinematic
from peridynamics.state import State

__all__ = ["StaticDofs", "norm"]


def norm(v: NDArray[np.float64]) -> float:
    """Euclidean norm of a flat vector without BLAS: ``np.linalg.norm``'s dot wakes
    OpenBLAS's threads, which then spin against Numba's workers and slow the next
    force evaluation several-fold on a small machine."""
    return math.sqrt(float(np.sum(np.square(v))))


class StaticDofs:
    """The dof layout and the loads of a static solve (attributes set by the solver).

    Attributes
    ----------
    model : Evaluator
    constraints : tuple of Kinematic
    load_steps : int
    load_time : float (s)
    proportional : bool
    groups : tuple of Dof, the force model's dof groups.
    width : int, dofs per point.
    _volume : (n width,) the point volume of every dof (m^3).
    """

    model: Evaluator
    constraints: Sequence[Kinematic]
    load_steps: int
    load_time: float
    proportional: bool
    groups: tuple[Dof, ...]
    width: int
    _volume: NDArray[np.float64]

    def _fixed_dofs(self) -> NDArray[np.bool_]:
        """Mask (n width,) of the dofs a condition prescribes: the displacements any
        condition writes (probed on a NaN array), the rotations of a ``Fixed`` with
        ``rotation``."""
        n, d = self.model.n_points, self.model.dim
        probe = np.full((n, d), np.nan)
        self._apply(probe, self.load_time)
        fixed = np.zeros((n, self.width), dtype=bool)
        fixed[:, :d] = ~np.isnan(probe)
        if self.width > d:
            for c in self.constraints:
                if isinstance(c, Fixed) and c.rotation:
                    fixed[c.nodes, d:] = True
        return fixed.reshape(-1)

    def _apply(self, u: NDArray[np.float64], t: float) -> None:
        scratch = np.zeros_like(u)
        dt = self.load_time / self.load_steps
        for c in self.constraints:
            c.apply(u, scratch, t, dt)

    def _gather(self, s: State) -> NDArray[np.float64]:
        return np.concatenate([s[g.value] for g in self.groups], axis=1)

    def _scatter(self, q: NDArray[np.float64], s: State) -> None:
        col = 0
        for g in self.groups:
            s[g.value][...] = q[:, col : col + g.components]
            col += g.components

    def _unbalanced(self, s: State) -> NDArray[np.float64]:
        """P = V (f + b) over all dofs, flat (n width,)."""
        f = np.concatenate([s[g.force] + s[g.body] for g in self.groups], axis=1)
        return self._volume * f.reshape(-1)

    def _set_loads(self, s: State, lam: float) -> NDArray[np.float64]:
        """Body forces at level lam; returns the flat prescribed values (n width,)."""
        t = lam * self.load_time
        scale = lam if self.proportional else 1.0
        self.model.external_force(t, s.body)
        if scale != 1.0:
            s.body *= scale
        target = np.zeros_like(s.u)
        self._apply(target, t)
        q = np.zeros((self.model.n_points, self.width))
        q[:, : self.model.dim] = scale * target
        return q.reshape(-1)
