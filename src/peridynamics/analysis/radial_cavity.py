"""Reference solution for a thick ring loaded by a pressure history on its inner surface.

Radially symmetric elastodynamics of an annulus a <= r <= b (the ring of PD wave dispersion
(n.d.), section 4.2, loaded by a blast on the wall of its cavity) in the radial displacement
u(r, t) (m):

    rho u_tt = M (u_rr + u_r / r - u / r**2)
    sigma_rr = M u_r + lam u / r,        sigma_tt = lam u_r + M u / r          (Pa)
    sigma_rr(a, t) = -p(t),              sigma_rr(b, t) = 0,         u = u_t = 0 at t = 0

(tension positive; p > 0 pushes the wall outwards). The in-plane moduli (Pa) are

    plane stress:  M = E / (1 - nu**2),                 lam = nu E / (1 - nu**2)
    plane strain:  M = lambda + 2 mu = E (1 - nu) / ((1 + nu)(1 - 2 nu)),  lam = lambda

with the dilatational wave speed c_p = sqrt(M / rho) (m/s). Two-dimensional bond-based
peridynamics fixes nu = 1/3, so the ring of PD wave dispersion (n.d.) is compared with plane
stress and nu = 1/3. The equation and the cylindrical spreading of a pulse emitted by a cavity
(amplitude ~ sqrt(a / r) far from the wall) are those of J. D. Achenbach, *Wave
Propagation in Elastic Solids* (North-Holland, 1973), chapters 2 and 4 (radially symmetric
waves, cavity under internal pressure). The static limit is Lame's thick cylinder; in plane
stress

    u(r) = p a**2 / (E (b**2 - a**2)) [(1 - nu) r + (1 + nu) b**2 / r]

and in plane strain u(r) = (1 + nu) p a**2 / (E (b**2 - a**2)) [(1 - 2 nu) r + b**2 / r].

Discretisation: linear finite elements on a uniform grid in r with the axisymmetric weak form
(weight r per radian; the stiffness is integrated with 3-point Gauss quadrature, the mass is
lumped, rho int N_i r dr), so the free outer surface is natural and the inner traction is the
nodal force p(t) a. Time integration is the explicit central difference scheme; the time step
is ``cfl`` times the stability limit 2 / omega_max, with omega_max bounded from above by
Gershgorin's theorem on M^-1 K (on a uniform grid this is h / c_p, the 1-D Courant limit).
Both are second-order accurate. Nodal stresses are recovered from the nodal displacements
with second-order finite differences for u_r (one-sided at the surfaces) and u / r exactly.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["RadialCavitySolution", "in_plane_moduli", "lame_displacement", "solve_radial_cavity"]

F = NDArray[np.float64]


@dataclass(frozen=True)
class RadialCavitySolution:
    """Radial displacement and stresses of the ring on a grid of radii and output times.

    Attributes
    ----------
    r : (n_r,) node radii (m), from the inner to the outer radius.
    t : (n_t,) output times (s).
    u : (n_t, n_r) radial displacement (m).
    sigma_rr, sigma_tt : (n_t, n_r) radial and hoop stress (Pa, tension positive).
    """

    r: F
    t: F
    u: F
    sigma_rr: F
    sigma_tt: F

    @property
    def pressure(self) -> F:
        """Mean in-plane compression -(sigma_rr + sigma_tt) / 2 (Pa), shape (n_t, n_r)."""
        return -0.5 * (self.sigma_rr + self.sigma_tt)

    def at(self, t: float, r: ArrayLike) -> dict[str, F]:
        """Fields at time ``t`` (s) and radii ``r`` (m), linearly interpolated in t and r.

        Returns a dict with ``u`` (m), ``sigma_rr``, ``sigma_tt`` and ``pressure`` (Pa), each
        shaped like ``r``. Raises ValueError outside the computed times or radii.
        """
        rq = np.asarray(r, dtype=float)
        tol = 1e-12 * max(abs(self.t[-1]), 1.0)
        if not self.t[0] - tol <= t <= self.t[-1] + tol:
            raise ValueError(f"t = {t} s is outside the output times [{self.t[0]}, {self.t[-1]}]")
        rtol = 1e-12 * self.r[-1]
        if rq.size and (rq.min() < self.r[0] - rtol or rq.max() > self.r[-1] + rtol):
            raise ValueError(f"r must lie in [{self.r[0]}, {self.r[-1]}] m")
        if self.t.size == 1:
            k, w = 0, 0.0
        else:
            k = int(np.clip(np.searchsorted(self.t, t, side="right") - 1, 0, self.t.size - 2))
            span = self.t[k + 1] - self.t[k]
            w = float(np.clip((t - self.t[k]) / span, 0.0, 1.0)) if span > 0 else 0.0
        out: dict[str, F] = {}
        for name in ("u", "sigma_rr", "sigma_tt"):
            field = getattr(self, name)
            row = field[k] if w == 0.0 else (1.0 - w) * field[k] + w * field[k + 1]
            out[name] = np.interp(rq.ravel(), self.r, row).reshape(rq.shape)
        out["pressure"] = -0.5 * (out["sigma_rr"] + out["sigma_tt"])
        return out


def in_plane_moduli(
    youngs_modulus: float, poisson_ratio: float, plane: Literal["stress", "strain"] = "stress"
) -> tuple[float, float]:
    """(M, lam) in Pa: sigma_rr = M u_r + lam u / r for plane stress or plane strain."""
    E, nu = float(youngs_modulus), float(poisson_ratio)
    if plane == "stress":
        return E / (1.0 - nu**2), nu * E / (1.0 - nu**2)
    if plane == "strain":
        lam = nu * E / ((1.0 + nu) * (1.0 - 2.0 * nu))
        mu = E / (2.0 * (1.0 + nu))
        return lam + 2.0 * mu, lam
    raise ValueError(f"plane must be 'stress' or 'strain', got {plane!r}")


def lame_displacement(
    r: ArrayLike,
    inner_radius: float,
    outer_radius: float,
    youngs_modulus: float,
    poisson_ratio: float,
    pressure: float,
    plane: Literal["stress", "strain"] = "stress",
) -> F:
    """Lame's static radial displacement (m) of a thick cylinder under internal ``pressure``
    (Pa) with a free outer surface, in plane stress or plane strain."""
    a, b, E, nu = float(inner_radius), float(outer_radius), float(youngs_modulus), poisson_ratio
    rr = np.asarray(r, dtype=float)
    k = pressure * a**2 / (E * (b**2 - a**2))
    if plane == "stress":
        return k * ((1.0 - nu) * rr + (1.0 + nu) * b**2 / rr)
    if plane == "strain":
        return k * (1.0 + nu) * ((1.0 - 2.0 * nu) * rr + b**2 / rr)
    raise ValueError(f"plane must be 'stress' or 'strain', got {plane!r}")


def _check_inputs(
    a: float, b: float, E: float, nu: float, rho: float, end_time: float, n: int, cfl: float
) -> None:
    if not (math.isfinite(a) and a > 0):
        raise ValueError(f"inner_radius must be a finite number > 0 m, got {a}")
    if not (math.isfinite(b) and b > a):
        raise ValueError(f"outer_radius must be > inner_radius ({a} m), got {b}")
    if not (math.isfinite(E) and E > 0):
        raise ValueError(f"youngs_modulus must be > 0 Pa, got {E}")
    if not (math.isfinite(nu) and -1.0 < nu < 0.5):
        raise ValueError(f"poisson_ratio must lie in (-1, 0.5), got {nu}")
    if not (math.isfinite(rho) and rho > 0):
        raise ValueError(f"density must be > 0 kg/m^3, got {rho}")
    if not (math.isfinite(end_time) and end_time > 0):
        raise ValueError(f"end_time must be > 0 s, got {end_time}")
    if n < 2:
        raise ValueError(f"n_elements must be an integer >= 2, got {n}")
    if not (math.isfinite(cfl) and 0 < cfl <= 1):
        raise ValueError(f"cfl must lie in (0, 1], got {cfl}")


def _assemble(r: F, M: float, lam: float, rho: float) -> tuple[F, F, F]:
    """Lumped mass and the (diagonal, off-diagonal) of the symmetric tridiagonal stiffness,
    per radian, of linear elements with nodes ``r``."""
    r1, r2 = r[:-1], r[1:]
    h = r2 - r1
    # mass: rho int N_i r dr (row sums of the consistent matrix)
    mass = np.zeros_like(r)
    mass[:-1] += rho * h * (2.0 * r1 + r2) / 6.0
    mass[1:] += rho * h * (r1 + 2.0 * r2) / 6.0
    # stiffness: int [M N_i' N_j' r + lam (N_i' N_j + N_i N_j') + M N_i N_j / r] dr
    xg, wg = np.polynomial.legendre.leggauss(3)
    k11 = M * 0.5 * (r1 + r2) / h - lam  # M/h^2 int r dr = M r_mid / h; lam term diag(-1, 1)
    k22 = M * 0.5 * (r1 + r2) / h + lam
    k12 = -M * 0.5 * (r1 + r2) / h
    for x, w in zip(xg, wg, strict=True):
        n2 = 0.5 * (1.0 + x)
        n1 = 1.0 - n2
        rg = r1 + n2 * h
        jw = 0.5 * w * h / rg
        k11 = k11 + M * n1 * n1 * jw
        k22 = k22 + M * n2 * n2 * jw
        k12 = k12 + M * n1 * n2 * jw
    diag = np.zeros_like(r)
    diag[:-1] += k11
    diag[1:] += k22
    return mass, diag, k12


def _stresses(u: F, r: F, M: float, lam: float) -> tuple[F, F]:
    """Nodal (sigma_rr, sigma_tt) of rows of nodal displacements ``u`` (..., n_r)."""
    du = np.gradient(u, r, axis=-1, edge_order=2)
    ur = u / r
    return M * du + lam * ur, lam * du + M * ur


def _output_times(
    output_times: Sequence[float] | None, n_steps: int, dt: float, end_time: float
) -> NDArray[np.floating]:
    """The output times (s): every step (``None``) or ``output_times`` checked and clipped
    to [0, end_time]."""
    if output_times is None:
        t_out = np.arange(n_steps + 1) * dt
        t_out[-1] = end_time
        return t_out
    t_out = np.asarray(output_times, dtype=float).ravel()
    if t_out.size == 0 or not np.all(np.isfinite(t_out)):
        raise ValueError("output_times must be a non-empty sequence of finite times (s)")
    if np.any(np.diff(t_out) < 0):
        raise ValueError("output_times must be non-decreasing")
    eps = 1e-12 * end_time
    if t_out[0] < -eps or t_out[-1] > end_time + eps:
        raise ValueError(f"output_times must lie in [0, end_time = {end_time}] s")
    return np.clip(t_out, 0.0, end_time)


def solve_radial_cavity(
    inner_radius: float,
    outer_radius: float,
    youngs_modulus: float,
    poisson_ratio: float,
    density: float,
    pressure: Callable[[float], float],
    end_time: float,
    output_times: Sequence[float] | None = None,
    n_elements: int = 400,
    plane: Literal["stress", "strain"] = "stress",
    cfl: float = 0.5,
) -> RadialCavitySolution:
    """Radial displacement and stresses of a ring a <= r <= b at rest at t = 0, loaded by
    the pressure ``pressure(t)`` (Pa, t in s; positive pushes outwards) on r = a, free at r = b.

    Parameters
    ----------
    inner_radius, outer_radius : a and b (m), 0 < a < b.
    youngs_modulus : E (Pa) > 0.
    poisson_ratio : nu in (-1, 0.5).
    density : rho (kg/m^3) > 0.
    pressure : p(t) (Pa), called once per time step.
    end_time : last time (s) > 0; the time step is adjusted so that it is hit exactly.
    output_times : times (s) in [0, end_time] at which the fields are returned (displacements
        linearly interpolated between steps). ``None`` returns every time step, including
        t = 0: mind the memory, n_steps x (n_elements + 1) x 3 floats.
    n_elements : number of equal linear elements in r (>= 2).
    plane : ``"stress"`` (a thin ring, the 2-D peridynamic model) or ``"strain"``.
    cfl : fraction of the central-difference stability limit, in (0, 1].

    The equations, moduli, scheme and sources are in the module docstring.
    """
    a, b = float(inner_radius), float(outer_radius)
    E, nu, rho = float(youngs_modulus), float(poisson_ratio), float(density)
    end_time, cfl = float(end_time), float(cfl)
    if isinstance(n_elements, bool) or int(n_elements) != n_elements:
        raise ValueError(f"n_elements must be an integer >= 2, got {n_elements}")
    n = int(n_elements)
    _check_inputs(a, b, E, nu, rho, end_time, n, cfl)
    if plane not in ("stress", "strain"):
        raise ValueError(f"plane must be 'stress' or 'strain', got {plane!r}")
    if not callable(pressure):
        raise ValueError("pressure must be a callable p(t) returning Pa")
    M, lam = in_plane_moduli(E, nu, plane)

    r = np.linspace(a, b, n + 1)
    mass, diag, off = _assemble(r, M, lam, rho)
    # Gershgorin bound on the largest eigenvalue of M^-1 K -> stable step 2 / omega_max
    row = np.abs(diag)
    row[:-1] += np.abs(off)
    row[1:] += np.abs(off)
    dt_stable = 2.0 / math.sqrt(float(np.max(row / mass)))
    n_steps = max(1, math.ceil(end_time / (cfl * dt_stable) - 1e-9))
    dt = end_time / n_steps

    t_out = _output_times(output_times, n_steps, dt, end_time)
    s = t_out / dt
    k_out = np.minimum(np.floor(s + 1e-9).astype(np.int64), n_steps - 1)
    w_out = np.clip(s - k_out, 0.0, 1.0)
    w_out[w_out < 1e-9] = 0.0
    U = np.zeros((t_out.size, r.size))

    inv_m = 1.0 / mass
    dt2 = dt * dt
    f = np.zeros_like(r)

    def accel(u: F, t: float) -> F:
        f[:] = diag * u
        f[:-1] += off * u[1:]
        f[1:] += off * u[:-1]
        np.negative(f, out=f)
        f[0] += float(pressure(t)) * a
        return f * inv_m

    u_old = np.zeros_like(r)
    u_cur = 0.5 * dt2 * accel(u_old, 0.0)  # at rest: u_1 = dt^2 / 2 a_0
    ptr, n_out = 0, t_out.size
    for step in range(n_steps):
        # here u_old = u(t_step), u_cur = u(t_step + dt)
        while ptr < n_out and k_out[ptr] == step:
            w = w_out[ptr]
            U[ptr] = u_old if w == 0.0 else (1.0 - w) * u_old + w * u_cur
            ptr += 1
        if step + 1 < n_steps:
            u_new = 2.0 * u_cur - u_old + dt2 * accel(u_cur, (step + 1) * dt)
            u_old, u_cur = u_cur, u_new
    if not np.all(np.isfinite(U)):
        raise FloatingPointError("the solution blew up; check the pressure history")
    srr, stt = _stresses(U, r, M, lam)
    return RadialCavitySolution(
        r=r, t=np.asarray(t_out, dtype=np.float64), u=U, sigma_rr=srr, sigma_tt=stt
    )
