"""The force models the contract harness checks: one small model per family and case.

Every family-specific line of the harness lives here; ``test_force_models.py`` sees a
:class:`Case` only. A case builds a force model and a deformed :class:`State` (random
displacement of a few per cent of the spacing, a share of bond pairs broken, history
fields set) and may name a NumPy twin of its kernels. A new family is one more entry
of :data:`CASES` (plus, if it has one, a ``twin_*`` function).

The clouds are small (20 to 130 points) so that dense finite-difference tangents and
eigenvalues stay cheap, and jittered with random volumes where the family allows it
(no lattice symmetry hides an error).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cache, partial
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.bodies.build import select_bonds
from peridynamics.bodies.composite import BodyPart, CompositeForceModel
from peridynamics.bodies.interface import InterfaceBonds
from peridynamics.bonds.bonds import build_bonds
from peridynamics.damage.bond_softening import SofteningBonds
from peridynamics.damage.critical_stretch import CriticalStretch
from peridynamics.damage.sed import SEDSoftening
from peridynamics.families.base import ForceModel
from peridynamics.families.correspondence.force import DEGENERATE_RATIO
from peridynamics.families.correspondence.material import CorrespondenceMaterial
from peridynamics.families.lps.material import LPSMaterial
from peridynamics.families.lps.plastic import LPSPlasticity
from peridynamics.families.micropolar.material import MicropolarMaterial
from peridynamics.families.pmb.force import PMBForceModel
from peridynamics.families.pmb.material import BondBasedMaterial
from peridynamics.families.pmb_sed.stiffness import SoftenedStiffness
from peridynamics.families.pmb_softening.force import softening_force_model
from peridynamics.geometry.cloud import PointCloud
from peridynamics.geometry.generators import bar, box, rectangle
from peridynamics.kernels import correspondence as kernels_correspondence
from peridynamics.kernels import (
    reference,
    reference_correspondence,
    reference_lps,
    reference_micropolar,
    reference_softening,
)
from peridynamics.state import State
from tests.helpers import EXAMPLES, load_script

DX = 1e-3
#: a twin comparison: (what, value of the code under test, value of the NumPy twin)
Pairs = list[tuple[str, NDArray[Any], NDArray[Any]]]


@dataclass
class Built:
    """A force model and a deformed State of it.

    ``restore`` rebuilds what the family derives from the State after a checkpoint is
    read (default: ``model.on_restore``); ``extra_fields`` names the history fields the
    family keeps beyond :meth:`ForceModel.state_fields` (SED levels)."""

    model: ForceModel
    state: State
    restore: Callable[[State], None] | None = None
    extra_fields: tuple[str, ...] = ()


@dataclass(frozen=True)
class Case:
    """One family (or variant) as the harness sees it.

    Attributes
    ----------
    id : str
        Test id.
    build : callable
        () -> :class:`Built`; called once per test session (cached by :func:`built`),
        and once more by the checkpoint contract (a fresh model reads the State back).
    twin : callable, optional
        (model, state after prepass + force) -> [(what, value, twin value)]: the NumPy
        twins of :mod:`peridynamics.kernels` for this family.
    rotation : float
        Angle (rad) of the rigid rotation: finite for geometrically exact families,
        small for linearised ones (their rigid-motion force is O(angle^2)).
    set_rotation : callable, optional
        (state, angle) -> None for families with rotational dofs (theta = angle).
    """

    id: str
    build: Callable[[], Built]
    twin: Callable[[ForceModel, State], Pairs] | None = None
    rotation: float = 0.3
    set_rotation: Callable[[State, float], None] | None = field(default=None)


# -- shared pieces ------------------------------------------------------------------------
def blank_state(model: ForceModel) -> State:
    """A State at rest with every field the model's interface declares: its dof groups
    (value, rate, force, body), ``intact`` as built, ``max_stretch`` and
    :meth:`ForceModel.state_fields` (zero), then the model's ``init_state`` if any."""
    n = model.n_points
    st = State(intact=np.array(model.bonds.bond_intact, dtype=np.uint8), max_stretch=np.zeros(n))
    for dof in model.dofs():
        for name in (dof.value, dof.rate, dof.force, dof.body):
            st[name] = np.zeros((n, dof.components))
    for spec in model.state_fields():
        rows = {"point": n, "bond": model.bonds.n_bonds}.get(spec.where, spec.rows)
        shape = (rows,) if spec.components == 0 else (rows, spec.components)
        st[spec.name] = np.zeros(shape, dtype=spec.dtype)
    init = getattr(model, "init_state", None)
    if init is not None:
        init(st)
    return st


