"""Directional bias of a damage field: grid-axis bands show up as a 4-fold harmonic.

Damage around a centre (an impact, a blast hole, a crack source) on a regular grid
tends to run along the grid axes and diagonals; on an isotropic medium it should not
prefer any direction. :func:`damage_anisotropy` bins the points of an annulus
``r_min <= |x - center| <= r_max`` (in a plane: two coordinate axes of a 3-D cloud) by
polar angle theta and measures

* the mean damage per bin, ``D(theta_k)``, and its Fourier harmonics
  ``c_m = (1/N) sum_k D_k exp(-i m theta_k)``: the amplitude ratio
  ``A_m = 2 |c_m| / c_0`` is the relative amplitude of the ``cos(m (theta - phi_m))``
  part of D (``D = D0 (1 + a cos 4 theta)`` gives ``A_4 = a``: the bin averaging,
  a factor sinc(m w / 2) for bins of width w, is divided out). Square-grid bias shows
  up at m = 4 (axes and diagonals differ) and m = 8; n points of the annulus with
  independent damage values give a noise floor of about
  ``2 std(damage) / (mean(damage) sqrt(n))`` (root mean square);
* the damage extent per bin, the largest radius of a point with damage ``>=
  threshold`` (``r_min`` where none), and the ratio of its largest to smallest value.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray


@dataclass(frozen=True)
class DamageAnisotropy:
    """Result of :func:`damage_anisotropy`.

    Attributes
    ----------
    angles : ndarray, shape (n_bins,)
        Bin centres theta_k (rad) in [-pi, pi), measured from the first in-plane axis
        towards the second.
    mean_damage : ndarray, shape (n_bins,)
        Mean damage (dimensionless, 0..1) of the points in each bin.
    count : ndarray of int, shape (n_bins,)
        Points per bin.
    extent : ndarray, shape (n_bins,)
        Largest radius (m) of a point with damage >= threshold in each bin
        (``r_min`` where there is none).
    mean : float
        The mean of ``mean_damage`` over the bins, c_0.
    harmonic_4, harmonic_8 : float
        Amplitude ratios A_4 = 2 |c_4| / c_0 and A_8 = 2 |c_8| / c_0 (0 for a
        direction-independent field; 0 when c_0 = 0).
    phase_4 : float
        Angle (rad, in [-pi/4, pi/4)) of a maximum of the 4-fold part: near 0 when the
        damage runs along the in-plane axes, near +-pi/4 along the diagonals.
    extent_ratio : float
        max(extent) / min(extent) (inf when the smallest extent is 0).
    """

    angles: NDArray[np.float64]
    mean_damage: NDArray[np.float64]
    count: NDArray[np.int64]
    extent: NDArray[np.float64]
    mean: float
    harmonic_4: float
    harmonic_8: float
    phase_4: float
    extent_ratio: float

    def harmonic(self, m: int) -> float:
        """Amplitude ratio A_m = 2 |c_m| / c_0 of harmonic ``m >= 1`` of the binned damage."""
        return _amplitude(self.mean_damage, self.angles, m)[0]


def _amplitude(
    values: NDArray[np.float64], angles: NDArray[np.float64], m: int
) -> tuple[float, float]:
    """(A_m, phase of the maximum of the m-fold part) of bin means ``values`` at the
    equally spaced bin centres ``angles``; A_m is divided by the bin average of
    cos(m theta), sinc(m w / 2) (w the bin width), so that it estimates the harmonic of
    the field itself."""
    c0 = float(np.mean(values))
    cm = complex(np.mean(values * np.exp(-1j * m * angles)))
    if c0 <= 0:
        return 0.0, 0.0
    half = 0.5 * m * 2.0 * np.pi / len(values)
    return 2.0 * abs(cm) / c0 * half / np.sin(half), float(np.angle(cm)) / m


def _in_plane(
    dim: int, center: ArrayLike, axes: Sequence[int]
) -> tuple[int, int, NDArray[np.float64]]:
    """The two in-plane axes and the in-plane centre (2,), checked."""
    if len(axes) != 2:
        raise ValueError(f"axes must name two in-plane axes, got {tuple(axes)}")
    a0, a1 = int(axes[0]), int(axes[1])
    if a0 == a1 or not (0 <= a0 < dim and 0 <= a1 < dim):
        raise ValueError(f"axes must be two distinct axes of the {dim}-D cloud")
    c = np.asarray(center, dtype=np.float64).reshape(-1)
    if c.shape == (dim,):
        c = c[[a0, a1]]
    elif c.shape != (2,):
        raise ValueError(f"center must have {dim} or 2 coordinates, got {c.size}")
    return a0, a1, c


def damage_anisotropy(
    x: ArrayLike,
    damage: ArrayLike,
    center: ArrayLike,
    r_min: float,
    r_max: float,
    n_bins: int = 72,
    threshold: float = 0.5,
    axes: Sequence[int] = (0, 1),
) -> DamageAnisotropy:
    """Bin the damage of an annulus by polar angle and measure its directional bias.

    Parameters
    ----------
    x : array_like, shape (n_points, dim), dim in (2, 3)
        Reference positions (m).
    damage : array_like, shape (n_points,)
        Point damage (dimensionless, 0..1).
    center : array_like, shape (dim,) or (2,)
        Centre of the annulus (m): a point of the cloud's space or its two in-plane
        coordinates.
    r_min, r_max : float
        Inner and outer radius of the annulus (m), 0 <= r_min < r_max; the distance is
        measured in the plane of ``axes``.
    n_bins : int
        Number of angular bins (> 16, so that the 8-fold harmonic is resolved; 72:
        5 degrees). Every bin must hold at least one point.
    threshold : float
        Damage at and above which a point counts for the extent.
    axes : (int, int)
        The two in-plane coordinate axes of a 3-D cloud (default x and y).

    Returns
    -------
    DamageAnisotropy

    Raises
    ------
    ValueError
        On inconsistent shapes, radii or axes, or an empty bin (too many bins for the
        points of the annulus).
    """
    pts = np.asarray(x, dtype=np.float64)
    d = np.asarray(damage, dtype=np.float64).reshape(-1)
    if pts.ndim != 2 or pts.shape[1] not in (2, 3):
        raise ValueError(f"x must have shape (n_points, 2 or 3), got {pts.shape}")
    if d.shape != (pts.shape[0],):
        raise ValueError(f"damage must have shape ({pts.shape[0]},), got {d.shape}")
    a0, a1, c = _in_plane(pts.shape[1], center, axes)
    if not (np.isfinite(r_min) and np.isfinite(r_max) and 0 <= r_min < r_max):
        raise ValueError(f"need 0 <= r_min < r_max (m), got r_min={r_min}, r_max={r_max}")
    if int(n_bins) != n_bins or n_bins <= 16:
        raise ValueError(f"n_bins must be an integer > 16 (8-fold harmonic), got {n_bins}")
    n_bins = int(n_bins)
    rel = pts[:, [a0, a1]] - c
    r = np.hypot(rel[:, 0], rel[:, 1])
    ring = (r >= r_min) & (r <= r_max)
    theta = np.arctan2(rel[ring, 1], rel[ring, 0])
    width = 2.0 * np.pi / n_bins
    # bin k covers [-pi + k w, -pi + (k + 1) w): its centre is -pi + (k + 1/2) w
    k = np.minimum(((theta + np.pi) / width).astype(np.int64), n_bins - 1)
    count = np.bincount(k, minlength=n_bins)
    if np.any(count == 0):
        raise ValueError(
            f"{int(np.sum(count == 0))} of {n_bins} angular bins hold no point of the "
            f"annulus {r_min}..{r_max} m ({int(ring.sum())} points): use fewer bins or a "
            "wider annulus"
        )
    mean_damage = np.bincount(k, d[ring], minlength=n_bins) / count
    angles = np.asarray(-np.pi + (np.arange(n_bins) + 0.5) * width, dtype=np.float64)
    extent = np.full(n_bins, float(r_min))
    hit = d[ring] >= threshold
    np.maximum.at(extent, k[hit], r[ring][hit])
    a4, phase4 = _amplitude(mean_damage, angles, 4)
    a8, _ = _amplitude(mean_damage, angles, 8)
    phase4 = (phase4 + np.pi / 4) % (np.pi / 2) - np.pi / 4
    low = float(extent.min())
    return DamageAnisotropy(
        angles=angles,
        mean_damage=mean_damage,
        count=count,
        extent=extent,
        mean=float(np.mean(mean_damage)),
        harmonic_4=a4,
        harmonic_8=a8,
        phase_4=float(phase4),
        extent_ratio=float(extent.max()) / low if low > 0 else float("inf"),
    )
