"""The tension-softening envelope of a PMB bond (bilinear / trilinear, Petersson 1981).

A bond follows the linear PMB law f = c s up to its strength s0 = f_t / E, then softens
linearly to zero force at s_f (bilinear), or in two linear pieces through the knee
(s1, beta s0) with s1 = s0 + r (s_f - s0) (trilinear). s_f is chosen so that breaking
one bond costs the same energy as the brittle PMB bond of the critical stretch s_c that
the fracture energy G0 gives at this horizon
(:meth:`~peridynamics.families.pmb.material.BondBasedMaterial.critical_stretch`):
int_0^s_f g(s) ds = s_c^2 / 2, i.e.

* bilinear:  s0 s_f / 2 = s_c^2 / 2                        -> s_f = s_c^2 / s0
* trilinear: s0^2/2 + s0 (s_f - s0)(r + beta)/2 = s_c^2/2   -> s_f = s0 + (s_c^2/s0 - s0)/(r + beta)

so G0 is conserved whatever delta (docs/theory_bond_based.md, "Tension softening"). The
law's parameters (bond law, f_t, G0, knee) are
:class:`peridynamics.damage.bond_softening.SofteningBonds`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.kernels.reference_softening import envelope


@dataclass(frozen=True)
class SofteningEnvelope:
    """The softening envelope of a bond (stretch units: force = c g(s)).

    Parameters
    ----------
    s0 : float
        Peak stretch f_t / E (dimensionless).
    s_c : float
        Critical stretch of the brittle bond with the same fracture energy.
    s_f : float
        Stretch at which the bond carries nothing (> s0).
    r, beta : float
        Knee: s1 = s0 + r (s_f - s0), g(s1) = beta s0 (0 < r, beta < 1).
    """

    s0: float
    s_c: float
    s_f: float
    r: float
    beta: float

    @property
    def s1(self) -> float:
        """Stretch of the knee."""
        return self.s0 + self.r * (self.s_f - self.s0)

    def g(self, s: NDArray[np.float64] | float) -> NDArray[np.float64]:
        """Envelope g(s), shape like ``s`` (s >= 0)."""
        return envelope(np.asarray(s, dtype=np.float64), self.s0, self.s_f, self.r, self.beta)

    def work(self) -> float:
        """int_0^s_f g(s) ds (exact for the piecewise-linear envelope) = s_c^2 / 2."""
        s0, s1, sf, b = self.s0, self.s1, self.s_f, self.beta
        return 0.5 * s0 * s0 + 0.5 * (s1 - s0) * (s0 + b * s0) + 0.5 * (sf - s1) * b * s0


def softening_envelope(
    criterion: Any,
    material: object,
    dim: int,
    horizon: float,
    cross_section: float,
    plane: str | None,
) -> SofteningEnvelope:
    """The envelope of the bond law ``criterion`` (a
    :class:`~peridynamics.damage.bond_softening.SofteningBonds`: ``tensile_strength``,
    ``fracture_energy``, ``knee_point()``) for ``material`` (a BondBasedMaterial) at this
    horizon (m).

    Raises ValueError when the brittle critical stretch s_c of G0 at this horizon
    does not exceed s0 = f_t / E: the bond could not reach f_t with that energy."""
    youngs = getattr(material, "youngs_modulus", None)
    critical = getattr(material, "critical_stretch", None)
    if youngs is None or critical is None:
        raise ValueError(
            "damage.bond_law: softening bond laws are for bond-based material.model "
            f"pmb / bond_based (got {type(material).__name__})"
        )
    s0 = criterion.tensile_strength / youngs
    s_c = float(critical(criterion.fracture_energy, dim, horizon, cross_section, plane))
    if not s_c > s0:
        raise ValueError(
            f"damage.fracture_energy G0 = {criterion.fracture_energy:g} J/m^2 gives the "
            f"brittle critical stretch s_c = {s_c:.6g} at horizon {horizon:.6g} m, not "
            "above the bond strength s0 = damage.tensile_strength / E = "
            f"{criterion.tensile_strength:g} / {youngs:g} = {s0:.6g}: no softening tail is "
            "left. Use a smaller horizon (s_c grows as 1/sqrt(delta)), a lower "
            "tensile_strength, a larger fracture_energy, or bond_law 'brittle'"
        )
    r, beta = criterion.knee_point()
    s_f = s0 + (s_c * s_c / s0 - s0) / (r + beta)
    return SofteningEnvelope(s0=s0, s_c=s_c, s_f=s_f, r=r, beta=beta)
