"""Checks of ``material.plasticity`` on the LPS family (the elastic-plastic LPS of
Mitchell (2011), docs/theory_plasticity.md): ``type: j2`` with ``yield_stress`` and
``hardening_modulus`` (isotropic hardening only), a 3-D body, explicit dynamics,
dynamic relaxation or the static (Newton) solver on the Numba backend, one body, no
thermal expansion, no viscoelasticity, no ``plastic_strain`` damage. A run on several
MPI ranks is refused at build time (``build/decomposed.py``)."""

from __future__ import annotations

from typing import Any

from peridynamics.deck.history_limits import history_errors
from peridynamics.deck.types import Errors


def lps_plasticity_errors(deck: Any) -> Errors:
    """What ``material.plasticity`` of ``model: lps`` does not run with."""
    errors: Errors = []
    key = "material.plasticity"
    m = deck.material
    p = m.plasticity
    if p.type != "j2":
        errors.append(
            (
                f"{key}.type",
                f"model lps has the elastic-plastic LPS of Mitchell (2011) only: type j2 "
                f"(got {p.type!r}); use model correspondence for drucker_prager",
            )
        )
    elif p.kinematic_modulus != 0.0:
        errors.append(
            (
                f"{key}.kinematic_modulus",
                "model lps hardens isotropically only (hardening_modulus); remove "
                "kinematic_modulus or use model correspondence",
            )
        )
    if getattr(p, "strain", "small") != "small":
        errors.append(
            (
                f"{key}.strain",
                "model lps has the small-strain plastic LPS only; remove strain or use model "
                "correspondence for strain: logarithmic",
            )
        )
    if deck.dim != 3:
        errors.append((key, "model lps needs a 3-D body for plasticity (no 2-D deviatoric split)"))
    if getattr(m, "viscoelastic", None) is not None:
        errors.append((key, "material.plasticity and material.viscoelastic do not combine"))
    errors += history_errors(
        deck, key, ("explicit", "adr", "static"),
        "{solver} does not commit the plastic history; use explicit, adr or static with "
        "material.plasticity",
    )  # fmt: skip
    if deck.damage.model == "plastic_strain":
        errors.append(
            (
                "damage.model",
                "plastic_strain reads the history of the correspondence laws; with model lps "
                "use critical_stretch",
            )
        )
    return errors
