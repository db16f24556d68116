"""Correspondence (non-ordinary state-based) peridynamics, 2-D and 3-D, with
zero-energy-mode control.

Silling et al. (2007), section 15 (the correspondence material model); the force state
and its stabilisations follow PD zero-energy modes (n.d.): eqs 1-6 (model), eq. 16
(Silling 2017) and eqs 17-25 (the linearised-bond stabilised correspondence model,
LBSCMM). The kernels are :mod:`peridynamics.kernels.correspondence` (NumPy twins in
:mod:`peridynamics.kernels.reference_correspondence`); equations, the stiffness bound
and the measured accuracy: docs/theory_correspondence.md.

Conventions
-----------
* Influence function omega = 1 for an intact bond, 0 for a broken one (eq. 12), times
  the partial volume of the bond list (``bonds.bond_volume``), consistently in K, F and
  the force sum.
* The pre-pass (:meth:`CorrespondenceForceModel.prepass`) writes the deformation
  gradient ``F`` (``state["deformation_gradient"]``, (n, d*d) row-major), the force
  tensor ``A = (P - sigma^s) K^-1`` (``state["force_tensor"]``) and the stabilisation
  coefficient (``state["stabilization"]``) of every point; the force pass reads them
  at both ends of each bond (a parallel run exchanges them for ghosts).
* Broken bonds leave K and F (both are sums over the intact bonds). A family whose
  shape tensor has lost nearly all of its extent, ``det K_i <= DEGENERATE_RATIO *
  det K_i(reference)`` (or a singular K), is *degenerate*: the point has no force
  state (K^-1 = 0, F = I, no stabilisation), its bonds carry only the force state of
  their other end, and the damage laws break its remaining bonds (the point is then
  fully damaged). No NaN can arise.
* The deformation gradient is exact for every affine displacement at every point,
  surfaces included (the patch test), so no surface correction is applied.
* Every variant has a potential energy (hyperelastic law plus the quadratic
  stabilisation energy), so the force is its exact gradient and the tangent is
  symmetric.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, ClassVar, Protocol

import numpy as np
from numpy.typing import NDArray

from peridynamics.bonds.bonds import Bonds
from peridynamics.families.base import FieldSpec, ForceModel, LargestStretchPass
from peridynamics.geometry.cloud import PointCloud
from peridynamics.kernels import correspondence as kernels
from peridynamics.kernels import correspondence_force as force_kernels

if TYPE_CHECKING:
    from peridynamics.state import State

#: a family is degenerate when det K falls to this fraction of its reference value
#: (2-D: e.g. the smaller principal moment down to 1 % with the larger one kept)
DEGENERATE_RATIO = 1e-2
_LAW_KERNELS = {"st_venant_kirchhoff": kernels.LAW_SVK, "linear_elastic": kernels.LAW_LINEAR}
_MODES = {
    "none": kernels.MODE_NONE,
    "silling2017": kernels.MODE_SILLING,
    "lbscmm": kernels.MODE_LBSCMM,
}


class CorrespondenceConstants(Protocol):
    """What the force model reads of its material
    (:class:`~peridynamics.families.correspondence.material.CorrespondenceMaterial`)."""

    @property
    def stabilization(self) -> str: ...

    @property
    def stabilization_g(self) -> float: ...

    def constitutive_law(self, dim: int, plane: str | None) -> Any: ...

    def micromodulus(
        self, dim: int, horizon: float, thickness: float, plane: str | None
    ) -> float: ...

    def horizon_volume(self, dim: int, horizon: float, thickness: float) -> float: ...


class CorrespondenceForceModel(LargestStretchPass, ForceModel):
    """Correspondence force model over a directed CSR bond list.

    Parameters
    ----------
    cloud : PointCloud
        2-D (plane stress or plane strain) or 3-D cloud.
    bonds : Bonds
        Bond list of ``cloud``.
    material : CorrespondenceMaterial (:class:`CorrespondenceConstants`)

    Attributes
    ----------
    mode : int
        0 none, 1 Silling (2017), 2 LBSCMM.
    micromodulus : float
        c of the LBSCMM bond (N/m^6), also the bond-based reference of the Silling
        penalty C = c / delta.
    det_reference : (n,) det K_i of the reference families (pre-cracked bonds out).
    reach : int
        The force of a point depends on the displacements up to 2 bonds away (the
        deformation gradients of its neighbours), used by the finite-difference tangent.
    """

    name: ClassVar[str] = "correspondence"
    spectral_bound: ClassVar[bool] = True  # the evaluator tightens the bound
    #: random bond loss raises the largest eigenvalue (30 % of the bonds of a plate
    #: broken: 3.5 times): with a damage law that can break bonds the analytic bound stays
    stiffens_with_damage: ClassVar[bool] = True
    reach: ClassVar[int] = 2

    def __init__(self, cloud: PointCloud, bonds: Bonds, material: CorrespondenceConstants) -> None:
        if cloud.dim not in (2, 3):
            raise ValueError("material.model correspondence is a 2-D / 3-D model")
        self.cloud = cloud
        self.bonds = bonds
        self.material = material
        d = cloud.dim
        self.law = material.constitutive_law(d, cloud.plane)
        self.mode = _MODES[material.stabilization]
        thickness = cloud.cross_section if d == 2 else 1.0
        self.micromodulus = material.micromodulus(d, bonds.horizon, thickness, cloud.plane)
        self.silling_g = material.stabilization_g * material.horizon_volume(
            d, bonds.horizon, thickness
        )
        self.weight = np.ascontiguousarray(bonds.bond_volume, dtype=np.float64)
        self.bond_xi = np.ascontiguousarray(bonds.bond_xi, dtype=np.float64)
        self.length = np.ascontiguousarray(bonds.bond_length, dtype=np.float64)
        n_own = len(bonds.offsets) - 1
        self.det_reference = np.empty(n_own)
        kernels.shape_determinant(
            self.bond_xi, bonds.offsets, self.weight, bonds.bond_intact, self.det_reference
        )
        self.stab_base = np.full(cloud.n_points, 0.5 * self.micromodulus)
        self._bound: NDArray[np.float64] | None = None
        self._scratch: tuple[NDArray[np.float64], ...] | None = None
        self._rows: NDArray[np.float64] | None = None
        self._active: NDArray[np.float64] | None = None
        #: the bond flags K^-1 and M of the scratch rows were made with (None: remake)
        self._geometry_intact: NDArray[np.uint8] | None = None

    # -- fields and passes ----------------------------------------------------------------
    def state_fields(self) -> tuple[FieldSpec, ...]:
        """F (n, d*d), A (n, d*d), the stabilisation coefficient (n,) and the
        degenerate flag (n,), written by :meth:`prepass`."""
        dd = self.dim * self.dim
        return (
            FieldSpec("deformation_gradient", components=dd),
            FieldSpec("force_tensor", components=dd),
            FieldSpec("stabilization"),
            FieldSpec("family_active"),
        )

    def kinematics(
        self, u: NDArray[np.float64], intact: NDArray[np.uint8]
    ) -> tuple[NDArray[np.float64], ...]:
        """(F, K^-1, sigma^s, omega_0, active, stab) of every owned point at ``u`` with
        the bonds ``intact``: shapes (n, d, d) x 3, (n,) x 3 (a fresh computation, the
        State is not touched)."""
        b = self.bonds
        n_all, d = u.shape
        kinv = np.empty((n_all, d, d))
        fgrad = np.empty((n_all, d, d))
        sigma_s = np.empty((n_all, d, d))
        omega0 = np.zeros(n_all)
        active = np.zeros(n_all)
        kernels.prepass(
            self.bond_xi, self.length, u, b.offsets, b.bond_j, self.weight, intact,
            self.det_reference, DEGENERATE_RATIO, self.mode, self.stab_base, kinv, fgrad,
            sigma_s, omega0, active, np.empty_like(self._work_rows(n_all)), False,
        )  # fmt: skip
        # (scratch rows of its own: those of the pre-pass keep M between steps; ``reuse``
        # passed, not left to its default: one compiled signature of the kernel, not two)
        stab = self._stabilization(omega0, active)
        return fgrad, kinv, sigma_s, omega0, active, stab

    def prepass(self, state: State) -> None:
        """F, A = (P - sigma^s) K^-1 and the stabilisation coefficient of every owned
        point into the State (fields of :meth:`state_fields`, allocated when missing)."""
        n_all, d = state.u.shape
        for spec in self.state_fields():
            if spec.name not in state:
                shape = (n_all, spec.components) if spec.components else (n_all,)
                state[spec.name] = np.zeros(shape)
        if self._scratch is None or self._scratch[0].shape[0] != n_all:
            self._scratch = tuple(np.zeros((n_all, d, d)) for _ in range(3)) + (np.zeros(n_all),)
            self._geometry_intact = None
        kinv, sigma_s, work, omega0 = self._scratch
        fgrad = self._tensor(state, "deformation_gradient")
        amat = self._tensor(state, "force_tensor")
        active = self._active_rows(n_all)
        b = self.bonds
        # K^-1, omega0, the degenerate flags and LBSCMM's M depend on the bonds alone:
        # kept while the State's bonds are those they were made with
        kept = self._geometry_intact
        reuse = kept is not None and np.array_equal(kept, state.intact)
        kernels.prepass(
            self.bond_xi, self.length, state.u, b.offsets, b.bond_j, self.weight, state.intact,
            self.det_reference, DEGENERATE_RATIO, self.mode, self.stab_base, kinv, fgrad,
            sigma_s, omega0, active, self._work_rows(n_all), reuse,
        )  # fmt: skip
        if not reuse:
            self._geometry_intact = state.intact.copy()
        n = len(b.offsets) - 1
        state["family_active"][:n] = active[:n]
        state["stabilization"][:n] = self._stabilization(omega0, active)[:n]
        self._force_tensor(state, fgrad[:n], kinv[:n], sigma_s[:n], active[:n], work[:n], amat[:n])

    def _force_tensor(
        self,
        state: State,
        fgrad: NDArray[np.float64],
        kinv: NDArray[np.float64],
        sigma_s: NDArray[np.float64],
        active: NDArray[np.float64],
        work: NDArray[np.float64],
        amat: NDArray[np.float64],
    ) -> None:
        """A = (P(F) - sigma^s) K^-1 of the owned points (n, d, d) into ``amat`` (a
        law with history overrides this: :mod:`.plastic_force`)."""
        law_id = _LAW_KERNELS.get(self.law.name)
        if law_id is not None:
            kernels.force_tensor(
                fgrad, kinv, sigma_s, active, self.law.lame, self.law.shear, law_id, work, amat
            )
        else:  # any other law through its NumPy interface
            piola = self.law.first_piola(fgrad) * active[:, None, None]
            amat[...] = np.einsum("nab,nbc->nac", piola - sigma_s, kinv)

    def _active_rows(self, n_all: int) -> NDArray[np.float64]:
        """The degenerate flags of the last full pre-pass (n_all,), kept with K^-1."""
        if self._active is None or self._active.shape[0] != n_all:
            self._active = np.zeros(n_all)
            self._geometry_intact = None
        return self._active

    def _work_rows(self, n_all: int) -> NDArray[np.float64]:
        """Scratch rows of the pre-pass kernel, (n_all, 3 m + m^2), m = d (d + 1) / 2."""
        m = 3 if self.dim == 2 else 6
        if self._rows is None or self._rows.shape[0] != n_all:
            self._rows = np.empty((n_all, 3 * m + m * m))
        return self._rows

    def _stabilization(
        self, omega0: NDArray[np.float64], active: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """Per-point stabilisation coefficient (0 on degenerate points), shape like
        ``active``: c/2 (LBSCMM), G C / omega_0 (Silling), 0 (none)."""
        if self.mode == kernels.MODE_LBSCMM:
            return np.asarray(active * self.stab_base[: len(active)])
        if self.mode == kernels.MODE_SILLING:
            c_pen = self.micromodulus / self.bonds.horizon
            return np.divide(
                active * self.silling_g * c_pen, omega0, out=np.zeros_like(omega0),
                where=omega0 > 0,
            )  # fmt: skip
        return np.zeros_like(active)

    def _tensor(self, state: State, name: str) -> NDArray[np.float64]:
        """A (n_all, d*d) field of the State as a (n_all, d, d) view."""
        n_all, d = state.u.shape
        a = state[name]
        if not a.flags.c_contiguous:
            raise ValueError(f"state[{name!r}] must be C-contiguous")
        return np.asarray(a.reshape(n_all, d, d))

    def force(self, state: State) -> None:
        """Correspondence force density (N/m^3) into ``state.force``; reads the fields of
        the last :meth:`prepass`. Pure: never breaks a bond. The largest stretch is not
        tracked here (the family loop vectorises without that max):
        ``update_max_stretch`` (:class:`~peridynamics.families.base.LargestStretchPass`)."""
        if "force_tensor" not in state:
            raise KeyError(
                "state has no 'force_tensor' field: call CorrespondenceForceModel.prepass("
                "state) before force(state)"
            )
        b = self.bonds
        force_kernels.FORCE_KERNELS[self.cloud.dim](
            self.bond_xi, self.length, state.u, b.offsets, b.bond_j, self.weight, state.intact,
            self._tensor(state, "force_tensor"), self._tensor(state, "deformation_gradient"),
            state["stabilization"], self.mode, state.force,
        )  # fmt: skip

    def energy_density(self, state: State) -> NDArray[np.float64]:
        """W_i = active_i W(F_i) + stabilisation energy (J/m^3), shape (n,), recomputed
        from ``state.u`` and ``state.intact`` (the State is not changed)."""
        b = self.bonds
        n = len(b.offsets) - 1
        fgrad, _, _, _, active, stab = self.kinematics(state.u, state.intact)
        w = active[:n] * self.law.energy_density(fgrad[:n])
        extra = np.empty(n)
        kernels.stabilization_energy(
            self.bond_xi, self.length, state.u, b.offsets, b.bond_j, self.weight, state.intact,
            fgrad, stab, self.mode, extra,
        )  # fmt: skip
        return np.asarray(w + extra)

    # -- stresses ---------------------------------------------------------------------------
    def cauchy_stress(self, u: NDArray[np.float64], intact: NDArray[np.uint8]) -> NDArray:
        """Cauchy stress sigma = P F^T / det F of every owned point (Pa), (n, d, d); zero
        on a degenerate point. Plane stress: the in-plane components."""
        n = len(self.bonds.offsets) - 1
        fgrad, _, _, _, active, _ = self.kinematics(u, intact)
        f = fgrad[:n]
        piola = self.law.first_piola(f)
        jac = np.linalg.det(f)
        jac = np.where(jac > 0, jac, 1.0)
        sigma = np.einsum("nab,ncb->nac", piola, f) / jac[:, None, None]
        return np.asarray(sigma * active[:n, None, None])

    def point_stress(self, state: State) -> NDArray[np.float64]:
        """The Cauchy stress of the constitutive law at the nonlocal F of every point
        (n, d, d) (Pa): :meth:`cauchy_stress` at ``state.u`` and ``state.intact``."""
        return np.asarray(self.cauchy_stress(state.u, state.intact))

    def max_principal_stress(
        self, u: NDArray[np.float64], intact: NDArray[np.uint8]
    ) -> NDArray[np.float64]:
        """Largest principal Cauchy stress of every owned point (Pa), shape (n,)."""
        sigma = self.cauchy_stress(u, intact)
        sym = 0.5 * (sigma + np.swapaxes(sigma, 1, 2))
        if self.dim == 2:
            a, b, c = sym[:, 0, 0], sym[:, 1, 1], sym[:, 0, 1]
            return np.asarray(0.5 * (a + b) + np.sqrt(0.25 * (a - b) ** 2 + c * c))
        return np.asarray(np.linalg.eigvalsh(sym)[:, -1])

    def degenerate_families(
        self, intact: NDArray[np.uint8], det: NDArray[np.float64]
    ) -> NDArray[np.bool_]:
        """Points whose family is degenerate with the bonds ``intact`` (n_bonds,) uint8:
        ``det K_i <= DEGENERATE_RATIO det K_i(reference)`` (or not a number) where the
        reference family had extent, shape (n_owned,); ``det`` (n_owned,) receives
        det K_i. What the failure laws ask (:mod:`peridynamics.damage.principal_stress`)."""
        kernels.shape_determinant(self.bond_xi, self.bonds.offsets, self.weight, intact, det)
        return np.asarray(~(det > DEGENERATE_RATIO * self.det_reference) & (self.det_reference > 0))

    # -- stiffness bound ------------------------------------------------------------------
    def stiffness_bound(self) -> NDArray[np.float64]:
        """Per-point bound K_i (N/m^4), shape (n,), such that ``dt = min_i sqrt(2 rho_i /
        K_i)`` is a stable explicit step of the model linearised at the reference state.

        Derivation (docs/theory_correspondence.md). With ``H_i = sum_k eta_k (x) g_k``,
        ``g_k = w_k K_i^-1 xi_k``, the point energy of the constitutive law is at most
        ``V_i c_C |H_i|^2 / 2`` (c_C the largest modulus of the elasticity tensor on
        symmetric tensors) and, by Cauchy-Schwarz, ``|H_i|^2 <= G_i sum_k |g_k|
        |eta_k|^2`` with ``G_i = sum_k |g_k|``; the Silling energy is at most
        ``stab_i / 2 sum_k w_k |eta_k|^2`` (z is the least-squares residual of eta);
        the LBSCMM energy, with ``(xi.z)^2 <= 2 (xi.eta)^2 + 2 (xi.H xi)^2``, at most
        ``c/2 sum_k w_k |eta_k|^2 / L_k + |H_i|^2 c/2 sum_k w_k L_k``. Every term is a
        bond-based form ``1/2 sum_k s_k |eta_k|^2``, and ``|eta|^2 <= 2 |u_i|^2 + 2
        |u_j|^2`` gives ``u.K.u <= 2 sum_p D_p |u_p|^2`` with ``D_p`` the sum of s_k over
        the bonds at p: ``K_p = D_p / V_p``.
        """
        if self._bound is None:
            self._bound = self._bound_of_reference()
        return self._bound.copy()

    def _bound_of_reference(self) -> NDArray[np.float64]:
        b = self.bonds
        n = len(b.offsets) - 1
        d = self.dim
        intact = b.bond_intact
        u0 = np.zeros((self.cloud.n_points, d))
        _, kinv, _, _, active, stab = self.kinematics(u0, intact)
        bi = b.bond_i.astype(np.intp)
        bj = b.bond_j.astype(np.intp)
        w = self.weight * intact
        g = w[:, None] * np.einsum("kab,kb->ka", kinv[bi], self.bond_xi)
        g_sum = np.zeros((n, d))
        np.add.at(g_sum, bi, g)
        gram = np.zeros((n, d, d))
        np.add.at(gram, bi, g[:, :, None] * g[:, None, :])
        lam_eta = np.linalg.eigvalsh(gram)[:, -1]
        lam_u = np.linalg.eigvalsh(gram + g_sum[:, :, None] * g_sum[:, None, :])[:, -1]
        n_fam = np.bincount(bi, w > 0, minlength=n)
        vol = self.cloud.volume
        cv = vol[:n] * self.law.max_modulus(d)
        # two valid bounds of the point energy, the smaller (in trace) taken per point:
        # (a) |H|^2 <= lam_eta sum_k |eta_k|^2 <= lam_eta sum_k 2 (|u_i|^2 + |u_j|^2)
        # (b) |H|^2 <= lam_u (|u_i|^2 + sum_j |u_j|^2), H = sum_k u_j (x) g_k - u_i (x) sum g
        use_b = lam_u <= 2.0 * lam_eta
        to_self = np.where(use_b, cv * lam_u, 2.0 * n_fam * cv * lam_eta)
        to_nbr = np.where(use_b, cv * lam_u, 2.0 * cv * lam_eta)
        dsum = to_self + np.bincount(bj, to_nbr[bi] * (w > 0), minlength=n)[:n]
        pair = np.zeros(b.n_bonds)  # 2 x the bond-based coefficient, to D_i and D_j
        if self.mode == kernels.MODE_SILLING:
            pair = 2.0 * vol[bi] * stab[bi] * w
        elif self.mode == kernels.MODE_LBSCMM:
            l_min = np.full(n, np.inf)
            np.minimum.at(l_min, bi, np.where(w > 0, self.length, np.inf))
            pair = vol[bi] * active[bi] * self.micromodulus * w / l_min[bi]
        dsum = dsum + np.bincount(bi, pair, minlength=n) + np.bincount(bj, pair, minlength=n)[:n]
        return np.asarray(0.5 * dsum / vol[:n])
