"""Isotropic bond-based families on a regular 3-D grid (``discretisation.isotropic_family``).

A bond-based (PMB) family on a cubic grid is not isotropic: its energy under a uniform
strain depends on the family only through the fourth moment
``M = sum_k w_k n_k n_k n_k n_k`` (``w_k = c(|xi_k|) beta_k V_j |xi_k|``, Silling (2000)),
and the grid's family has the cubic symmetry of the lattice, not the isotropic
``M_xxxx = 3 M_xxyy`` of the continuous ball. At delta = 3.015 dx (truncated partial
volumes) ``M_xxyy / M_xxxx = 0.368`` instead of 1/3: the interior of a body has
nu = 0.269 and E = 0.962 E0 (Born & Huang (1954): the cubic lattice with the Cauchy
relation), and the axis surface correction
(:func:`peridynamics.bonds.surface.energy_correction_factors`), which calibrates the
three axial moduli, cannot change that.

The fix here multiplies every bond's micromodulus by a factor quartic in the bond
direction, ``g(n) = 1 + phi(n) . lam`` (``phi`` the quartic monomials of
:func:`peridynamics.families.calibration.quartic_values`), with ``lam`` the
minimum-norm change (``min sum_k w_k (g_k - 1)^2``) that gives one complete family of
the lattice the isotropic fourth moment at its own second moment ``m = sum_k w_k``
(the interior solution of the moment method,
:func:`peridynamics.bonds.surface.moment_correction_factors`, which the irregular clouds
use point by point). ``lam`` comes from the lattice offsets within the bond search
radius, not from a point of the cloud: every point, every rank of a decomposed run and
every body gets the same factors bit for bit, and the factor of a bond depends on its
direction alone (no ghost families are needed). Only clouds on an axis-aligned grid of
their spacing get them (grid geometries; not mesh centroids or jittered grids, whose
families have no lattice symmetry). The surface correction then scales these bonds as
before, so the interior has E0 and nu = 1/4 (Silling (2000)) and the
surfaces the axial calibration.
"""

from __future__ import annotations

import math
import warnings
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds, setup_chunk_bonds
from peridynamics.bonds.partial_volume import PartialVolume, partial_volume_factor, search_radius
from peridynamics.bonds.search import bond_chunks
from peridynamics.families.calibration import (
    isotropic_fourth_moment,
    quartic_monomials,
    quartic_values,
)
from peridynamics.kernels.isotropy import direction_factors as kernel_direction_factors

#: the factor of every lattice bond must stay within these (a quartic this far from 1
#: would mean a family too small to be made isotropic; 0.83-1.30 at delta = 3.015 dx)
ISOTROPY_BOUNDS: tuple[float, float] = (0.25, 4.0)


def on_grid(x: NDArray[np.float64], spacing: float, tol: float = 1e-6) -> bool:
    """Whether the points ``x`` (n, dim) (m) lie on one axis-aligned grid of ``spacing``
    (to ``tol`` spacings): grid geometries do, mesh centroids and jittered grids not."""
    if len(x) == 0:
        return True
    r = (x - x[0]) / spacing
    return bool(np.max(np.abs(r - np.rint(r))) <= tol)


def lattice_offsets(
    horizon: float, spacing: float, rule: PartialVolume, dim: int
) -> NDArray[np.float64]:
    """The bond vectors xi (m) of one complete family of the regular grid of ``spacing``,
    shape (n, dim): the grid offsets within the search radius of the partial-volume
    ``rule`` with a non-zero partial volume."""
    reach = search_radius(horizon, spacing, rule)
    k = int(math.floor(reach / spacing))
    axis = np.arange(-k, k + 1, dtype=np.float64)
    grid = np.stack(np.meshgrid(*([axis] * dim), indexing="ij"), -1).reshape(-1, dim)
    xi = grid * spacing
    length = np.sqrt(np.einsum("ij,ij->i", xi, xi))
    keep = (length > 0) & (partial_volume_factor(length, horizon, spacing, rule) > 0)
    return np.ascontiguousarray(xi[keep])


