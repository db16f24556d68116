"""The force-model and damage-law seams.

A **force model** is one model family (bond-based PMB, ordinary state-based LPS, ...).
It declares the fields it needs, computes its reference quantities once, optionally
runs a per-point pre-pass (LPS: the dilatation) whose results the force pass reads at
both ends of each bond, and evaluates forces *purely*: it never breaks a bond. It also
gives its strain energy, a per-point stiffness bound (stable time step, fictitious
density of dynamic relaxation) and, where it has one, a sparse tangent; every model
has the finite-difference tangent of :mod:`peridynamics.families.tangent` as fallback
and test oracle. Capabilities a family may declare (the evaluator asks them and never
tests a class): a fused explicit step (:meth:`ForceModel.fused_step`: the damage law's
trial and commit inside the force pass), per-point counts of the bonds that step broke
(:attr:`ForceModel.broken_counts`), a bond stiffness that SED softening rescales
(:attr:`ForceModel.sed_softening`) and a local damage of its own
(:meth:`ForceModel.point_damage`, several bodies with interfaces).

A **damage law** proposes (``trial``) which bonds fail at a state; the solver decides
when to ``commit`` the proposal (explicit dynamics: every step; dynamic relaxation and
static solvers: on an accepted load step). The history it changes (``intact``) lives
in the :class:`~peridynamics.state.State`. The interface lives here, below both the
families and the laws (:mod:`peridynamics.damage`), so that a family can name the law
it fuses with and a law the force model it reads, without importing each other.

Units: force densities N/m^3, energy densities J/m^3, stiffness bounds N/m^4 (so that
``dt_i = sqrt(2 rho_i / K_i)`` is a time for a density in kg/m^3), tangents N/m.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar, NamedTuple

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.geometry.cloud import PointCloud
from peridynamics.kernels import bond_based
from peridynamics.kernels import stress as stress_kernels

if TYPE_CHECKING:
    from peridynamics.state import State


@dataclass(frozen=True)
class Dof:
    """A group of degrees of freedom per point that a solver integrates.

    ``value`` is the displacement-like field (``u``), ``rate`` its velocity (``v``),
    ``force`` the conjugate internal force density, ``body`` the external one, all of
    shape (n, components). Translational models have one group; a micropolar model adds
    rotations (``theta``, ``omega``, ``moment``, ``body_moment``).
    """

    value: str
    rate: str
    force: str
    body: str
    components: int


class FusedStep(NamedTuple):
    """What a fused explicit step (:meth:`ForceModel.fused_step`) did (a named tuple:
    cheap to make once per explicit step).

    Attributes
    ----------
    broken : int
        Directed bonds broken (not yet added to ``state.bonds_broken``: the evaluator
        adds them).
    counted : bool
        The force model's :attr:`~ForceModel.broken_counts` hold this step's bonds broken
        per point (a decomposed run counts its owned points' bonds from them).
    energy_done : bool
        The step also computed the SED-softening energy (``sed.energy``).
    """

    broken: int
    counted: bool = True
    energy_done: bool = False


@dataclass(frozen=True)
class FieldSpec:
    """A field a model family adds to the State: per point (``(n, components)`` or
    ``(n,)`` for ``components == 0``) or per bond; ``history`` fields are decided by a
    damage law and committed by the solver. A field of any other kind (``where`` another
    word, such as ``"interface"``) has ``rows`` rows."""

    name: str
    where: str = "point"  # "point", "bond" or another kind with explicit ``rows``
    components: int = 0
    dtype: str = "float64"
    history: bool = False
    rows: int = -1


class ForceModel(ABC):
    """One model family evaluated over a directed CSR bond list.

    Subclasses set ``name`` (the deck's ``material.model``), compute reference
    quantities in ``__init__`` and implement :meth:`force`, :meth:`energy_density` and
    :meth:`stiffness_bound`. The kernels loop over the points that own a family,
    ``len(bonds.offsets) - 1``.
    """

    name: ClassVar[str] = ""
    #: capability: a per-bond ``stiffness`` that SED softening may rescale in place
    #: (:mod:`peridynamics.families.pmb_sed`)
    sed_softening: ClassVar[bool] = False
    #: capability: the evaluator may tighten :meth:`stiffness_bound` (the stable step,
    #: the fictitious density of dynamic relaxation) by a Lanczos estimate of the
    #: largest eigenvalue of the linearised force (:mod:`peridynamics.evaluation.spectral`);
    #: for families with one dof group whose analytic bound is loose
    spectral_bound: ClassVar[bool] = False
    #: the largest eigenvalue can grow as bonds break (a correspondence family whose
    #: shape tensor loses bonds): the set-up estimate of ``spectral_bound`` then holds
    #: only while no bond can break
    stiffens_with_damage: ClassVar[bool] = False
    cloud: PointCloud
    bonds: Bonds

    @property
    def dim(self) -> int:
        return self.cloud.dim

    @property
    def n_points(self) -> int:
        return self.cloud.n_points

    def dofs(self) -> tuple[Dof, ...]:
        """Degrees of freedom per point (default: the displacement, ``dim`` components)."""
        return (Dof("u", "v", "force", "body", self.dim),)

    def state_fields(self) -> tuple[FieldSpec, ...]:
        """Extra fields (pre-pass results, history) the State must hold."""
        return ()

    def prepass(self, state: State) -> None:  # noqa: B027 - optional hook
        """Per-point reductions the force pass reads at both ends of a bond (default:
        none). Results go into the State's fields declared by :meth:`state_fields`."""

    @abstractmethod
    def force(self, state: State) -> None:
        """Fill ``state.force`` (n, dim) with the internal force density (N/m^3) from
        ``state.u`` and ``state.intact`` (and, for most families, ``state.max_stretch``
        (n,) with the largest tensile stretch of an intact bond of each point; see
        :meth:`update_max_stretch`). Pure: never breaks a bond."""

    def update_max_stretch(self, state: State, above: float = 0.0) -> None:  # noqa: B027
        """Make ``state.max_stretch`` (n,) the largest stretch of an intact bond of each
        point at ``state.u``, at least where it exceeds ``above`` (elsewhere it may be
        0). Default: nothing, the force pass fills it everywhere; a model whose force
        pass does not (PMB: its family loop vectorises without the max) computes it here.
        Solvers call this before they read ``state.max_stretch``."""

    @abstractmethod
    def energy_density(self, state: State) -> NDArray[np.float64]:
        """Strain energy density W_i (J/m^3), shape (n,), such that the force is
        V_i f_i = -d(sum_j W_j V_j)/du_i. Computed from the State's value fields and
        ``intact`` alone: per-point reductions (dilatation, deformation gradient) are
        recomputed, so no :meth:`prepass` is needed first."""

    @abstractmethod
    def stiffness_bound(self) -> NDArray[np.float64]:
        """Per-point stiffness bound K_i (N/m^4) of the undamaged model: the stable
        explicit step is ``min_i sqrt(2 rho_i / K_i)`` (Silling & Askari 2005) and the
        fictitious density of dynamic relaxation is built from it (Kilic & Madenci
        2010)."""

    def dof_inertia(self, k: int) -> NDArray[np.float64]:
        """Inertia of dof group k per unit mass density, shape (n,): 1 for
        displacements; a rotation's (m^2) is the squared radius of gyration."""
        return np.ones(self.n_points)

    def dof_stiffness_bound(self, k: int) -> NDArray[np.float64]:
        """Stiffness bound of dof group k, shape (n,), with the contract of
        :meth:`stiffness_bound` (``dt_i = sqrt(2 rho_i inertia_i / K_i)`` is stable)."""
        if k != 0:
            raise NotImplementedError(f"the {self.name!r} model has one dof group")
        return self.stiffness_bound()

    def bond_stretch(self, state: State) -> NDArray[np.float64]:
        """Stretch of every directed bond (n_bonds,) at ``state.u``: the quantity the
        critical-stretch criterion compares with s0 (default: |xi + eta|/|xi| - 1)."""
        b = self.bonds
        out = np.empty(b.n_bonds)
        bond_based.bond_stretch(self.cloud.x, state.u, b.offsets, b.bond_j, out)
        return out

    def commit_history(self, state: State, fresh: bool = False) -> None:  # noqa: B027
        """Commit the history of a path-dependent constitutive law (plasticity): what
        the last evaluation proposed becomes the history the next one starts from. The
        evaluator calls it when the solver commits (every explicit step, an accepted
        load step of dynamic relaxation); ``fresh``: recompute the proposal at
        ``state.u`` first (the last evaluation may have been elsewhere). Default:
        nothing (elastic laws)."""

    def tangent(self, state: State) -> sp.csr_matrix | None:
        """Analytic tangent K = -d(V f)/dq (N/m), shape (n c, n c) with c the dof
        components per point in the order of :meth:`dofs` (``dim`` for displacement-only
        models), or ``None`` when the model has none (the finite-difference tangent is
        used instead)."""
        return None

    def on_restore(self, state: State) -> None:  # noqa: B027 - optional hook
        """Rebuild derived quantities after a State was read from a checkpoint."""

    def init_state(self, state: State) -> None:  # noqa: B027 - optional hook
        """Set the fields of :meth:`state_fields` that do not start at zero (default:
        none; interface bonds of several bodies start as built)."""

    # -- capabilities ---------------------------------------------------------------------
    def fused_step(self, state: State, law: DamageLaw, sed: Any = None) -> FusedStep | None:
        """Explicit fast path: ``law``'s trial and commit and :meth:`force` in one pass
        (the same bits as the calls in turn), with the SED energy of ``sed`` where the
        family can; ``None`` (the default) when this model does not fuse with ``law``,
        and then the evaluator calls them in turn."""
        return None

    @property
    def broken_counts(self) -> NDArray[np.int64] | None:
        """Bonds broken per owned point by the last fused step (n_owned,), or None."""
        return None

    def point_damage(
        self, intact: NDArray[np.uint8], interface_intact: NDArray[np.uint8] | None
    ) -> NDArray[np.float64] | None:
        """Local damage phi (n,) of a model whose bonds are not all in ``bonds``
        (interfaces between bodies); None (the default): the evaluator's, from ``bonds``."""
        return None

    def pair_force_coefficients(self, state: State) -> NDArray[np.float64] | None:
        """Pair-force coefficient g_k of every directed bond (n_bonds,) (N/m^4): the
        model's force density on point i from bond k is ``g_k (xi_k + eta_k)``, so that
        ``f_i = sum_k g_k y_k``; zero for a broken bond. None (the default): the model's
        pair forces are not central (correspondence, micropolar)."""
        return None

    def point_stress(self, state: State) -> NDArray[np.float64] | None:
        """Stress of every point that owns a family (n, d, d) (Pa): by default the
        peridynamic (virial) stress ``1/2 sum_k g_k y_k (x) xi_k`` of
        :meth:`pair_force_coefficients` (Lehoucq & Silling (2008), for a homogeneous
        deformation; :mod:`peridynamics.kernels.stress`); None when the model has
        neither pair forces nor a stress of its own."""
        g = self.pair_force_coefficients(state)
        if g is None:
            return None
        b = self.bonds
        out = np.empty((len(b.offsets) - 1, self.dim, self.dim))
        stress_kernels.virial_stress(self.cloud.x, state.u, b.offsets, b.bond_j, g, out)
        return out


class LargestStretchPass:
    """Mixin of a force model whose force pass does not track the largest stretch (its
    family loop vectorises without that max): :meth:`update_max_stretch` is the pass of
    :func:`peridynamics.kernels.bond_based.largest_stretch` over the bonds of the
    reference positions ``cloud.x``."""

    cloud: PointCloud
    bonds: Bonds

    def update_max_stretch(self, state: State, above: float = 0.0) -> None:
        """``state.max_stretch`` (n,): the largest stretch r/L - 1 of an intact bond of
        each point where it exceeds ``above``, 0 elsewhere."""
        b = self.bonds
        bond_based.largest_stretch(
            self.cloud.x, state.u, b.offsets, b.bond_j, state.intact, above, state.max_stretch
        )


class DamageLaw(ABC):
    """Decides which bonds fail. ``trial`` proposes, ``commit`` applies."""

    name: ClassVar[str] = ""

    @property
    def active(self) -> bool:
        """False for a law that never breaks anything."""
        return True

    def bind(self, force_model: ForceModel) -> None:  # noqa: B027 - optional hook
        """Attach the force model the law reads (stresses, softening history); default:
        the law reads none."""

    @abstractmethod
    def trial(self, state: State) -> int:
        """Propose the bonds that fail at ``state`` (kept by the law until
        ``commit``); returns the number of directed bonds proposed. Does not change
        the State."""

    @abstractmethod
    def commit(self, state: State) -> int:
        """Apply the last proposal to ``state.intact`` (and ``state.bonds_broken``);
        returns the number of directed bonds broken."""

    # -- capabilities (what force models and the evaluator may ask) -----------------------
    def stretch_thresholds(self) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:
        """(point_s0 (n,), family_s0_min (n,)) of a critical-stretch law, which a force
        model may apply inside its force pass; None (default) for other laws."""
        return None

    def stretch_cap(self) -> float:
        """The largest stretch an intact bond can keep after a commit at the State's
        displacement: after ``trial`` and ``commit`` (or a force pass that runs them),
        every intact bond is stretched less than this. ``inf`` (default): no such
        promise. A solver's stability check need not look for bonds stretched beyond
        it."""
        return math.inf

    @property
    def fused_model(self) -> ForceModel | None:
        """The force model that runs this law's trial and commit inside its force pass
        (its :meth:`ForceModel.fused_step`), or None (default)."""
        return None

    @property
    def proposed(self) -> NDArray[np.uint8] | None:
        """The last proposal, a (n_bonds,) uint8 flag per directed bond, or None for a
        law that keeps none (a decomposed run counts its owned bonds from it)."""
        return None
