"""Short-range contact (peridynamics.evaluation.short_range_contact): Numba kernels ==
brute-force NumPy twin,
force == -grad(energy), intact-bond exclusion, momentum conservation, Verlet-list
rebuilds (also with far-away points) and a 2-D collision of two elastic blocks. The
friction is tested in test_contact_friction.py."""

from __future__ import annotations

import numpy as np
import pytest

from peridynamics import BondBasedMaterial, Evaluator, PointCloud, build_bonds
from peridynamics.bonds.search import brute_force_pairs
from peridynamics.evaluation.short_range_contact import ShortRangeContact
from peridynamics.geometry import bar, box, rectangle
from peridynamics.kernels.short_range_contact import (
    contact_energy_reference,
    contact_force_reference,
)

# the long tier (CI: pytest -m long): the contact kernels compile for half a minute cold
pytestmark = pytest.mark.long

DX = 1e-3
CS = 1e20  # N/m^6


def make_cloud(dim: int) -> PointCloud:
    if dim == 1:
        return bar(0.03, DX, area=1e-4)
    if dim == 2:
        return rectangle((0.010, 0.008), DX, thickness=1e-3)
    return box((0.005, 0.004, 0.004), DX)


def scene(dim: int, seed: int, symmetric: bool = True, noise: float = 0.3):
    """Perturbed grid, horizon 1.5 dx (bonds to the nearest and diagonal neighbours
    only), about 30 % of the bonds broken at random."""
    cloud = make_cloud(dim)
    bonds = build_bonds(cloud, 1.5 * DX, "truncated")
    rng = np.random.default_rng(seed)
    u = rng.normal(size=cloud.x.shape) * noise * DX + rng.normal(size=dim) * 0.01
    intact = (rng.random(bonds.n_bonds) > 0.3).astype(np.uint8)
    if symmetric:  # as the solver keeps them: a bond is broken in both directions
        intact = np.minimum(intact, intact[bonds.reverse_index()])
    return cloud, bonds, u, intact


def reference(cloud, bonds, u, intact, d_c, c_s=CS):
    return contact_force_reference(
        cloud.x, u, cloud.volume, bonds.offsets, bonds.bond_j, intact, d_c, c_s
    )


def numba_force(contact: ShortRangeContact, u, intact):
    f = np.zeros_like(u)
    contact.add_force(u, intact, f)
    return f


def rel_err(a, b) -> float:
    return float(np.abs(a - b).max() / np.abs(b).max())


def contact_categories(cloud, bonds, u, intact, d_c):
    """Numbers of pairs closer than d_c that are joined by an intact bond (either
    direction), by a broken bond only, and never bonded."""
    n = cloud.n_points
    y = cloud.x + u
    close = brute_force_pairs(y, d_c)
    r = np.linalg.norm(y[close[:, 1]] - y[close[:, 0]], axis=1)
    close = close[r < d_c]
    key = bonds.bond_i.astype(np.int64) * n + bonds.bond_j
    k_ij = np.searchsorted(key, close[:, 0] * n + close[:, 1])
    k_ji = np.searchsorted(key, close[:, 1] * n + close[:, 0])
    k_ij = np.minimum(k_ij, len(key) - 1)
    k_ji = np.minimum(k_ji, len(key) - 1)
    bonded = key[k_ij] == close[:, 0] * n + close[:, 1]
    on = bonded & ((intact[k_ij] != 0) | (intact[k_ji] != 0))
    return int(on.sum()), int((bonded & ~on).sum()), int((~bonded).sum())


@pytest.mark.parametrize("dim", [1, 2, 3])
@pytest.mark.parametrize("symmetric", [True, False])
def test_force_matches_brute_force_reference(dim: int, symmetric: bool) -> None:
    d_c = 1.6 * DX  # reaches never-bonded pairs (2 dx apart) of the perturbed grid
    for seed in range(3):
        cloud, bonds, u, intact = scene(dim, seed, symmetric)
        n_on, n_broken, n_free = contact_categories(cloud, bonds, u, intact, d_c)
        assert n_on > 0 and n_broken > 0 and n_free > 0  # every case is exercised
        contact = ShortRangeContact(cloud.x, cloud.volume, bonds, d_c, CS)
        f = numba_force(contact, u, intact)
        assert rel_err(f, reference(cloud, bonds, u, intact, d_c)) < 1e-12
        assert contact.n_pairs_in_contact(u, intact) == n_broken + n_free
        e_ref = contact_energy_reference(
            cloud.x, u, cloud.volume, bonds.offsets, bonds.bond_j, intact, d_c, CS
        )
        assert contact.energy(u, intact) == pytest.approx(e_ref, rel=1e-12)
        # add_force ADDS
        g = np.ones_like(u)
        contact.add_force(u, intact, g)
        np.testing.assert_allclose(g - 1.0, f, rtol=0, atol=1e-12 * np.abs(f).max())


