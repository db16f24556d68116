"""Coulomb friction in the short-range pair contact
(peridynamics.evaluation.short_range_contact): Numba ==
brute-force NumPy twin, linear momentum, friction power == work of the friction forces,
stick and slide of one pair, one stopping force shared by several contacts, and the
frictionless path unchanged bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from peridynamics import PointCloud, build_bonds
from peridynamics.bonds.search import brute_force_pairs
from peridynamics.evaluation.short_range_contact import ShortRangeContact
from peridynamics.geometry import bar, box, rectangle
from peridynamics.kernels import short_range_contact as kernels
from peridynamics.kernels.short_range_contact import contact_force_reference
from peridynamics.kernels.short_range_friction import contact_friction_reference

# the long tier (CI: pytest -m long): the friction kernels compile for long cold
pytestmark = pytest.mark.long

DX = 1e-3
CS = 1e20  # N/m^6
MU_S, MU_K = 0.5, 0.3


def make_cloud(dim: int) -> PointCloud:
    if dim == 1:
        return bar(0.03, DX, area=1e-4)
    if dim == 2:
        return rectangle((0.010, 0.008), DX, thickness=1e-3)
    return box((0.005, 0.004, 0.004), DX)


def moving_scene(dim: int, seed: int):
    """Perturbed grid, horizon 1.5 dx, about 30 % of the bonds broken (in both
    directions), random velocities (m/s) and densities (kg/m^3)."""
    cloud = make_cloud(dim)
    bonds = build_bonds(cloud, 1.5 * DX, "truncated")
    rng = np.random.default_rng(seed)
    u = rng.normal(size=cloud.x.shape) * 0.3 * DX + rng.normal(size=dim) * 0.01
    intact = (rng.random(bonds.n_bonds) > 0.3).astype(np.uint8)
    intact = np.minimum(intact, intact[bonds.reverse_index()])
    v = rng.normal(size=u.shape)
    rho = rng.uniform(1000.0, 3000.0, cloud.n_points)
    return cloud, bonds, u, intact, v, rho


def reference(cloud, bonds, u, intact, d_c):
    return contact_force_reference(
        cloud.x, u, cloud.volume, bonds.offsets, bonds.bond_j, intact, d_c, CS
    )


def rel_err(a, b) -> float:
    return float(np.abs(a - b).max() / np.abs(b).max())


@pytest.mark.parametrize("dim", [2, 3])
def test_friction_matches_brute_force_reference_and_conserves_momentum(dim: int) -> None:
    d_c, dt = 1.6 * DX, 1e-7  # both sticking and sliding pairs (checked below)
    for seed in range(2):
        cloud, bonds, u, intact, v, rho = moving_scene(dim, seed)
        contact = ShortRangeContact(cloud.x, cloud.volume, bonds, d_c, CS, None, MU_S, MU_K)
        f = np.zeros_like(u)
        power = contact.add_force_with_friction(u, v, intact, f, rho, dt)
        f_ref, p_ref = contact_friction_reference(
            cloud.x, u, v, cloud.volume, rho, bonds.offsets, bonds.bond_j, intact, d_c, CS,
            MU_S, MU_K, dt,
        )  # fmt: skip
        assert rel_err(f, f_ref) < 1e-12
        assert power == pytest.approx(p_ref, rel=1e-12)
        assert power < 0
        vf = cloud.volume[:, None] * f
        assert np.abs(vf.sum(axis=0)).max() < 1e-14 * np.abs(vf).sum()
        # the power is the work rate of the friction forces, sum V_i F_t,i . v_i
        f_n = reference(cloud, bonds, u, intact, d_c)
        work = float(np.sum(cloud.volume[:, None] * (f - f_n) * v))
        assert power == pytest.approx(work, rel=1e-9)
        # the same through add_force with keywords
        g = np.zeros_like(u)
        assert contact.add_force(u, intact, g, v=v, density=rho, dt=dt) == power
        assert np.array_equal(g, f)
        with pytest.raises(ValueError, match="friction"):
            contact.add_force(u, intact, g)
    # both regimes occurred: stopping force below and above mu_s L for some pairs
    y = cloud.x + u
    pairs = brute_force_pairs(y, d_c)
    e = y[pairs[:, 1]] - y[pairs[:, 0]]
    r = np.linalg.norm(e, axis=1)
    w = v[pairs[:, 0]] - v[pairs[:, 1]]
    vt = w - e * (np.sum(e * w, axis=1) / r**2)[:, None]
    m = rho * cloud.volume
    m_ij = m[pairs[:, 0]] * m[pairs[:, 1]] / (m[pairs[:, 0]] + m[pairs[:, 1]])
    stop = m_ij * np.linalg.norm(vt, axis=1) / dt
    load = cloud.volume[pairs[:, 0]] * cloud.volume[pairs[:, 1]] * CS * (d_c - r) / d_c
    assert np.any(stop < MU_S * load) and np.any(stop > 4 * MU_S * load)


@pytest.mark.parametrize("dim", [1, 2, 3])
def test_frictionless_path_is_the_old_kernel_bit_for_bit(dim: int) -> None:
    """mu = 0 (the default) runs the unchanged frictionless kernel, whatever the entry
    point; in 1-D there is no tangential direction, so friction is off too."""
    d_c = 1.6 * DX
    cloud, bonds, u, intact, v, rho = moving_scene(dim, 3)
    plain = ShortRangeContact(cloud.x, cloud.volume, bonds, d_c, CS)
    plain.rebuild(u)
    f_old = np.zeros_like(u)
    kernels.add_contact_force(
        cloud.x, u, cloud.volume, plain.pair_offsets, plain.pair_j, plain.pair_bond_ij,
        plain.pair_bond_ji, intact, d_c, CS, f_old,
    )  # fmt: skip
    zero = ShortRangeContact(cloud.x, cloud.volume, bonds, d_c, CS, None, 0.0, 0.0)
    variants = [
        lambda c, f: c.add_force(u, intact, f),
        lambda c, f: c.add_force(u, intact, f, v=v, density=rho, dt=1e-7),
        lambda c, f: c.add_force_with_friction(u, v, intact, f, rho, 1e-7),
    ]
    for c in (plain, zero):
        for call in variants:
            f = np.zeros_like(u)
            assert call(c, f) == 0.0
            assert np.array_equal(f, f_old)
    if dim == 1:
        rough = ShortRangeContact(cloud.x, cloud.volume, bonds, d_c, CS, None, MU_S, MU_K)
        assert not rough.has_friction
        f = np.zeros_like(u)
        assert rough.add_force_with_friction(u, v, intact, f, rho, 1e-7) == 0.0
        assert np.array_equal(f, f_old)


def two_points(slip: float):
    """Two unbonded points 0.5 dx apart along x with different volumes and densities,
    pressed together, slipping at ``slip`` (m/s) along y relative to each other."""
    vol = np.array([1.0, 2.0]) * DX * DX * 1e-3
    rho = np.array([1000.0, 3000.0])
    x = np.array([[0.0, 0.0], [DX, 0.0]])
    cloud = PointCloud(x=x, volume=vol, spacing=DX, cross_section=1e-3, plane="stress")
    bonds = build_bonds(cloud, 1.5 * DX)
    contact = ShortRangeContact(x, vol, bonds, 0.9 * DX, CS, None, MU_S, MU_K)
    u = np.array([[0.0, 0.0], [-0.5 * DX, 0.0]])
    v = np.array([[0.2, 0.1 + slip], [-0.1, 0.1]])
    intact = np.zeros(bonds.n_bonds, dtype=np.uint8)
    fn = CS * (0.9 * DX - 0.5 * DX) / (0.9 * DX)  # N/m^6
    m = rho * vol
    return contact, u, v, intact, vol, rho, fn, m[0] * m[1] / (m[0] + m[1])


def test_single_pair_slides_with_kinetic_friction_and_sticks_in_one_step() -> None:
    dt = 1e-7
    contact, u, v, intact, vol, rho, fn, m_red = two_points(0.0)
    limit = MU_S * fn * vol[0] * vol[1] * dt / m_red  # slip at which the stop force = mu_s N
    for frac, sticks in ((1.01, False), (0.99, True), (0.2, True)):
        contact, u, v, intact, vol, rho, fn, m_red = two_points(frac * limit)
        f = np.zeros_like(u)
        power = contact.add_force_with_friction(u, v, intact, f, rho, dt)
        push = fn * vol  # normal force density: i pushed to -x, j to +x
        np.testing.assert_allclose(f[:, 0], [-push[1], push[0]], rtol=1e-12)
        slip = frac * limit
        if sticks:
            t = m_red * slip / dt  # N
            np.testing.assert_allclose(f[:, 1], [-t / vol[0], t / vol[1]], rtol=1e-9)
            v_next = v + dt * f / rho[:, None]  # one explicit step
            assert abs(v_next[0, 1] - v_next[1, 1]) < 1e-12 * slip
            assert power == pytest.approx(-t * slip, rel=1e-9)
        else:
            t = MU_K * fn * vol[0] * vol[1]  # N
            np.testing.assert_allclose(f[:, 1], [-t / vol[0], t / vol[1]], rtol=1e-12)
            assert power == pytest.approx(-t * slip, rel=1e-9)
        assert abs(vol @ f[:, 1]) < 1e-15 * t


def test_several_contacts_do_not_overshoot_the_stick() -> None:
    """A light point resting on three heavy points that move together: sticking, the
    three contacts share one stopping force, so one step brings the slip towards zero
    without reversing it (each taking the whole stopping force would reverse it ~2x)."""
    r0 = 0.6 * DX
    angles = np.radians([-60.0, -90.0, -120.0])
    x = np.vstack([[0.0, 0.0], np.column_stack([r0 * np.cos(angles), r0 * np.sin(angles)])])
    vol = np.full(4, DX * DX * 1e-3)
    rho = np.array([1000.0, 1e9, 1e9, 1e9])
    cloud = PointCloud(x=x, volume=vol, spacing=DX, cross_section=1e-3, plane="stress")
    bonds = build_bonds(cloud, 1.5 * DX)
    intact = ((bonds.bond_i > 0) & (bonds.bond_j > 0)).astype(np.uint8)  # heavy: one body
    u = np.zeros_like(x)
    group = np.array([0.3, -0.2])
    slip = np.array([1e-3, 0.0])
    v = np.vstack([group + slip, np.tile(group, (3, 1))])
    d_c, dt = 0.9 * DX, 1e-7
    rough = ShortRangeContact(x, vol, bonds, d_c, CS, None, MU_S, MU_K)
    f = np.zeros_like(x)
    rough.add_force_with_friction(u, v, intact, f, rho, dt)
    f_t = f - reference(cloud, bonds, u, intact, d_c)
    load = CS * (d_c - r0) / d_c * vol[0] * vol[1:]  # N per contact
    assert np.linalg.norm(f_t[0]) * vol[0] < MU_S * load.sum()  # it sticks
    rel_next = slip + dt * f_t[0] / rho[0]
    assert 0.0 <= rel_next[0] < slip[0]
    assert np.linalg.norm(rel_next) < np.linalg.norm(slip)


def test_friction_arguments() -> None:
    cloud = make_cloud(2)
    bonds = build_bonds(cloud, 1.5 * DX)
    for mu in ((0.2, 0.3), (-0.1, -0.2), (np.inf, 0.1)):
        with pytest.raises(ValueError, match="friction"):
            ShortRangeContact(cloud.x, cloud.volume, bonds, 0.9 * DX, CS, None, *mu)
    c = ShortRangeContact.from_cloud(cloud, bonds, CS, friction_static=0.4, friction_kinetic=0.2)
    assert (c.friction_static, c.friction_kinetic) == (0.4, 0.2)
    u = np.zeros_like(cloud.x)
    intact = bonds.bond_intact.copy()
    with pytest.raises(ValueError, match="dt"):
        c.add_force_with_friction(u, u, intact, u.copy(), 1000.0, 0.0)