def jittered(base: PointCloud, seed: int) -> PointCloud:
    """``base`` with positions jittered by 15 % of the spacing and volumes by 30 %."""
    rng = np.random.default_rng(seed)
    x = base.x + rng.uniform(-0.15, 0.15, base.x.shape) * base.spacing
    vol = base.volume * rng.uniform(0.7, 1.3, base.n_points)
    return PointCloud(x, vol, base.spacing, base.cross_section, base.plane, irregular=True)


def plate(nx: int = 8, ny: int = 7, plane: str = "stress", seed: int | None = 1) -> PointCloud:
    cloud = rectangle((nx * DX, ny * DX), DX, thickness=2e-3, plane=plane)
    return cloud if seed is None else jittered(cloud, seed)


def block(n: tuple[int, int, int] = (5, 5, 4), seed: int | None = 2) -> PointCloud:
    cloud = box(tuple(k * DX for k in n), DX)
    return cloud if seed is None else jittered(cloud, seed)


def deform(
    model: ForceModel, st: State, seed: int, amp: float = 0.02, broken: float = 0.1
) -> State:
    """Random displacement (``amp`` spacings) and a share ``broken`` of bond pairs cut."""
    rng = np.random.default_rng(seed)
    st.u[...] = rng.normal(0.0, amp * model.cloud.spacing, st.u.shape)
    b = model.bonds
    if broken:
        hit = np.flatnonzero(rng.random(b.n_bonds) < broken)
        st.intact[hit] = 0
        st.intact[b.reverse_index()[hit]] = 0
    return st


def _bond_twin(model: ForceModel, st: State, stiffness: NDArray[np.float64]) -> Pairs:
    b = model.bonds
    args = (model.cloud.x, st.u, b.bond_i, b.bond_j, b.bond_length, stiffness, st.intact)
    return [
        ("force", st.force, reference.force(*args)),
        ("energy", model.energy_density(st), reference.strain_energy_density(*args)),
        ("stretch", model.bond_stretch(st), reference.stretch(*args[:5])),
    ]


# -- PMB --------------------------------------------------------------------------------
def pmb(dim: int, profile: str = "conical") -> Built:
    """PMB on a jittered cloud, energy-method (moment) surface correction."""
    base = {1: bar(0.02, DX, area=3e-6), 2: plate(seed=None), 3: block(seed=None)}[dim]
    cloud = jittered(base, 10 + dim)
    model = PMBForceModel(
        cloud,
        build_bonds(cloud, 3.015 * DX),
        BondBasedMaterial(70e9, 2700.0, profile=profile),  # type: ignore[arg-type]
        surface_correction=True,
    )
    assert np.ptp(model.bonds.bond_correction) > 0.5  # the correction is at work
    return Built(model, deform(model, blank_state(model), seed=dim))


def twin_pmb(model: ForceModel, st: State) -> Pairs:
    assert isinstance(model, PMBForceModel)
    return _bond_twin(model, st, model.stiffness)


# -- tension-softening PMB -------------------------------------------------------------------
SOFT = {"E": 30e9, "rho": 2400.0, "ft": 3e6, "g0": 20.0}


def pmb_softening(dim: int) -> Built:
    """Trilinear softening bonds with no-fail points, every bond in tension past the
    peak (an isotropic stretch of s_f / 2 plus noise), the history kappa above the
    current stretch (unloading and reloading: there the force is the gradient of the
    energy). No bond is near s = 0, where the force has a kink (compression keeps the
    full stiffness) that central differences would straddle."""
    cloud = plate() if dim == 2 else block()
    bonds = build_bonds(cloud, 3.015 * DX)
    law = SofteningBonds("trilinear", SOFT["ft"], SOFT["g0"], knee=(0.3, 0.4),
                         no_fail=np.array([0, 5]))  # fmt: skip
    model = softening_force_model(
        law, BondBasedMaterial(SOFT["E"], SOFT["rho"]), cloud, bonds, True
    )
    sf = model.envelope.s_f
    st = deform(model, blank_state(model), seed=20 + dim, amp=0.05 * sf, broken=0.05)
    st.u += 0.5 * sf * (cloud.x - cloud.x.mean(axis=0))
    b = model.bonds
    s = reference.stretch(cloud.x, st.u, b.bond_i, b.bond_j, b.bond_length)
    assert s.min() > 0.2 * sf  # far from the kink at s = 0 and past the peak s0
    above = s + np.random.default_rng(30 + dim).uniform(0.02, 0.5, b.n_bonds) * sf
    st["bond_kappa"][:] = np.maximum(above, above[b.reverse_index()])
    return Built(model, st)


