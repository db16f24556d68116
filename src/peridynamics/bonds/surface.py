"""Energy-method surface correction for bond-based models (Madenci & Oterkus 2014, ch. 4).

For each coordinate direction ``k`` a uniform uniaxial strain ``eps`` along ``k`` is
applied (linearised bond stretch, so the factors do not depend on ``eps``); the point
strain-energy density ``W_k,i`` of the discrete model is compared
with the continuum value ``W_inf``: ``lambda_k,i = W_inf / W_k,i``. The bond factor in
direction ``k`` is the mean of its end points, ``G_k = (lambda_k,i + lambda_k,j) / 2``,
and the bond factor is the ellipse/ellipsoid interpolation over the bond direction n:

    G = [ sum_k (n_k / G_k)^2 ]^(-1/2)

This also removes the interior discretisation error of the chosen partial-volume rule
for uniaxial loading.

On irregular clouds (jittered grids, mesh centroids) the axis calibration leaves the
fourth moment of every family free apart from its ``xxxx``, ``yyyy`` (``zzzz``)
components, and the family of a jittered grid is biased towards the diagonals (the
axis bonds at the rim of the truncated partial volume drop out at random): a jittered
plate has nu 2 % (jitter 0.25) to 7 % (jitter 0.1) above 1/3, a box 2.5 % above 1/4.
:func:`moment_correction_factors` calibrates the whole fourth moment instead and brings
both within about 1 % (docs/theory_bond_based.md, "Irregular point clouds").
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds, setup_chunk_bonds
from peridynamics.bonds.search import bond_chunks

#: a family's influence calibration: (bonds, weight) -> (factor per bond, residual per
#: point), as :func:`peridynamics.families.calibration.calibrate_influence`
Calibration = Callable[[Bonds, NDArray[np.float64]], tuple[NDArray[np.float64], NDArray]]

#: a point ratio within this of 1 is a complete family whose discrete energy is the
#: continuum's (round-off of the energy sums: 5e-15 measured on a 1-D bar)
COMPLETE_TOL = 1e-9

#: the dimensionless fourth moment <n_x^4> of the continuous ball, 3 / (d (d + 2))
_COS4 = {1: 1.0, 2: 3.0 / 8.0, 3: 1.0 / 5.0}


def energy_correction_factors(
    x: NDArray[np.float64],
    bonds: Bonds,
    stiffness: NDArray[np.float64],
    continuum_energy_density: float,
    strain: float = 1e-6,
    comm: Any = None,
) -> NDArray[np.float64]:
    """Per-bond correction factors, shape (n_bonds,).

    Parameters
    ----------
    x : (n_points, dim) reference positions (m).
    bonds : the bond list (its current correction is ignored).
    stiffness : (n_bonds,) uncorrected bond stiffness ``c(|xi|) * beta * V_j`` (N/m^3).
    continuum_energy_density : float
        Strain-energy density of the infinite body under uniaxial strain ``strain`` (J/m^3).
    comm : Communicator, optional
        Exchanges the point ratios of ghost points in a decomposed run (see
        :func:`bond_factors_from_point_ratios`); ``None``: one process.
    """
    n, dim = x.shape
    lam = np.empty((dim, n))
    w = np.zeros((dim, n))  # points without bonds keep 0, as in one bincount over all bonds
    # ranges of whole rows: each point's sum adds the same terms in the same order; the
    # bond vectors, lengths and owners are derived per range (the list need not hold them)
    for a, b in bond_chunks(bonds.offsets, setup_chunk_bonds(dim)):
        xi = bonds.bond_range("bond_xi", a, b)
        length = bonds.bond_range("bond_length", a, b)
        owner = bonds.bond_range("bond_i", a, b)
        p0, p1 = int(owner[0]), int(owner[-1]) + 1
        for k in range(dim):  # one uniform-strain evaluation per direction
            # linearised stretch xi.eta/|xi|^2 of u = strain * x_k e_k: exact, so the
            # factors carry neither round-off (small strain) nor geometric nonlinearity
            s = strain * (xi[:, k] / length) ** 2
            w[k, p0:p1] = np.bincount(
                owner - p0, stiffness[a:b] * s * s * length, minlength=p1 - p0
            )
    with np.errstate(divide="ignore"):  # ghosts without a family (MPI): exchanged below
        for k in range(dim):
            lam[k] = continuum_energy_density / (0.25 * w[k])
    return bond_factors_from_point_ratios(bonds, lam, comm)


def bond_factors_from_point_ratios(
    bonds: Bonds, ratios: NDArray[np.float64], comm: Any = None
) -> NDArray[np.float64]:
    """Bond factors G = [sum_k (n_k / G_k)^2]^(-1/2), G_k = (lambda_k,i + lambda_k,j)/2,
    shape (n_bonds,), from the per-direction point ratios ``ratios`` (dim, n_points)
    = W_inf / W_k,i of any model family (the shared step of the energy method).

    Where a point's family is complete and its discrete energy is the continuum's
    (``lambda_k,i = 1`` to round-off, :data:`COMPLETE_TOL`; on a regular 1-D grid with the
    truncated partial volumes every point at least delta from an end), its bonds keep
    ``G_k = 1``: the mean would stiffen the bonds from such a point into the surface layer
    on one side only, a net force on a point under a uniform strain that it carries
    exactly without correction (a ghost force). With delta = dx in 1-D the correction
    is then the identity and the model is the finite-difference scheme of Lu & Wang
    (2016), eq. 17 (the end points' only bonds reach complete families).

    ``comm`` (a communicator with ``size`` and ``exchange``, given by the caller; ``None``
    in one process): in a decomposed run the ghosts, which have no family on this rank,
    take their owner's ratios."""
    out = np.empty(bonds.n_bonds)
    dim = ratios.shape[0]
    if comm is not None and comm.size > 1:  # ghosts without a family here take their owner's ratios
        r = np.ascontiguousarray(ratios.T)
        comm.exchange(r)
        ratios = r.T
    for a, b in bond_chunks(bonds.offsets, setup_chunk_bonds(dim)):  # bounded transients
        bi, bj = bonds.bond_range("bond_i", a, b), bonds.bond_j[a:b]
        n_hat = bonds.bond_range("bond_xi", a, b) / bonds.bond_range("bond_length", a, b)[:, None]
        acc = np.zeros(b - a)
        for k in range(dim):  # loop over the (<= 3) directions only
            ri, rj = ratios[k][bi], ratios[k][bj]
            # a far end with no family here (a second-layer ghost of a rank whose bodies
            # are set up without an exchange, parallel/bodies.py) has no ratio: only a
            # ghost's bonds reach it, whose forces no rank uses; take the near end's
            rj = np.where(np.isfinite(rj), rj, ri)
            complete = (np.abs(ri - 1.0) <= COMPLETE_TOL) | (np.abs(rj - 1.0) <= COMPLETE_TOL)
            g_k = np.where(complete, 1.0, 0.5 * (ri + rj))
            acc += (n_hat[:, k] / g_k) ** 2
        out[a:b] = 1.0 / np.sqrt(acc)
    return out


def moment_correction_factors(
    x: NDArray[np.float64],
    bonds: Bonds,
    stiffness: NDArray[np.float64],
    continuum_energy_density: float,
    strain: float = 1e-6,
    *,
    calibrate: Calibration,
) -> NDArray[np.float64]:
    """Per-bond factors that give every point the continuum energy for *every* uniform
    strain (the moment method), shape (n_bonds,).

    Under a homogeneous small strain eps the energy of point i is
    ``W_i = 1/4 sum_k w_k (n_k . eps . n_k)^2`` with ``w_k = stiffness_k |xi_k|``: it
    depends on the family only through its fourth moment ``M_i = sum_k w_k n_k^(x4)``,
    and it is the continuum energy for every eps exactly when
    ``M_i = m_inf (d d + d d + d d) / (d (d + 2))`` (the isotropic tensor whose
    ``xxxx`` component gives the uniaxial ``W_inf``). Each point gets owner factors
    ``h_k = (m_inf / m_i) g_k``, where ``g_k`` are the influence factors of
    :func:`peridynamics.families.calibration.calibrate_influence` (the minimum-norm quartic in the
    bond direction, bounded to [0.25, 4] where a cut family needs more) that give the
    family the isotropic fourth moment at its own total ``m_i = sum_k w_k``; the bond
    factor is the mean of its two ends, ``G_ij = (h_ij + h_ji) / 2`` (symmetric: the
    force stays a pair force). Pre-cracked bonds are counted as intact, as in
    :func:`energy_correction_factors`. On a regular grid this also removes the cubic
    anisotropy of the lattice (which the axis method keeps), so the grid results
    differ from :func:`energy_correction_factors`.

    Parameters
    ----------
    x : ndarray, shape (n_points, dim)
        Reference positions (m).
    bonds : Bonds
        The bond list (its current correction is ignored).
    stiffness : ndarray, shape (n_bonds,)
        Uncorrected bond stiffness ``c(|xi|) beta V_j`` (N/m^3 per unit stretch).
    continuum_energy_density : float
        Strain-energy density of the infinite body under uniaxial strain ``strain``
        (J/m^3).
    strain : float
        The uniaxial strain of ``continuum_energy_density`` (the factors do not
        depend on it).
    calibrate : callable
        The family's influence calibration ``(bonds, weight) -> (factor, residual)``
        (:func:`peridynamics.families.calibration.calibrate_influence`), given by the
        caller: points and bonds know no model family.

    Returns
    -------
    ndarray, shape (n_bonds,)
        Symmetric factors G_ij = G_ji > 0.
    """
    n, dim = x.shape
    w = stiffness * bonds.bond_length
    m_i = np.bincount(bonds.bond_i, w, minlength=n)
    # W_inf = 1/4 eps^2 M_xxxx = 1/4 eps^2 m_inf <n_x^4>
    m_inf = 4.0 * continuum_energy_density / (strain * strain * _COS4[dim])
    every = bonds.replace(bond_intact=np.ones_like(bonds.bond_intact))
    # the calibration weighs bond k by weight_k |xi_k|^2: pass w / |xi|^2
    g, _ = calibrate(every, stiffness / bonds.bond_length)
    h = g * (m_inf / m_i)[bonds.bond_i]
    return np.asarray(0.5 * (h + h[bonds.reverse_index()]), dtype=np.float64)
