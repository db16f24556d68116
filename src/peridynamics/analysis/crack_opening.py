"""Crack-opening profiles and the mode-I stress intensity factor by displacement
extrapolation.

The opening of a straight crack from the displacements of the points: in the frame
of the crack (s along the crack from its first point, n normal to it), the points
within one spacing above the crack line (0 < n <= spacing) and within one spacing
below it (-spacing <= n < 0) are sorted into bins of one spacing along s, and the
opening of a bin is the mean normal displacement of its upper points less that of
its lower points,

    COD(s) = <u . e_n>_above - <u . e_n>_below        (m)

The mode-I stress intensity factor follows from the leading term of the near-tip
field of linear elasticity, COD(r) = 8 K_I / E' sqrt(r / (2 pi)) at a distance r
behind the tip (E' = E in plane stress, E / (1 - nu^2) in plane strain): the apparent
factor K(r) = E'/8 COD(r) sqrt(2 pi / r) is fitted by a straight line in r over a
window behind the tip and extrapolated to r = 0 (displacement extrapolation). With the
next term of the field (r^(3/2) in the opening) K(r) is linear in r, so the
extrapolation removes it.

Where the tip of the discrete crack is not where the line says (a bond-cut crack ends
between grid points, and the nonlocal zone blunts it), K(r) = E'/8 COD sqrt(2 pi / r)
with the wrong r grows without bound towards the tip. ``k_and_tip_from_opening``
fits the tip as well: with r' = r + d the distance to the effective tip,
(E'/8)^2 2 pi COD^2 = K_I^2 r' (1 + c r'), a quadratic in r (exact for Griffith's crack,
c = -1/(2a)); the effective tip is its root r = -d and K_I^2 its slope there.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

F = NDArray[np.float64]

__all__ = ["crack_opening", "k_and_tip_from_opening", "k_from_opening", "lefm_opening"]


def _frame(line: Sequence[Sequence[float]]) -> tuple[F, F, F, float]:
    """Start point (2,), unit tangent (2,), unit normal (2,) and length (m) of the
    crack line from its first point to its second."""
    p = np.asarray(line, dtype=np.float64)
    if p.shape != (2, 2):
        raise ValueError(f"the crack line is two 2-D points, got shape {p.shape}")
    t = p[1] - p[0]
    length = float(np.linalg.norm(t))
    if length == 0.0:
        raise ValueError("the crack line's two points coincide")
    t = t / length
    return p[0], t, np.array([-t[1], t[0]]), length


def crack_opening(
    x: F,
    u: F,
    line: Sequence[Sequence[float]],
    spacing: float,
) -> tuple[F, F]:
    """Opening displacement profile along a straight crack.

    Parameters
    ----------
    x : (n, 2) or (n, 3) reference positions of the points (m); only the first two
        components are used.
    u : (n, 2) or (n, 3) displacements of the points (m).
    line : (2, 2) the crack's two end points (m), for example the mouth (or the
        centre) and the tip. The profile runs from the first point to the second;
        "above" is the side of the normal obtained by turning the direction of the
        line by +90 degrees.
    spacing : float
        Grid spacing (m): the width of the strips above and below the line and the
        length of a bin along it.

    Returns
    -------
    s : (m,) distance of the bin centres from the first point of the line (m).
    cod : (m,) opening of each bin (m): the mean displacement normal to the line of
        the points above less that of the points below (positive when the faces
        separate). Bins with no point on one side are left out.

    Raises
    ------
    ValueError
        If the line is not two distinct 2-D points or ``spacing`` is not positive.
    """
    if not spacing > 0.0:
        raise ValueError(f"spacing must be positive, got {spacing}")
    p0, t, nrm, length = _frame(line)
    x2 = np.asarray(x, dtype=np.float64)[:, :2] - p0
    u2 = np.asarray(u, dtype=np.float64)[:, :2]
    s, n, un = x2 @ t, x2 @ nrm, u2 @ nrm
    nbins = max(1, int(np.ceil(length / spacing - 1e-9)))
    k = np.floor(s / spacing).astype(np.intp)
    inside = (k >= 0) & (k < nbins) & (np.abs(n) <= spacing) & (n != 0.0)
    up, low = inside & (n > 0.0), inside & (n < 0.0)
    cnt_up = np.bincount(k[up], minlength=nbins)
    cnt_low = np.bincount(k[low], minlength=nbins)
    sum_up = np.bincount(k[up], weights=un[up], minlength=nbins)
    sum_low = np.bincount(k[low], weights=un[low], minlength=nbins)
    ok = (cnt_up > 0) & (cnt_low > 0)
    centres = ((np.arange(nbins) + 0.5) * spacing).astype(np.float64)
    cod: F = sum_up[ok] / np.maximum(cnt_up[ok], 1) - sum_low[ok] / np.maximum(cnt_low[ok], 1)
    return centres[ok], cod


def lefm_opening(r: F, k_i: float, e_prime: float) -> F:
    """Opening (m) of the leading mode-I near-tip field, 8 K_I / E' sqrt(r / (2 pi)),
    at distances ``r`` (m) behind the tip; ``k_i`` in Pa sqrt(m), ``e_prime`` in Pa."""
    return 8.0 * k_i / e_prime * np.sqrt(np.asarray(r, dtype=np.float64) / (2.0 * np.pi))


def k_from_opening(
    r: F,
    cod: F,
    e_prime: float,
    window: Sequence[float],
) -> tuple[float, F, F]:
    """Mode-I stress intensity factor by displacement extrapolation.

    Parameters
    ----------
    r : (m,) distances behind the tip (m), for example ``tip_s - s`` of
        ``crack_opening`` with the line running towards the tip.
    cod : (m,) opening at ``r`` (m).
    e_prime : float
        E' (Pa): E in plane stress, E / (1 - nu^2) in plane strain.
    window : (2,) the range of r (m) of the fit, ``(r_min, r_max)``; keep r_min a few
        horizons from the tip (the nonlocal zone) and r_max well inside the crack.

    Returns
    -------
    k_i : float
        K_I (Pa sqrt(m)), the intercept at r = 0 of the straight line fitted by least
        squares to K(r) = E'/8 COD(r) sqrt(2 pi / r) over the window.
    r_fit : (k,) the distances used (m).
    k_apparent : (k,) K(r) at them (Pa sqrt(m)).

    Raises
    ------
    ValueError
        If fewer than two points lie in the window.
    """
    r = np.asarray(r, dtype=np.float64)
    cod = np.asarray(cod, dtype=np.float64)
    lo, hi = float(window[0]), float(window[1])
    use = (r >= lo) & (r <= hi) & (r > 0.0)
    if use.sum() < 2:
        raise ValueError(f"fewer than two opening values with r in [{lo}, {hi}] m")
    rf = r[use]
    ka = e_prime / 8.0 * cod[use] * np.sqrt(2.0 * np.pi / rf)
    slope, intercept = np.polyfit(rf, ka, 1)
    return float(intercept), rf, ka


def k_and_tip_from_opening(
    r: F,
    cod: F,
    e_prime: float,
    window: Sequence[float],
) -> tuple[float, float]:
    """Mode-I stress intensity factor and the effective tip from the opening.

    Fits q(r) = (E'/8)^2 2 pi COD(r)^2 by a quadratic c_0 + c_1 r + c_2 r^2 over the
    window (least squares); its root nearest r = 0, r_0 = -d, is the effective tip and
    K_I = sqrt(q'(r_0)) = sqrt(c_1 + 2 c_2 r_0).

    Parameters
    ----------
    r : (m,) distances behind the assumed tip (m).
    cod : (m,) opening at ``r`` (m).
    e_prime : float
        E' (Pa).
    window : (2,) range of r (m) of the fit.

    Returns
    -------
    k_i : float
        K_I (Pa sqrt(m)).
    shift : float
        d (m), how far the effective tip lies ahead of the assumed one.

    Raises
    ------
    ValueError
        If fewer than three points lie in the window, or the fitted quadratic has no
        real root or no positive slope there.
    """
    r = np.asarray(r, dtype=np.float64)
    cod = np.asarray(cod, dtype=np.float64)
    use = (r >= float(window[0])) & (r <= float(window[1])) & (r > 0.0)
    if use.sum() < 3:
        raise ValueError(f"fewer than three opening values with r in {tuple(window)} m")
    q = 2.0 * np.pi * (e_prime / 8.0 * cod[use]) ** 2
    c2, c1, c0 = np.polyfit(r[use], q, 2)
    roots = np.roots([c2, c1, c0]) if c2 != 0.0 else np.array([-c0 / c1])
    roots = roots[np.isreal(roots)].real
    if not len(roots):
        raise ValueError("the squared opening does not vanish near the tip")
    r0 = float(roots[np.argmin(np.abs(roots))])
    slope = 2.0 * c2 * r0 + c1
    if not slope > 0.0:
        raise ValueError("the squared opening does not grow with r in the window")
    return float(np.sqrt(slope)), -r0
