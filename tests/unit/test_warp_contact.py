"""Short-range contact on the Warp device (peridynamics.backends.warp_short_range_contact)
against the host ShortRangeContact, on Warp's CPU device: the same Verlet lists (pairs, row order,
bond indices), the same rebuilds, forces to 1e-12 relative to max |force| (frictionless
and with Coulomb friction), for two blocks pressed together and a plate with broken
bonds whose points come into contact."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("warp", reason="warp-lang not installed (pip install '.[gpu]')")
pytestmark = pytest.mark.gpu  # the Warp tier (pytest -m gpu); the smoke test: test_warp_kernels.py

from peridynamics import BondBasedMaterial, Evaluator, PointCloud, build_bonds  # noqa: E402
from peridynamics.backends.warp_device import DeviceModel, DeviceState  # noqa: E402
from peridynamics.backends.warp_short_range_contact import DeviceContact, supports  # noqa: E402
from peridynamics.evaluation.short_range_contact import ShortRangeContact  # noqa: E402
from peridynamics.geometry import box, rectangle  # noqa: E402

DX = 1e-3
CS = 1e20  # N/m^6
TOL = 1e-12


def blocks(dim: int) -> tuple[PointCloud, int]:
    """Two blocks (6 x 5 in 2-D, 4 x 3 x 3 in 3-D) whose facing layers are dx apart."""
    shape = (6, 5) if dim == 2 else (4, 3, 3)
    axes = [(np.arange(k) + 0.5) * DX for k in shape]
    a = np.column_stack([g.ravel() for g in np.meshgrid(*axes, indexing="ij")])
    shift = np.zeros(dim)
    shift[0] = shape[0] * DX
    x = np.vstack([a, a + shift])
    vol = DX**dim * (1e-3 if dim == 2 else 1.0)
    extra = {"cross_section": 1e-3, "plane": "stress"} if dim == 2 else {}
    cloud = PointCloud(x=x, volume=np.full(len(x), vol), spacing=DX, **extra)
    return cloud, len(a)


def plate(dim: int) -> PointCloud:
    if dim == 2:
        return rectangle((0.008, 0.006), DX, thickness=1e-3)
    return box((0.004, 0.004, 0.003), DX)


class Pair:
    """A host ShortRangeContact and a DeviceContact of the same model."""

    def __init__(self, cloud, bonds, contact, rho=None):
        self.contact = contact
        self.model = Evaluator(cloud, bonds, BondBasedMaterial(70e9, 2700.0), contact=contact)
        if rho is not None:
            self.model.density[:] = rho
        self.dm = DeviceModel(self.model, "cpu")
        self.ds = DeviceState(self.dm, self.model.new_state())
        self.dev = DeviceContact(self.model, self.dm)

    def forces(self, u, intact, f0, v=None, dt=None):
        """(device, host) force after adding the contact to f0."""
        ds = self.ds
        ds.u.assign(u)
        ds.intact.assign(intact)
        ds.force.assign(f0)
        host = f0.copy()
        if v is None:
            self.dev.add(ds)
            self.contact.add_force(u, intact, host)
        else:
            ds.v.assign(v)
            self.model.time_step = dt
            self.dev.add(ds)
            self.host_power = self.contact.add_force(
                u, intact, host, v=v, density=self.model.density, dt=dt
            )
        return ds.force.numpy(), host

    def assert_same_lists(self):
        off, pj, bij, bji = self.dev.lists()
        c = self.contact
        np.testing.assert_array_equal(off, c.pair_offsets)
        np.testing.assert_array_equal(pj, c.pair_j)
        np.testing.assert_array_equal(bij, c.pair_bond_ij)
        np.testing.assert_array_equal(bji, c.pair_bond_ji)
        assert self.dev.n_rebuilds == c.n_rebuilds
        assert self.dev.n_candidate_pairs == c.n_candidate_pairs


def rel_err(dev, host, f0) -> float:
    """Difference relative to the largest contact force density (0 only if equal when
    there is no contact force)."""
    err, scale = np.abs(dev - host).max(), np.abs(host - f0).max()
    if scale == 0:
        return 0.0 if err == 0 else np.inf
    return float(err / scale)


@pytest.mark.parametrize("dim", [2, 3])
def test_blocks_pressed_together_match_host_with_rebuilds(dim: int) -> None:
    """Block B is pushed into block A in steps (the contact distance is reached after a
    few): every step the same lists and forces as the host; a step beyond skin / 2
    rebuilds on both."""
    cloud, na = blocks(dim)
    bonds = build_bonds(cloud, 1.5 * DX, "truncated")
    rng = np.random.default_rng(dim)
    across = (bonds.bond_i < na) != (bonds.bond_j < na)
    intact = (rng.random(bonds.n_bonds) > 0.2).astype(np.uint8)
    intact[across] = 0  # separate bodies, some bonds inside them broken too
    contact = ShortRangeContact(cloud.x, cloud.volume, bonds, 0.9 * DX, CS)
    p = Pair(cloud, bonds, contact)
    u = np.zeros_like(cloud.x)
    f0 = rng.normal(size=u.shape) * 1e9
    worst, in_contact = 0.0, 0
    for _step in range(12):
        u[na:, 0] -= 0.06 * DX  # B moves 0.06 dx a step toward A
        u += rng.normal(size=u.shape) * 0.005 * DX
        dev, host = p.forces(u, intact, f0)
        worst = max(worst, rel_err(dev, host, f0))
        p.assert_same_lists()
        in_contact = contact.n_pairs_in_contact(u, intact)
    assert in_contact > 0  # the blocks are in contact at the end
    assert 2 <= contact.n_rebuilds <= 6  # rebuilt, but not every step
    assert worst <= TOL, worst


@pytest.mark.parametrize("dim", [2, 3])
def test_plate_with_broken_bonds_matches_host(dim: int) -> None:
    """Perturbed plate, 30 % of the bonds broken, d_c = 1.6 dx: many pairs in reach are
    bonded (excluded only while their bond is intact). Small steps (no rebuild), one
    point moved beyond skin / 2 (rebuild), then a large motion (rebuild)."""
    cloud = plate(dim)
    bonds = build_bonds(cloud, 1.5 * DX, "truncated")
    rng = np.random.default_rng(10 + dim)
    u0 = rng.normal(size=cloud.x.shape) * 0.3 * DX
    intact = (rng.random(bonds.n_bonds) > 0.3).astype(np.uint8)
    intact = np.minimum(intact, intact[bonds.reverse_index()])
    d_c = 1.6 * DX
    contact = ShortRangeContact(cloud.x, cloud.volume, bonds, d_c, CS)
    p = Pair(cloud, bonds, contact)
    f0 = np.zeros_like(u0)
    dev, host = p.forces(u0, intact, f0)
    # the bonds matter: without the exclusion the host force would differ
    none = np.zeros_like(intact)
    free = np.zeros_like(u0)
    ShortRangeContact(cloud.x, cloud.volume, bonds, d_c, CS).add_force(u0, none, free)
    assert np.abs(free - host).max() > 0.1 * np.abs(host).max()
    worst = rel_err(dev, host, f0)
    p.assert_same_lists()
    limit = 0.5 * contact.skin
    for _ in range(3):  # every point moves by just under skin / 2: no rebuild
        step = rng.normal(size=u0.shape)
        step *= 0.99 * limit / np.linalg.norm(step, axis=1)[:, None]
        dev, host = p.forces(u0 + step, intact, f0)
        worst = max(worst, rel_err(dev, host, f0))
    assert p.dev.n_rebuilds == contact.n_rebuilds == 1
    u = u0.copy()
    u[5, 0] += 1.01 * limit  # one point beyond skin / 2
    intact[rng.random(bonds.n_bonds) < 0.2] = 0  # more bonds break meanwhile
    dev, host = p.forces(u, intact, f0)
    worst = max(worst, rel_err(dev, host, f0))
    assert p.dev.n_rebuilds == contact.n_rebuilds == 2
    p.assert_same_lists()
    u = u0 + rng.normal(size=u0.shape) * 0.5 * DX  # large motion
    dev, host = p.forces(u, intact, f0)
    worst = max(worst, rel_err(dev, host, f0))
    assert p.dev.n_rebuilds == contact.n_rebuilds == 3
    p.assert_same_lists()
    assert worst <= TOL, worst


@pytest.mark.parametrize("dim", [2, 3])
def test_friction_matches_host(dim: int) -> None:
    cloud = plate(dim)
    bonds = build_bonds(cloud, 1.5 * DX, "truncated")
    rng = np.random.default_rng(20 + dim)
    u = rng.normal(size=cloud.x.shape) * 0.3 * DX
    intact = (rng.random(bonds.n_bonds) > 0.3).astype(np.uint8)
    intact = np.minimum(intact, intact[bonds.reverse_index()])
    v = rng.normal(size=u.shape)
    rho = rng.uniform(1000.0, 3000.0, cloud.n_points)
    contact = ShortRangeContact(
        cloud.x, cloud.volume, bonds, 1.6 * DX, CS, friction_static=0.5, friction_kinetic=0.3
    )
    p = Pair(cloud, bonds, contact, rho)
    f0 = np.zeros_like(u)
    for dt in (1e-7, 1e-9):  # sticking and sliding pairs
        dev, host = p.forces(u, intact, f0, v=v, dt=dt)
        assert rel_err(dev, host, f0) <= TOL
        power = p.dev.friction_power()
        assert power < 0
        assert abs(power - p.host_power) <= TOL * abs(p.host_power)
    frictionless = np.zeros_like(u)
    ShortRangeContact(cloud.x, cloud.volume, bonds, 1.6 * DX, CS).add_force(u, intact, frictionless)
    assert np.abs(dev - frictionless).max() > 1e-3 * np.abs(frictionless).max()


@pytest.mark.parametrize("far", [1e3, 1e12])
def test_far_away_point_and_non_finite_displacements(far: float) -> None:
    cloud = plate(3)
    bonds = build_bonds(cloud, 1.5 * DX, "truncated")
    rng = np.random.default_rng(3)
    u = rng.normal(size=cloud.x.shape) * 0.3 * DX
    u[0] += far
    intact = (rng.random(bonds.n_bonds) > 0.3).astype(np.uint8)
    contact = ShortRangeContact(cloud.x, cloud.volume, bonds, 1.6 * DX, CS)
    p = Pair(cloud, bonds, contact)
    f0 = np.zeros_like(u)
    dev, host = p.forces(u, intact, f0)
    p.assert_same_lists()
    assert rel_err(dev, host, f0) <= TOL
    u[1, 0] = np.nan  # as on the host, a build (not the skin test) rejects it
    p.ds.u.assign(u)
    with pytest.raises(ValueError, match="NaN"):
        contact.rebuild(u)
    with pytest.raises(ValueError, match="NaN"):
        p.dev.rebuild(p.ds.u)


def test_supports() -> None:
    cloud = plate(2)
    bonds = build_bonds(cloud, 1.5 * DX, "truncated")
    model = Evaluator(cloud, bonds, BondBasedMaterial(70e9, 2700.0))
    assert supports(model) is None
    model.contact = object()
    assert "contact" in supports(model)