def twin_pmb_softening(model: Any, st: State) -> Pairs:
    b = model.bonds
    args = (model.cloud.x, st.u, b.bond_i, b.bond_j, b.bond_length, model.stiffness, st.intact,
            st["bond_kappa"], model.point_s0, model.point_sf, *model.knee)  # fmt: skip
    f_ref, smax_ref = reference_softening.force(*args)
    return [
        ("force", st.force, f_ref),
        ("max_stretch", st.max_stretch, smax_ref),
        ("energy", model.energy_density(st), reference_softening.energy_density(*args)),
    ]


# -- SED-softening PMB -----------------------------------------------------------------
def pmb_sed() -> Built:
    """PMB whose bond stiffness SED softening lowered: random levels 0..N+1 per point
    (history field ``sed_level``), the stiffness rebuilt from them."""
    cloud = plate()
    mat = BondBasedMaterial(4.71e9, 1810.0)
    model = PMBForceModel(cloud, build_bonds(cloud, 3.015 * DX), mat, surface_correction=True)
    params = SEDSoftening()
    soft = SoftenedStiffness(params, model, mat.youngs_modulus, np.full(cloud.n_points, 3e-3))
    st = deform(model, blank_state(model), seed=40)
    st["sed_level"] = np.random.default_rng(41).integers(0, params.levels + 2, cloud.n_points)
    soft.restore(st)
    return Built(model, st, restore=soft.restore, extra_fields=("sed_level",))


def twin_pmb_sed(model: ForceModel, st: State) -> Pairs:
    """The bond stiffness stiffness0 (f_i + f_j) / 2 from the levels, then the PMB twin."""
    assert isinstance(model, PMBForceModel)
    b, params = model.bonds, SEDSoftening()
    k0 = model.material.bond_stiffness(model.cloud, b)
    f = params.factor(st["sed_level"])
    k_ref = k0 * 0.5 * (f[b.bond_i] + f[b.bond_j])
    return [("stiffness", model.stiffness, k_ref), *_bond_twin(model, st, k_ref)]


# -- LPS --------------------------------------------------------------------------------
def lps(dim: int, influence: str, correction: bool, plane: str = "stress") -> Built:
    """LPS on a jittered cloud; ``correction``: the per-point influence calibration."""
    cloud = plate(nx=9, ny=8, plane=plane) if dim == 2 else block((6, 5, 5))
    mat = LPSMaterial(2e9, 0.2, 1500.0, influence=influence)  # type: ignore[arg-type]
    model = mat.force_model(cloud, build_bonds(cloud, 3.015 * DX), surface_correction=correction)
    assert not correction or np.ptp(model.calibration_factor) > 0.5  # far from uniform
    return Built(model, deform(model, blank_state(model), seed=50 + dim))


def twin_lps(model: Any, st: State) -> Pairs:
    b, n = model.bonds, model.n_points
    args = (model.cloud.x, st.u, b.bond_i, b.bond_j, b.bond_length, model.omega_volume)
    theta = reference_lps.dilatation(*args, st.intact, model.theta_scale, n)
    f_ref, smax = reference_lps.force(
        *args,
        st.intact,
        theta,
        model.dilatation_coef,
        model.extension_coef,
        n,
        model.omega_volume_far,
    )
    w_ref = reference_lps.energy_density(
        *args, st.intact, model.theta_scale, model.k_theta, model.extension_coef, n
    )
    vol, rev = model.cloud.volume, b.reverse_index()
    wv_far = vol[b.bond_j] * model.omega_volume[rev] / vol[b.bond_i]  # V_i wvf = V_j wv'
    m_ref = reference_lps.weighted_volume(b.bond_i, b.bond_length, model.omega_volume,
                                          b.bond_intact, n)  # fmt: skip
    return [
        ("weighted_volume", model.weighted_volume, m_ref),
        ("far weights", model.omega_volume_far, wv_far),
        ("dilatation", st["dilatation"], theta),
        ("force", st.force, f_ref),
        ("max_stretch", st.max_stretch, smax),
        ("energy", model.energy_density(st), w_ref),
    ]


def lps_plastic() -> Built:
    """Elastic-plastic LPS (3-D, surface correction) with a yield stress far above the
    state's stress: zero history, the plastic kernels in their elastic branch (force =
    -grad energy and rigid motion hold only at a fixed history that does not yield)."""
    mat = LPSMaterial(2e9, 0.2, 1500.0, plasticity=LPSPlasticity(1e12, 1e9))
    cloud = block((6, 5, 5))
    model = mat.force_model(cloud, build_bonds(cloud, 3.015 * DX), surface_correction=True)
    return Built(model, deform(model, blank_state(model), seed=57))


