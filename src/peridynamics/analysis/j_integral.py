"""The J-integral of a 2-D crack tip from the point fields of a peridynamic solution.

Rice's contour integral evaluated on the peridynamic fields, as Stenström & Eriksson
(2019) do with the displacement derivatives of the peridynamic solution (here: the
nonlocal deformation gradient of every family,
:func:`peridynamics.evaluation.stress.displacement_gradient`, and the model's stress,
:func:`peridynamics.evaluation.stress.point_stress`):

    J = sum over the contour of (W n_1 - sigma_ab n_b du_a/dx_1) ds       (J/m^2)

in the frame of the crack (x_1 along the direction of growth, x_2 normal to the faces,
the tip at the origin), with W = 1/2 sigma_ab du_a/dx_b (linear elasticity; the strain
energy density of a linear model). The contour is a rectangle around the tip, half
sizes (h_1, h_2), from the lower crack face counter-clockwise to the upper one,
sampled by the midpoint rule at ``spacing / 2``; the fields at a sample point are the
Shepard (inverse distance, (1 - r/R)^2) average of the points within R = 1.5 spacing
that lie on the sample's side of the crack (behind the tip). With the tip at least
~3 horizons inside the contour and the contour away from the surfaces, the near-tip
nonlocal zone does not enter. Mode I: K_I = sqrt(E' J) (E' = E in plane stress,
E / (1 - nu^2) in plane strain).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import cKDTree

F = NDArray[np.float64]

__all__ = ["contour", "j_integral"]


def contour(half: Sequence[float], spacing: float) -> tuple[F, F, F]:
    """Sample points (m, 2), outward unit normals (m, 2) and lengths ds (m,) of the
    rectangle of half sizes ``half`` (m) around the origin, from the lower crack face
    (x_1 < 0, x_2 = 0-) counter-clockwise to the upper one, at about ``spacing / 2``."""
    h1, h2 = float(half[0]), float(half[1])
    pts, nrm, ds = [], [], []
    # (start, end, normal): the five straight pieces of the path
    legs = [((-h1, 0.0), (-h1, -h2), (-1.0, 0.0)), ((-h1, -h2), (h1, -h2), (0.0, -1.0)),
            ((h1, -h2), (h1, h2), (1.0, 0.0)), ((h1, h2), (-h1, h2), (0.0, 1.0)),
            ((-h1, h2), (-h1, 0.0), (-1.0, 0.0))]  # fmt: skip
    for a, b, n in legs:
        a_, b_ = np.asarray(a), np.asarray(b)
        length = float(np.linalg.norm(b_ - a_))
        m = max(1, int(np.ceil(length / (0.5 * spacing))))
        t = (np.arange(m) + 0.5) / m
        pts.append(a_ + t[:, None] * (b_ - a_))
        nrm.append(np.broadcast_to(np.asarray(n), (m, 2)))
        ds.append(np.full(m, length / m))
    return np.concatenate(pts), np.concatenate(nrm), np.concatenate(ds)


def _average(x: F, values: F, samples: F, radius: float) -> F:
    """Shepard average of ``values`` (n, ...) at ``samples`` (m, 2) over the points of
    ``x`` (n, 2) within ``radius`` on the sample's side of the crack (x_2 of the same
    sign where x_1 < 0); NaN where no point is near."""
    tree = cKDTree(x)
    near = tree.query_ball_point(samples, radius)
    out = np.full((len(samples),) + values.shape[1:], np.nan)
    for s, idx in enumerate(near):
        idx = np.asarray(idx, dtype=np.intp)
        p = samples[s]
        if p[0] < 0.0 and len(idx):  # behind the tip: only points on this face's side
            idx = idx[np.sign(x[idx, 1]) == np.sign(p[1])]
        if not len(idx):
            continue
        r = np.linalg.norm(x[idx] - p, axis=1)
        w = (1.0 - r / radius) ** 2
        out[s] = np.tensordot(w / w.sum(), values[idx], axes=1)
    return out


def j_integral(
    x: F,
    grad_u: F,
    sigma: F,
    tip: Sequence[float],
    half: Sequence[float],
    spacing: float,
    direction: Sequence[float] = (1.0, 0.0),
) -> float:
    """Rice's J (J/m^2) of the crack tip ``tip`` on a rectangular contour.

    Parameters
    ----------
    x : (n, 2) reference positions of the points (m).
    grad_u : (n, 2, 2) displacement gradient du_a/dx_b (F - I) of every point.
    sigma : (n, 2, 2) in-plane stress of every point (Pa).
    tip : (2,) crack tip (m).
    half : (2,) half sizes of the rectangle along and across the crack (m).
    spacing : float
        Grid spacing (m): the Shepard radius is 1.5 spacing, the samples spacing / 2.
    direction : (2,) direction of crack growth (the crack lies behind the tip).

    Returns
    -------
    float
        J (J/m^2), the energy release rate of a linear elastic body.

    Raises
    ------
    ValueError
        If a sample point of the contour has no point near it (the contour leaves the
        body).
    """
    e1 = np.asarray(direction, dtype=np.float64)
    e1 = e1 / np.linalg.norm(e1)
    rot = np.array([e1, [-e1[1], e1[0]]])  # rows: the crack frame's axes
    xl = (np.asarray(x, dtype=np.float64) - np.asarray(tip, dtype=np.float64)) @ rot.T
    gl = np.einsum("ia,nab,jb->nij", rot, grad_u, rot)
    sl = np.einsum("ia,nab,jb->nij", rot, sigma, rot)
    pts, nrm, ds = contour(half, spacing)
    both = np.concatenate([gl.reshape(-1, 4), sl.reshape(-1, 4)], axis=1)
    at = _average(xl, both, pts, 1.5 * spacing)
    if np.isnan(at).any():
        raise ValueError("the J contour leaves the body: make it smaller or move it")
    g, s = at[:, :4].reshape(-1, 2, 2), at[:, 4:].reshape(-1, 2, 2)
    w = 0.5 * np.einsum("nab,nab->n", s, g)
    traction = np.einsum("nab,nb->na", s, nrm)
    integrand = w * nrm[:, 0] - np.einsum("na,na->n", traction, g[:, :, 0])
    return float(np.sum(integrand * ds))
