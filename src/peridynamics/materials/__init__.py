"""Constitutive laws. Each is a small class around pure kernel functions."""

from typing import Any

from peridynamics.materials.bond_based import PROFILES, BondBasedMaterial, fixed_poisson_ratio


def _lps(*args: object, **kw: object) -> object:
    from peridynamics.materials.lps import LPSMaterial

    return LPSMaterial(*args, **kw)  # type: ignore[arg-type]


def _micropolar(*args: object, **kw: object) -> object:
    from peridynamics.materials.micropolar import MicropolarMaterial

    return MicropolarMaterial(*args, **kw)  # type: ignore[arg-type]


def _correspondence(*args: object, **kw: object) -> object:
    from peridynamics.materials.correspondence import CorrespondenceMaterial

    return CorrespondenceMaterial(*args, **kw)  # type: ignore[arg-type]


#: the registry of model families: ``material.model`` -> material class (or factory)
MATERIALS: dict[str, Any] = {
    "pmb": BondBasedMaterial,
    "bond_based": BondBasedMaterial,
    "lps": _lps,
    "micropolar": _micropolar,
    "correspondence": _correspondence,
}

__all__ = ["MATERIALS", "PROFILES", "BondBasedMaterial", "fixed_poisson_ratio"]
