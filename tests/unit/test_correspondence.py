"""Correspondence model: patch test, Numba == NumPy, force == -grad energy, zero-energy
modes of a periodic patch, the stiffness bound, degenerate families, 3-D moduli."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse.linalg as spla

from peridynamics.bonds.bonds import Bonds, build_bonds
from peridynamics.evaluation import Evaluator
from peridynamics.families.correspondence.material import CorrespondenceMaterial
from peridynamics.geometry.cloud import PointCloud
from peridynamics.geometry.generators import box, rectangle

STABS = ("none", "silling2017", "lbscmm")


def _plate(dx: float = 1e-3, nx: int = 12, ny: int = 10, rule: str = "truncated"):
    cloud = rectangle((nx * dx, ny * dx), dx, thickness=1e-3, plane="stress")
    return cloud, build_bonds(cloud, 3.015 * dx, rule)


def _block(dx: float = 1e-3, n: tuple[int, int, int] = (7, 6, 6), rule: str = "truncated"):
    cloud = box(tuple(k * dx for k in n), dx)
    return cloud, build_bonds(cloud, 2.015 * dx, rule)


def _model(cloud, bonds, stab: str, nu: float = 0.3, law: str = "st_venant_kirchhoff") -> Evaluator:
    return Evaluator(cloud, bonds, CorrespondenceMaterial(70e9, nu, 2700.0, stab, law=law))


def _forces(m: Evaluator, u: np.ndarray, intact: np.ndarray | None = None):
    s = m.new_state()
    s.u[...] = u
    if intact is not None:
        s.intact[...] = intact
    m.force_model.prepass(s)
    m.force_model.force(s)
    return s


@pytest.mark.parametrize("rule", ["truncated", "extended", "none"])
@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("stab", STABS)
def test_patch_test_affine_field(stab: str, dim: int, rule: str) -> None:
    cloud, bonds = (
        _plate(nx=17, ny=16, rule=rule) if dim == 2 else _block(n=(12, 12, 12), rule=rule)
    )
    m = _model(cloud, bonds, stab)
    rng = np.random.default_rng(1)
    h = rng.normal(size=(dim, dim)) * 1e-3
    s = _forces(m, cloud.x @ h.T + rng.normal(size=dim) * 1e-6)
    f_grad = s["deformation_gradient"].reshape(-1, dim, dim)
    assert np.abs(f_grad - (np.eye(dim) + h)).max() <= 1e-10 * np.abs(h).max() + 1e-15
    # interior: every neighbour's family is complete (2 horizons from the surface)
    x = cloud.x
    lo, hi = x.min(axis=0), x.max(axis=0)
    depth = np.minimum(x - lo, hi - x).min(axis=1)
    interior = depth >= 2 * bonds.horizon - 1e-12
    assert interior.sum() >= 4
    scale = np.abs(s.force).max()  # the surface forces of the affine field
    assert scale > 0
    assert np.abs(s.force[interior]).max() <= 1e-10 * scale


def _periodic_patch(n: int = 9, delta: float = 3.0) -> tuple[PointCloud, Bonds]:
    """n x n lattice, dx = 1, periodic bonds within delta (inclusive), full volumes."""
    g = np.arange(n, dtype=float)
    x = np.array([(a, b) for a in g for b in g])
    offs = [(a, b) for a in range(-3, 4) for b in range(-3, 4) if 0 < a * a + b * b <= delta**2]
    bi, bj, xi = [], [], []
    for p in range(n * n):
        a0, b0 = divmod(p, n)
        for a, b in offs:
            bi.append(p)
            bj.append(((a0 + a) % n) * n + (b0 + b) % n)
            xi.append((a, b))
    xi_a = np.array(xi, dtype=float)
    nb = len(bi)
    bonds = Bonds(
        offsets=np.arange(0, nb + 1, len(offs), dtype=np.int64),
        bond_i=np.array(bi, dtype=np.int32),
        bond_j=np.array(bj, dtype=np.int32),
        bond_xi=xi_a,
        bond_length=np.linalg.norm(xi_a, axis=1),
        bond_volume=np.ones(nb),
        bond_correction=np.ones(nb),
        bond_intact=np.ones(nb, dtype=np.uint8),
        horizon=delta,
        partial_volume="none",
    )
    cloud = PointCloud(x=x, volume=np.ones(n * n), spacing=1.0, cross_section=1.0, plane="stress")
    return cloud, bonds


def _dense_stiffness(m: Evaluator, h: float = 1e-6) -> np.ndarray:
    """K = -d(V f)/du by central differences, one dof at a time (dense)."""
    n, d = m.n_points, m.dim
    k = np.zeros((n * d, n * d))
    vol = m.cloud.volume
    for col in range(n * d):
        u = np.zeros((n, d))
        u.flat[col] = h
        fp = _forces(m, u).force * vol[:, None]
        u.flat[col] = -h
        fm_ = _forces(m, u).force * vol[:, None]
        k[:, col] = -(fp - fm_).ravel() / (2 * h)
    return k


def test_zero_energy_modes_of_a_periodic_patch() -> None:
    """Periodic patch (docs/theory_correspondence.md; 9 x 9 lattice, E = 1, nu = 0.3,
    plane stress): the plain model has many near-zero non-rigid modes, LBSCMM and the
    default Silling penalty none; the stiffness is symmetric."""
    cloud, bonds = _periodic_patch()
    stats = {}
    for stab in STABS:
        m = Evaluator(cloud, bonds, CorrespondenceMaterial(1.0, 0.3, 1.0, stab))
        k = _dense_stiffness(m)
        asym = np.abs(k - k.T).max() / np.abs(k).max()
        assert asym < 1e-8, (stab, asym)
        ev = np.linalg.eigvalsh(0.5 * (k + k.T))
        assert np.abs(ev[:2]).max() < 1e-8  # the two translations
        assert ev[2] > 1e-8  # no other zero mode on this lattice: the softest is small
        stats[stab] = (ev[2], int(np.sum(ev[2:] < 0.05)), ev[-1])
    low, count, top = stats["none"]
    assert low == pytest.approx(5.0e-4, rel=0.05)
    assert count == 144
    assert top == pytest.approx(0.233, rel=0.01)
    low, count, top = stats["lbscmm"]
    assert low == pytest.approx(0.13119, rel=1e-3)
    assert count == 0
    assert top == pytest.approx(1.0556, rel=1e-3)
    low, count, top = stats["silling2017"]  # the default penalty g = 0.1
    assert count == 0
    assert low == pytest.approx(0.12506, rel=1e-3)
    assert top == pytest.approx(0.30822, rel=1e-3)


def test_degenerate_family_has_no_force_state_and_no_nan() -> None:
    cloud, bonds = _plate(nx=8, ny=8)
    m = _model(cloud, bonds, "lbscmm")
    intact = bonds.bond_intact.copy()
    p = 27
    own = slice(bonds.offsets[p], bonds.offsets[p + 1])
    keep = np.abs(bonds.bond_xi[own, 1]) < 1e-12  # only the bonds along x stay
    intact[own] = keep
    rev = bonds.reverse_index()
    intact[rev[own]] = keep
    s = _forces(m, np.random.default_rng(4).normal(size=cloud.x.shape) * 1e-6, intact)
    assert s["family_active"][p] == 0.0
    assert s["family_active"].sum() == cloud.n_points - 1
    assert np.array_equal(s["deformation_gradient"][p], [1.0, 0.0, 0.0, 1.0])
    assert np.isfinite(s.force).all()
    # everything broken: also fine
    s = _forces(m, np.zeros_like(cloud.x), np.zeros_like(intact))
    assert np.isfinite(s.force).all() and not s.force.any()


def test_principal_stress_criterion_breaks_at_the_tensile_strength() -> None:
    """Uniaxial stress sigma_xx = E eps (linear law, plane stress, nu = 0 so the
    affine field is a uniaxial stress): bonds break where the mean of the two points'
    sigma_1 reaches f_t, not below."""
    from peridynamics.damage.critical_stretch import CriticalStretch
    from peridynamics.damage.principal_stress import CorrespondenceFailure

    cloud, bonds = _plate(nx=10, ny=8)
    f_t = 7e6
    crit = CorrespondenceFailure(CriticalStretch(np.inf), tensile_strength=f_t)
    mat = CorrespondenceMaterial(70e9, 0.0, 2700.0, "lbscmm", 1.0, "linear_elastic")
    m = Evaluator(cloud, bonds, mat, damage=crit)
    for factor, expect in ((0.999, 0), (1.001, bonds.n_bonds)):
        eps = factor * f_t / 70e9
        s = m.new_state()
        s.u[:, 0] = eps * cloud.x[:, 0]
        assert m.damage_law.trial(s) == expect
    s1 = m.force_model.max_principal_stress(s.u, s.intact)
    assert s1 == pytest.approx(1.001 * f_t, rel=1e-9)


@pytest.mark.long
def test_3d_box_in_uniaxial_tension_gives_e_and_nu() -> None:
    """Static linear solve of a correspondence box (direct, finite-difference tangent):
    E and nu from the interior displacement gradient within 2 %."""
    dx = 1e-3
    cloud = box((15 * dx, 7 * dx, 7 * dx), dx)
    bonds = build_bonds(cloud, 2.015 * dx)
    E, nu = 70e9, 0.25
    mat = CorrespondenceMaterial(E, nu, 2700.0, "lbscmm", 1.0, "linear_elastic")
    m = Evaluator(cloud, bonds, mat)
    s = m.new_state()
    k = m.tangent(s).tocsr()
    x = cloud.x
    n, d = x.shape
    strain = 1e-4
    u = np.zeros((n, d))
    fixed = np.zeros((n, d), dtype=bool)
    left = x[:, 0] < 2 * dx
    right = x[:, 0] > x[:, 0].max() - 2 * dx
    fixed[left | right, 0] = True
    length = x[right, 0].mean() - x[left, 0].mean()
    u[right, 0] = strain * length
    c = x.mean(axis=0)
    on_axis = (np.abs(x[:, 1] - c[1]) < 1e-9) & (np.abs(x[:, 2] - c[2]) < 1e-9)
    ends = np.flatnonzero(on_axis & (left | right))
    fixed[ends, 1:] = True
    side = np.flatnonzero(left & (np.abs(x[:, 2] - c[2]) < 1e-9) & (x[:, 1] > c[1] + 2 * dx))
    fixed[side, 2] = True
    fd, fr = np.flatnonzero(~fixed.ravel()), np.flatnonzero(fixed.ravel())
    rhs = -k[fd][:, fr] @ u.ravel()[fr]
    sol = spla.spsolve(k[fd][:, fd].tocsc(), rhs)
    uu = u.ravel().copy()
    uu[fd] = sol
    u = uu.reshape(n, d)
    reaction = (k @ uu).reshape(n, d)[right, 0].sum()  # N applied to the pulled layer
    mid = np.abs(x[:, 0] - c[0]) < 3.5 * dx
    a = np.column_stack([x[mid], np.ones(mid.sum())])
    grad = np.linalg.lstsq(a, u[mid], rcond=None)[0][:3].T  # du_a/dx_b
    e_xx, e_yy, e_zz = np.diag(grad)
    area = 7 * dx * 7 * dx
    E_meas = reaction / area / e_xx
    nu_meas = -0.5 * (e_yy + e_zz) / e_xx
    print(f"3-D box: E {E_meas / E - 1:+.2%}, nu {nu_meas / nu - 1:+.2%}")
    assert E_meas == pytest.approx(E, rel=0.02)
    assert nu_meas == pytest.approx(nu, rel=0.02)
