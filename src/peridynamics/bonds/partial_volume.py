"""Partial-volume ("volume correction") factors beta(|xi|) in [0, 1].

Two forms appear in the papers this package implements (full references in
docs/references.md):

* ``"truncated"`` -- Lu & Wang (2016), eq. 9 (Silling & Askari 2005; identical to Madenci &
  Oterkus 2014): beta = 1 for |xi| <= delta - dx/2, beta = (delta - |xi|)/dx + 1/2 for
  delta - dx/2 < |xi| <= delta, 0 beyond delta. A node exactly at |xi| = delta gets 1/2,
  which makes PD with delta = dx identical to central finite differences (Lu & Wang (2016),
  eq. 17).
* ``"extended"`` -- SED-PD (2021), eq. 11: beta = 1 for |xi| <= delta - dx/2,
  beta = (delta + dx/2 - |xi|)/dx for delta - dx/2 < |xi| < delta + dx/2, 0 beyond: the
  family reaches delta + dx/2.
* ``"none"`` -- beta = 1 inside delta.

Irregular clouds (jittered grids, mesh centroids): both rules only use the nominal
spacing ``dx`` (the grid's, or the spacing given for a mesh), the right scale there.
``"truncated"`` jumps from beta ~ 1/2 to 0 at |xi| = delta; on the grid at
delta = 3.015 dx the axis neighbours at 3 dx sit just inside, on a jittered grid they
count by chance, which biases the family towards the diagonals. A correction that
calibrates the whole fourth moment of each family
(:func:`peridynamics.bonds.surface.moment_correction_factors`) removes that bias and
both rules then give E and nu within 2 %; ``"extended"``, continuous in |xi|, gives the
smaller non-affine relaxation (docs/theory_bond_based.md, "Irregular point clouds").
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import NDArray

PartialVolume = Literal["truncated", "extended", "none"]
PARTIAL_VOLUME_RULES: tuple[str, ...] = ("truncated", "extended", "none")

#: relative tolerance that keeps nodes at exactly |xi| = delta in the family
HORIZON_TOL = 1e-9


def search_radius(horizon: float, dx: float, rule: PartialVolume) -> float:
    """Largest bond length that can get a non-zero factor (m)."""
    reach = horizon + 0.5 * dx if rule == "extended" else horizon
    return reach * (1.0 + HORIZON_TOL)


def partial_volume_factor(
    length: NDArray[np.float64], horizon: float, dx: float, rule: PartialVolume
) -> NDArray[np.float64]:
    """Factor beta for bonds of reference ``length`` (m), shape (n_bonds,)."""
    length = np.asarray(length, dtype=np.float64)
    h = horizon * (1.0 + HORIZON_TOL)
    if rule == "none":
        return np.where(length <= h, 1.0, 0.0)
    if rule == "truncated":
        beta = np.clip((horizon - length) / dx + 0.5, 0.0, 1.0)
        return np.where(length <= h, beta, 0.0)
    if rule == "extended":
        beta = np.clip((horizon + 0.5 * dx - length) / dx, 0.0, 1.0)
        return np.where(length < (horizon + 0.5 * dx) * (1 - HORIZON_TOL), beta, 0.0)
    raise ValueError(f"unknown partial-volume rule {rule!r}; use one of {PARTIAL_VOLUME_RULES}")