def isotropy_coefficients(
    xi: NDArray[np.float64], weight: NDArray[np.float64]
) -> NDArray[np.float64]:
    """``lam`` (P,) of the factor ``g(n) = 1 + phi(n) . lam`` that gives the family of
    bond vectors ``xi`` (n, dim) and energy weights ``weight`` (n,) (``w_k`` of the module
    docstring) the isotropic fourth moment at its own second moment, with the least
    weighted change. Raises ``ValueError`` when the family cannot get it within
    :data:`ISOTROPY_BOUNDS`."""
    length = np.sqrt(np.einsum("ij,ij->i", xi, xi))
    phi = quartic_values(xi / length[:, None])
    target = isotropic_fourth_moment(xi.shape[1])
    m = float(weight.sum())
    a = phi.T @ (weight[:, None] * phi)
    b = m * target - phi.T @ weight
    lam = np.linalg.lstsq(a, b, rcond=None)[0]
    g = 1.0 + phi @ lam
    moment = phi.T @ (weight * g) / m
    if not (np.all(g >= ISOTROPY_BOUNDS[0]) and np.all(g <= ISOTROPY_BOUNDS[1])) or not (
        np.allclose(moment, target, rtol=0.0, atol=1e-12)
    ):
        raise ValueError(
            f"a family of {len(xi)} bonds cannot be made isotropic (factors "
            f"{g.min():.3g}-{g.max():.3g}); use a larger horizon or set "
            "discretisation.isotropic_family: false"
        )
    return np.asarray(lam, dtype=np.float64)


def direction_factors(bonds: Bonds, lam: NDArray[np.float64], dim: int) -> NDArray[np.float64]:
    """``g(n_k) = 1 + phi(n_k) . lam`` of every directed bond of a ``dim``-D bond list,
    shape (n_bonds,): the compiled :func:`peridynamics.kernels.isotropy.direction_factors`,
    range by range (bounded transients; each bond's factor is the same bits in any range)."""
    out = np.empty(bonds.n_bonds)
    monos = np.asarray(quartic_monomials(dim), dtype=np.int64)
    for a, b in bond_chunks(bonds.offsets, setup_chunk_bonds(dim)):
        xi = np.ascontiguousarray(bonds.bond_range("bond_xi", a, b), dtype=np.float64)
        out[a:b] = kernel_direction_factors(xi, lam, monos)
    return out


def lattice_family(
    material: Any,
    dim: int,
    horizon: float,
    spacing: float,
    rule: PartialVolume,
    cross_section: float,
    plane: str | None,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """One complete family of the regular grid of ``spacing``: its bond vectors ``xi``
    (n, dim) (m, :func:`lattice_offsets`), their lengths (n,) (m) and ``c(|xi|) beta``
    (n,) (N/m^6, the micromodulus of ``material``'s profile,
    ``material.micromodulus(length, dim, horizon, cross_section, plane)``, times the
    partial volume factor of ``rule``)."""
    xi = lattice_offsets(horizon, spacing, rule, dim)
    length = np.sqrt(np.einsum("ij,ij->i", xi, xi))
    c = material.micromodulus(length, dim, horizon, cross_section, plane)
    beta = partial_volume_factor(length, horizon, spacing, rule)
    return xi, length, c * beta


def lattice_isotropy_factors(
    material: Any, dim: int, bonds: Bonds, cross_section: float, plane: str | None
) -> NDArray[np.float64]:
    """Per-bond factors (n_bonds,) that make every complete family of the regular grid
    of ``bonds.spacing`` isotropic for ``material``'s micromodulus profile
    (:func:`lattice_family`)."""
    rule = cast(PartialVolume, bonds.partial_volume)
    xi, length, c_beta = lattice_family(
        material, dim, bonds.horizon, bonds.spacing, rule, cross_section, plane
    )
    lam = isotropy_coefficients(xi, c_beta * length)
    return direction_factors(bonds, lam, dim)


def grid_isotropy_factors(material: Any, cloud: Any, bonds: Bonds) -> NDArray[np.float64] | None:
    """:func:`lattice_isotropy_factors` of a 3-D ``cloud`` on an axis-aligned grid of its
    spacing when ``material.isotropic_family``, else ``None`` (1-D, 2-D, irregular clouds,
    the key off). A family that cannot be made isotropic (delta = dx in 3-D: six axis
    bonds, no shear stiffness) keeps the grid's with a warning naming the key."""
    if not (
        material.isotropic_family
        and cloud.dim == 3
        and not cloud.irregular
        and on_grid(cloud.x, cloud.spacing)
    ):
        return None
    try:
        return lattice_isotropy_factors(
            material, cloud.dim, bonds, cloud.cross_section, cloud.plane
        )
    except ValueError as exc:
        warnings.warn(
            f"discretisation.isotropic_family: {exc}; its bonds keep the grid's (cubic) family",
            UserWarning,
            stacklevel=3,
        )
        return None
