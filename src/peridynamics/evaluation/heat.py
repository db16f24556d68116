"""Bond-based peridynamic heat conduction (Bobaru & Duangpanya (2010,
2012)): the conduction operator on the mechanics' bond list.

    rho c_v dT_i/dt = sum_j kappa lambda_ij mu_ij (T_j - T_i) / |xi| beta_ij V_j + s_i

with the constant micro-conductivity ``kappa`` from the classical conductivity ``k``
(W/(m K)) (:func:`micro_conductivity`), ``beta_ij V_j`` the partial volume of the bond
list (:mod:`peridynamics.bonds.partial_volume`), ``mu_ij`` the bond's intact flag (a
broken bond conducts no heat: an insulated crack, Bobaru & Duangpanya (2012))
and ``lambda_ij`` the surface correction (:func:`thermal_correction_factors`).

The operator ``L`` (``(L T)_i = sum_j G_ij (T_j - T_i)``) times the point volumes,
``V L``, is symmetric (``V_i G_ij = V_j G_ji``): the heat leaving i through a bond
enters j, so the total heat ``sum_i V_i rho c T_i`` changes only through the sources.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.bonds.surface import bond_factors_from_point_ratios
from peridynamics.geometry.cloud import PointCloud
from peridynamics.kernels import heat as kernels

F = NDArray[np.float64]


def micro_conductivity(
    conductivity: float, dim: int, horizon: float, cross_section: float = 1.0
) -> float:
    """The constant micro-conductivity kappa (W/(m^(d+3) K) per unit ``cross_section``)
    that gives the classical conductivity ``k`` in the bulk.

    Matching the nonlocal operator on a quadratic field, or the "thermal potential"
    1/4 sum kappa (T_j - T_i)^2 / |xi| V_j under a uniform gradient G with k G^2 / 2
    (the same moment, ``int kappa xi_x^2 / |xi| dV = 2 k``):

    * 1-D, bar of area A:            kappa = 2 k / (A delta^2)
    * 2-D, plate of thickness h:     kappa = 6 k / (pi h delta^3)
    * 3-D:                           kappa = 6 k / (pi delta^4)

    (the 1-D and 2-D values as in Bobaru & Duangpanya (2010, 2012); the 3-D value by
    the same integral.)

    Parameters
    ----------
    conductivity : float, k (W/(m K)).
    dim : {1, 2, 3}.
    horizon : float, delta (m).
    cross_section : float, A (m^2) in 1-D, h (m) in 2-D, 1 in 3-D.
    """
    if not (conductivity > 0 and horizon > 0 and cross_section > 0):
        raise ValueError("conductivity, horizon and cross section must be > 0")
    if dim == 1:
        return 2.0 * conductivity / (cross_section * horizon**2)
    if dim == 2:
        return 6.0 * conductivity / (math.pi * cross_section * horizon**3)
    if dim == 3:
        return 6.0 * conductivity / (math.pi * horizon**4)
    raise ValueError(f"dim must be 1, 2 or 3, got {dim}")


def point_conductivity(bonds: Bonds, conductance: F, n: int, dim: int) -> F:
    """The diagonal of each point's effective conductivity tensor (dim, n) (W/(m K)):
    ``K_aa,i = 1/2 sum_k G_k xi_a^2`` (the heat potential of a unit gradient along a,
    times 2); ``k`` in the bulk of a corrected or fine-grained model."""
    xi = bonds.bond_xi
    owner = bonds.bond_i
    return np.stack(
        [0.5 * np.bincount(owner, conductance * xi[:, a] ** 2, minlength=n) for a in range(dim)]
    )


def thermal_correction_factors(
    bonds: Bonds, conductance: F, conductivity: float, n: int, dim: int
) -> F:
    """Surface-correction factors per bond (n_bonds,) by the energy method
    (Madenci & Oterkus (2014) for mechanics; Oterkus, Madenci & Agwai (2014) for
    heat): the point ratios ``lambda_a,i = k / K_aa,i``
    (:func:`point_conductivity`) under a unit gradient along each axis a, combined into
    a bond factor as the mechanics' (the ellipse of the end points' means:
    :func:`peridynamics.bonds.surface.bond_factors_from_point_ratios`)."""
    k_pt = point_conductivity(bonds, conductance, n, dim)
    with np.errstate(divide="ignore"):
        ratios = conductivity / k_pt
    return bond_factors_from_point_ratios(bonds, ratios)


def bulk_factor(bonds: Bonds, conductance: F, conductivity: float, n: int, dim: int) -> float:
    """k over the mean effective conductivity (:func:`point_conductivity`) of the point
    with the largest family: the one factor that removes the quadrature error of the
    family sum in the bulk."""
    i = int(np.argmax(np.diff(bonds.offsets)))
    k_pt = point_conductivity(bonds, conductance, n, dim)[:, i]
    return float(conductivity / np.mean(k_pt))


class HeatConduction:
    """The conduction operator of a body: bond conductances, heat capacity, rate,
    stable step and the sparse matrix.

    Parameters
    ----------
    cloud : PointCloud
    bonds : Bonds, the mechanics' bond list (its partial volumes).
    conductivity : float, k (W/(m K)).
    density : float or (n,) array, rho (kg/m^3).
    specific_heat : float or (n,) array, c_v (J/(kg K)).
    correction : {"surface", "bulk", "none"}
        ``surface``: scale the bonds by :func:`thermal_correction_factors` (the
        default); ``bulk``: by one factor, k over the effective conductivity of the
        largest family (the quadrature error of the family sum, for bodies whose
        boundary families a fictitious layer completes); ``none``: the analytic kappa.

    Attributes
    ----------
    kappa : float, the micro-conductivity (:func:`micro_conductivity`).
    conductance : (n_bonds,) G_k = kappa lambda_k beta_k V_j / |xi_k| (W/(m^3 K)).
    capacity : (n,) rho c_v (J/(m^3 K)).
    """

    def __init__(
        self,
        cloud: PointCloud,
        bonds: Bonds,
        conductivity: float,
        density: float | F,
        specific_heat: float | F,
        correction: str = "surface",
    ) -> None:
        self.cloud, self.bonds = cloud, bonds
        self.conductivity = float(conductivity)
        n, dim = cloud.n_points, cloud.dim
        self.kappa = micro_conductivity(conductivity, dim, bonds.horizon, cloud.cross_section)
        g = self.kappa * bonds.bond_volume / bonds.bond_length
        if correction == "surface":
            g = g * thermal_correction_factors(bonds, g, self.conductivity, n, dim)
        elif correction == "bulk":
            g = g * bulk_factor(bonds, g, self.conductivity, n, dim)
        elif correction != "none":
            raise ValueError(f"correction must be surface, bulk or none, got {correction!r}")
        self.conductance = np.ascontiguousarray(g, dtype=np.float64)
        self.capacity = np.broadcast_to(
            np.asarray(density, float) * np.asarray(specific_heat, float), (n,)
        ).copy()
        if not np.all(self.capacity > 0):
            raise ValueError("density and specific heat must be > 0")
        self.inv_capacity = 1.0 / self.capacity

    @property
    def n_points(self) -> int:
        """Number of points."""
        return self.cloud.n_points

    def rate(self, temperature: F, intact: NDArray[np.uint8], out: F) -> F:
        """The conduction heat rate density h_i (W/m^3) into ``out`` (n,)."""
        kernels.heat_rate(
            temperature, self.bonds.offsets, self.bonds.bond_j, self.conductance, intact, out
        )
        return out

    def row_sum(self, intact: NDArray[np.uint8]) -> F:
        """sum_k G_k mu_k per point (n,) (W/(m^3 K))."""
        out = np.empty(self.n_points)
        kernels.conductance_row_sum(self.bonds.offsets, self.conductance, intact, out)
        return out

    def stable_time_step(self, intact: NDArray[np.uint8], extra: F | None = None) -> float:
        """The forward-Euler bound min_i rho c_i / (sum_k G_k mu_k + e_i) (s).

        The eigenvalues of C^-1 L lie in [-2 max_i r_i / c_i, 0] (Gershgorin, with the
        row sum r_i = sum_k G_k mu_k equal to the diagonal), so forward Euler is stable
        for dt <= 2 / max |lambda| >= min_i c_i / r_i. ``extra`` (n,) (W/(m^3 K)) adds a
        diagonal term of the boundary conditions (convection h / l)."""
        r = self.row_sum(intact)
        if extra is not None:
            r = r + extra
        live = r > 0
        if not np.any(live):
            return math.inf
        return float(np.min(self.capacity[live] / r[live]))

    def matrix(self, intact: NDArray[np.uint8]) -> sp.csr_matrix:
        """L (n, n) (W/(m^3 K)), ``(L T)_i = sum_k G_k mu_k (T_j - T_i)``; ``diag(V) L``
        is symmetric."""
        n = self.n_points
        b = self.bonds
        g = self.conductance * intact
        off = sp.csr_matrix((g, b.bond_j.astype(np.int64), b.offsets), shape=(n, n))
        return (off - sp.diags(np.asarray(off.sum(axis=1)).ravel())).tocsr()

    def heat_content(self, temperature: F, reference: float = 0.0) -> float:
        """sum_i V_i rho c_i (T_i - T_ref) (J), the stored heat."""
        v = self.cloud.volume
        return float(np.sum(v * self.capacity * (temperature - reference)))