def twin_lps_plastic(model: Any, st: State) -> Pairs:
    from peridynamics.kernels import reference_lps_plasticity as twins

    b = model.bonds
    args = (model.cloud.x, st.u, b.bond_i, b.bond_j, b.bond_length, model.omega_volume)
    ep, q = st["lps_plastic_extension"], st["lps_plastic_strain"]
    p = model.plasticity
    theta, scale, _ = twins.return_map(
        *args, st.intact, model.theta_scale, model.extension_coef, ep, q, model.shear,
        p.yield_stress, p.hardening_modulus,
    )  # fmt: skip
    f_ref, _ = twins.force(
        *args, model.omega_volume_far, st.intact, theta, model.dilatation_coef,
        model.extension_coef, model.reverse, ep, scale,
    )  # fmt: skip
    w_ref = twins.energy_density(
        *args, st.intact, model.theta_scale, model.k_theta, model.extension_coef, ep,
        model.n_points,
    )  # fmt: skip
    return [("dilatation", st["dilatation"], theta), ("force", st.force, f_ref),
            ("energy", model.energy_density(st), w_ref)]  # fmt: skip


# -- micropolar -------------------------------------------------------------------------
def micropolar(plane: str) -> Built:
    """2-D micropolar plate with rotations (theta ~ 1e-3 rad beside u ~ 1e-2 dx)."""
    cloud = rectangle((0.06, 0.05), 0.01, thickness=1.0, plane=plane)
    mat = MicropolarMaterial(200e9, 0.2, 7800.0, rotational_stiffness_ratio=1.0 / 12.0)
    model = mat.force_model(cloud, build_bonds(cloud, 3.015 * 0.01), surface_correction=True)
    st = deform(model, blank_state(model), seed=60)
    st["theta"][:] = np.random.default_rng(61).normal(0.0, 1e-3, st["theta"].shape)
    return Built(model, st)


def twin_micropolar(model: Any, st: State) -> Pairs:
    b, k = model.bonds, model.springs
    args = (model.cloud.x, st.u, st["theta"], b.bond_i, b.bond_j, model.weight, st.intact,
            k.axial, k.shear, k.rotational)  # fmt: skip
    f_ref, m_ref = reference_micropolar.force(*args)
    stretch = reference_micropolar.bond_measures(*args[:5])[3]
    smax = np.zeros(model.n_points)
    np.maximum.at(smax, b.bond_i, np.where(st.intact != 0, stretch, 0.0))
    return [
        ("force", st.force, f_ref),
        ("moment", st["moment"], m_ref),
        ("energy", model.energy_density(st), reference_micropolar.energy_density(*args)),
        ("stretch", model.bond_stretch(st), stretch),
        ("max_stretch", st.max_stretch, smax),
    ]


def rotate_theta(st: State, angle: float) -> None:
    st["theta"][:] = angle


# -- correspondence ---------------------------------------------------------------------
def correspondence(dim: int, stab: str, law: str = "st_venant_kirchhoff") -> Built:
    """Finite strain (a few per cent: SVK is nonlinear there) with broken bonds."""
    cloud = plate(seed=None) if dim == 2 else block(seed=None)
    horizon = (3.015 if dim == 2 else 2.015) * DX
    mat = CorrespondenceMaterial(70e9, 0.3, 2700.0, stab, law=law)  # type: ignore[arg-type]
    model = mat.force_model(cloud, build_bonds(cloud, horizon))
    return Built(model, deform(model, blank_state(model), seed=70 + dim, amp=0.03, broken=0.1))


def twin_correspondence(model: Any, st: State) -> Pairs:
    b, d = model.bonds, model.dim
    args = (model.bond_xi, st.u, b.offsets, b.bond_j, model.weight, st.intact)
    _, fgrad, _, _, active = reference_correspondence.prepass(
        *args, model.det_reference, DEGENERATE_RATIO, model.mode, model.stab_base
    )
    f_ref = reference_correspondence.force(
        *args, st["force_tensor"].reshape(-1, d, d), fgrad, st["stabilization"], model.mode
    )
    w = np.empty(model.n_points)
    kernels_correspondence.stabilization_energy(
        *args[:1], model.length, *args[1:], st["deformation_gradient"].reshape(fgrad.shape),
        st["stabilization"], model.mode, w,
    )  # fmt: skip
    w_ref = reference_correspondence.stabilization_energy(
        *args, fgrad, st["stabilization"], model.mode
    )
    return [
        ("family_active", st["family_active"], active),
        ("deformation_gradient", st["deformation_gradient"].reshape(fgrad.shape), fgrad),
        ("force", st.force, f_ref),
        ("stabilisation energy", w, w_ref),
    ]