@pytest.mark.parametrize("dim", [2, 3])
def test_force_is_minus_energy_gradient(dim: int) -> None:
    d_c = 1.6 * DX
    cloud, bonds, u, intact = scene(dim, 7)
    contact = ShortRangeContact(cloud.x, cloud.volume, bonds, d_c, CS)
    vf = cloud.volume[:, None] * numba_force(contact, u, intact)  # force on each point (N)
    h = 1e-5 * DX  # round-off and truncation errors both ~1e-10 relative

    def slope(w):  # central difference of the energy along the displacement field w
        return (contact.energy(u + h * w, intact) - contact.energy(u - h * w, intact)) / (2 * h)

    rng = np.random.default_rng(1)
    scale = np.abs(vf).max()
    assert scale > 0
    for _ in range(6):  # random directions: dE/dh = -sum V_i F_i . w_i
        w = rng.normal(size=u.shape)
        assert abs(slope(w) + np.sum(vf * w)) < 1e-8 * np.abs(vf * w).sum()  # meas. 2e-10
    points = rng.choice(np.flatnonzero(np.abs(vf).max(axis=1) > 0), 8, replace=False)
    for i in points:  # single components of points in contact
        for c in range(dim):
            w = np.zeros_like(u)
            w[i, c] = 1.0
            assert abs(slope(w) + vf[i, c]) < 1e-8 * scale  # measured 6e-10
    assert contact.n_rebuilds == 1  # the probes are far below skin / 2


def test_intact_bond_excludes_the_pair_and_breaking_it_switches_contact_on() -> None:
    v = DX * DX * 1e-3
    cloud = PointCloud(
        x=[[0.0, 0.0], [DX, 0.0]], volume=[v, v], spacing=DX, cross_section=1e-3, plane="stress"
    )
    bonds = build_bonds(cloud, 1.5 * DX)
    assert bonds.n_bonds == 2
    d_c = 0.9 * DX
    contact = ShortRangeContact(cloud.x, cloud.volume, bonds, d_c, CS)
    u = np.array([[0.0, 0.0], [-0.5 * DX, 0.0]])  # 0.5 dx apart: well inside d_c
    for flags in ([1, 1], [1, 0], [0, 1]):  # an intact bond in either direction excludes
        intact = np.array(flags, dtype=np.uint8)
        assert not numba_force(contact, u, intact).any()
        assert contact.n_pairs_in_contact(u, intact) == 0
        assert contact.energy(u, intact) == 0.0
    intact = np.zeros(2, dtype=np.uint8)
    f = numba_force(contact, u, intact)
    push = CS * (d_c - 0.5 * DX) / d_c * v  # N/m^3
    np.testing.assert_allclose(f, [[-push, 0.0], [push, 0.0]], rtol=1e-14)
    assert contact.n_pairs_in_contact(u, intact) == 1
    e = v * v * CS * (d_c - 0.5 * DX) ** 2 / (2 * d_c)
    assert contact.energy(u, intact) == pytest.approx(e, rel=1e-14)
    np.testing.assert_allclose(f, reference(cloud, bonds, u, intact, d_c), rtol=1e-14)


@pytest.mark.parametrize("dim", [2, 3])
def test_linear_and_angular_momentum_are_conserved(dim: int) -> None:
    cloud, bonds, u, intact = scene(dim, 3, symmetric=False)
    contact = ShortRangeContact(cloud.x, cloud.volume, bonds, 1.6 * DX, CS)
    vf = cloud.volume[:, None] * numba_force(contact, u, intact)
    scale = np.abs(vf).sum()
    assert scale > 0
    assert np.abs(vf.sum(axis=0)).max() < 1e-14 * scale
    y = cloud.x + u
    if dim == 2:  # z-component of y x (V F)
        torque = y[:, 0] * vf[:, 1] - y[:, 1] * vf[:, 0]
    else:
        torque = np.cross(y, vf)
    lever = (np.linalg.norm(y, axis=1) * np.linalg.norm(vf, axis=1)).sum()
    assert np.abs(torque.sum(axis=0)).max() < 1e-14 * lever


