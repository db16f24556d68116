"""The model evaluator: owns the physics order of one force evaluation.

A :class:`Evaluator` composes a force model (one model family, :mod:`peridynamics.families`)
with a damage law, the optional extras and the external loads, and is the one place
that calls their kernels and the communicator. The order of one evaluation
(:meth:`Evaluator.evaluate`) is:

1. damage: the law's trial and commit (only when the solver commits at this
   evaluation: every step in explicit dynamics, never inside a dynamic-relaxation or
   Newton iteration);
2. the force model's pre-pass (per-point reductions such as the LPS dilatation);
3. the force model's pure force pass (when committing, then the force model's
   ``commit_history``: the plastic history of a path-dependent law);
4. SED softening levels (committed with the damage), their new bond stiffness acting
   from the next evaluation on;
5. contact; 6. mass damping; 7. viscous bond forces.

In a run decomposed over MPI ranks the evaluation starts with the halo exchange of
the displacement, the velocity and any further dof group (rotations) through
``comm.exchange``; the ghosts of the first layer own their bond families on every
rank that holds them (:mod:`peridynamics.parallel.local`), so the pre-pass fields they
need at both ends of a bond are computed there and need no second exchange.

External loads are filled separately by :meth:`Evaluator.external_force`. A force model
that declares a fused step (:meth:`~peridynamics.families.base.ForceModel.fused_step`:
PMB with a committing critical-stretch law, the tension-softening bonds with their law,
several bodies each their way) runs steps 1 and 3 (PMB in 2-D also the SED energy of
step 4) as one pass over the bonds, which gives the same bits as the separate calls.
The energies, damage, stresses and the stable step are
:class:`~peridynamics.evaluation.measures.Measures`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.communicator import Communicator, active_comm
from peridynamics.damage.critical_stretch import NO_DAMAGE
from peridynamics.damage.sed import SEDSoftening
from peridynamics.evaluation.measures import Measures
from peridynamics.families.base import DamageLaw, ForceModel
from peridynamics.families.pmb_sed import SoftenedStiffness
from peridynamics.families.registry import build_force_model
from peridynamics.families.tangent import finite_difference_tangent
from peridynamics.families.viscosity import BondViscosity
from peridynamics.geometry.cloud import PointCloud
from peridynamics.kernels.viscous import add_viscous_force
from peridynamics.loading.conditions import BodyForce
from peridynamics.state import State


@dataclass
class Evaluator(Measures):
    """A peridynamic body: force model + damage law + extras + loads.

    Parameters
    ----------
    cloud : PointCloud
    bonds : Bonds
    material : object with ``force_model(cloud, bonds, surface_correction)``
        :class:`~peridynamics.families.pmb.material.BondBasedMaterial` (PMB) or
        :class:`~peridynamics.families.lps.material.LPSMaterial` (LPS); its ``youngs_modulus``
        and ``density`` are read by the extras.
    damage : CriticalStretch, CorrespondenceFailure or SofteningBonds
        Failure criterion with a ``law(x, bonds)`` method; ``NO_DAMAGE`` keeps every
        bond. A criterion that names a model family (``force_family``: the
        tension-softening bond laws) has that family build the force model in place of
        the material (:func:`~peridynamics.families.registry.build_force_model`).
    body_forces : sequence of BodyForce
        Force-like loads (body forces, tractions spread over a layer).
    surface_correction : bool
        Apply the force model's surface correction (PMB: the energy method of Madenci &
        Oterkus 2014; LPS: the per-point influence calibration). Off by default here, as
        a low-level constructor states everything; decks default to ``true``
        (``discretisation.surface_correction``), which gives the nominal E.
    viscosity : BondViscosity, optional
        Viscous bond forces (PD wave dispersion (n.d.), eqs 52-56) from the velocity
        of the State; ``None`` or both coefficients 0 is plain PD.
    softening : SEDSoftening, optional
        Strain-energy-density softening of the bond stiffness (PMB only).
    contact : object with ``add_force(u, intact, force)``, optional
        Short-range contact between points not joined by an intact bond.
    damping : float
        Mass-proportional damping coefficient c_d (1/s): adds -rho c_d v to the force
        density (local damping for quasi-static runs by explicit dynamics).
    comm : Communicator
        Global reductions (serial by default).
    rigid : RigidSystem, optional
        Rigid bodies (platens, strikers) touching the points through contact
        (:mod:`peridynamics.bodies.rigid`); their fields live in the State.

    Examples
    --------
    >>> import numpy as np
    >>> import peridynamics as pd
    >>> grid = np.meshgrid(np.arange(10), np.arange(5), indexing="ij")
    >>> x = np.stack(grid, -1).reshape(-1, 2) * 1e-3  # m
    >>> cloud = pd.PointCloud(x=x, volume=np.full(50, 1e-9), spacing=1e-3, plane="stress")
    >>> bonds = pd.build_bonds(cloud, 3.015e-3)
    >>> material = pd.BondBasedMaterial(70e9, 2700.0)
    >>> model = pd.Evaluator(cloud, bonds, material, pd.CriticalStretch(0.01))
    >>> model.dim
    2
    """

    cloud: PointCloud
    bonds: Bonds
    material: Any
    damage: Any = NO_DAMAGE
    body_forces: Sequence[BodyForce] = ()
    surface_correction: bool = False
    viscosity: BondViscosity | None = None
    softening: SEDSoftening | None = None
    contact: Any = None
    damping: float = 0.0
    comm: Communicator = field(default_factory=active_comm)
    rigid: Any = None
    force_model: ForceModel = field(init=False, repr=False)
    damage_law: DamageLaw = field(init=False, repr=False)
    density: NDArray[np.float64] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        c = self.cloud
        self.force_model = build_force_model(
            self.material, self.damage, c, self.bonds, self.surface_correction
        )
        self.bonds = self.force_model.bonds  # with the surface-correction factors
        law_for = getattr(self.damage, "law_for", None)  # several bodies: per-body laws
        self.damage_law = (
            law_for(self.force_model)
            if law_for is not None
            else self.damage.law(c.x, self.bonds, c.global_ids)
        )
        self.damage_law.bind(self.force_model)  # a law that reads the force model
        self.time_step = 1.0  # set by an explicit solver: the friction law reads it
        self.friction_power = 0.0  # W, of the last evaluation (<= 0)
        self.density = np.full(c.n_points, self.material.density)
        if not (np.isfinite(self.damping) and self.damping >= 0):
            raise ValueError(f"damping must be >= 0 (1/s), got {self.damping}")
        self._sed: SoftenedStiffness | None = None
        if self.softening is not None:
            if not self.force_model.sed_softening:
                raise ValueError(
                    "damage.sed_softening softens bond stiffness and needs material.model "
                    f"'pmb' (got {self.force_model.name!r})"
                )
            self._sed = SoftenedStiffness(
                self.softening, self.force_model, self.material.youngs_modulus, self.point_s0
            )
        self._viscous: tuple[float, float] | None = None
        if self.viscosity is not None and self.viscosity.active:
            self._viscous = self.viscosity.coefficients(
                c.dim,
                self.bonds.horizon,
                c.cross_section,
                self.material.youngs_modulus,
                self.material.density,
            )

    @property
    def point_s0(self) -> NDArray[np.float64]:
        """Critical stretch per point (n,) of the critical-stretch law (inf: never)."""
        return self._critical_law().point_s0

    @point_s0.setter
    def point_s0(self, value: NDArray[np.float64]) -> None:
        self._critical_law().point_s0 = value

    @property
    def family_s0_min(self) -> NDArray[np.float64]:
        """Smallest bond threshold of each family (n,)."""
        return self._critical_law().family_s0_min

    @family_s0_min.setter
    def family_s0_min(self, value: NDArray[np.float64]) -> None:
        self._critical_law().family_s0_min = value

    def _critical_law(self) -> Any:
        law = self.damage_law
        if law.stretch_thresholds() is None:
            raise AttributeError(f"the damage law {law.name!r} has no critical stretch")
        return law

    # -- state -------------------------------------------------------------------------
    def new_state(self) -> State:
        """A State at rest with every field the model needs (bonds as built, levels 0)."""
        n, d = self.n_points, self.dim
        s = State(
            u=np.zeros((n, d)),
            v=np.zeros((n, d)),
            force=np.zeros((n, d)),
            body=np.zeros((n, d)),
            u_prev=np.zeros((n, d)),
            intact=self.bonds.bond_intact.copy(),
            max_stretch=np.zeros(n),
        )
        for dof in self.force_model.dofs()[1:]:  # rotations of a micropolar model
            for name in (dof.value, dof.rate, dof.force, dof.body):
                s[name] = np.zeros((n, dof.components))
        self._add_force_model_fields(s)
        self.force_model.init_state(s)  # fields that do not start at zero (interface bonds)
        if self._sed is not None:
            s["sed_level"] = np.zeros(n, dtype=np.int64)
        if self.rigid is not None:
            self.rigid.init_fields(s)
        if self.has_friction:
            s["friction_work"] = np.zeros(1)
        return s

    @property
    def has_friction(self) -> bool:
        """True when some contact has Coulomb friction (or rigid bodies are present: the
        State then records the friction work, zero without friction)."""
        return self.rigid is not None or bool(getattr(self.contact, "has_friction", False))

    def add_friction_work(self, state: State, dt: float) -> None:
        """Add the energy dissipated by friction over a step of ``dt`` (J), the power of
        the last evaluation times dt, to the State field ``friction_work``."""
        if "friction_work" in state:
            state["friction_work"][0] -= self.friction_power * dt

    def _add_force_model_fields(self, s: State) -> None:
        """Allocate the fields the force model declares, sized from ``s.u`` (points) and
        ``s.intact`` (bonds)."""
        for spec in self.force_model.state_fields():
            rows = {"point": len(s.u), "bond": len(s.intact)}.get(spec.where, spec.rows)
            shape = (rows, spec.components) if spec.components else (rows,)
            s[spec.name] = np.zeros(shape, dtype=spec.dtype)

    def on_restore(self, state: State) -> None:
        """Rebuild what follows from history fields after a checkpoint was read."""
        if self._sed is not None:
            if "sed_level" not in state or state["sed_level"].shape != (self.n_points,):
                raise ValueError("the checkpoint has no SED softening levels for this model")
            self._sed.restore(state)
        self.force_model.on_restore(state)

    # -- evaluation --------------------------------------------------------------------
    def evaluate(self, state: State, commit: bool = True) -> int:
        """Fill ``state.force`` with the internal force density (N/m^3) at ``state.u``
        (velocity-dependent parts from ``state.v``), in the order of the module
        docstring. With ``commit`` the damage law's trial is committed first (and SED
        levels rise); without it the evaluation is pure. Returns the number of directed
        bonds broken (also added to ``state.bonds_broken``)."""
        fm, law, sed = self.force_model, self.damage_law, self._sed
        broken = 0
        energy_done = False
        before = state.bonds_broken
        fused = False  # breaking inside the force pass (its per-point counts)
        if self.comm.size > 1:
            self.exchange_dofs(state)
        step = fm.fused_step(state, law, sed) if commit else None
        if step is not None:  # the law's trial and commit inside the force pass
            broken = step.broken
            state.bonds_broken += broken
            fused = step.counted
            energy_done = step.energy_done
        else:
            if commit and law.active:
                law.trial(state)
                broken = law.commit(state)
            fm.prepass(state)
            fm.force(state)
            if commit:
                fm.commit_history(state)
        if sed is not None and commit:
            sed.update(state, energy_computed=energy_done)
        self._extras(state)
        if broken and self.comm.size > 1:  # count the owned families' bonds only
            broken = self._owned_broken(fused)
            state.bonds_broken = before + broken
        return broken

    def exchange_dofs(self, state: State) -> None:
        """Halo exchange of what the force pass reads: u, v and further dof groups."""
        fields = [state.u, state.v]
        for dof in self.force_model.dofs()[1:]:
            fields += [state[dof.value], state[dof.rate]]
        self.comm.exchange_fields(fields)  # one message per neighbour rank

    def _owned_broken(self, fused: bool) -> int:
        """Bonds of owned points broken by this evaluation (the ghosts of the first layer
        break theirs too, as their owners do): from the per-point counts of a force pass
        that breaks bonds (``fused``) or from the damage law's proposal."""
        n_own = self.comm.n_owned
        counts = self.force_model.broken_counts
        if fused and counts is not None:
            return int(counts[:n_own].sum())
        law = self.damage_law
        by_law = getattr(law, "owned_broken", None)  # several bodies: the law counts
        if by_law is not None:
            return int(by_law(n_own))
        proposed = law.proposed
        if proposed is None:
            raise RuntimeError(f"the damage law {law.name!r} cannot count owned bonds")
        return int(np.count_nonzero(proposed[: self.owned_bonds]))

    def _extras(self, state: State) -> None:
        """Contact, mass damping and viscous bond forces, added to ``state.force``."""
        power = 0.0
        if self.contact is not None:
            if self.has_friction:
                power = self.contact.add_force(
                    state.u, state.intact, state.force, v=state.v, density=self.density,
                    dt=self.time_step,
                )  # fmt: skip
            else:
                self.contact.add_force(state.u, state.intact, state.force)
        if self.rigid is not None:
            power += self.rigid.add_force(state, state.u, state.v, self.cloud.x, state.force)
        self.friction_power = power
        if self.damping > 0:
            state.force -= (self.damping * self.density)[:, None] * state.v
        if self._viscous is not None:
            b = self.bonds
            add_viscous_force(
                self.cloud.x, state.u, state.v, b.offsets, b.bond_j, self.inv_length,
                b.bond_volume, state.intact, self._viscous[0], self._viscous[1], state.force,
            )  # fmt: skip

    def commit_damage(self, state: State) -> int:
        """Trial and commit of the damage law (and SED levels) at ``state.u``: what a
        static solver does on an accepted load step. Returns the bonds broken."""
        before = state.bonds_broken
        self.damage_law.trial(state)
        broken = self.damage_law.commit(state)
        if self._sed is not None:
            self._sed.update(state)
        self.force_model.commit_history(state, fresh=True)
        if broken and self.comm.size > 1:  # count the owned families' bonds only
            broken = self._owned_broken(False)
            state.bonds_broken = before + broken
        return broken

    def internal_force(
        self,
        u: NDArray,
        intact: NDArray[np.uint8],
        force: NDArray,
        max_stretch: NDArray,
        v: NDArray | None = None,
    ) -> int:
        """:meth:`evaluate` with commit on bare arrays (a convenience for scripts and tests
        of displacement-only models; solvers pass a State). ``intact`` is updated in
        place and ``max_stretch`` filled. Models with history fields (SED softening) need
        :meth:`evaluate`."""
        if self._sed is not None or any(f.history for f in self.force_model.state_fields()):
            raise ValueError("a model with history fields keeps them in a State: use evaluate")
        if self._viscous is not None and v is None:
            raise ValueError("a model with viscosity needs the velocity v in internal_force")
        s = State(
            u=u,
            v=np.zeros_like(u) if v is None else v,
            force=force,
            intact=intact,
            max_stretch=max_stretch,
        )
        self._add_force_model_fields(s)
        broken = self.evaluate(s, commit=True)
        self.force_model.update_max_stretch(s)
        return broken

    def force_of(self, u: NDArray, intact: NDArray[np.uint8] | None = None) -> NDArray:
        """Pure internal force density (N/m^3) at displacement ``u`` (no damage), a new
        (n, dim) array: for oracles and tangents."""
        s = self.new_state()
        s.u[...] = u
        if intact is not None:
            s.intact[...] = intact
        self.evaluate(s, commit=False)
        return s.force.copy()

    def tangent(self, state: State) -> sp.csr_matrix:
        """Tangent K = -d(V f)/du (N/m), shape (n dim, n dim): the force model's analytic
        one, else the finite-difference tangent."""
        k = self.force_model.tangent(state)
        if k is None:
            k = finite_difference_tangent(self.force_model, state)
        return k

    def external_force(self, t: float, out: NDArray) -> None:
        """Fill ``out`` (n, dim) with the external body-force density at time t (N/m^3)."""
        if not self.body_forces and not out.any():
            return  # nothing to add and already zero (the common case)
        out.fill(0.0)
        for load in self.body_forces:
            load.add_to(out, t)
