"""Dispersion relations of discrete bond-based peridynamics.

Closed forms (Lu & Wang (2016), section 2; PD wave dispersion (n.d.), section 2; full
references in docs/references.md):

* :func:`fully_discrete_1d` -- 1-D PD with the partial-volume rule of Lu & Wang (2016)
  (weight 1/2 on the neighbour at exactly delta = m dx) and central-difference time
  stepping (Lu & Wang (2016), eq. 12, which as printed repeats the last term
  (cos(m k dx) - 1)/(2m); it is counted once here):
  ``cos(w dt) - 1 = [2 c^2 dt^2 / (m^2 dx^2)] {sum_{q<m} (cos(q k dx) - 1)/q
  + (cos(m k dx) - 1)/(2m)}``.
* :func:`semi_discrete_1d` -- PD wave dispersion (n.d.), eqs 17-21: full nodal volumes,
  n = floor(delta/h) neighbours per side, phase velocity, frequency and group velocity against
  N_h = kappa h / (2 pi).
* :func:`continuous_1d` -- PD wave dispersion (n.d.), eqs 14-16, the integral
  (non-discretised) operator.
* :func:`semi_discrete_2d` -- PD wave dispersion (n.d.), eq. 32, direction theta, the
  paper's scalar operator over the lattice family.
* :func:`bloch_dispersion` -- the same quantities computed from the *actual* bond list of
  a patch built by the engine (any horizon, partial-volume rule, micromodulus profile,
  surface correction): the Bloch-wave dynamical matrix of one interior point.

Velocities are relative to the bar speed v0 = sqrt(E / rho); frequencies to
omega0 = v0 / h.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import brentq
from scipy.special import sici

F = NDArray[np.float64]


def _one_minus_cos(x: ArrayLike) -> F:
    """1 - cos x computed as 2 sin^2(x/2): no cancellation for small wavenumbers."""
    return 2.0 * np.sin(0.5 * np.asarray(x, dtype=float)) ** 2


# ------------------------------------------------------------ 1-D, Lu & Wang (2016)
def discrete_weights_1d(m: int) -> F:
    """Weights w_q, q = 1..m, of the 1-D stencil of Lu & Wang (2016): 1, ..., 1, 1/2."""
    if m < 1:
        raise ValueError("m = delta/dx must be an integer >= 1")
    w = np.ones(m)
    w[-1] = 0.5
    return w


def fully_discrete_1d(
    k: ArrayLike, dx: float, m: int, dt: float, youngs_modulus: float, density: float
) -> F:
    """Angular frequency omega(k) (rad/s) of 1-D PD with central differences (Lu & Wang
    (2016), eq. 12, last term counted once).

    Parameters
    ----------
    k : wavenumbers (rad/m), any shape.
    dx : grid spacing (m); m : horizon ratio delta/dx (integer); dt : time step (s).

    Returns NaN where the scheme is unstable for that wavenumber (|cos(omega dt)| > 1).
    """
    k = np.asarray(k, dtype=float)
    c2 = youngs_modulus / density
    q = np.arange(1, m + 1)
    w = discrete_weights_1d(m)
    # cos(w dt) - 1 = -2 sin^2(w dt / 2): solve for the sine (no cancellation at small dt)
    s = np.sum(w * _one_minus_cos(np.multiply.outer(k, q) * dx) / q, axis=-1)
    return _omega_from_half_sine2(c2 * dt**2 / (m**2 * dx**2) * s, dt)


def _omega_from_half_sine2(sin2: F, dt: float) -> F:
    """omega = 2 asin(sqrt(sin2)) / dt where sin2 = sin^2(omega dt / 2) <= 1, NaN above."""
    sin2 = np.asarray(sin2, dtype=float)
    with np.errstate(invalid="ignore"):
        return np.where(sin2 <= 1.0, 2.0 * np.arcsin(np.sqrt(np.clip(sin2, 0, 1))) / dt, np.nan)


def semi_discrete_omega_1d(
    k: ArrayLike, dx: float, m: int, youngs_modulus: float, density: float
) -> F:
    """omega(k) (rad/s) of the same 1-D stencil without time discretisation:
    omega^2 = 4 c^2 / (m^2 dx^2) sum_q w_q (1 - cos(q k dx)) / q (the dt -> 0 limit of
    :func:`fully_discrete_1d`)."""
    k = np.asarray(k, dtype=float)
    q = np.arange(1, m + 1)
    w = discrete_weights_1d(m)
    s = np.sum(w * _one_minus_cos(np.multiply.outer(k, q) * dx) / q, axis=-1)
    return np.sqrt(youngs_modulus / density * 4.0 * s / (m**2 * dx**2))


def fdm_1d(k: ArrayLike, dx: float, dt: float, youngs_modulus: float, density: float) -> F:
    """Central-difference FDM: cos(omega dt) - 1 = (c dt / dx)^2 (cos(k dx) - 1) (rad/s)."""
    k = np.asarray(k, dtype=float)
    courant2 = youngs_modulus / density * dt**2 / dx**2
    return _omega_from_half_sine2(0.5 * courant2 * _one_minus_cos(k * dx), dt)


# --------------------------------------------------- 1-D, PD wave dispersion (n.d.)
@dataclass(frozen=True)
class Dispersion:
    """A dispersion curve against N_h = kappa h / (2 pi); all arrays shape (n,)."""

    N_h: F
    v_over_v0: F
    omega_over_omega0: F
    group_velocity_over_v0: F

    def as_dict(self) -> dict[str, list[float]]:
        """JSON-ready mapping (the ``peridynamics dispersion --json`` contract)."""
        return {k: np.asarray(v).tolist() for k, v in self.__dict__.items()}


def neighbours_1d(m: float) -> int:
    """n = floor(delta / h) neighbours per side (PD wave dispersion (n.d.): full volumes,
    bond lengths up to delta)."""
    if m < 1:
        raise ValueError("m = delta/h must be >= 1")
    return int(np.floor(m + 1e-9))


def semi_discrete_1d(N_h: ArrayLike, m: float = 3.015) -> Dispersion:
    """PD wave dispersion (n.d.), eqs 19-21 and the group velocity, for delta = m h (full volumes).

    v/v0 = (1 / (pi N_h m)) sqrt(S), omega/omega0 = (2/m) sqrt(S),
    v_g/v0 = (1/m) sum_j sin(2 pi N_h j) / sqrt(S), with S = sum_j (1 - cos 2 pi N_h j)/j.
    The long-wave limit (N_h -> 0) is sqrt(n (n + 1)) / m. At integer N_h > 0 the group
    velocity jumps from -v_long to +v_long; the returned value there is +v_long.
    """
    nh = np.atleast_1d(np.asarray(N_h, dtype=float))
    j = np.arange(1, neighbours_1d(m) + 1)
    x = 2.0 * np.pi * np.multiply.outer(nh, j)
    S = np.sum(_one_minus_cos(x) / j, axis=-1)
    G = np.sum(np.sin(x), axis=-1)
    n = len(j)
    with np.errstate(invalid="ignore", divide="ignore"):
        v = np.where(nh == 0, np.sqrt(n * (n + 1)) / m, np.sqrt(S) / (np.pi * nh * m))
        vg = np.where(S > 1e-300, G / (m * np.sqrt(S)), np.sqrt(n * (n + 1)) / m)
    return Dispersion(nh, np.abs(v), 2.0 / m * np.sqrt(S), vg)


def zero_energy_points_1d(n_max: int = 2) -> F:
    """N_h with v = 0 at kappa != 0: the non-zero integers (PD wave dispersion (n.d.), Fig. 2)."""
    return np.arange(1, n_max + 1, dtype=float)


def zero_group_velocity_points_1d(m: float = 3.015, N_max: float = 1.0, samples: int = 4000) -> F:
    """N_h in (0, N_max) where the group velocity vanishes (roots of sum_j sin(2 pi N_h j)).

    Integer N_h (where S = 0 too) are excluded; for m = 3.015 the roots in (0, 1) are
    0.25, 1/3, 0.5, 2/3, 0.75 (the zero-slope points of PD wave dispersion (n.d.), Fig. 3;
    reference values in tests/verification/test_dispersion.py).
    """
    j = np.arange(1, neighbours_1d(m) + 1)

    def g(x: float) -> float:
        return float(np.sum(np.sin(2.0 * np.pi * x * j)))

    grid = np.linspace(1e-6, N_max - 1e-6, samples)
    vals = np.array([g(x) for x in grid])  # a few thousand scalar evaluations
    roots = []
    for a, b, fa, fb in zip(grid[:-1], grid[1:], vals[:-1], vals[1:], strict=True):
        if fa == 0.0:
            roots.append(a)
        elif fa * fb < 0:
            roots.append(brentq(g, a, b, xtol=1e-14))
    r = np.array(roots)
    return r[np.abs(r - np.round(r)) > 1e-9]


def continuous_1d(kappa_delta: ArrayLike) -> F:
    """PD wave dispersion (n.d.), eqs 14-16: v/v0 = (2 / (kappa delta)) sqrt(Cin(kappa delta))
    for the integral operator with c = 2E/(A delta^2), Cin(x) = gamma + ln x - Ci(x)."""
    x = np.abs(np.atleast_1d(np.asarray(kappa_delta, dtype=float)))  # even in kappa
    with np.errstate(divide="ignore", invalid="ignore"):
        cin = np.euler_gamma + np.log(x) - sici(x)[1]
        # small x: the series sum_k (-1)^(k+1) x^(2k) / (2k (2k)!) avoids cancellation
        x2 = x * x
        series = x2 / 4 - x2**2 / 96 + x2**3 / 4320 - x2**4 / 322560 + x2**5 / 36288000
        cin = np.where(x < 0.5, series, cin)
        return np.where(x > 0, 2.0 / x * np.sqrt(np.maximum(cin, 0.0)), 1.0)


# --------------------------------------------------- 2-D, PD wave dispersion (n.d.)
def lattice_family_2d(m: float) -> F:
    """Lattice bond vectors (in units of h) no longer than m h, shape (n, 2)."""
    r = int(np.ceil(m))
    i, j = np.meshgrid(np.arange(-r, r + 1), np.arange(-r, r + 1), indexing="ij")
    v = np.column_stack([i.ravel(), j.ravel()]).astype(float)
    d = np.hypot(v[:, 0], v[:, 1])
    return v[(d > 0) & (d <= m * (1 + 1e-9))]


def semi_discrete_2d(N_h: ArrayLike, m: float = 3.015, theta_deg: float = 0.0) -> Dispersion:
    """PD wave dispersion (n.d.), eq. 32 (the paper's scalar operator), direction theta (degrees).

    |v/v0| = (3/(kappa delta)) sqrt((h/(pi delta)) sum_j (h/|xi_j|)(1 - cos kappa xi_j.b))
    over the lattice family |xi_j| <= delta; omega/omega0 = 2 pi N_h v/v0; the group
    velocity is d omega / d kappa along b, in closed form.
    """
    nh = np.atleast_1d(np.asarray(N_h, dtype=float))
    xi = lattice_family_2d(m)
    t = np.radians(theta_deg)
    a = xi @ np.array([np.cos(t), np.sin(t)])  # xi.b / h
    r = np.hypot(xi[:, 0], xi[:, 1])  # |xi| / h
    phase = 2.0 * np.pi * np.multiply.outer(nh, a)
    S = np.sum(_one_minus_cos(phase) / r, axis=-1)
    G = np.sum(a * np.sin(phase) / r, axis=-1)
    pref = 1.0 / (np.pi * m)  # (h/(pi delta))
    with np.errstate(invalid="ignore", divide="ignore"):
        # omega/omega0 = kappa h v/v0 = (3/m) sqrt(pref S)
        omega = 3.0 / m * np.sqrt(pref * S)
        long = 3.0 / m * np.sqrt(pref * 0.5 * np.sum(a * a / r))  # limit of v/v0
        v = np.where(nh == 0, long, omega / (2.0 * np.pi * nh))
        vg = np.where(S > 1e-300, (3.0 / m) * np.sqrt(pref) * G / (2.0 * np.sqrt(S)), long)
    return Dispersion(nh, np.abs(v), omega, vg)


def oscillation_index_2d(
    m: float = 3.015,
    thetas_deg: ArrayLike | None = None,
    N_range: tuple[float, float] = (1.0, 2.0),
    samples: int = 2001,
) -> F:
    """Largest |d(v/v0)/dN_h| over the high band N_h in ``N_range`` for each direction
    (PD wave dispersion (n.d.), Fig. 6); default directions 0..360 degrees in 1-degree steps."""
    th = np.arange(0.0, 361.0, 1.0) if thetas_deg is None else np.asarray(thetas_deg, float)
    nh = np.linspace(N_range[0], N_range[1], samples)
    out = np.empty(len(th))
    for k, t in enumerate(th):  # over directions (a few hundred), vectorised in N_h
        v = semi_discrete_2d(nh, m, float(t)).v_over_v0
        out[k] = np.max(np.abs(np.gradient(v, nh)))
    return out


# ------------------------------------------------------------- Bloch waves from bonds
def bloch_dispersion(model: object, point: int, wavevectors: ArrayLike, mode: str = "scalar") -> F:
    """omega (rad/s) of Bloch waves u_j = a exp(i k.x_j) seen by one point's family.

    Linearising the engine's bond force about the reference state gives
    rho omega^2 a = D(k) a with the dynamical matrix
    ``D(k) = sum_k stiffness_k / |xi_k| (1 - cos k.xi_k) P_k``, where ``P_k`` is the
    projector n n^T (``mode="tensor"``, the full bond-based operator) or 1
    (``mode="scalar"``, PD wave dispersion (n.d.), eq. 9). The family, partial volumes, micromodulus
    profile and surface correction are those of ``model`` (a
    :class:`~peridynamics.evaluation.evaluator.Evaluator`); ``point`` should be an interior point.

    Returns shape (n_k,) for "scalar" and (n_k, dim) (ascending) for "tensor".
    """
    b = model.bonds  # type: ignore[attr-defined]
    sl = slice(int(b.offsets[point]), int(b.offsets[point + 1]))
    xi = b.bond_xi[sl]
    w = model.stiffness[sl] / b.bond_length[sl]  # type: ignore[attr-defined]
    rho = float(model.density[point])  # type: ignore[attr-defined]
    kv = np.atleast_2d(np.asarray(wavevectors, dtype=float))
    if kv.shape[1] != xi.shape[1]:
        kv = kv.T
    one_minus_cos = _one_minus_cos(kv @ xi.T)  # (n_k, n_bonds)
    if mode == "scalar":
        return np.sqrt(np.maximum(one_minus_cos @ w, 0.0) / rho)
    if mode != "tensor":
        raise ValueError("mode is 'scalar' or 'tensor'")
    n = xi / b.bond_length[sl, None]
    proj = np.einsum("bi,bj->bij", n, n)
    D = np.einsum("kb,b,bij->kij", one_minus_cos, w, proj)
    return np.sqrt(np.maximum(np.linalg.eigvalsh(D), 0.0) / rho)


# --------------------------------------------------------------------- parameter advice
@dataclass(frozen=True)
class Advice:
    """Coarsest grid meeting a phase-speed tolerance up to a frequency."""

    m: int
    spacing: float
    horizon: float
    max_phase_error: float
    frequency: float
    table: list[dict[str, float]]


def advise_1d(
    frequency: float,
    tolerance: float,
    youngs_modulus: float,
    density: float,
    m_values: ArrayLike = (1, 2, 3, 4, 5, 6, 8, 10),
    m_min: int = 3,
    safety: float = 0.8,
) -> Advice:
    """Coarsest dx (and its m) whose phase-speed error stays below ``tolerance`` for all
    frequencies up to ``frequency`` (Hz), with the Lu & Wang (2016) stencil and central
    differences at ``safety`` x the stable step.

    For each m the largest dx is found by bisection; the advice is the m >= ``m_min``
    (fracture needs a few neighbours) with the coarsest dx. The phase-speed error at a
    frequency f is |v(f)/v0 - 1| with v = omega/k on the discrete branch.
    """
    if not (frequency > 0 and 0 < tolerance < 1):
        raise ValueError("need frequency > 0 Hz and 0 < tolerance < 1")
    c = np.sqrt(youngs_modulus / density)
    omega_max = 2.0 * np.pi * frequency

    def error(dx: float, m: int) -> float:
        dt = safety * dx / c * _stable_fraction_1d(m)
        k_hi = min(np.pi / dx, 4.0 * omega_max / c)
        k = np.linspace(k_hi / 4000, k_hi, 4000)
        om = fully_discrete_1d(k, dx, m, dt, youngs_modulus, density)
        if not np.all(np.isfinite(om)) or om.max() < omega_max:
            return np.inf  # unstable, or the grid cannot carry that frequency at all
        upto = k <= k[np.argmax(om >= omega_max)]
        return float(np.max(np.abs(om[upto] / k[upto] / c - 1.0)))

    table = []
    for m in (int(v) for v in np.atleast_1d(m_values)):
        lo, hi = 1e-4 * c / frequency, c / frequency  # dx range (m)
        if error(lo, m) > tolerance:
            continue
        for _ in range(60):  # bisection on dx
            mid = np.sqrt(lo * hi)
            lo, hi = (mid, hi) if error(mid, m) <= tolerance else (lo, mid)
        table.append(
            {"m": m, "spacing_m": lo, "horizon_m": m * lo, "max_phase_error": error(lo, m)}
        )
    eligible = [r for r in table if r["m"] >= m_min] or table
    if not eligible:
        raise ValueError("no grid meets the tolerance")
    best = max(eligible, key=lambda r: r["spacing_m"])
    return Advice(
        int(best["m"]),
        best["spacing_m"],
        best["horizon_m"],
        best["max_phase_error"],
        frequency,
        table,
    )


def _stable_fraction_1d(m: int) -> float:
    """Silling-Askari stable step of the Lu & Wang (2016) stencil in units of dx/c:
    sqrt(2 rho / sum_q 2 w_q c_pd A dx / (q dx)) = m / sqrt(2 sum_q w_q / q)."""
    q = np.arange(1, m + 1)
    return float(m / np.sqrt(2.0 * np.sum(discrete_weights_1d(m) / q)))


@dataclass(frozen=True)
class ViscousDispersion:
    """PD wave dispersion (n.d.), eqs 40-44 with linear viscosity b1; arrays shape (n,) against N_h.

    ``v_real_over_v0`` and ``v_imag_over_v0`` are the real and imaginary parts of the
    complex phase velocity v' (a wave decays as exp(kappa v_imag t)); ``damping_ratio``
    is |v_i / v| with v the undamped phase velocity (eq. 44).
    """

    N_h: F
    v_real_over_v0: F
    v_imag_over_v0: F
    damping_ratio: F

    def as_dict(self) -> dict[str, list[float]]:
        """JSON-ready mapping."""
        return {k: np.asarray(v).tolist() for k, v in self.__dict__.items()}


def viscous_1d(N_h: ArrayLike, m: float = 3.015, b1: float = 0.5) -> ViscousDispersion:
    """Complex phase velocity of 1-D PD with the linear bond viscosity of PD wave dispersion
    (n.d.), eqs 36-44.

    With gamma = b1 delta / (4 v0) (the rate constant equivalent to f_1 = b1 alpha_p zeta,
    see :mod:`peridynamics.families.viscosity`) eq. 41 has the root (eq. 42)
    v' = -i gamma M / (2 rho kappa) + sqrt(M / (rho kappa^2) - (gamma M / (2 rho kappa))^2),
    i.e. v_i / v0 = -(b1 pi N_h m / 4) (v/v0)^2 and |v_i / v| = (b1 / 4) sqrt(S) with
    S = sum_j (1 - cos 2 pi N_h j) / j (eq. 44): periodic in N_h like omega, so the damping
    is not selective (PD wave dispersion (n.d.), Fig. 7). Where |v_i| exceeds v the wave is
    overdamped and the real part is 0.
    """
    if not (np.isfinite(b1) and b1 >= 0):
        raise ValueError(f"b1 must be a finite number >= 0, got {b1}")
    d = semi_discrete_1d(N_h, m)
    nh, v = d.N_h, d.v_over_v0
    vi = -(b1 * np.pi * nh * m / 4.0) * v**2
    vr = np.sqrt(np.maximum(v**2 - vi**2, 0.0))
    j = np.arange(1, neighbours_1d(m) + 1)
    S = np.sum(_one_minus_cos(2.0 * np.pi * np.multiply.outer(nh, j)) / j, axis=-1)
    return ViscousDispersion(nh, vr, vi, b1 / 4.0 * np.sqrt(S))
