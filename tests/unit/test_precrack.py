"""Pre-cracks cut exactly the bonds that cross them (independent brute force)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from peridynamics import BondBasedMaterial, Evaluator, build_bonds
from peridynamics.bonds import RectangleCrack, SegmentCrack, make_crack
from peridynamics.geometry import box, rectangle
from peridynamics.kernels import reference

DX = 1e-3
DELTA = 3.015 * DX
DAMAGED = 0.0  # phi above this counts as damaged (intact families give exactly 0)


def segments_cross(a, b, p, q):
    """Proper crossing of segments a-b (n, 2) with p-q, by orientation signs.

    Crack end points are chosen off the grid lines so that no bond touches them.
    """

    def orient(o, s, t):
        return (s[..., 0] - o[..., 0]) * (t[..., 1] - o[..., 1]) - (s[..., 1] - o[..., 1]) * (
            t[..., 0] - o[..., 0]
        )

    p = np.broadcast_to(p, a.shape)
    q = np.broadcast_to(q, a.shape)
    return (orient(p, q, a) * orient(p, q, b) < 0) & (orient(a, b, p) * orient(a, b, q) < 0)


def point_segment_distance(x, p, q):
    d = q - p
    t = np.clip((x - p) @ d / (d @ d), 0.0, 1.0)
    return np.linalg.norm(x - (p + t[:, None] * d), axis=1)


CRACKS_2D = {
    # edge crack between two grid rows, tip at a generic x
    "edge": ((-0.001, 0.010), (0.00837, 0.010)),
    # inclined interior crack with generic end points
    "inclined": ((0.00521, 0.00313), (0.01433, 0.01671)),
}


@pytest.mark.parametrize("name", sorted(CRACKS_2D))
def test_segment_crack_cuts_exactly_crossing_bonds(name):
    p, q = (np.array(v) for v in CRACKS_2D[name])
    cloud = rectangle((0.02, 0.02), DX)
    crack = make_crack([p, q])
    assert isinstance(crack, SegmentCrack)
    b = build_bonds(cloud, DELTA, cracks=[crack])
    xa, xb = cloud.x[b.bond_i], cloud.x[b.bond_j]
    expected_cut = segments_cross(xa, xb, p, q)
    assert expected_cut.sum() > 50
    assert np.array_equal(b.bond_intact == 0, expected_cut)
    # same thing through Bonds.cut on an uncut list
    b0 = build_bonds(cloud, DELTA)
    assert np.array_equal(b0.cut(cloud.x, [crack]).bond_intact, b.bond_intact)
    assert np.all(b0.bond_intact == 1)  # frozen: cut() returned a copy
    # symmetric
    rev = b.reverse_index()
    assert np.array_equal(b.bond_intact, b.bond_intact[rev])

    # damage is positive exactly at points owning a cut bond, all within delta of the crack
    model = Evaluator(cloud, b, BondBasedMaterial(70e9, 2700.0))
    phi = model.point_damage(b.bond_intact)
    phi_ref = reference.damage(b.bond_i, b.bond_volume, b.bond_intact, cloud.n_points)
    np.testing.assert_allclose(phi, phi_ref, rtol=1e-12, atol=1e-15)
    owners = np.zeros(cloud.n_points, bool)
    owners[b.bond_i[expected_cut]] = True
    assert np.array_equal(phi > DAMAGED, owners)
    dist = point_segment_distance(cloud.x, p, q)
    assert np.all(dist[phi > DAMAGED] <= DELTA)
    assert np.all(phi[dist > DELTA] == 0.0)
    # the two points nearest to the middle of the crack lose a good part of their family,
    # but never more than half (for each bond xi, at most one of xi and -xi crosses)
    mid = 0.5 * (p + q)
    near = np.argsort(np.linalg.norm(cloud.x - mid, axis=1))[:2]
    assert np.all(phi[near] > 0.2)
    assert np.all(phi <= 0.5 + 1e-12)


def test_segment_crack_tip_touch_counts_as_crossing():
    crack = SegmentCrack((0.0, 0.0), (1.0, 0.0))
    a = np.array([[1.0, -1.0], [1.0 + 1e-9, -1.0], [0.5, 0.1], [0.5, -1.0]])
    b = np.array([[1.0, 1.0], [1.0 + 1e-9, 1.0], [0.5, 1.0], [0.5, 1.0]])
    assert crack.crosses(a, b).tolist() == [True, False, False, True]


def _rect_brute_force(xa, xb, p0, ea, eb):
    nrm = np.cross(ea, eb)
    da = (xa - p0) @ nrm
    db = (xb - p0) @ nrm
    straddle = da * db < 0
    t = np.divide(da, da - db, out=np.zeros_like(da), where=straddle)
    hit = xa + t[:, None] * (xb - xa)
    ca = (hit - p0) @ ea / (ea @ ea)  # edges are perpendicular
    cb = (hit - p0) @ eb / (eb @ eb)
    return straddle & (ca > 0) & (ca < 1) & (cb > 0) & (cb < 1)


RECTS_3D = {
    # plane z = 4 dx (between layers), generic in-plane extent, reaching out of the box
    "flat": ((-0.001, 0.00113, 0.004), (0.00537, 0, 0), (0, 0.00578, 0)),
    # tilted by 30 degrees about x, through the box centre
    "tilted": (
        (0.00071, 0.00143, 0.00531),
        (0.0061, 0, 0),
        (0, 0.0052 * np.cos(np.pi / 6), -0.0052 * np.sin(np.pi / 6)),
    ),
}


@pytest.mark.parametrize("name", sorted(RECTS_3D))
def test_rectangle_crack_cuts_exactly_crossing_bonds(name):
    p0, ea, eb = (np.array(v, dtype=float) for v in RECTS_3D[name])
    cloud = box((0.008, 0.008, 0.008), DX)
    crack = make_crack([p0, p0 + ea, p0 + eb])
    assert isinstance(crack, RectangleCrack)
    b = build_bonds(cloud, DELTA, cracks=[crack])
    expected = _rect_brute_force(cloud.x[b.bond_i], cloud.x[b.bond_j], p0, ea, eb)
    assert expected.sum() > 100
    assert np.array_equal(b.bond_intact == 0, expected)
    rev = b.reverse_index()
    assert np.array_equal(b.bond_intact, b.bond_intact[rev])
    model = Evaluator(cloud, b, BondBasedMaterial(70e9, 2700.0))
    phi = model.point_damage(b.bond_intact)
    owners = np.bincount(b.bond_i, expected, cloud.n_points) > 0
    assert np.array_equal(phi > DAMAGED, owners)
    # damaged points lie within a horizon of the crack plane
    nrm = np.cross(ea, eb) / np.linalg.norm(np.cross(ea, eb))
    assert np.all(np.abs((cloud.x[phi > DAMAGED] - p0) @ nrm) <= DELTA)


def test_two_cracks_union():
    cloud = rectangle((0.02, 0.02), DX)
    c1 = make_crack([(0.0021, 0.005), (0.0113, 0.005)])
    c2 = make_crack([(0.0151, 0.0031), (0.0151 + 1e-7, 0.0173)])
    b1 = build_bonds(cloud, DELTA, cracks=[c1])
    b2 = build_bonds(cloud, DELTA, cracks=[c2])
    b12 = build_bonds(cloud, DELTA, cracks=[c1, c2])
    assert np.array_equal(b12.bond_intact, b1.bond_intact & b2.bond_intact)


def test_make_crack_validation():
    with pytest.raises(ValueError, match="perpendicular"):
        make_crack([(0, 0, 0), (1, 0, 0), (1, 1, 0)])
    with pytest.raises(ValueError):
        make_crack([(0, 0), (1, 0), (0, 1)])
    with pytest.raises(ValueError):
        make_crack([(0, 0, 0), (1, 0, 0)])


def test_rectangle_crack_emits_no_runtime_warning():
    cloud = box((0.006, 0.006, 0.006), DX)
    p0, ea, eb = (np.array(v, dtype=float) for v in RECTS_3D["tilted"])
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        build_bonds(cloud, DELTA, cracks=[make_crack([p0, p0 + ea, p0 + eb])])
