"""The fracture energy of a bond-based family on a regular grid
(``discretisation.lattice_fracture_energy``).

The critical stretch of :meth:`BondBasedMaterial.critical_stretch
<peridynamics.families.pmb.material.BondBasedMaterial.critical_stretch>` comes from the
continuous family: G0 is the energy of the bonds that cross a unit area of a plane,
integrated over the ball of radius delta (Silling & Askari (2005), eq. 17; Ha & Bobaru
(2010)). A grid's family is a sum over lattice offsets, with partial volumes, the
micromodulus profile, the isotropy factors of
:mod:`peridynamics.families.pmb.isotropy` and the interior factor of the surface
correction: the energy its bonds hold across a plane differs. Per unit area of a plane
normal to a grid axis (x) between two columns of points, each offset ``xi_k`` with
``xi_k,x > 0`` crosses it ``xi_k,x / dx`` times per column of cross-section ``V / dx``,
so that

    G_lattice = sum_{xi_k,x > 0} xi_k,x * (1/2) k_k s_c^2 |xi_k|

with ``k_k = c(|xi_k|) beta_k V g_k lambda`` the bond stiffness per unit stretch
(N/m^3; the point volume V cancels). At delta = 3.015 dx with truncated partial volumes
and the surface correction on, ``G_lattice = 0.946 G0`` (2-D) and ``0.944 G0`` (3-D):
the grid's bonds hold 5-6 % less than G0. :func:`lattice_fracture_energy_ratio`
computes the ratio; the material then uses ``G0 / ratio`` in the critical stretch, so
that the interior lattice holds G0 exactly (brittle bonds and the softening envelopes
alike). Near surfaces the corrected bonds hold more per unit area (the surface
correction stiffens them); that part is not calibrated.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.partial_volume import PartialVolume
from peridynamics.families.calibration import quartic_values
from peridynamics.families.pmb.force import CALIBRATION_STRAIN
from peridynamics.families.pmb.isotropy import isotropy_coefficients, lattice_family, on_grid


@dataclass(frozen=True)
class GridFamily:
    """One complete family of a regular grid as a run builds it.

    Attributes
    ----------
    dim : int
        1, 2 or 3.
    horizon, spacing : float
        delta and dx (m).
    rule : {"truncated", "extended", "none"}
        The partial-volume rule.
    cross_section : float
        Bar area (m^2, 1-D), plate thickness (m, 2-D); 1 in 3-D.
    plane : {"stress", "strain"} or None
        The 2-D model.
    surface_correction : bool
        Whether the bonds get the (interior) energy surface-correction factor.
    """

    dim: int
    horizon: float
    spacing: float
    rule: PartialVolume
    cross_section: float
    plane: str | None
    surface_correction: bool


def lattice_bond_stiffness(
    material: Any, grid: GridFamily
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The bond vectors ``xi`` (n, dim) (m) of one complete family of the regular grid
    and their stiffness per unit stretch ``k`` (n,) (N/m^3) as an interior point of a
    run has them: ``c(|xi|) beta V``, times the isotropy factors (3-D, when
    ``material.isotropic_family``; a family that cannot be made isotropic keeps its
    factors, as the force model's does) and the interior factor of the energy surface
    correction (when ``surface_correction``), the operations of
    :class:`~peridynamics.families.pmb.force.PMBForceModel`."""
    dim, horizon, area, plane = grid.dim, grid.horizon, grid.cross_section, grid.plane
    xi, length, c_beta = lattice_family(
        material, dim, horizon, grid.spacing, grid.rule, area, plane
    )
    volume = grid.spacing**dim * (area if dim < 3 else 1.0)
    k = c_beta * volume
    if grid.surface_correction:
        if dim == 3 and material.isotropic_family:
            try:
                lam = isotropy_coefficients(xi, c_beta * length)
                k = k * (1.0 + quartic_values(xi / length[:, None]) @ lam)
            except ValueError:  # the force model keeps the grid's family (and warns)
                pass
        s = CALIBRATION_STRAIN * (xi[:, 0] / length) ** 2
        w = float(np.sum(k * s * s * length))
        w_inf = material.uniaxial_energy_density(CALIBRATION_STRAIN, dim, horizon, area, plane)
        k = k * (w_inf / (0.25 * w))
    return xi, np.asarray(k, dtype=np.float64)


def lattice_fracture_energy_ratio(material: Any, grid: GridFamily) -> float:
    """G_lattice / G0 (dimensionless): the energy per unit area (J/m^2) that the bonds of
    the grid's interior family hold across a plane normal to a grid axis when they break
    at the continuum critical stretch of G0, over G0 (module docstring)."""
    xi, k = lattice_bond_stiffness(material, grid)
    g0 = 1.0  # J/m^2: the ratio does not depend on it (s_c^2 is proportional to G0)
    continuum = replace(material, fracture_energy_factor=1.0)  # the continuum calibration
    s_c = continuum.critical_stretch(g0, grid.dim, grid.horizon, grid.cross_section, grid.plane)
    length = np.sqrt(np.einsum("ij,ij->i", xi, xi))
    cross = xi[:, 0] > 0.0
    held = float(np.sum(xi[cross, 0] * 0.5 * k[cross] * s_c * s_c * length[cross]))
    return held / g0


def fracture_energy_factor(
    material: Any, cloud: Any, bonds: Any, surface_correction: bool
) -> float:
    """The factor ``1 / ratio`` of :func:`lattice_fracture_energy_ratio` for the points of
    ``cloud`` (a :class:`~peridynamics.geometry.cloud.PointCloud`) and their ``bonds``.

    Raises ValueError when the points are not on a regular grid of their spacing
    (mesh centroids, jittered grids: no lattice family to calibrate on)."""
    if cloud.irregular or not on_grid(cloud.x, cloud.spacing):
        raise ValueError(
            "the points are not on a regular grid of their spacing (a mesh or a jittered "
            "grid): the calibration needs the grid's family; remove the key or use a "
            "grid geometry"
        )
    grid = GridFamily(
        cloud.dim, bonds.horizon, bonds.spacing, cast(PartialVolume, bonds.partial_volume),
        cloud.cross_section, cloud.plane, surface_correction,
    )  # fmt: skip
    ratio = lattice_fracture_energy_ratio(material, grid)
    if not (math.isfinite(ratio) and ratio > 0.0):
        raise ValueError(f"the grid's family holds {ratio:.3g} G0 across a plane")
    return 1.0 / ratio