def candidate_pairs(contact: ShortRangeContact) -> set[tuple[int, int]]:
    i = np.repeat(np.arange(contact.x.shape[0]), np.diff(contact.pair_offsets))
    j = contact.pair_j
    assert np.all(np.diff(j.astype(np.int64) + i * contact.x.shape[0]) > 0)  # rows sorted
    return {(a, b) for a, b in zip(i.tolist(), j.tolist(), strict=True) if a < b}


def test_verlet_list_rebuilds_only_when_needed() -> None:
    d_c = 1.6 * DX
    cloud, bonds, u0, intact = scene(2, 11)
    contact = ShortRangeContact(cloud.x, cloud.volume, bonds, d_c, CS)
    assert contact.skin == pytest.approx(0.5 * d_c)
    f = numba_force(contact, u0, intact)
    assert contact.n_rebuilds == 1
    bf = brute_force_pairs(cloud.x + u0, contact.cutoff)
    assert candidate_pairs(contact) == set(map(tuple, bf.tolist()))
    assert contact.n_candidate_pairs == len(bf)
    rng = np.random.default_rng(0)
    limit = 0.5 * contact.skin
    for _ in range(10):  # every point moves by just under skin / 2: no rebuild
        step = rng.normal(size=u0.shape)
        step *= 0.99 * limit / np.linalg.norm(step, axis=1)[:, None]
        u = u0 + step
        f = numba_force(contact, u, intact)
        assert rel_err(f, reference(cloud, bonds, u, intact, d_c)) < 1e-12
    assert contact.n_rebuilds == 1
    u = u0.copy()
    u[5, 0] += 1.01 * limit  # one point beyond skin / 2: rebuild
    numba_force(contact, u, intact)
    assert contact.n_rebuilds == 2
    u = u0 + rng.normal(size=u0.shape) * 0.5 * DX  # large motion: rebuild, still exact
    f = numba_force(contact, u, intact)
    assert contact.n_rebuilds == 3
    assert rel_err(f, reference(cloud, bonds, u, intact, d_c)) < 1e-12
    bf = brute_force_pairs(cloud.x + u, contact.cutoff)
    assert candidate_pairs(contact) == set(map(tuple, bf.tolist()))


@pytest.mark.parametrize("dim", [1, 2, 3])
@pytest.mark.parametrize("far", [1e3, 1e12])
def test_far_away_point_does_not_break_the_search(dim: int, far: float) -> None:
    """A point flown far away makes a huge bounding box: the grid falls back to sparse
    keys (1e3 m) or to larger cells (1e12 m) and stays exact."""
    d_c = 1.6 * DX
    cloud, bonds, u, intact = scene(dim, 5)
    u[0] += far
    contact = ShortRangeContact(cloud.x, cloud.volume, bonds, d_c, CS)
    f = numba_force(contact, u, intact)
    assert rel_err(f, reference(cloud, bonds, u, intact, d_c)) < 1e-12
    bf = brute_force_pairs(cloud.x + u, contact.cutoff)
    assert candidate_pairs(contact) == set(map(tuple, bf.tolist()))


def test_arguments_and_defaults() -> None:
    cloud = make_cloud(2)
    bonds = build_bonds(cloud, 3.015 * DX)
    for kw, name in (
        ({"contact_distance": 0.0}, "contact_distance"),
        ({"contact_distance": np.nan}, "contact_distance"),
        ({"stiffness": -1.0}, "stiffness"),
        ({"skin": 0.0}, "skin"),
    ):
        args = {"contact_distance": 0.9 * DX, "stiffness": CS, "skin": None} | kw
        with pytest.raises(ValueError, match=name):
            ShortRangeContact(cloud.x, cloud.volume, bonds, **args)
    contact = ShortRangeContact.from_cloud(cloud, bonds, CS)
    assert contact.contact_distance == pytest.approx(0.9 * DX)
    assert ShortRangeContact.parks_stiffness(2.0, 0.9, 3.0) == pytest.approx(15 * 2 * 0.3)
    # the undeformed grid is force-free even with every bond broken (d_c < spacing)
    broken = np.zeros(bonds.n_bonds, dtype=np.uint8)
    u = np.zeros_like(cloud.x)
    assert not numba_force(contact, u, broken).any()
    with pytest.raises(ValueError, match="intact"):
        contact.add_force(u, broken[:-1], np.zeros_like(u))
    with pytest.raises(ValueError, match="NaN"):
        contact.rebuild(np.full_like(u, np.nan))


