"""The optimisers of ``peridynamics calibrate`` and the uncertainty at the optimum
(docs/calibration.md).

The optimiser works on unit variables z in [0, 1]^n (each parameter's linear or log
scale over its bounds, :class:`~peridynamics.app.calibrate_spec.Parameter`), so that
one finite-difference step and one tolerance suit parameters of any magnitude.

- ``least_squares``: :func:`scipy.optimize.least_squares` (trust-region reflective,
  bounded) with a forward-difference Jacobian whose n runs are one parallel batch;
- ``global``: :func:`scipy.optimize.differential_evolution` (Storn & Price 1997) over
  the bounds, each generation (``updating="deferred"``) one parallel batch, followed by
  least squares from its best point;
- ``restarts``: further least-squares starts at Latin-hypercube points, the best kept.

Uncertainty (Bates & Watts 1988, ch. 2): with J the Jacobian of the residuals with
respect to the physical parameters at the optimum, m residuals and n parameters,
``s^2 = sum r^2 / (m - n)``, covariance ``C = s^2 (J^T J)^-1``, standard errors
``sqrt(diag C)``, intervals ``p +- t_{(1+c)/2, m-n} se`` (Student's t), correlations
``C_ij / (se_i se_j)``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.app.calibrate_spec import CalibrationError, Options, Parameter

#: cost given to a run that did not complete, in the global search
FAILED_COST = 1e30

Residuals = Callable[[list[list[float]]], list[NDArray[np.float64] | None]]


class BudgetSpent(RuntimeError):
    """``options.max_runs`` reached."""


@dataclass
class Objective:
    """Residuals of unit-variable points, memoised (a point is never run twice in one
    calibration), in parallel batches through ``batch`` (physical values in, one
    residual vector or ``None`` out per point)."""

    params: list[Parameter]
    batch: Residuals
    max_runs: int
    memo: dict[tuple[float, ...], NDArray[np.float64] | None] = field(default_factory=dict)
    best: tuple[float, NDArray[np.float64]] | None = None

    def physical(self, z: NDArray[np.float64]) -> list[float]:
        """Unit variables -> physical parameter values."""
        return [p.from_unit(v) for p, v in zip(self.params, z, strict=True)]

    def many(self, zs: list[NDArray[np.float64]]) -> list[NDArray[np.float64] | None]:
        """Residuals of several points (the new ones run as one batch)."""
        keys = [tuple(float(v) for v in np.clip(z, 0.0, 1.0)) for z in zs]
        new = list(dict.fromkeys(k for k in keys if k not in self.memo))
        if new:
            if len(self.memo) + len(new) > self.max_runs:
                raise BudgetSpent
            for k, r in zip(new, self.batch([self.physical(np.array(k)) for k in new]),
                            strict=True):  # fmt: skip
                self.memo[k] = r
                if r is not None:
                    cost = 0.5 * float(r @ r)
                    if self.best is None or cost < self.best[0]:
                        self.best = (cost, np.array(k))
        return [self.memo[k] for k in keys]

    def one(self, z: NDArray[np.float64]) -> NDArray[np.float64]:
        """Residuals of one point (a failed run raises)."""
        r = self.many([z])[0]
        if r is None:
            raise CalibrationError(f"calibrate: the run at {self.physical(z)} did not complete")
        return r

    def jacobian(self, z: NDArray[np.float64], step: float) -> NDArray[np.float64]:
        """Forward differences in the unit variables (backward at the upper bound); the
        n runs are one batch."""
        z = np.clip(np.asarray(z, dtype=np.float64), 0.0, 1.0)
        steps = np.where(z + step <= 1.0, step, -step)
        points = [z.copy() for _ in range(len(z))]
        for k, pt in enumerate(points):
            pt[k] += steps[k]
        r0 = self.one(z)
        cols = []
        for k, r in enumerate(self.many(points)):
            if r is None:
                raise CalibrationError(
                    f"calibrate: a Jacobian run of {self.params[k].key} did not complete; "
                    "lower options.fd_step or narrow the bounds"
                )
            cols.append((r - r0) / steps[k])
        return np.column_stack(cols)


def least_squares_from(obj: Objective, z0: NDArray[np.float64], opts: Options) -> Any:
    """Bounded least squares from ``z0`` (SciPy's ``trf``)."""
    from scipy.optimize import least_squares

    return least_squares(
        obj.one, z0, jac=lambda z: obj.jacobian(z, opts.fd_step), bounds=(0.0, 1.0),
        method="trf", x_scale=1.0, xtol=opts.tolerance, ftol=opts.tolerance,
        gtol=opts.tolerance, max_nfev=opts.max_runs,
    )  # fmt: skip


def global_search(obj: Objective, opts: Options) -> NDArray[np.float64]:
    """Differential evolution over [0, 1]^n, one batch per generation; the best point."""
    from scipy.optimize import differential_evolution

    def cost(zs: NDArray[np.float64]) -> NDArray[np.float64]:  # zs: (n, S), vectorized
        pts = [zs[:, j] for j in range(zs.shape[1])] if zs.ndim == 2 else [zs]
        out = [FAILED_COST if r is None else 0.5 * float(r @ r) for r in obj.many(pts)]
        return np.array(out, dtype=np.float64)

    n = len(obj.params)
    res = differential_evolution(
        cost, [(0.0, 1.0)] * n, popsize=opts.population, maxiter=opts.generations,
        seed=opts.seed, polish=False, init="latinhypercube", updating="deferred",
        vectorized=True, tol=0.0, atol=0.0,
    )  # fmt: skip
    return np.asarray(res.x)


def starts(params: list[Parameter], opts: Options) -> list[NDArray[np.float64]]:
    """The first start (``initial``, else the middle of each scale) and ``restarts``
    Latin-hypercube points."""
    z0 = np.array([p.to_unit(p.initial) if p.initial is not None else 0.5 for p in params])
    out = [z0]
    if opts.restarts:
        from scipy.stats import qmc

        out += list(qmc.LatinHypercube(d=len(params), seed=opts.seed).random(opts.restarts))
    return out


def optimise(obj: Objective, opts: Options) -> tuple[NDArray[np.float64], dict[str, Any]]:
    """Run the chosen method; returns the best unit point and what happened."""
    info: dict[str, Any] = {"method": opts.method, "starts": [], "stopped": "converged"}
    try:
        firsts = starts(obj.params, opts)
        if opts.method == "global":
            firsts[0] = global_search(obj, opts)
            info["global_best"] = obj.physical(firsts[0])
        for z0 in firsts:
            res = least_squares_from(obj, z0, opts)
            info["starts"].append({
                "start": obj.physical(z0), "end": obj.physical(res.x),
                "cost": float(res.cost), "status": int(res.status), "message": res.message,
            })  # fmt: skip
    except BudgetSpent:
        info["stopped"] = f"options.max_runs ({obj.max_runs}) reached"
    if obj.best is None:
        raise CalibrationError("calibrate: no run completed; see the run.log of the runs")
    return obj.best[1], info


def uncertainty(
    params: list[Parameter], values: list[float], jac_unit: NDArray[np.float64],
    res: NDArray[np.float64], confidence: float,
) -> dict[str, Any]:  # fmt: skip
    """Standard errors, intervals and correlations of the fitted parameters from the
    Jacobian at the optimum (module docstring). ``jac_unit``: (m, n) with respect to the
    unit variables; ``res``: (m,) residuals there."""
    from scipy.stats import t as student

    m, n = jac_unit.shape
    dof = m - n
    # in the unit variables (columns of comparable size), then C_p = D C_z D with
    # D = diag(dp/dz): a pseudo-inverse of the physical J^T J would drop the columns of
    # large-valued parameters (E ~ 1e10 Pa) as if they were null directions
    scale = np.array([p.dvalue_dunit(v) for p, v in zip(params, values, strict=True)])
    s2 = float(res @ res) / dof if dof > 0 else float("nan")
    sv = np.linalg.svd(jac_unit, compute_uv=False)
    cond = float(sv[0] / sv[-1]) if sv[-1] > 0 else float("inf")
    cov = s2 * (scale[:, None] * np.linalg.pinv(jac_unit.T @ jac_unit) * scale[None, :])
    se = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    tq = float(student.ppf(0.5 * (1.0 + confidence), dof)) if dof > 0 else float("nan")
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(se, se)
    out = []
    for k, p in enumerate(params):
        z = p.to_unit(values[k])
        out.append({
            "key": p.key, "name": p.label, "value": values[k], "std_error": float(se[k]),
            "interval": [values[k] - tq * float(se[k]), values[k] + tq * float(se[k])],
            "relative_std_error": float(se[k] / abs(values[k])) if values[k] else None,
            "at_bound": bool(z < 1e-6 or z > 1 - 1e-6),
        })  # fmt: skip
    return {
        "parameters": out, "residuals": m, "dof": dof, "s2": s2, "t_quantile": tq,
        "confidence": confidence, "covariance": cov.tolist(), "correlation": corr.tolist(),
        "condition_number": cond, "identifiable": bool(np.isfinite(cond) and cond < 1e8),
    }  # fmt: skip
