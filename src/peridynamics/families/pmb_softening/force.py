"""PMB bonds with a tension-softening law (bilinear / trilinear, Petersson 1981).

The force of a bond depends on its history kappa (the largest tensile stretch it has
reached, the per-bond State field ``bond_kappa``), so the model declares that field.
The force pass is pure: it uses the trial history kappa' = max(kappa, s) of the
displacement it is given, so the force follows the softening envelope within a
dynamic-relaxation iteration, and the damage law
(:class:`peridynamics.damage.bond_softening.BondSofteningLaw`) commits kappa' when the
solver accepts the state. Kernels: :mod:`peridynamics.kernels.bond_softening`; the
envelope: :mod:`peridynamics.families.pmb_softening.envelope`. The family is chosen by the
damage section (``damage.bond_law``), so the evaluator builds it with
:func:`softening_force_model` from the law's parameters and the material.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.families.base import DamageLaw, FieldSpec, FusedStep
from peridynamics.families.pmb.force import PMBConstants, PMBForceModel
from peridynamics.families.pmb.material import BondBasedMaterial
from peridynamics.families.pmb_softening.envelope import SofteningEnvelope, softening_envelope
from peridynamics.families.tangent import finite_difference_tangent
from peridynamics.geometry.cloud import PointCloud
from peridynamics.kernels import bond_softening as ks
from peridynamics.kernels.reference_softening import factor as softening_factor

if TYPE_CHECKING:
    from peridynamics.state import State

#: the per-bond history field: largest tensile stretch reached (dimensionless)
KAPPA = "bond_kappa"


class PMBSofteningForceModel(PMBForceModel):
    """PMB bonds whose force follows a tension-softening envelope.

    f_ij = stiffness h(kappa') s (xi + eta)/|xi + eta| with h the secant factor
    g(kappa')/kappa' of the envelope for s > 0 (1 up to the peak stretch s0), h = 1 in
    compression and h = 0 once kappa' >= s_f.

    Parameters
    ----------
    cloud : PointCloud
    bonds : Bonds
    material : BondBasedMaterial
    surface_correction : bool
        Energy-method surface correction (as :class:`PMBForceModel`).
    envelope : SofteningEnvelope
        s0, s_f and the knee (r, beta) of every bond.
    no_fail : (k,) int array, optional
        Points whose bonds never soften nor break (per-point s0 = s_f = inf).

    Attributes
    ----------
    point_s0, point_sf : (n,) per-point peak and failure stretch (inf on no-fail
        points); a bond uses the mean of its two points' values.
    knee : (r, beta) of the envelope.
    """

    name = "pmb"
    #: the critical-stretch fast path does not apply: the softening law has its own
    fused_breaking = False
    #: the per-bond history field the law commits (capability the law asks for)
    kappa_field: ClassVar[str] = KAPPA

    def __init__(
        self,
        cloud: PointCloud,
        bonds: Bonds,
        material: PMBConstants,
        surface_correction: bool,
        envelope: SofteningEnvelope,
        no_fail: NDArray[np.intp] | None = None,
    ) -> None:
        super().__init__(cloud, bonds, material, surface_correction)
        n = len(self.bonds.offsets) - 1
        self.envelope = envelope
        self.point_s0 = np.full(n, envelope.s0)
        self.point_sf = np.full(n, envelope.s_f)
        if no_fail is not None and len(no_fail):
            self.point_s0[np.asarray(no_fail)] = np.inf
            self.point_sf[np.asarray(no_fail)] = np.inf
        self.knee = (float(envelope.r), float(envelope.beta))
        self._soft_kernel = ks.FORCE_KERNELS[cloud.dim]

    def state_fields(self) -> tuple[FieldSpec, ...]:
        """The per-bond history kappa (``bond_kappa``), float64, committed by the law."""
        return (FieldSpec(KAPPA, where="bond", history=True),)

    def _run(self, state: State, commit: bool) -> int:
        b = self.bonds
        r, beta = self.knee
        return int(
            self._soft_kernel(
                self.cloud.x, state.u, b.offsets, b.bond_j, self.inv_length, self.stiffness,
                state.intact, state[KAPPA], self.point_s0, self.point_sf, r, beta,
                state.force, state.max_stretch, commit, self._broken_scratch,
            )
        )  # fmt: skip

    def pair_force_coefficients(self, state: State) -> NDArray[np.float64]:
        """g_k = stiffness_k h_k s_k / r_k (n_bonds,) (N/m^4) with the secant factor h of
        the envelope at the trial history max(kappa, s) (the force pass's pair force,
        through the NumPy form of ``reference_softening.factor``)."""
        b = self.bonds
        y = b.bond_xi + (state.u[b.bond_j] - state.u[b.bond_i])
        r = np.sqrt(np.einsum("ij,ij->i", y, y))
        s = r * self.inv_length - 1.0
        bi, bj = b.bond_i, b.bond_j
        s0b = 0.5 * (self.point_s0[bi] + self.point_s0[bj])
        sfb = 0.5 * (self.point_sf[bi] + self.point_sf[bj])
        h = softening_factor(s, state[KAPPA], state.intact, s0b, sfb, *self.knee)
        return np.asarray(self.stiffness * h * s / r)

    def update_max_stretch(self, state: State, above: float = 0.0) -> None:
        """Nothing: the softening force pass fills ``state.max_stretch`` itself."""

    def force(self, state: State) -> None:
        """Force density (N/m^3) into ``state.force`` with the trial history
        max(kappa, s); ``state.max_stretch`` gets the largest tensile stretch of a bond
        that still carries load. Pure: neither kappa nor ``intact`` change."""
        self._run(state, commit=False)

    def force_and_commit(self, state: State) -> int:
        """Explicit fast path: the law's trial, its commit (kappa and ``intact``) and
        :meth:`force` in one pass over the bonds, the same bits as the three calls in
        turn. Returns the number of directed bonds broken (not added to
        ``state.bonds_broken``: the evaluator does that)."""
        return self._run(state, commit=True)

    def fused_step(self, state: State, law: DamageLaw, sed: Any = None) -> FusedStep | None:
        """With the law bound to this model (``law.fused_model is self``): its trial,
        commit and the force in one pass (:meth:`force_and_commit`); None otherwise."""
        if law.fused_model is not self:
            return None
        return FusedStep(self.force_and_commit(state))

    def force_and_break(
        self, state: State, point_s0: NDArray[np.float64], family_s0_min: NDArray[np.float64]
    ) -> int:
        raise NotImplementedError("softening bonds break through force_and_commit")

    def force_sed_and_break(
        self,
        state: State,
        point_s0: NDArray[np.float64],
        family_s0_min: NDArray[np.float64],
        k0l: NDArray[np.float64],
        tensile: bool,
        energy: NDArray[np.float64],
    ) -> int:
        raise NotImplementedError("SED softening does not combine with softening bonds")

    def trial(
        self, state: State, kappa_out: NDArray[np.float64], proposed: NDArray[np.uint8]
    ) -> int:
        """Trial history of every bond into ``kappa_out`` (n_bonds,) and the bonds that
        fail into ``proposed`` (n_bonds,) uint8; returns how many fail. The State is
        not changed."""
        b = self.bonds
        return int(
            ks.trial(
                self.cloud.x, state.u, b.offsets, b.bond_j, self.inv_length, state.intact,
                state[KAPPA], self.point_s0, self.point_sf, kappa_out, proposed,
            )
        )  # fmt: skip

    def energy_density(self, state: State) -> NDArray[np.float64]:
        """Recoverable energy W_i = 1/4 sum_k stiffness_k h_k s_k^2 |xi_k| (J/m^3), shape
        (n,), with the trial history; the force is -grad of sum W_i V_i wherever no bond
        is on the envelope (s <= kappa), i.e. on unloading and reloading."""
        b = self.bonds
        r, beta = self.knee
        out = np.empty(len(b.offsets) - 1)
        ks.energy_density(
            self.cloud.x, state.u, b.offsets, b.bond_j, self.inv_length, b.bond_length,
            self.stiffness, state.intact, state[KAPPA], self.point_s0, self.point_sf, r,
            beta, out,
        )  # fmt: skip
        return out

    def tangent(self, state: State) -> sp.csr_matrix:
        """Finite-difference tangent K = -d(V f)/du (N/m) of the pure force at the
        committed history (:mod:`peridynamics.families.tangent`)."""
        return finite_difference_tangent(self, state)


def softening_force_model(
    criterion: Any,
    material: object,
    cloud: PointCloud,
    bonds: Bonds,
    surface_correction: bool = False,
) -> PMBSofteningForceModel:
    """The PMB force model with the bond law ``criterion``
    (:class:`~peridynamics.damage.bond_softening.SofteningBonds`) for ``material``: what
    the evaluator builds instead of the material's own force model when the damage
    section asks for a softening bond law."""
    if not isinstance(material, BondBasedMaterial):
        raise ValueError(
            "damage.bond_law: softening bond laws are for bond-based material.model "
            f"pmb / bond_based (got {type(material).__name__})"
        )
    env = softening_envelope(
        criterion, material, cloud.dim, bonds.horizon, cloud.cross_section, cloud.plane
    )
    return PMBSofteningForceModel(
        cloud, bonds, material, surface_correction, env, criterion.no_fail
    )
