"""``damage.model: plastic_strain`` -> the critical-equivalent-plastic-strain law (one
registry line in :data:`~peridynamics.build.materials.DAMAGE_LAWS`)."""

from __future__ import annotations

import math
from typing import Any

from peridynamics import deck as dk
from peridynamics.bonds.bonds import Bonds
from peridynamics.damage.critical_stretch import CriticalStretch
from peridynamics.damage.plastic_strain import PlasticStrainFailure
from peridynamics.geometry import PointCloud


def build_plastic_strain_law(
    dmg: dk.Damage, m: Any, material: Any, cloud: PointCloud, bonds: Bonds, no_fail: Any
) -> PlasticStrainFailure:
    """alpha_c of ``damage.critical_plastic_strain``, with the critical stretch (given, or
    from ``fracture_energy``; off when neither) and ``tensile_strength`` (off when not
    given)."""
    assert dmg.critical_plastic_strain is not None  # validated with model plastic_strain
    s0 = dmg.critical_stretch
    if s0 is None and dmg.fracture_energy is not None:
        s0 = material.critical_stretch(
            dmg.fracture_energy, cloud.dim, bonds.horizon, cloud.cross_section, cloud.plane
        )
    f_t = dmg.tensile_strength
    return PlasticStrainFailure(
        dmg.critical_plastic_strain,
        CriticalStretch(math.inf if s0 is None else s0, no_fail),
        math.inf if f_t is None else f_t,
    )
