"""What the evaluator measures of a State: energies, bond counts, local damage, stresses,
stiffness bounds and the stable explicit step.

:class:`Measures` is the half of :class:`~peridynamics.evaluation.evaluator.Evaluator` that reads a
State without changing it; the other half (:mod:`peridynamics.evaluation.evaluator`) owns
the order of an evaluation. Global sums and minima go through the model's communicator,
over the owned points of a decomposed run.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.evaluation.spectral import SpectralEstimate, largest_eigenvalue
from peridynamics.evaluation.stability import StableStep
from peridynamics.kernels import bond_based
from peridynamics.kernels.viscous import add_viscous_force
from peridynamics.state import State

if TYPE_CHECKING:
    from peridynamics.bonds.bonds import Bonds
    from peridynamics.communicator import Communicator
    from peridynamics.families.base import DamageLaw, ForceModel
    from peridynamics.geometry.cloud import PointCloud


class Measures:
    """Energies, damage, stresses and stable steps of a
    :class:`~peridynamics.evaluation.evaluator.Evaluator` (a mixin: it reads the model's
    cloud, bonds, force model, communicator, densities and extras)."""

    cloud: PointCloud
    bonds: Bonds
    material: Any
    force_model: ForceModel
    damage_law: DamageLaw
    comm: Communicator
    rigid: Any
    density: NDArray[np.float64]
    _viscous: tuple[float, float] | None
    _sed: Any

    @property
    def viscous_coefficients(self) -> tuple[float, float] | None:
        """The viscous bond-force coefficients (linear, quadratic) this model applies,
        or None without ``material.viscosity`` (what another backend must reproduce)."""
        return self._viscous

    @property
    def sed_stiffness(self) -> Any:
        """The SED softening of the bond stiffness
        (:class:`~peridynamics.families.pmb_sed.stiffness.SoftenedStiffness`), or None without
        ``damage.sed_softening``."""
        return self._sed

    def _add_force_model_fields(self, s: State) -> None:
        raise NotImplementedError  # the model's (:mod:`peridynamics.evaluation.evaluator`)

    def new_state(self) -> State:
        raise NotImplementedError  # the model's (:mod:`peridynamics.evaluation.evaluator`)

    def exchange_dofs(self, state: State) -> None:
        raise NotImplementedError  # the model's (:mod:`peridynamics.evaluation.evaluator`)

    @property
    def dim(self) -> int:
        """Spatial dimension."""
        return self.cloud.dim

    @property
    def inv_length(self) -> NDArray[np.float64]:
        """1/|xi| (1/m), shape (n_bonds,), made by the bond list on first use."""
        return self.bonds.inv_length

    @property
    def n_points(self) -> int:
        """Number of points."""
        return self.cloud.n_points

    @property
    def stiffness(self) -> NDArray[np.float64]:
        """Bond stiffness (N/m^6 m^3) of a bond-based force model (raises otherwise)."""
        k = getattr(self.force_model, "stiffness", None)
        if k is None:
            raise AttributeError(f"the {self.force_model.name!r} model has no bond stiffness")
        return k

    def inertia(self, k: int) -> NDArray[np.float64]:
        """Mass density of dof group k of the force model (kg/m^3 for displacements,
        kg/m for rotations: rho times the model's inertia factor), shape (n,)."""
        if k == 0:
            return self.density
        return self.density * self.force_model.dof_inertia(k)

    def viscous_power(self, u: NDArray, v: NDArray, intact: NDArray[np.uint8]) -> float:
        """Power of the viscous forces sum_i V_i F_visc_i . v_i (W); never positive. 0 for
        a model without viscosity."""
        if self._viscous is None:
            return 0.0
        b = self.bonds
        f = np.zeros_like(u)
        add_viscous_force(
            self.cloud.x, u, v, b.offsets, b.bond_j, self.inv_length, b.bond_volume,
            intact, self._viscous[0], self._viscous[1], f,
        )  # fmt: skip
        own = self.comm.owned
        return self.comm.sum(float(np.sum(self.cloud.volume[own, None] * f[own] * v[own])))

    def strain_energy_density(self, u: NDArray, intact: NDArray[np.uint8]) -> NDArray:
        """W_i (J/m^3), shape (n,), of the force model. ``energy_density`` recomputes
        its per-point reductions (dilatation, deformation gradient) from ``u`` itself, so
        no pre-pass is run here."""
        s = State(u=u, intact=intact)
        self._add_force_model_fields(s)
        return self.force_model.energy_density(s)

    def strain_energy(self, u: NDArray, intact: NDArray[np.uint8]) -> float:
        """Total strain energy sum W_i V_i (J), reduced over ranks."""
        # np.sum, not @: a BLAS dot can wake OpenBLAS threads that then spin against
        # Numba's workers and slow the next force evaluations
        own = self.comm.owned
        w = self.strain_energy_density(u, intact)[own]
        local = float(np.sum(w * self.cloud.volume[own]))
        return self.comm.sum(local)

    def state_energies(self, s: State) -> tuple[float, float]:
        """(kinetic, strain) energy (J) of a State, rotations included, over ranks."""
        fm = self.force_model
        groups = fm.dofs()
        if len(groups) == 1 and not any(f.history for f in fm.state_fields()):
            # displacement only, no history (softening bonds): the energy of (u, intact)
            strain = self.strain_energy(s.u, s.intact)
        else:  # further dof groups (rotations) live in the State
            own = self.comm.owned
            w = fm.energy_density(s)[own]
            strain = self.comm.sum(float(np.sum(w * self.cloud.volume[own])))
        kinetic = self.kinetic_energy(s.v)
        if self.rigid is not None:  # free rigid bodies (strikers)
            kinetic += self.rigid.kinetic_energy(s)
        for k, dof in enumerate(groups[1:], start=1):
            own = self.comm.owned
            rate = s[dof.rate][own]
            mass = (self.inertia(k) * self.cloud.volume)[own]
            local = 0.5 * np.sum(mass * np.sum(rate * rate, axis=1))
            kinetic += self.comm.sum(float(local))
        return kinetic, strain

    def kinetic_energy(self, v: NDArray) -> float:
        """Total kinetic energy 1/2 sum rho_i V_i |v_i|^2 (J), reduced over ranks."""
        own = self.comm.owned
        mass = (self.density * self.cloud.volume)[own]
        local = float(0.5 * np.sum(mass * np.sum(v[own] * v[own], axis=1)))
        return self.comm.sum(local)

    @property
    def owned_bonds(self) -> int:
        """Directed bonds of the owned points' families: the first ``owned_bonds`` of the
        list (all of them in a serial run; a rank of a decomposed run also holds the
        families of its first ghost layer after them)."""
        n_own = self.comm.n_owned
        return self.bonds.n_bonds if n_own is None else int(self.bonds.offsets[n_own])

    def bond_counts(self, s: State) -> tuple[float, float]:
        """(directed bonds broken during the run, directed bonds) of the owned families,
        over ranks: the pre-cracked bonds count as neither."""
        end = self.owned_bonds
        failed = int(np.count_nonzero(self.bonds.bond_intact[:end])) - int(
            np.count_nonzero(s.intact[:end])
        )
        return self.comm.sum(float(failed)), self.comm.sum(float(end))

    def point_damage(
        self, intact: NDArray[np.uint8], interface_intact: NDArray[np.uint8] | None = None
    ) -> NDArray:
        """Local damage phi (Lu & Wang (2016), eq. 7), shape (n,). With several bodies the
        bonds of their interfaces count too (``interface_intact``: the State field of that
        name; ``None``: as built)."""
        own = self.force_model.point_damage(intact, interface_intact)
        if own is not None:  # bonds beyond ``bonds`` (interfaces between bodies)
            return own
        out = np.empty(self.n_points)
        b = self.bonds
        if "bond_volume" in b.held or b.x is None or b.point_volume is None:
            bond_based.damage(b.offsets, b.bond_volume, intact, out)
        else:  # derived in the kernel: the bond list keeps no partial volumes for it
            bond_based.damage_derived(
                b.x, b.offsets, b.bond_j, b.point_volume, b.horizon, b.spacing,
                bond_based.PARTIAL_VOLUME_CODES[b.partial_volume], intact, out,
            )  # fmt: skip
        return out

    def largest_stretch(self, s: State) -> NDArray[np.float64]:
        """Largest stretch r/|xi| - 1 of an intact bond of each point (0 where none is
        stretched), shape (n,), at ``s.u``: what the ``max_stretch`` probe reports, for
        every model family (the PMB force pass does not track it)."""
        b = self.bonds
        out = np.empty(self.n_points)
        bond_based.largest_stretch(self.cloud.x, s.u, b.offsets, b.bond_j, s.intact, 0.0, out)
        return out

    def max_stretch_after_commit(self, s: State, above: float) -> None:
        """``s.max_stretch`` as ``force_model.update_max_stretch(s, above)`` gives it (the
        largest stretch of an intact bond of each point where it exceeds ``above``, 0
        elsewhere), right after an evaluation that committed the damage law at ``s.u``.

        When the law promises that no intact bond is then stretched beyond its
        :meth:`~peridynamics.families.base.DamageLaw.stretch_cap`, and that cap is below
        ``above`` with a margin far above rounding (a critical stretch of a few per cent
        against the stability check's 100 %), the answer is 0 on every point: the pass
        over the bonds is skipped (it cost about a tenth of a PMB step at the check's
        default interval).
        """
        cap = self.comm.max(self.damage_law.stretch_cap())
        if (1.0 + cap) * (1.0 + 1e-9) < (1.0 + above) * (1.0 - 1e-9):
            s.max_stretch[: self._n_families] = 0.0
        else:
            self.force_model.update_max_stretch(s, above)

    def section_stress(self, u: NDArray, intact: NDArray[np.uint8], position: float) -> float:
        """1-D stress (Pa, tension positive) across the section x = ``position``: the sum
        of the forces of all intact bonds that cross it, divided by the area (Lu & Wang (2016)
        section 3: PD stress from the force flux, comparable with the FDM stress)."""
        if self.dim != 1:
            raise ValueError("section_stress is defined for 1-D bars")
        b = self.bonds
        x = self.cloud.x[:, 0]
        cross = (x[b.bond_i] < position) & (x[b.bond_j] > position)
        k = np.flatnonzero(cross)
        i, j = b.bond_i[k], b.bond_j[k]
        e = (x[j] - x[i]) + (u[j, 0] - u[i, 0])
        r = np.abs(e)
        # force on the left point i from j (N): stiffness (1/L - 1/r) e mu V_i
        f = self.stiffness[k] * (self.inv_length[k] - 1.0 / r) * e * intact[k]
        return float(np.sum(f * self.cloud.volume[i]) / self.cloud.cross_section)

    def point_stress(self, u: NDArray, intact: NDArray[np.uint8]) -> NDArray:
        """Peridynamic (virial) stress of each point, shape (n, dim, dim) (Pa):
        sigma_i = 1/2 sum_k f_k (xi_k + eta_k) (x) xi_k, with f_k the elastic bond force
        density of bond k times V_j (Lehoucq & Silling 2008, the bond-based form used for
        stress maps; viscous forces are not included). For a uniform strain it equals the
        continuum stress of the model in the bulk. Not used in the time loop (NumPy)."""
        b = self.bonds
        xi = b.bond_xi
        e = xi + (u[b.bond_j] - u[b.bond_i])
        r = np.linalg.norm(e, axis=1)
        g = self.stiffness * intact * (self.inv_length - 1.0 / r)  # c V s / r
        pair = 0.5 * g[:, None, None] * e[:, :, None] * xi[:, None, :]
        out = np.zeros((self.n_points, self.dim, self.dim))
        np.add.at(out, b.bond_i, pair)
        return out

    def pressure(self, u: NDArray, intact: NDArray[np.uint8]) -> NDArray:
        """Mean compressive stress -tr(sigma) / dim of each point, shape (n,) (Pa)."""
        return -np.trace(self.point_stress(u, intact), axis1=1, axis2=2) / self.dim

    #: tighten the bounds of a family that declares ``spectral_bound`` by the Lanczos
    #: estimate of :mod:`peridynamics.evaluation.spectral` (False: the analytic bound)
    use_spectral_bound: bool = True

    @property
    def spectral_applies(self) -> bool:
        """True when the stable step and :meth:`stiffness_bound` use the Lanczos estimate
        (the family declares ``spectral_bound``, one dof group, not switched off; for a
        family that ``stiffens_with_damage``, only while no bond can break; no contact
        and no rigid bodies: their stiffness is not in the estimate at the reference
        state, where nothing touches, so they keep the per-point bound's margin)."""
        if getattr(self, "contact", None) is not None or getattr(self, "rigid", None) is not None:
            return False
        fm = self.force_model
        # several bodies (a composite with ``models``): what every body's family declares
        parts = getattr(fm, "models", None) or (fm,)
        return (
            self.use_spectral_bound
            and all(getattr(m, "spectral_bound", False) for m in parts)
            and len(fm.dofs()) == 1
            and not (
                any(getattr(m, "stiffens_with_damage", False) for m in parts)
                and self._bonds_can_break()
            )
        )

    def _bonds_can_break(self) -> bool:
        """False only for a critical-stretch law whose thresholds are all infinite (no
        damage) on every rank; any other law may break bonds."""
        thresholds = self.damage_law.stretch_thresholds()
        here = thresholds is None or not bool(np.all(np.isinf(thresholds[0])))
        return bool(self.comm.any(here))

    def spectral_estimate(self, metric: str) -> SpectralEstimate:
        """The Lanczos estimate (:func:`~peridynamics.evaluation.spectral.largest_eigenvalue`)
        of the largest eigenvalue of W^-1 K at the reference state, made once per metric:
        ``"mass"`` (W = rho V: omega_max^2, 1/s^2) or ``"bound"`` (W = 2 diag(K_i V_i)
        of the family's analytic bound: the factor mu <= 1 it may be lowered by)."""
        cache: dict[str, SpectralEstimate] = self.__dict__.setdefault("_spectral_cache", {})
        if metric not in cache:
            vol = self.cloud.volume
            if metric == "mass":
                weight = self.density * vol
            elif metric == "bound":
                weight = 2.0 * self.force_model.stiffness_bound() * vol[: self._n_families]
                weight = np.concatenate([weight, np.zeros(self.n_points - len(weight))])
            else:
                raise ValueError(f"unknown metric {metric!r}: use 'mass' or 'bound'")
            cache[metric] = largest_eigenvalue(self, np.asarray(weight, dtype=np.float64))
        return cache[metric]

    @property
    def _n_families(self) -> int:
        return len(self.bonds.offsets) - 1

    def stiffness_bound(self) -> NDArray[np.float64]:
        """Per-point stiffness bound K_i of the force model (N/m^4), shape (n,): the
        family's analytic bound, lowered by the factor min(1, SAFETY mu) of the Lanczos
        estimate (:meth:`spectral_estimate`, metric ``"bound"``) where it applies, so that
        K <= 2 diag(K_i V_i) still holds (the contract of dynamic relaxation's density)."""
        bound = self.force_model.stiffness_bound()
        if not self.spectral_applies:
            return bound
        mu = self.spectral_estimate("bound").bound
        return np.asarray(bound * min(1.0, mu) if mu > 0 else bound)

    def _elastic_bond_stiffness(self) -> NDArray[np.float64]:
        """Bond stiffness of a bond-based model, or the PMB-equivalent micromodulus times
        the partial volume for other families (viscous rate constant, contact)."""
        k = getattr(self.force_model, "stiffness", None)
        if k is not None:
            return np.asarray(k)
        c = self.cloud
        c0 = self.material.micromodulus_constant(
            c.dim, self.bonds.horizon, c.cross_section, c.plane
        )
        return c0 * self.bonds.bond_volume

    def stable_step(self) -> StableStep:
        """The stable explicit step and its parts
        (:class:`~peridynamics.evaluation.stability.StableStep`): the elastic bound
        dt_el, min over points and dof groups of Silling & Askari's sqrt(2 rho / K_i)
        (s), or, where :attr:`spectral_applies`, the larger 2 / sqrt(SAFETY theta) of the
        Lanczos estimate theta of omega_max^2 (:mod:`peridynamics.evaluation.spectral`);
        the mass damping c_d (1/s); and gamma (s), the largest ratio of viscous to elastic
        bond coefficient (the 1-D rate constant of PD wave dispersion (n.d.),
        eq. 39). The quadratic viscosity depends on the amplitude and is not included.
        """
        dt = np.inf
        for group in range(len(self.force_model.dofs())):
            bound = self.force_model.dof_stiffness_bound(group)
            with np.errstate(divide="ignore"):
                per_point = np.where(bound > 0, np.sqrt(2.0 * self.inertia(group) / bound), np.inf)
            dt = min(dt, self.comm.min(float(per_point.min()) if per_point.size else np.inf))
        if self.spectral_applies and np.isfinite(dt):
            # omega_max^2 <= min(SAFETY theta, analytic): never shorter than the analytic step
            lam = self.spectral_estimate("mass").bound
            if lam > 0:
                dt = max(dt, 2.0 / float(np.sqrt(lam)))
        gamma = 0.0
        if self._viscous is not None and self._viscous[0] > 0:
            k = self._elastic_bond_stiffness()
            ok = k > 0
            ratio = self.bonds.bond_volume[ok] / k[ok]
            gamma = self.comm.max(float(self._viscous[0] * ratio.max()) if ratio.size else 0.0)
        return StableStep(float(dt), float(getattr(self, "damping", 0.0)), gamma)

    def stable_time_step(self) -> float:
        """Largest stable explicit step (s): Silling & Askari's bound lowered by the mass
        damping and the linear viscosity, dt = dt_el / (sqrt(1 + xi^2) + xi) with xi the
        damping ratio of the fastest mode (:mod:`peridynamics.evaluation.stability`)."""
        return self.stable_step().value