@pytest.mark.long
def test_two_blocks_collide_and_bounce_back_elastically() -> None:
    """Two 6 x 6 elastic blocks, every bond between them broken, fly at each other
    (+-v0): the contact keeps them apart, they bounce back, momentum is conserved and the
    collision is nearly elastic. Without contact they pass through each other."""
    E, rho, h, delta = 70e9, 2700.0, 1e-3, 3.015 * DX
    g = (np.arange(6) + 0.5) * DX
    gx, gy = np.meshgrid(g, g, indexing="ij")
    a = np.column_stack([gx.ravel(), gy.ravel()])
    x = np.vstack([a, a + [5 * DX + 1.5 * DX, 0.0]])  # facing rows 1.5 dx apart
    na = len(a)
    cloud = PointCloud(
        x=x, volume=np.full(len(x), DX * DX * h), spacing=DX, cross_section=h, plane="stress"
    )
    bonds = build_bonds(cloud, delta)
    across = (bonds.bond_i < na) != (bonds.bond_j < na)
    assert across.any()
    intact0 = bonds.bond_intact.copy()
    intact0[across] = 0  # two separate bodies
    material = BondBasedMaterial(E, rho)
    model = Evaluator(cloud, bonds, material)
    d_c = 0.9 * DX
    # a soft contact (0.3 c): contact time long against the blocks' vibration period,
    # so little energy goes into vibrations (15 c d_c / delta gives restitution ~0.87)
    c_s = 0.3 * material.micromodulus_constant(2, delta, h, "stress")
    contact = ShortRangeContact(cloud.x, cloud.volume, bonds, d_c, c_s)
    mass = rho * cloud.volume
    v0 = 50.0
    p_block = mass[:na].sum() * v0
    dt = 0.3 * model.stable_time_step()

    def simulate(with_contact: bool, n_steps: int = 3000):
        u = np.zeros_like(x)
        v = np.zeros_like(x)
        v[:na, 0], v[na:, 0] = v0, -v0
        intact = intact0.copy()
        f = np.zeros_like(x)
        smax = np.zeros(len(x))

        def accel():
            model.internal_force(u, intact, f, smax)
            if with_contact:
                contact.add_force(u, intact, f)
            return f / rho

        acc = accel()
        e0 = model.kinetic_energy(v)
        out = {"dmin": np.inf, "overlap": False, "p": 0.0, "e_err": 0.0, "ref_err": 0.0}
        touched, step = False, 0
        while step < n_steps:
            v += 0.5 * dt * acc
            u += dt * v
            acc = accel()
            v += 0.5 * dt * acc
            step += 1
            y = x + u
            d = np.sqrt(((y[:na, None, :] - y[None, na:, :]) ** 2).sum(-1)).min()
            out["dmin"] = min(out["dmin"], d)
            out["overlap"] |= bool(y[:na, 0].max() >= y[na:, 0].min())
            out["p"] = max(out["p"], np.abs((mass[:, None] * v).sum(axis=0)).max())
            touched |= d < d_c
            if with_contact and (step % 10 == 0 or d < d_c and step % 5 == 0):
                e = model.kinetic_energy(v) + model.strain_energy(u, intact)
                e += contact.energy(u, intact)
                out["e_err"] = max(out["e_err"], abs(e - e0) / e0)
                if d < d_c:
                    fc = numba_force(contact, u, intact)
                    f_ref = reference(cloud, bonds, u, intact, d_c, c_s)
                    out["ref_err"] = max(out["ref_err"], rel_err(fc, f_ref))
            if with_contact and touched and d > 2 * d_c:
                break  # separated again
        out["steps"] = step
        out["ke_ratio"] = model.kinetic_energy(v) / e0
        out["restitution"] = -(mass[:na] @ v[:na, 0]) / mass[:na].sum() / v0
        return out

    res = simulate(True)
    # measured: 309 steps, dmin 0.81 d_c, |p| 8e-16 p_block, energy drift 2.3e-4,
    # restitution 0.987, KE ratio 0.989, 3 rebuilds
    assert res["steps"] < 3000  # they did bounce back apart
    assert not res["overlap"]
    assert res["dmin"] > 0.5 * d_c
    assert res["p"] < 1e-12 * p_block
    assert res["ref_err"] < 1e-12
    assert res["e_err"] < 5e-3  # KE + strain + contact energy
    assert 0.97 < res["restitution"] < 1.0
    assert 0.97 < res["ke_ratio"] < 1.01
    assert 1 < contact.n_rebuilds < res["steps"] // 10
    # control: the same flight without contact interpenetrates (measured dmin 0.003 d_c)
    ghost = simulate(False, res["steps"])
    assert ghost["overlap"] and ghost["dmin"] < 0.5 * d_c
