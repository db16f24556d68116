"""One equilibrium solve of adaptive dynamic relaxation: the fictitious density (ADR-2)
and the damped pseudo-dynamics (ADR-3)...(ADR-6) from U' = 0 to the convergence test of
:mod:`peridynamics.solvers.adr` (Kilic & Madenci (2010); the equations and the choices
are in that module's docstring). The load stepping and damage rounds around it are
:class:`peridynamics.solvers.adr.ADRSolver`.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from peridynamics.evaluation import Evaluator
from peridynamics.kernels.adr import adr_norms, adr_update
from peridynamics.state import State

__all__ = ["MAX_DAMPING", "Relaxation", "fictitious_density", "flat"]

#: upper clamp of c dt (Madenci & Oterkus: c = 1.9 when the estimate exceeds 2)
MAX_DAMPING = 1.9


def flat(a: NDArray[np.float64]) -> NDArray[np.float64]:
    """A 1-D view of a C-contiguous (n, dim) array (writes go through)."""
    if not a.flags.c_contiguous:
        raise ValueError("ADR needs C-contiguous state arrays")
    return a.reshape(-1)


def fictitious_density(model: Evaluator, density_factor: float, dt: float) -> NDArray[np.float64]:
    """lambda_ii = density_factor / 4 * dt^2 * K_i per dof (n dim,) from the model's
    stiffness bound K_i (ADR-2); a point without stiffness gets the largest value."""
    bound = np.asarray(model.stiffness_bound(), dtype=np.float64)
    lam = 0.25 * density_factor * dt**2 * bound
    if not np.all(np.isfinite(lam)) or not np.any(lam > 0):
        raise ValueError("the model's stiffness bound is not finite and positive")
    lam = np.where(lam > 0, lam, lam.max())  # a point without stiffness never moves
    return np.repeat(lam, model.dim)


class Relaxation:
    """The damped fictitious dynamics of ADR on one model, and its working arrays.

    Parameters
    ----------
    model : Evaluator
    lam : (n dim,) fictitious density lambda_ii per dof (:func:`fictitious_density`).
    free : (n dim,) uint8, 1 for a free dof, 0 for a constrained one.
    dt : float
        Fictitious time step.
    tolerance : float
        Relative residual of equilibrium.
    max_iterations : int
        Iterations allowed per solve.

    Attributes
    ----------
    target : (n dim,) displacement of the constrained dofs (m), set by the load step.
    load_norm : float
        Load norm max(||V b||_free, ||R||_fixed) of the last iteration (N).
    """

    def __init__(
        self,
        model: Evaluator,
        lam: NDArray[np.float64],
        free: NDArray[np.uint8],
        dt: float,
        tolerance: float,
        max_iterations: int,
    ) -> None:
        self.model = model
        self.dt = dt
        self.tolerance = tolerance
        self.max_iterations = max_iterations
        d = model.dim
        self.inv_lambda = 1.0 / lam
        self.volume = np.repeat(np.asarray(model.cloud.volume, dtype=np.float64), d)
        self.free = free
        m = model.n_points * d
        self.v = np.zeros(m)  # fictitious velocity U'^{n-1/2}
        self.force_prev = np.zeros(m)
        self.target = np.zeros(m)
        self.sums = np.zeros(4)
        self.load_norm = 0.0
        self._warmed = False

    def warm_up(self) -> None:
        """Compile (or load from the cache) the kernels on tiny arrays."""
        if self._warmed:
            return
        z = np.zeros(2)
        one = np.ones(2)
        adr_norms(z, z, z, z, z, one, one, np.ones(2, np.uint8), 1.0, np.zeros(4))
        adr_update(z.copy(), z.copy(), z, z, one, np.ones(2, np.uint8), z, 0.0, 1.0, True)
        self._warmed = True

    def relax(self, s: State, floor: float = 0.0) -> tuple[int, float, bool]:
        """ADR from U' = 0 at ``s.u`` to equilibrium under the current loads.

        Parameters
        ----------
        s : State
        floor : float
            Smallest load norm (N) the residual is measured against (the largest load
            norm of the earlier load steps).

        Returns
        -------
        iterations : int
            Force evaluations after the start (0 when already in equilibrium).
        residual : float
            Final relative residual (NaN when the solution became non-finite).
        converged : bool
        """
        m, dt = self.model, self.dt
        u, f, b = flat(s.u), flat(s.force), flat(s.body)
        v, fprev, sums = self.v, self.force_prev, self.sums
        free, inv_lam, vol, target = self.free, self.inv_lambda, self.volume, self.target
        fixed = free == 0
        u[fixed] = target[fixed]
        v[:] = 0.0
        m.evaluate(s, commit=False)
        fprev[:] = f
        comm = m.comm
        k = len(u) if comm.n_owned is None else comm.n_owned * m.dim  # owned dofs
        b_free = np.where(free[:k] == 1, vol[:k] * b[:k], 0.0)
        load = math.sqrt(comm.sum(float(np.sum(b_free * b_free))))
        floor = max(floor, np.finfo(np.float64).tiny)
        it = 0
        while True:
            adr_norms(u[:k], v[:k], f[:k], fprev[:k], b[:k], vol[:k], inv_lam[:k], free[:k],
                      dt, sums)  # fmt: skip
            if comm.size > 1:  # sums over every rank's owned dofs
                sums[:] = comm.sum_array(sums)
            self.load_norm = max(load, math.sqrt(sums[1]))
            residual = math.sqrt(sums[0]) / max(self.load_norm, floor)
            if residual <= self.tolerance:
                return it, residual, True
            if not math.isfinite(residual):
                return it, float("nan"), False
            if it >= self.max_iterations:
                return it, residual, False
            c = 0.0
            if it > 0 and sums[3] > 0.0 and sums[2] > 0.0:
                c = min(2.0 * math.sqrt(sums[2] / sums[3]), MAX_DAMPING / dt)
            fprev[:] = f
            adr_update(u, v, f, b, inv_lam, free, target, c, dt, it == 0)
            m.evaluate(s, commit=False)
            it += 1