# -- several bodies ---------------------------------------------------------------------
def composite() -> Built:
    """Two blocks side by side, PMB (left) and LPS (right), joined by interface bonds;
    each body's surface correction on."""
    flat = rectangle((10 * DX, 7 * DX), DX, thickness=DX, plane="stress")
    order = np.argsort(flat.x[:, 0] > 5 * DX, kind="stable")
    cloud = jittered(PointCloud(flat.x[order], flat.volume[order], DX, DX, "stress"), 80)
    n0 = int(np.sum(flat.x[:, 0] < 5 * DX))
    body = (np.arange(cloud.n_points) >= n0).astype(np.int64)
    bonds = build_bonds(cloud, 3.015 * DX)
    same = body[bonds.bond_i] == body[bonds.bond_j]
    pmb_mat = BondBasedMaterial(70e9, 2700.0)
    parts = (
        BodyPart("a", 0, n0, pmb_mat, CriticalStretch(1.0)),
        BodyPart("b", n0, cloud.n_points, LPSMaterial(20e9, 0.25, 1000.0), CriticalStretch(1.0)),
    )
    c0 = pmb_mat.micromodulus_constant(2, 3.015 * DX, DX, "stress")
    iface = InterfaceBonds("a/b", select_bonds(bonds, ~same), 0.7 * c0, 1.0)
    model = CompositeForceModel(cloud, select_bonds(bonds, same), parts, True, (iface,))
    st = deform(model, blank_state(model), seed=81)
    cut = np.arange(0, iface.n_bonds, 7)  # interface bond pairs, both directions
    st["interface_intact"][cut] = 0
    st["interface_intact"][iface.bonds.reverse_index()[cut]] = 0
    return Built(model, st)


# -- the toy family of docs/adding.md ---------------------------------------------------------
def toy() -> Built:
    mod = load_script(EXAMPLES / "toy_family" / "toy_family.py", "toy_family")
    cloud = plate()
    model = mod.ToySpringModel(cloud, build_bonds(cloud, 3.015 * DX), c=1e20)
    return Built(model, deform(model, blank_state(model), seed=90))


def twin_toy(model: Any, st: State) -> Pairs:
    """The toy is NumPy itself; the PMB twin with its stiffness is an independent oracle."""
    return _bond_twin(model, st, model.k)[:2]


CASES: list[Case] = [
    Case("pmb-1d", lambda: pmb(1, "constant"), twin_pmb),
    Case("pmb-2d", lambda: pmb(2, "conical"), twin_pmb),
    Case("pmb-3d", lambda: pmb(3, "constant"), twin_pmb),
    Case("pmb-3d-conical", lambda: pmb(3, "conical"), twin_pmb),
    Case("pmb_softening-2d", lambda: pmb_softening(2), twin_pmb_softening),
    Case("pmb_softening-3d", lambda: pmb_softening(3), twin_pmb_softening),
    Case("pmb_sed-2d", pmb_sed, twin_pmb_sed),
    Case("lps-2d", lambda: lps(2, "constant", True), twin_lps),
    Case("lps-2d-strain", lambda: lps(2, "inverse", False, "strain"), twin_lps),
    Case("lps-3d", lambda: lps(3, "inverse", True), twin_lps),
    Case("lps_plastic-3d", lps_plastic, twin_lps_plastic),
    Case("micropolar-stress", lambda: micropolar("stress"), twin_micropolar, 1e-7, rotate_theta),
    Case("micropolar-strain", lambda: micropolar("strain"), twin_micropolar, 1e-7, rotate_theta),
    *(
        Case(
            f"correspondence-{stab}-{d}d",
            partial(correspondence, d, stab),
            twin_correspondence,
        )
        for d in (2, 3)
        for stab in ("none", "silling2017", "lbscmm")
    ),
    *(
        Case(
            f"correspondence-linear-{d}d",
            partial(correspondence, d, stab, "linear_elastic"),
            twin_correspondence,
            1e-7,
        )
        for d, stab in ((2, "lbscmm"), (3, "silling2017"))
    ),
    Case("composite-pmb+lps+interface", composite),
    Case("toy_spring", toy, twin_toy),
]


@cache
def built(case_id: str) -> Built:
    """The case built once per session (the tests copy its State)."""
    return next(c for c in CASES if c.id == case_id).build()


__all__ = ["CASES", "Built", "Case", "ForceModel", "blank_state", "built"]
