"""Thermal expansion, the capability a model family declares in the registry
(``Family.thermal`` of :mod:`peridynamics.families.registry`): a variant of its force model
that reads the thermal strain of every point from the State.

The thermal strain ``eps_i`` (State field ``thermal_strain``, (n,), dimensionless) is
the free isotropic expansion of point i: ``alpha (T_i - T_ref)`` in 3-D, in 1-D and in
plane stress, ``(1 + nu) alpha (T_i - T_ref)`` in plane strain (the in-plane strain of
a body held at ``eps_zz = 0``, Timoshenko & Goodier (1970)); the
coupling (:mod:`peridynamics.solvers.thermomechanical`) writes it from the
temperature. A variant subtracts it from the deformation of every bond or point
(docs/theory_thermal.md); the damage laws and the largest stretch compare the
mechanical stretch. A variant is made from a built force model by :meth:`of` (the same
reference quantities, no copy of the arrays), so that a run without thermal expansion
keeps its class, its kernels and its bits.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Self

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from peridynamics.families.base import DamageLaw, FieldSpec, FusedStep
from peridynamics.kernels import thermal_expansion as kernels

if TYPE_CHECKING:
    from peridynamics.state import State

#: the State field of the thermal strain (n,)
THERMAL_STRAIN = "thermal_strain"


def thermal_strain_of(state: State) -> NDArray[np.float64]:
    """The State's thermal strain (n_all,); a clear error when it has none."""
    if THERMAL_STRAIN not in state:
        raise KeyError(
            f"state has no {THERMAL_STRAIN!r} field: make the State with the thermal "
            "variant's evaluator (its state_fields declare it)"
        )
    return np.asarray(state[THERMAL_STRAIN])


class ThermalExpansion:
    """Mixin of a thermal-expansion variant (first base, before the family's force
    model): the thermal-strain field, the mechanical stretch for the damage laws and
    the largest stretch, no fused step (the damage law runs on its own) and, unless
    the variant has its own, the finite-difference tangent."""

    cloud: Any
    bonds: Any
    #: capability the coupling asks: the model reads ``state["thermal_strain"]``
    thermal_expansion: bool = True
    #: thermal strain per kelvin (1/K): alpha, or (1 + nu) alpha in plane strain
    strain_per_kelvin: float = 0.0
    #: the temperature of no thermal strain (K)
    reference_temperature: float = 0.0
    #: the temperature a new State starts at (K)
    initial_temperature: float = 0.0

    def configure(self, strain_per_kelvin: float, reference: float, initial: float) -> None:
        """Set the thermal strain per kelvin (1/K) from ``reference`` (K) and the
        temperature a new State starts at (K)."""
        self.strain_per_kelvin = float(strain_per_kelvin)
        self.reference_temperature = float(reference)
        self.initial_temperature = float(initial)

    def init_state(self, state: State) -> None:
        """A new State: ``T`` the initial temperature and its thermal strain."""
        super().init_state(state)  # type: ignore[misc]
        state["T"][:] = self.initial_temperature
        self.update_thermal_strain(state)

    def update_thermal_strain(self, state: State) -> None:
        """``state["thermal_strain"] = strain_per_kelvin (T - T_ref)`` at every point."""
        eps = state[THERMAL_STRAIN]
        np.subtract(state["T"], self.reference_temperature, out=eps)
        eps *= self.strain_per_kelvin

    @classmethod
    def of(cls, model: Any) -> Self:
        """The variant of a built force model of the family: shares its reference
        quantities (attributes), which the variant never changes."""
        if not isinstance(model, cls.__mro__[2]):
            raise TypeError(f"{cls.__name__}.of needs a {cls.__mro__[2].__name__}")
        new = cls.__new__(cls)
        new.__dict__.update(model.__dict__)
        return new

    def state_fields(self) -> tuple[FieldSpec, ...]:
        """The family's fields, the thermal strain (n,), the temperature ``T`` (n,) (K)
        and the heat supplied by the thermal sources ``heat_in`` (1,) (J)."""
        return (
            *super().state_fields(),  # type: ignore[misc]
            FieldSpec(THERMAL_STRAIN),
            FieldSpec("T"),
            FieldSpec("heat_in", where="total", rows=1),
        )

    def bond_stretch(self, state: State) -> NDArray[np.float64]:
        """Mechanical stretch s_k - (eps_i + eps_j)/2 of every directed bond (n_bonds,)."""
        b = self.bonds
        out = np.empty(b.n_bonds)
        kernels.mechanical_stretch(
            self.cloud.x, state.u, b.offsets, b.bond_j, thermal_strain_of(state), out
        )
        return out

    def update_max_stretch(self, state: State, above: float = 0.0) -> None:
        """``state.max_stretch`` (n,): the largest mechanical stretch of an intact bond
        of each point (0 if none is positive)."""
        b = self.bonds
        kernels.largest_mechanical_stretch(
            self.cloud.x, state.u, b.offsets, b.bond_j, state.intact, thermal_strain_of(state),
            state.max_stretch,
        )  # fmt: skip

    def fused_step(self, state: State, law: DamageLaw, sed: Any = None) -> FusedStep | None:
        """None: the damage law's trial and commit run on their own."""
        return None

    def tangent(self, state: State) -> sp.csr_matrix | None:
        """None: the finite-difference tangent of the variant's force."""
        return None
