"""Interior moduli of a static box run and the cubic-lattice moduli of bond-based
peridynamics, for the verify cases ``pmb_box_moduli`` and ``lps_box_nu_*``
(:mod:`peridynamics.app.verify_cases`).

The measured side reads the run's ``final_state.npz`` (reference positions ``x`` and
displacements ``u``) and fits a linear field to the points farther than one horizon
from every face, as ``benchmarks/lattice_moduli.py`` does. The reference side of the
bond-based box is the isotropic E0 and nu = 1/4 of Silling (2000) with
``discretisation.isotropic_family`` (the default), and otherwise a closed form of the
discrete model: on a cubic grid a bond-based
family has the elastic constants of its fourth moment ``M = sum_k w_k n_k^(x4)``
(``w_k`` the energy weight ``c(|xi|) beta V |xi|`` of bond k, n its direction), with
the Cauchy relation C12 = C44; the axis surface correction scales the interior so that
C11 is the continuum 1.2 E0 (nu = 1/4); with ``r = M_xxyy / M_xxxx`` (1/3 on the ball)
uniaxial stress gives ``nu = r / (1 + r)`` and
``E = (C11 - C12)(C11 + 2 C12) / (C11 + C12)``, C12 = r C11 (Born & Huang (1954),
ch. 3: the Cauchy relations of central pair forces; Silling (2000), eq. 64:
bond-based nu = 1/4 for an isotropic family).
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path
from typing import Any, Literal, cast

import numpy as np

Summary = dict[str, Any]


def interior_strains(summary: Summary) -> tuple[float, float, float]:
    """(eps_xx, eps_yy, eps_zz) of a least-squares linear fit of ``u`` over the points
    farther than one horizon from every face of the run's bounding box."""
    state = np.load(Path(summary["folder"]) / "final_state.npz")
    x, u = np.asarray(state["x"]), np.asarray(state["u"])
    margin = float(summary["results"]["horizon_m"])
    lo, hi = x.min(axis=0), x.max(axis=0)
    inner = np.all((x > lo + margin) & (x < hi - margin), axis=1)
    if int(inner.sum()) < 8:
        raise ValueError(f"{int(inner.sum())} interior points: the box is too thin")
    a = np.column_stack([x[inner], np.ones(int(inner.sum()))])
    grad = np.linalg.lstsq(a, u[inner], rcond=None)[0]  # (4, 3): d u_j / d x_i, offset
    return float(grad[0, 0]), float(grad[1, 1]), float(grad[2, 2])


def _traction(inputs: Summary) -> float:
    return abs(float(inputs["boundary_conditions"][0]["value"][0]))


def interior_e_ratio(summary: Summary) -> float:
    """sigma / (eps_xx E0): the interior modulus in units of the nominal E."""
    exx = interior_strains(summary)[0]
    return (
        _traction(summary["inputs"]) / exx / float(summary["inputs"]["material"]["youngs_modulus"])
    )


def interior_nu(summary: Summary) -> float:
    """-(eps_yy + eps_zz) / (2 eps_xx): the interior strain ratio."""
    exx, eyy, ezz = interior_strains(summary)
    return -0.5 * (eyy + ezz) / exx


@lru_cache(maxsize=16)
def _fourth_moment_ratio(m: float, partial_volume: str, profile: str) -> float:
    """``M_xxyy / M_xxxx`` of an interior family of a cubic grid (spacing 1, delta = m)."""
    from peridynamics.bonds import build_bonds
    from peridynamics.families.pmb import BondBasedMaterial
    from peridynamics.geometry import box

    n = 2 * int(np.ceil(m)) + 3
    cloud = box((float(n),) * 3, 1.0)
    rule = cast(Literal["truncated", "extended", "none"], partial_volume)
    bonds = build_bonds(cloud, m, rule)
    shape = cast(Literal["constant", "conical"], profile)
    k = BondBasedMaterial(1.0, 1.0, shape).bond_stiffness(cloud, bonds, corrected=False)
    centre = int(np.argmin(np.linalg.norm(cloud.x - cloud.x.mean(axis=0), axis=1)))
    own = bonds.bond_i == centre
    length = bonds.bond_length[own]
    nx = bonds.bond_xi[own] / length[:, None]
    w = k[own] * length
    return float((w * nx[:, 0] ** 2 * nx[:, 1] ** 2).sum() / (w * nx[:, 0] ** 4).sum())


def lattice_moduli(inputs: Summary) -> tuple[float, float]:
    """(E / E0, nu) of the corrected bond-based interior of the deck's cubic grid: the
    isotropic (1, 1/4) of Silling (2000), eq. 64, with ``discretisation.isotropic_family``
    (the default: the family's fourth moment is made isotropic,
    :mod:`peridynamics.families.pmb.isotropy`), the cubic lattice's without it."""
    disc, mat = inputs["discretisation"], inputs["material"]
    if disc.get("isotropic_family", True):
        return 1.0, 0.25
    hf = disc.get("horizon_factor")
    m = float(hf) if hf is not None else float(disc["horizon"]) / float(disc["spacing"])
    r = _fourth_moment_ratio(
        m, str(disc.get("partial_volume", "truncated")),
        str(mat.get("micromodulus_profile", "constant")),
    )  # fmt: skip
    c11 = 1.2  # E0 (1 - nu)/((1 + nu)(1 - 2 nu)) at nu = 1/4, the corrected axis modulus
    c12 = r * c11
    return (c11 - c12) * (c11 + 2 * c12) / (c11 + c12), c12 / (c11 + c12)
