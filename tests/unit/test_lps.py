"""Linear peridynamic solid: material, kernels vs NumPy twins, energy consistency,
affine patch, tangents (analytic, finite-difference, coloured), stiffness bound, static
solver plumbing."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.integrate import quad

from peridynamics.bonds import build_bonds
from peridynamics.families.lps.force import LPSForceModel
from peridynamics.families.lps.material import _FRACTURE_INTEGRALS, LPSMaterial
from peridynamics.families.tangent import (
    assemble_pattern,
    finite_difference_tangent,
    grid_colouring,
)
from peridynamics.geometry import PointCloud, box, rectangle
from peridynamics.geometry.cloud import Plane
from peridynamics.solvers.linear_static import reference_state, solve_linear_static
from peridynamics.state import State

DX = 1e-3
E = 2.0e9
RHO = 1500.0


def irregular_cloud(dim: int, seed: int, plane: Plane = "stress") -> PointCloud:
    """A small body with jittered positions and random nodal volumes."""
    rng = np.random.default_rng(seed)
    if dim == 2:
        base = rectangle((0.011, 0.009), DX, thickness=2e-3, plane=plane)
    else:
        base = box((0.006, 0.005, 0.005), DX)
    x = base.x + rng.uniform(-0.15, 0.15, base.x.shape) * DX
    vol = base.volume * rng.uniform(0.7, 1.3, base.n_points)
    return PointCloud(
        x=x, volume=vol, spacing=DX, cross_section=base.cross_section, plane=base.plane
    )


def broken_pairs(bonds, fraction: float, seed: int) -> np.ndarray:
    """Bond status with a random ``fraction`` of bonds broken in both directions."""
    rng = np.random.default_rng(seed)
    intact = np.ones(bonds.n_bonds, dtype=np.uint8)
    hit = np.flatnonzero(rng.random(bonds.n_bonds) < fraction)
    intact[hit] = 0
    intact[bonds.reverse_index()[hit]] = 0
    return intact


def model_and_state(dim, seed=0, nu=0.3, plane="stress", influence="constant", amp=0.02):
    cloud = irregular_cloud(dim, seed, plane)
    bonds = build_bonds(cloud, 3.015 * DX)
    mat = LPSMaterial(E, nu, RHO, influence=influence)
    model = mat.force_model(cloud, bonds)
    st = reference_state(model)
    rng = np.random.default_rng(seed + 1)
    st.u[:] = rng.normal(0.0, amp * DX, st.u.shape)
    return model, st


def evaluate(model, st):
    model.prepass(st)
    model.force(st)
    return st.force.copy()


# -- material ---------------------------------------------------------------------------
@pytest.mark.parametrize("nu", [0.5, -1.0, 0.7, -1.5, float("nan"), float("inf")])
def test_invalid_poisson_ratio_names_the_key(nu):
    with pytest.raises(ValueError, match=r"material\.poisson_ratio"):
        LPSMaterial(E, nu, RHO)


@pytest.mark.parametrize(
    ("kwargs", "key"),
    [
        ({"youngs_modulus": 0.0}, "youngs_modulus"),
        ({"youngs_modulus": float("nan")}, "youngs_modulus"),
        ({"density": -1.0}, "density"),
        ({"influence": "gaussian"}, "influence"),
    ],
)
def test_invalid_material_values_name_the_key(kwargs, key):
    args = {"youngs_modulus": E, "poisson_ratio": 0.25, "density": RHO} | kwargs
    with pytest.raises(ValueError, match=rf"material\.{key}"):
        LPSMaterial(**args)


def test_one_dimensional_or_planeless_cloud_is_rejected():
    mat = LPSMaterial(E, 0.25, RHO)
    with pytest.raises(ValueError, match="2-D and 3-D"):
        mat.coefficients(1, None)
    with pytest.raises(ValueError, match="plane"):
        mat.coefficients(2, None)


@pytest.mark.parametrize("nu", [-0.5, 0.0, 0.1, 0.25, 0.3, 0.45])
def test_coefficients_match_the_published_forms(nu):
    mat = LPSMaterial(E, nu, RHO)
    K, mu = mat.bulk_modulus, mat.shear_modulus
    c3 = mat.coefficients(3, None)  # Silling et al. 2007 / Peridigm: (3K - 5 mu)/m, 15 mu/m
    assert c3.theta_factor == 3.0
    assert c3.k_theta * c3.theta_factor == pytest.approx(3 * K - 5 * mu, rel=1e-13, abs=1e-3)
    assert c3.alpha == pytest.approx(15 * mu, rel=1e-14)
    pe = mat.coefficients(2, "strain")  # Le et al. 2014 plane strain: 2 (K - 5 mu / 3)
    assert pe.theta_factor == 2.0
    assert pe.k_theta * 2.0 == pytest.approx(2 * (K - 5 * mu / 3), rel=1e-13, abs=1e-3)
    assert pe.alpha == pytest.approx(8 * mu, rel=1e-14)
    ps = mat.coefficients(2, "stress")  # Le et al. 2014 plane stress (PDtools form)
    t = 2 * (2 * nu - 1) / (nu - 1)
    k_ = K + mu / 9 * ((nu + 1) / (2 * nu - 1)) ** 2
    assert ps.theta_factor == pytest.approx(t, rel=1e-14)
    assert ps.k_theta * ps.theta_factor == pytest.approx(
        t * k_ - 8 / 3 * mu * (2 - t / 3), rel=1e-12, abs=1e-3
    )
    # wave speeds
    assert mat.p_wave_speed(3, None) ** 2 * RHO == pytest.approx(K + 4 * mu / 3, rel=1e-13)
    lam_ps = E * nu / (1 - nu * nu)
    assert mat.p_wave_speed(2, "stress") ** 2 * RHO == pytest.approx(lam_ps + 2 * mu, rel=1e-13)
    assert mat.bar_wave_speed(2, "strain") == pytest.approx(
        math.sqrt(E / (1 - nu * nu) / RHO), rel=1e-14
    )
    assert mat.wave_speed() == pytest.approx(math.sqrt(E / RHO), rel=1e-15)


def _theta_hat_sq_integral(dim: int, p: int) -> float:
    """int_0^1 theta_hat(z)^2 dz by quadrature (critical-stretch construction)."""
    if dim == 3:
        m = 4 * math.pi * quad(lambda r: r ** (4 - p), 0, 1)[0]

        def theta(z):
            return 3 / m * quad(lambda r: r ** (-p) * 2 * math.pi * (1 - z / r) * r**4, z, 1)[0]

    else:
        m = 2 * math.pi * quad(lambda r: r ** (3 - p), 0, 1)[0]

        def theta(z):
            return (
                2 / m * quad(lambda r: r ** (-p) * 2 * math.acos(min(z / r, 1.0)) * r**3, z, 1)[0]
            )

    return quad(lambda z: theta(z) ** 2, 0, 1, epsabs=1e-13, limit=200)[0]


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize(("influence", "p"), [("constant", 0), ("inverse", 1)])
def test_critical_stretch_integrals(dim, influence, p):
    p_b, p_t = _FRACTURE_INTEGRALS[(dim, influence)]
    if dim == 3:
        assert p_b == pytest.approx(15 * (5 - p) / (4 * (6 - p)), rel=1e-15)
    else:
        assert p_b == pytest.approx(8 * (4 - p) / (math.pi * (5 - p)), rel=1e-15)
    assert p_t == pytest.approx(_theta_hat_sq_integral(dim, p), rel=1e-8)


def test_critical_stretch_values():
    g0, delta = 50.0, 3e-3
    mat = LPSMaterial(E, 0.25, RHO, influence="inverse")
    mu = mat.shear_modulus
    # nu = 1/4 in 3-D: A = K - 5 mu / 3 = 0, only Madenci & Oterkus's 3 mu term remains
    assert mat.critical_stretch(g0, 3, delta) == pytest.approx(
        math.sqrt(g0 / (3 * mu * delta)), rel=1e-13
    )
    for nu in (-0.9, 0.0, 0.2, 0.49):
        for dim, plane in ((3, None), (2, "stress"), (2, "strain")):
            s = LPSMaterial(E, nu, RHO).critical_stretch(g0, dim, delta, 1e-3, plane)
            assert math.isfinite(s) and s > 0
    with pytest.raises(ValueError, match="fracture_energy"):
        mat.critical_stretch(0.0, 3, delta)


def test_micromodulus_constant_is_the_bond_based_one():
    from peridynamics.families.pmb.material import BondBasedMaterial

    mat = LPSMaterial(E, 0.3, RHO)
    pmb = BondBasedMaterial(E, RHO)
    for dim, plane in ((2, "stress"), (2, "strain"), (3, None)):
        assert mat.micromodulus_constant(dim, 3e-3, 1e-2, plane) == pmb.micromodulus_constant(
            dim, 3e-3, 1e-2, plane
        )


# -- kernels vs twins -------------------------------------------------------------------
def test_max_stretch_is_largest_tensile_intact_stretch():
    """update_max_stretch: the largest r/L - 1 of an intact bond (NumPy over the bonds),
    0 under compression and where every bond is broken."""
    model, st = model_and_state(2, seed=5)
    st.u[:] = 0.0
    st.u[:, 0] = -1e-3 * model.cloud.x[:, 0]  # uniform compression: nothing stretched
    evaluate(model, st)
    model.update_max_stretch(st)
    assert np.all(st.max_stretch == 0.0)
    st.u[:] = np.random.default_rng(6).normal(0.0, 0.05 * DX, st.u.shape)
    b = model.bonds
    st.intact[::3] = 0
    y = b.bond_xi + st.u[b.bond_j] - st.u[b.bond_i]
    s = np.where(st.intact > 0, np.linalg.norm(y, axis=1) / b.bond_length - 1.0, -np.inf)
    expected = np.maximum(np.maximum.reduceat(s, b.offsets[:-1]), 0.0)
    model.update_max_stretch(st)
    np.testing.assert_allclose(st.max_stretch, expected, rtol=1e-12, atol=1e-15)
    assert expected.max() > 0.0
    st.u[:, 0] = 1e-3 * model.cloud.x[:, 0]
    st.intact[:] = 0  # every bond broken: no intact bond, no force
    f = evaluate(model, st)
    model.update_max_stretch(st)
    assert np.all(st.max_stretch == 0.0) and np.all(f == 0.0)


def test_force_needs_the_prepass():
    model, _ = model_and_state(2)
    n, d = model.n_points, model.dim
    st = State(
        u=np.zeros((n, d)),
        force=np.zeros((n, d)),
        intact=np.ones(model.bonds.n_bonds, np.uint8),
        max_stretch=np.zeros(n),
    )
    with pytest.raises(KeyError, match="prepass"):
        model.force(st)
    model.prepass(st)  # allocates the field
    assert st["dilatation"].shape == (n,)
    model.force(st)
    assert [s.name for s in model.state_fields()] == ["dilatation"]


# -- energy consistency -----------------------------------------------------------------
def test_surface_correction_factors_keep_the_model_conservative(serial_numba):
    """With surface_correction=True the per-point influence calibration changes the
    forces, and the force stays the gradient of the energy and the tangent symmetric."""
    cloud = irregular_cloud(2, 51)
    bonds = build_bonds(cloud, 3.015 * DX)
    g = np.random.default_rng(52).uniform(0.8, 1.3, cloud.n_points)
    bonds = bonds.with_correction(0.5 * (g[bonds.bond_i] + g[bonds.bond_j]))
    mat = LPSMaterial(E, 0.3, RHO)
    plain = mat.force_model(cloud, bonds)
    model = mat.force_model(cloud, bonds, surface_correction=True)
    st = reference_state(model)
    st.u[:] = np.random.default_rng(53).normal(0, 0.02 * DX, st.u.shape)
    f = evaluate(model, st)
    assert np.abs(f - evaluate(plain, st)).max() > 1e-3 * np.abs(f).max()
    vol = cloud.volume
    u0, h = st.u.copy(), 1e-6 * DX
    for i in (0, 17, 40):
        for c in range(2):
            st.u[:] = u0
            st.u[i, c] += h
            e_plus = float(np.sum(model.energy_density(st) * vol))
            st.u[i, c] -= 2 * h
            e_minus = float(np.sum(model.energy_density(st) * vol))
            grad = -(e_plus - e_minus) / (2 * h)
            assert grad == pytest.approx(vol[i] * f[i, c], abs=1e-6 * np.abs(vol * f.T).max())
    st.u[:] = u0
    k = model.tangent(st)
    assert abs(k - k.T).max() <= 1e-12 * abs(k).max()


# -- affine patch -----------------------------------------------------------------------
@pytest.mark.parametrize(
    ("dim", "plane", "rule", "influence"),
    [
        (2, "stress", "truncated", "constant"),
        (2, "strain", "extended", "inverse"),
        (3, None, "truncated", "inverse"),
        (3, None, "none", "constant"),
    ],
)
def test_affine_displacement_gives_zero_interior_force(dim, plane, rule, influence):
    """A homogeneous deformation (stretch, shear and rotation, finite) is in equilibrium
    at every point farther than two horizons from the surface."""
    n_side = 16
    size = (n_side * DX,) * dim
    cloud = rectangle(size, DX, plane=plane) if dim == 2 else box(size, DX)
    delta = 3.015 * DX
    bonds = build_bonds(cloud, delta, rule)
    model = LPSMaterial(E, 0.3, RHO, influence=influence).force_model(cloud, bonds)
    rng = np.random.default_rng(11)
    grad_u = rng.uniform(-2e-3, 2e-3, (dim, dim))
    st = reference_state(model)
    st.u[:] = (cloud.x - cloud.x.mean(axis=0)) @ grad_u.T + 1e-4
    f = evaluate(model, st)
    reach = 2 * float(bonds.bond_length.max())
    lo, hi = cloud.bounds
    inner = np.all((cloud.x > lo + reach) & (cloud.x < hi - reach), axis=1)
    assert inner.sum() >= 1
    scale = np.abs(f).max()  # the surface points are out of balance
    assert scale > 0
    assert np.abs(f[inner]).max() <= 1e-10 * scale
    # the dilatation of an interior point is the volumetric strain (to first order; plane
    # stress adds eps_zz = -nu / (1 - nu) tr(eps))
    expected = model.coefficients.theta_factor / dim * np.trace(grad_u)
    np.testing.assert_allclose(st["dilatation"][inner], expected, rtol=0, atol=5e-5)


def test_weighted_volume_interior_matches_the_integral():
    cloud = box((0.011, 0.011, 0.011), DX)
    delta = 4.015 * DX
    bonds = build_bonds(cloud, delta, "extended")
    model = LPSMaterial(E, 0.3, RHO).force_model(cloud, bonds)
    centre = np.argmin(np.sum((cloud.x - cloud.x.mean(axis=0)) ** 2, axis=1))
    # the extended rule integrates |xi|^2 over the ball to about 1 %
    assert model.weighted_volume[centre] == pytest.approx(4 * math.pi / 5 * delta**5, rel=0.02)


# -- tangents ---------------------------------------------------------------------------
def test_grid_colouring_separates_points():
    rng = np.random.default_rng(0)
    x = rng.uniform(0, 0.01, (400, 2))
    sep = 2.5e-3
    colours = grid_colouring(x, sep, 1e-3)
    for c in np.unique(colours):
        p = x[colours == c]
        if len(p) > 1:
            dist = np.sqrt(((p[:, None, :] - p[None, :, :]) ** 2).sum(-1))
            assert dist[np.triu_indices(len(p), 1)].min() > sep


def test_pattern_reach():
    model, _ = model_and_state(2)
    b = model.bonds
    p1 = assemble_pattern(b, reach=1)
    assert p1.nnz == b.n_bonds + model.n_points
    p2 = assemble_pattern(b, reach=2)
    assert p2.nnz > p1.nnz
    assert abs(p2 - p2.T).max() == 0


def test_coloured_fd_tangent_equals_brute_force(serial_numba):
    """Perturbing the points of a colour together gives the very same numbers as one
    point at a time (no point feels two perturbed points)."""
    cloud = rectangle((0.030, 0.016), DX, thickness=2e-3, plane="strain")
    bonds = build_bonds(cloud, 3.015 * DX)
    model = LPSMaterial(E, 0.2, RHO).force_model(cloud, bonds)
    st = reference_state(model)
    st.u[:] = np.random.default_rng(3).normal(0, 0.02 * DX, st.u.shape)
    st.intact[:] = broken_pairs(bonds, 0.1, seed=4)
    r_max = float(bonds.bond_length.max())
    colours = grid_colouring(cloud.x, 4 * r_max * (1 + 1e-9), DX)
    assert colours.max() + 1 <= 14 * 14 < model.n_points // 2
    coloured = finite_difference_tangent(model, st)
    brute = finite_difference_tangent(model, st, colours=np.arange(model.n_points))
    assert coloured.nnz == brute.nnz
    assert abs(coloured - brute).max() == 0.0
    with pytest.raises(ValueError, match="too coarse"):
        finite_difference_tangent(model, st, colours=np.zeros(model.n_points, dtype=int))


# -- stiffness bound and explicit stability --------------------------------------------
def _verlet(model, st, dt, steps, rho):
    """Velocity Verlet; returns the largest |u| seen."""
    f = evaluate(model, st)
    peak = 0.0
    for _ in range(steps):
        st.v[:] += 0.5 * dt * f / rho
        st.u[:] += dt * st.v
        f = evaluate(model, st)
        st.v[:] += 0.5 * dt * f / rho
        peak = max(peak, float(np.abs(st.u).max()))
        if not np.isfinite(peak) or peak > 1.0:
            break
    return peak


@pytest.mark.parametrize(
    ("dim", "plane", "nu"), [(2, "stress", 0.3), (2, "strain", 0.35), (3, None, 0.1)]
)
def test_stiffness_bound_gives_a_stable_step(dim, plane, nu, serial_numba):
    size = (14 * DX,) * dim
    cloud = rectangle(size, DX, plane=plane) if dim == 2 else box((9 * DX,) * 3, DX)
    bonds = build_bonds(cloud, 3.015 * DX)
    model = LPSMaterial(E, nu, RHO).force_model(cloud, bonds)
    kb = model.stiffness_bound()
    assert kb.shape == (model.n_points,) and np.all(kb > 0)
    dt = float(np.min(np.sqrt(2 * RHO / kb)))
    # the bound is conservative: the largest eigenvalue of V^-1 K / rho
    k = model.tangent(reference_state(model))
    v_half = sp.diags(1 / np.sqrt(np.repeat(cloud.volume, dim)))
    lam = spla.eigsh(v_half @ k @ v_half, k=1, which="LA", return_eigenvectors=False)[0]
    dt_true = 2.0 / math.sqrt(lam / RHO)
    assert 0.5 * dt_true < dt <= dt_true
    rng = np.random.default_rng(5)
    u0 = rng.normal(0, 1e-6 * DX, (model.n_points, dim))
    st = reference_state(model)
    st.u[:] = u0
    assert _verlet(model, st, 0.9 * dt, 300, RHO) < 20 * np.abs(u0).max()
    st = reference_state(model)
    st.u[:] = u0
    assert _verlet(model, st, 3.0 * dt, 300, RHO) > 1e3 * np.abs(u0).max()


def test_stiffness_bound_holds_after_bonds_break():
    model, _ = model_and_state(2, seed=41, nu=0.45)
    st = reference_state(model)
    st.intact[:] = broken_pairs(model.bonds, 0.3, seed=42)
    k = model.tangent(st)
    vol = np.repeat(model.cloud.volume, 2)
    v_half = sp.diags(1 / np.sqrt(vol))
    lam = spla.eigsh(v_half @ k @ v_half, k=1, which="LA", return_eigenvectors=False)[0]
    assert lam <= 2 * model.stiffness_bound().max()


# -- static solver plumbing -------------------------------------------------------------
class _NoTangent(LPSForceModel):
    """The same model without its analytic tangent: the solver falls back to FD."""

    def tangent(self, state):
        return None


def test_static_solver_fd_fallback_and_dirichlet_values(serial_numba):
    cloud = rectangle((12 * DX, 6 * DX), DX, plane="strain")
    bonds = build_bonds(cloud, 3.015 * DX)
    mat = LPSMaterial(E, 0.3, RHO)
    n, d = cloud.n_points, 2
    left = np.flatnonzero(cloud.x[:, 0] < DX)
    right = np.flatnonzero(cloud.x[:, 0] > 11 * DX)
    fixed = np.concatenate([left * d, right * d, [left[0] * d + 1]])
    values = np.concatenate([np.zeros(len(left)), np.full(len(right), 1e-6), [0.0]])
    body = np.zeros((n, d))
    u_an = solve_linear_static(mat.force_model(cloud, bonds), fixed, values, body)
    u_fd = solve_linear_static(_NoTangent(cloud, bonds, mat), fixed, values, body)
    u_cg = solve_linear_static(mat.force_model(cloud, bonds), fixed, values, body, method="cg")
    np.testing.assert_allclose(u_an.ravel()[fixed], values, rtol=0, atol=0)
    assert np.abs(u_fd - u_an).max() <= 1e-7 * np.abs(u_an).max()
    assert np.abs(u_cg - u_an).max() <= 1e-7 * np.abs(u_an).max()
    # the linear static solution is in equilibrium: free dofs carry no net force
    model = mat.force_model(cloud, bonds)
    reaction = model.tangent(reference_state(model)) @ u_an.ravel()
    free = np.setdiff1d(np.arange(n * d), fixed)
    assert np.abs(reaction[free]).max() <= 1e-9 * np.abs(reaction[fixed]).max()
    # and the reactions of the two ends balance
    assert abs(reaction[left * d].sum() + reaction[right * d].sum()) <= 1e-9 * abs(
        reaction[right * d].sum()
    )


def test_static_solver_rejects_bad_input():
    cloud = rectangle((8 * DX, 6 * DX), DX, plane="stress")
    model = LPSMaterial(E, 0.3, RHO).force_model(cloud, build_bonds(cloud, 3.015 * DX))
    body = np.zeros((cloud.n_points, 2))
    body[:, 0] = 1e6
    with pytest.raises(ValueError, match="rigid"):
        solve_linear_static(model, [0, 1], 0.0, body)  # rotation and translation free
    with pytest.raises(ValueError, match="fixed_dofs"):
        solve_linear_static(model, [cloud.n_points * 2], 0.0, body)
    with pytest.raises(ValueError, match="external_force"):
        solve_linear_static(model, [0, 1, 3], 0.0, body[:-1])
    with pytest.raises(ValueError, match="method"):
        solve_linear_static(model, [0, 1, 3], 0.0, body, method="qr")
