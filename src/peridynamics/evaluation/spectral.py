"""The largest eigenvalue of the linearised model, estimated at set-up by Lanczos.

The analytic per-point stiffness bounds of the state-based families
(:meth:`~peridynamics.families.base.ForceModel.stiffness_bound`) are sufficient but
loose: measured against a dense eigen-solve the correspondence bound is 6.8 (2-D) to
11.6 (3-D) times the largest eigenvalue of M^-1 K and the LPS bound 1.4-1.6 times
(``benchmarks/critical_step.py``), so the explicit step is up to 3.4 times shorter than
stable and dynamic relaxation's fictitious density as cautious. A family that declares
:attr:`~peridynamics.families.base.ForceModel.spectral_bound` has the evaluator tighten
its bound with the estimate made here.

**Operator.** At the reference state (u = 0, the bonds as built) the stiffness
K = -d(V f)/du (N/m) is applied to a vector by a one-sided difference of the force
model's pure force pass::

    K v ~ -V (f(h v / |v|_inf) - f(0)) |v|_inf / h,   h = STEP * spacing,

one force evaluation per product (the geometric nonlinearity errs by O(h / spacing) =
1e-6 relative, round-off by O(1e-16 spacing / h) = 1e-10). For a symmetric positive
metric W = diag(w) per point (repeated over the components) the largest eigenvalue of
W^-1 K is that of the symmetric B = W^-1/2 K W^-1/2, estimated by ``ITERATIONS``
steps of the Lanczos (1950) recurrence without re-orthogonalisation: the largest Ritz
value theta (the largest eigenvalue of the tridiagonal matrix) is a Rayleigh quotient
of B, so theta <= lambda_max and it converges from below, much faster than the Rayleigh
quotient of the power iteration of Underwood (1983) with the same number of products.
Two metrics are used:

* w = rho V (kg, the lumped mass): theta ~ omega_max^2 (1/s^2), the explicit step
  dt_el = 2 / sqrt(SAFETY theta) (central differences are stable for omega dt <= 2;
  Silling & Askari (2005), eq. 18 is the per-point bound it replaces);
* w = 2 K_i V_i (the family's analytic bound, N/m^4 m^3): theta = mu <= 1, the factor
  by which the bound may be lowered while K <= 2 diag(K_i V_i) still holds, the
  contract that dynamic relaxation's fictitious density needs
  (:mod:`peridynamics.solvers.adr`).

**Safety.** theta approaches lambda_max from below; measured on 400- and 512-point
plates and boxes (PMB, LPS, correspondence) theta / lambda_max is 0.93-0.98 after 5
products and >= 0.9985 after 30. ``SAFETY`` = 1.25 covers a shortfall of 20 % (larger
bodies, whose spectrum is denser at its top) and 25 % of stiffening beyond the
reference state (SVK tension, contact aside); the estimate is never used above the
analytic bound (``min(SAFETY theta, analytic)``), so the step is never shorter than
before and the bound never looser. Not covered (as by the analytic bound before it):
broken bonds that stiffen a correspondence family (its K^-1 grows; 30 % of bonds
broken at random raised lambda_max 3.5-fold on a 2-D plate).

**Cost.** ``ITERATIONS + 1`` force evaluations (pre-pass and force pass) per metric,
once per model: the explicit solver asks for the mass metric, dynamic relaxation for the
bound metric.

**MPI.** Products are formed on the owned points after the halo exchange of the
displacement (:meth:`~peridynamics.evaluation.evaluator.Evaluator.exchange_dofs`);
every dot product and the max-norm are reduced through the model's communicator, and
the start vector is a hash of the global point ids, so a decomposed run makes the same
estimate as the serial one up to the order of the sums (some 1e-13 relative), which the
rounding of the bound up to 4 significant digits removes: the decomposed run takes the
serial run's step, bit for bit.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import eigvalsh_tridiagonal

if TYPE_CHECKING:
    from peridynamics.bonds.bonds import Bonds
    from peridynamics.communicator import Communicator
    from peridynamics.families.base import ForceModel
    from peridynamics.geometry.cloud import PointCloud
    from peridynamics.state import State

#: Lanczos steps (force evaluations after the one at u = 0)
ITERATIONS = 30
#: factor on the largest Ritz value (it approaches lambda_max from below)
SAFETY = 1.25
#: finite-difference displacement relative to the spacing
STEP = 1e-6

Vector = NDArray[np.float64]


class LinearisedModel(Protocol):
    """What the estimate reads of a model
    (:class:`~peridynamics.evaluation.evaluator.Evaluator`)."""

    force_model: ForceModel
    comm: Communicator
    cloud: PointCloud
    bonds: Bonds

    @property
    def n_points(self) -> int: ...

    @property
    def dim(self) -> int: ...

    def new_state(self) -> State: ...

    def exchange_dofs(self, state: State) -> Any: ...


@dataclass(frozen=True)
class SpectralEstimate:
    """A Lanczos estimate of the largest eigenvalue of W^-1 K.

    Attributes
    ----------
    ritz : float
        Largest Ritz value theta <= lambda_max (1/s^2 for the mass metric,
        dimensionless for the bound metric).
    bound : float
        ``SAFETY * ritz`` rounded up to 4 significant digits (:func:`round_up`), what
        the stable step and the bound use.
    evaluations : int
        Force evaluations spent (products plus the one at u = 0).
    seconds : float
        Wall time of the estimate (s).
    """

    ritz: float
    bound: float
    evaluations: int
    seconds: float


def lanczos_largest(
    apply: Callable[[Vector], Vector],
    dot: Callable[[Vector, Vector], float],
    start: Vector,
    iterations: int = ITERATIONS,
) -> tuple[float, int]:
    """Largest Ritz value of a symmetric operator after ``iterations`` Lanczos steps.

    Parameters
    ----------
    apply : callable
        y -> B y for a symmetric B, arrays of the shape of ``start``.
    dot : callable
        The inner product (summed over ranks in a decomposed run).
    start : ndarray
        Start vector, not zero on some rank.
    iterations : int
        Products of B at most (fewer when a Krylov space is invariant).

    Returns
    -------
    theta : float
        Largest eigenvalue of the Lanczos tridiagonal matrix (<= lambda_max(B)).
    products : int
        Products of B made.
    """
    q = start / math.sqrt(dot(start, start))
    q_prev = np.zeros_like(q)
    alpha: list[float] = []
    beta: list[float] = []
    b = 0.0
    for _ in range(iterations):
        z = apply(q)
        a = dot(q, z)
        z -= a * q
        z -= b * q_prev
        alpha.append(a)
        b = math.sqrt(max(dot(z, z), 0.0))
        if not b > 1e-12 * max(abs(a), 1e-300) or not math.isfinite(b):
            break  # an invariant Krylov space: theta is an eigenvalue
        beta.append(b)
        q_prev, q = q, z / b
    if len(alpha) == 1:
        return alpha[0], 1
    theta = eigvalsh_tridiagonal(np.array(alpha), np.array(beta[: len(alpha) - 1]))[-1]
    return float(theta), len(alpha)


def round_up(value: float, digits: int = 4) -> float:
    """``value`` rounded up to ``digits`` significant digits: a decomposed run, whose
    sums run in another order, then gets the serial run's bits (unless the two values,
    some 1e-13 apart, straddle a rounding boundary)."""
    if not (value > 0 and math.isfinite(value)):
        return value
    quantum = 10.0 ** (math.floor(math.log10(value)) - digits + 1)
    return math.ceil(value / quantum) * quantum


def start_vector(ids: NDArray[np.int64], dim: int) -> Vector:
    """A pseudo-random start vector (n, dim) in [-1, 1), a hash of the global point ids
    (the same on every decomposition)."""
    k = ids.astype(np.float64)[:, None] * dim + np.arange(dim)[None, :]
    return np.asarray(2.0 * ((np.sin(12.9898 * k + 78.233) * 43758.5453) % 1.0) - 1.0)


def largest_eigenvalue(
    model: LinearisedModel,
    weight: Vector,
    iterations: int = ITERATIONS,
    safety: float = SAFETY,
) -> SpectralEstimate:
    """Estimate the largest eigenvalue of W^-1 K of the force model at the reference state.

    Parameters
    ----------
    model : LinearisedModel
        An :class:`~peridynamics.evaluation.evaluator.Evaluator`: its force model
        (pre-pass and force pass), communicator and cloud are read; its state is not
        touched (a fresh one is made).
    weight : ndarray, shape (n_points,)
        The metric w_i per point (> 0; a point with w_i <= 0 is left out): kg for the
        mass metric rho_i V_i.
    iterations : int
        Lanczos steps (force evaluations after the one at u = 0).
    safety : float
        Factor on the largest Ritz value.

    Returns
    -------
    SpectralEstimate
    """
    t0 = time.perf_counter()
    fm, comm = model.force_model, model.comm
    own = comm.owned
    s = model.new_state()
    s.intact[...] = model.bonds.bond_intact
    parallel = comm.size > 1

    def force(u: Vector) -> Vector:
        s.u[...] = u
        if parallel:
            model.exchange_dofs(s)
        fm.prepass(s)
        fm.force(s)
        return s.force

    n, d = model.n_points, model.dim
    f0 = force(np.zeros((n, d))).copy()
    ok = weight > 0
    inv_root = np.divide(1.0, np.sqrt(np.where(ok, weight, 1.0)), where=ok, out=np.zeros(n))
    inv_root = inv_root[:, None]
    vol = model.cloud.volume[:, None]
    h = STEP * model.cloud.spacing

    def apply(y: Vector) -> Vector:
        u = y * inv_root
        top = comm.max(float(np.abs(u[own]).max()) if u[own].size else 0.0)
        if not top > 0:
            return np.zeros_like(y)
        scale = h / top
        df = force(u * scale) - f0
        return np.asarray(-(vol * df) * (inv_root / scale))

    def dot(a: Vector, b: Vector) -> float:
        return comm.sum(float(np.sum(a[own] * b[own])))

    ids = model.cloud.global_ids
    ids = np.arange(n, dtype=np.int64) if ids is None else np.asarray(ids)
    start = start_vector(ids, d) * ok[:, None]
    theta, products = lanczos_largest(apply, dot, start, iterations)
    return SpectralEstimate(
        ritz=theta,
        bound=round_up(safety * theta),
        evaluations=products + 1,
        seconds=time.perf_counter() - t0,
    )
