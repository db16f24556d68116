"""Backtracking line search of the static solver's Newton update, for force models that
ask for it (``newton_line_search = True``, the elastic-plastic LPS of
:mod:`peridynamics.families.lps.plastic`).

Why: the internal force of a return-mapping plasticity law is only piecewise smooth in
the displacement (the yielded set of points changes). With the consistent tangent,
full Newton steps from the previous equilibrium (its prescribed displacements jumped to
the new level) can cycle between two yielded sets without converging: on an 8 x 3 x 3
LPS bar pulled past yield the yielded points flipped between 37 and 45 and a level had
not converged after 200 iterations (relative residual 3.9), where the backtracked steps
converge in 5 to 8 per level (docs/theory_plasticity.md, "Static solver (elastic-plastic
LPS)").

The step ``q + alpha dq`` is accepted at the first ``alpha = 1, 1/2, 1/4, ...`` that
decreases the free residual norm by the Armijo condition
``||P(q + alpha dq)|| <= (1 - c alpha) ||P(q)||`` (c = 1e-4; the Newton direction of
the exact tangent descends ``||P||`` at the rate ``-||P||``), the last one
(``alpha = 2^-MAX_HALVINGS``) if none does. Near the solution ``alpha = 1`` is taken,
so the quadratic convergence of Newton is kept. Every trial is one pure force
evaluation from the committed history (no commit).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.state import State

__all__ = ["ARMIJO", "MAX_HALVINGS", "backtrack"]

#: halvings of the Newton step before the last one is taken anyway
MAX_HALVINGS = 8
#: sufficient decrease of the free residual norm per unit step length
ARMIJO = 1e-4


def backtrack(solver: Any, s: State, dq: NDArray[np.float64], residual: float) -> int:
    """Move the free dofs of ``s`` by ``alpha dq`` (module docstring) and evaluate there.

    Parameters
    ----------
    solver : StaticSolver
        Gives ``_gather``, ``_scatter``, ``_unbalanced``, ``_norm``, ``width``,
        ``model`` and ``system.free`` (typed ``Any``: the solver imports this module).
    s : State
        At the current Newton iterate on entry (evaluated), at the accepted one on
        return (evaluated, ``commit=False``).
    dq : (n_free,) float
        The Newton correction of the free dofs (m; rad for rotations).
    residual : float
        ``||P_free||`` (N) at the current iterate, on the same free dofs.

    Returns
    -------
    int
        The number of halvings (0: the full Newton step).
    """
    free = solver.system.free
    q0 = solver._gather(s).reshape(-1).copy()
    alpha = 1.0
    halvings = 0
    while True:
        q = q0.copy()
        q[free] += alpha * dq
        solver._scatter(q.reshape(-1, solver.width), s)
        solver.model.evaluate(s, commit=False)
        if halvings == MAX_HALVINGS:
            return halvings
        trial = solver._norm(solver._unbalanced(s), free)
        if trial <= (1.0 - ARMIJO * alpha) * residual:  # False for NaN: halve
            return halvings
        alpha *= 0.5
        halvings += 1
