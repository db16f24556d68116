"""Strain-energy-density softening of bond stiffness (SED-PD (2021), eqs 18-24)
composed around a bond-based force model (one that declares the capability
``sed_softening``: a per-bond ``stiffness`` rescaled in place).

The parameters are :class:`peridynamics.damage.sed.SEDSoftening` (levels, thresholds,
residual factor), read here through :class:`SEDParameters`.

The levels (``state["sed_level"]``, a history field) rise irreversibly with the point
strain energy density computed with the initial moduli; the bond stiffness is
stiffness0 (f_i + f_j)/2 with the point factors of the levels, and acts from the next
force evaluation on.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol

import numpy as np
from numpy.typing import NDArray

from peridynamics.kernels.sed import sed_levels, sed_stiffness, sed_stiffness_raised, sed_update

if TYPE_CHECKING:
    from peridynamics.state import State


class SEDParameters(Protocol):
    """What the softening reads of its parameters
    (:class:`~peridynamics.damage.sed.SEDSoftening`)."""

    @property
    def levels(self) -> int: ...

    @property
    def residual(self) -> float: ...

    @property
    def energy(self) -> str: ...

    def thresholds(
        self, youngs_modulus: float, point_s0: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...


class SoftenedStiffness:
    """SED softening bound to a PMB force model (it rescales ``model.stiffness``).

    Parameters
    ----------
    softening : SEDSoftening (:class:`SEDParameters`)
    force_model : PMBForceModel (a model with ``sed_softening``)
    youngs_modulus : float
        E (Pa) of the thresholds W_A = E s^2 / 2, W_C = k_c W_A.
    point_s0 : (n,) critical stretch per point (inf: never softens).
    """

    def __init__(
        self,
        softening: SEDParameters,
        force_model: Any,
        youngs_modulus: float,
        point_s0: NDArray[np.float64],
    ) -> None:
        self.params = softening
        self.fm = force_model
        n = len(force_model.bonds.offsets) - 1
        self.stiffness0 = force_model.stiffness.copy()
        w_a, w_c = softening.thresholds(youngs_modulus, point_s0)
        # no-fail points (s0 = inf) never soften: a finite sentinel keeps the kernel's
        # arithmetic free of infinities
        self.w_a = np.where(np.isfinite(w_a), w_a, 1e300)
        self.w_c = np.where(np.isfinite(w_c), w_c, 1e300)
        self.factor = np.ones(n)
        self.energy = np.zeros(n)
        self.raised = np.zeros(n, dtype=np.uint8)
        self.k0l = 0.25 * self.stiffness0 * force_model.bonds.bond_length
        self.tensile = softening.energy == "tensile"

    def update(self, state: State, energy_computed: bool = False) -> int:
        """Raise the levels of ``state["sed_level"]`` from the SED at ``state.u`` (or from
        ``energy`` when the fused force pass already computed it) and rebuild the
        stiffness of the bonds whose points rose. Returns the number of points raised."""
        p, b, level = self.params, self.fm.bonds, state["sed_level"]
        if energy_computed:
            changed = sed_levels(self.energy, self.w_a, self.w_c, p.levels, level, self.raised)
        else:
            changed = sed_update(
                self.fm.cloud.x, state.u, b.offsets, b.bond_j, b.bond_length, self.stiffness0,
                state.intact, self.w_a, self.w_c, p.levels, level, self.energy, self.tensile,
                self.raised,
            )  # fmt: skip
        if changed:  # the new moduli act from the next force evaluation on
            sed_stiffness_raised(
                b.offsets, b.bond_j, self.stiffness0, level, p.levels, p.residual, self.factor,
                self.fm.stiffness, self.raised,
            )  # fmt: skip
        return int(changed)

    def restore(self, state: State) -> None:
        """Point factors and bond stiffness from the levels of a restored State."""
        b, p = self.fm.bonds, self.params
        sed_stiffness(
            b.offsets, b.bond_j, self.stiffness0, state["sed_level"], p.levels, p.residual,
            self.factor, self.fm.stiffness,
        )  # fmt: skip
