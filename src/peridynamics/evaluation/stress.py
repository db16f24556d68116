"""Stress and strain of every point, and the quantities derived from them.

The stress is the force model's own (:meth:`~peridynamics.families.base.ForceModel.point_stress`):
the peridynamic (virial) stress of the pair forces for the bond-based families and LPS,
the Cauchy stress of the constitutive law at the nonlocal F for correspondence. The
strain is the small-strain tensor of the nonlocal deformation gradient of every family
(:func:`peridynamics.kernels.stress.deformation_gradient`, unit influence, partial
volumes), the same for every model.

Both are returned as full 3 x 3 tensors (Pa, dimensionless), shape (n, 3, 3), for the
points that own a family (every point of a serial run; the owned points and the first
ghost layer of a rank). In 2-D the out-of-plane components follow the cloud's plane
(Hooke's law with the model's Poisson ratio nu, which holds for the linear elastic
models):

* plane stress: sigma_zz = 0, eps_zz = -nu / (1 - nu) (eps_xx + eps_yy);
* plane strain: sigma_zz = nu (sigma_xx + sigma_yy), eps_zz = 0.

In 1-D only the xx components are set. Derived: the von Mises stress
sqrt(3/2 s:s) with s the deviator, the pressure -tr(sigma)/3 (compression positive),
the principal stresses (descending) and their directions.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.families.pmb.material import fixed_poisson_ratio
from peridynamics.kernels import stress as kernels
from peridynamics.state import State

__all__ = [
    "displacement_gradient",
    "point_strain",
    "point_stress",
    "poisson_ratio",
    "pressure",
    "principal_stresses",
    "von_mises",
]


def poisson_ratio(model: Any) -> float | None:
    """The Poisson ratio of ``model``'s material (``material.poisson_ratio``; the one
    bond-based PD implies otherwise); None in 1-D."""
    cloud = model.cloud
    nu = getattr(getattr(model, "material", None), "poisson_ratio", None)
    if nu is None:
        return fixed_poisson_ratio(cloud.dim, cloud.plane)
    return float(nu)


def _full(t: NDArray[np.float64]) -> NDArray[np.float64]:
    """(n, d, d) -> (n, 3, 3), zero outside the d x d block."""
    n, d = t.shape[0], t.shape[1]
    out = np.zeros((n, 3, 3))
    out[:, :d, :d] = t
    return out


def point_stress(model: Any, state: State) -> NDArray[np.float64]:
    """Stress of every point that owns a family (n, 3, 3) (Pa), tension positive.

    Parameters
    ----------
    model : Evaluator
        The model (its ``force_model``, ``cloud`` and material are read).
    state : State
        The state whose displacement and intact bonds are read (not changed).

    Returns
    -------
    ndarray, shape (n, 3, 3)
        The model's stress (see the module), with sigma_zz of a 2-D plane-strain model.

    Raises
    ------
    ValueError
        If the model's family has no stress (micropolar).
    """
    fm = model.force_model
    sigma = fm.point_stress(state)
    if sigma is None:
        raise ValueError(f"the {fm.name!r} model gives no point stress")
    out = _full(np.asarray(sigma))
    cloud = model.cloud
    if cloud.dim == 2 and cloud.plane == "strain":
        nu = poisson_ratio(model) or 0.0
        out[:, 2, 2] = nu * (out[:, 0, 0] + out[:, 1, 1])
    return out


def displacement_gradient(model: Any, state: State) -> NDArray[np.float64]:
    """Displacement gradient F - I of every point that owns a family (n, d, d)
    (dimensionless), F the nonlocal deformation gradient of its intact bonds
    (:func:`peridynamics.kernels.stress.deformation_gradient`); zero where the family is
    degenerate (fewer than ``dim`` independent intact bonds)."""
    b = model.bonds
    x = model.cloud.x
    n, d = len(b.offsets) - 1, x.shape[1]
    fgrad = np.empty((n, d, d))
    kernels.deformation_gradient(
        x, state.u, b.offsets, b.bond_j, np.asarray(b.bond_volume, dtype=np.float64),
        state.intact, fgrad,
    )  # fmt: skip
    return np.asarray(fgrad - np.eye(d))


def point_strain(model: Any, state: State) -> NDArray[np.float64]:
    """Small strain sym(F) - I of every point that owns a family (n, 3, 3)
    (dimensionless), from :func:`displacement_gradient`; in 2-D plane stress
    eps_zz = -nu / (1 - nu) (eps_xx + eps_yy)."""
    grad = displacement_gradient(model, state)
    out = _full(0.5 * (grad + np.swapaxes(grad, 1, 2)))
    cloud = model.cloud
    if cloud.dim == 2 and cloud.plane == "stress":
        nu = poisson_ratio(model) or 0.0
        out[:, 2, 2] = -nu / (1.0 - nu) * (out[:, 0, 0] + out[:, 1, 1])
    return out


def von_mises(sigma: NDArray[np.float64]) -> NDArray[np.float64]:
    """von Mises stress sqrt(3/2 s:s) (n,) (Pa) of the (n, 3, 3) stresses ``sigma``,
    s = sym(sigma) - tr(sigma)/3 I."""
    sym = 0.5 * (sigma + np.swapaxes(sigma, 1, 2))
    dev = sym - np.trace(sym, axis1=1, axis2=2)[:, None, None] / 3.0 * np.eye(3)
    return np.asarray(np.sqrt(1.5 * np.einsum("nab,nab->n", dev, dev)))


def pressure(sigma: NDArray[np.float64]) -> NDArray[np.float64]:
    """Pressure -tr(sigma)/3 (n,) (Pa, compression positive) of (n, 3, 3) stresses."""
    return np.asarray(-np.trace(sigma, axis1=1, axis2=2) / 3.0)


def principal_stresses(
    sigma: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Principal stresses (n, 3), largest first (Pa), and their unit directions
    (n, 3, 3): ``directions[:, :, k]`` belongs to ``values[:, k]``; of sym(sigma)."""
    sym = 0.5 * (sigma + np.swapaxes(sigma, 1, 2))
    w, v = np.linalg.eigh(sym)
    return np.asarray(w[:, ::-1]), np.asarray(v[:, :, ::-1])
