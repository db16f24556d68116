"""Point clouds, grid generators, regions and mesh import."""

from __future__ import annotations

import warnings

import meshio
import numpy as np
import pytest
from matplotlib.path import Path

from peridynamics.geometry import (
    Ball,
    Box,
    CylinderRegion,
    Everywhere,
    HalfSpace,
    NearestPoint,
    PointCloud,
    Polygon,
    bar,
    box,
    cylinder,
    from_mesh,
    rectangle,
)

RNG = np.random.default_rng(0)
P2 = RNG.uniform(-1, 2, (2000, 2))
P3 = RNG.uniform(-1, 2, (2000, 3))


# -- regions --------------------------------------------------------------------------
def test_box_and_ball_masks_match_their_definitions():
    bx = Box([0.0, 0.2], [1.0, 0.7])
    m = bx(P2)
    assert m.dtype == bool and m.shape == (len(P2),)
    want = (P2[:, 0] >= 0) & (P2[:, 0] <= 1) & (P2[:, 1] >= 0.2) & (P2[:, 1] <= 0.7)
    assert np.array_equal(m, want)
    ball = Ball([0.5, 0.5, 0.5], 0.8)
    assert np.array_equal(ball(P3), np.linalg.norm(P3 - 0.5, axis=1) <= 0.8)
    # inclusive boundaries, half-open slabs with inf
    edge = np.array([[0.0, 0.2], [1.0, 0.7], [1.0 + 1e-9, 0.5], [0.5, 0.5]])
    assert bx(edge).tolist() == [True, True, False, True]
    slab = Box([-np.inf, 0.5], [np.inf, np.inf])
    assert np.array_equal(slab(P2), P2[:, 1] >= 0.5)
    assert Ball([0.0, 0.0], 1.0)(
        np.array([[1.0, 0.0], [0.6, 0.8], [0.0, 1.0 + 1e-9]])
    ).tolist() == [True, True, False]
    with pytest.raises(ValueError):
        Box([1.0, 0.0], [0.0, 1.0])
    with pytest.raises(ValueError):
        Box([0.0, 0.0], [1.0, 1.0])(P3)


def test_region_algebra():
    a = Box([0.0, 0.0], [1.0, 1.0])
    b = Ball([1.0, 1.0], 0.7)
    c = HalfSpace([0.3, 0.0], [1.0, 1.0])
    ma, mb, mc = a(P2), b(P2), c(P2)
    assert np.array_equal((a & b)(P2), ma & mb)
    assert np.array_equal((a | b)(P2), ma | mb)
    assert np.array_equal((~a)(P2), ~ma)
    assert np.array_equal((a & ~b)(P2), ma & ~mb)
    assert np.array_equal((a & b & c)(P2), ma & mb & mc)
    assert np.array_equal((a | b & c)(P2), ma | (mb & mc))
    assert np.array_equal((~(a | b))(P2), ~ma & ~mb)  # De Morgan
    assert np.array_equal((~~a)(P2), ma)
    assert np.all(Everywhere()(P2))
    assert not np.any((a & ~a)(P2))
    # the operands are not modified by combination
    assert np.array_equal(a(P2), ma)


def test_halfspace_nearest_point_and_cylinder():
    hs = HalfSpace([0.5, 0.5, 0.5], [0.0, 0.0, -3.0])  # normal need not be unit
    assert np.array_equal(hs(P3), P3[:, 2] <= 0.5)
    on = np.array([[7.0, -3.0, 0.5]])
    assert hs(on).tolist() == [True]

    loc = np.array([0.3, 0.3])
    m = NearestPoint(loc)(P2)
    assert m.sum() == 1
    assert np.argmax(m) == np.argmin(np.linalg.norm(P2 - loc, axis=1))
    ties = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0]])
    assert NearestPoint([0.0, 0.0])(ties).tolist() == [True, False, False]

    cyl = CylinderRegion([0.0, 0.0, 0.0], [0.0, 0.0, 2.0], radius=0.5, length=1.0)
    want = (np.hypot(P3[:, 0], P3[:, 1]) <= 0.5) & (P3[:, 2] >= 0) & (P3[:, 2] <= 1)
    assert np.array_equal(cyl(P3), want)
    # an oblique axis: compare with projections written out here
    axis = np.array([1.0, 1.0, 0.0]) / np.sqrt(2)
    cyl2 = CylinderRegion([0.1, 0.0, 0.2], [1.0, 1.0, 0.0], radius=0.4, length=1.2)
    d = P3 - [0.1, 0.0, 0.2]
    s = d @ axis
    r = np.linalg.norm(d - s[:, None] * axis, axis=1)
    assert np.array_equal(cyl2(P3), (s >= 0) & (s <= 1.2) & (r <= 0.4))


L_SHAPE = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]


@pytest.mark.parametrize(
    "verts", [L_SHAPE, L_SHAPE[::-1], [(0.1, -0.3), (1.7, 0.2), (0.9, 1.9), (0.6, 0.7)]]
)
def test_polygon_interior_matches_matplotlib(verts):
    poly = Polygon(verts)
    got = poly(P2)
    path = Path(np.asarray(verts, dtype=float))
    # points off the boundary by more than a tiny margin: matplotlib decides
    inside = path.contains_points(P2, radius=1e-9) & path.contains_points(P2, radius=-1e-9)
    outside = ~path.contains_points(P2, radius=1e-9) & ~path.contains_points(P2, radius=-1e-9)
    assert inside.sum() > 100 and outside.sum() > 100
    assert np.all(got[inside]) and not np.any(got[outside])


def test_polygon_points_on_edges_and_vertices_are_inside():
    poly = Polygon(L_SHAPE)
    on = np.array(
        [
            [0.0, 0.0],
            [2.0, 0.0],
            [1.0, 1.0],
            [0.0, 2.0],  # vertices (incl. the reflex one)
            [1.0, 0.0],
            [2.0, 0.5],
            [1.5, 1.0],
            [1.0, 1.5],
            [0.5, 2.0],
            [0.0, 1.0],  # edges
        ]
    )
    assert np.all(poly(on))
    out = np.array(
        [[1.5, 1.5], [2.0 + 1e-6, 0.5], [1.0 + 1e-6, 1.5], [-1e-6, 1.0], [0.5, 2.0 + 1e-6]]
    )
    assert not np.any(poly(out))
    tri = Polygon([(0, 0), (1, 0), (0, 1)])
    hyp = np.column_stack([np.linspace(0, 1, 11), 1 - np.linspace(0, 1, 11)])
    assert np.all(tri(hyp))
    assert not np.any(tri(hyp + 1e-6))
    with pytest.raises(ValueError):
        Polygon([(0, 0), (1, 1)])


# -- generators ------------------------------------------------------------------------
def test_bar_generators():
    c = bar(0.01, 1e-3, area=4e-6, origin=1.0)
    assert c.n_points == 10 and c.dim == 1
    np.testing.assert_allclose(c.x[:, 0], 1.0 + (np.arange(10) + 0.5) * 1e-3, rtol=1e-14)
    np.testing.assert_allclose(c.volume, 4e-9, rtol=1e-14)
    assert c.cross_section == 4e-6 and c.plane is None
    c2 = bar(0.01, 1e-3, nodes_on_boundary=True)
    assert c2.n_points == 11
    np.testing.assert_allclose(c2.x[:, 0], np.arange(11) * 1e-3, atol=1e-15)
    with pytest.warns(UserWarning, match="not a whole multiple"):  # 3 cells, centred
        c3 = bar(0.01, 3e-3)
    np.testing.assert_allclose(c3.x[:, 0], 0.0005 + (np.arange(3) + 0.5) * 3e-3, rtol=1e-14)
    with pytest.raises(ValueError, match="shorter than the spacing"):
        bar(0.002, 3e-3)


def test_rectangle_and_box_grids():
    c = rectangle((0.004, 0.003), 1e-3, thickness=0.002, origin=(1.0, -1.0), plane="strain")
    assert c.n_points == 12 and c.plane == "strain" and c.cross_section == 0.002
    np.testing.assert_allclose(c.volume.sum(), 0.004 * 0.003 * 0.002, rtol=1e-12)
    lo, hi = c.bounds
    np.testing.assert_allclose(lo, [1.0005, -0.9995])
    np.testing.assert_allclose(hi, [1.0035, -0.9975])
    b = box((0.003, 0.002, 0.004), 1e-3)
    assert b.n_points == 24 and b.dim == 3
    np.testing.assert_allclose(b.volume, 1e-9)
    # cell centres are unique
    assert len(np.unique(np.round(b.x / 1e-4).astype(int), axis=0)) == 24


def test_cylinder_keeps_exactly_the_grid_points_inside():
    dx, r, length = 1e-3, 4.3e-3, 5e-3
    c = cylinder(r, length, dx, origin=(0.1, 0.2, 0.0))
    # the cubic grid the cylinder is cut from, rebuilt here
    n_r = int(np.ceil(r / dx))
    ax = (np.arange(2 * n_r) + 0.5) * dx - n_r * dx
    az = (np.arange(5) + 0.5) * dx
    gx, gy, gz = np.meshgrid(ax + 0.1, ax + 0.2, az, indexing="ij")
    g = np.column_stack([gx.ravel(), gy.ravel(), gz.ravel()])
    keep = np.hypot(g[:, 0] - 0.1, g[:, 1] - 0.2) <= r
    assert c.n_points == keep.sum()
    assert {tuple(p) for p in np.round(c.x / 1e-5).astype(int)} == {
        tuple(p) for p in np.round(g[keep] / 1e-5).astype(int)
    }
    np.testing.assert_allclose(c.volume, dx**3)


def test_rectangle_with_hole_and_remove_reindexes_node_sets():
    dx = 1e-3
    hole = Ball([0.005, 0.004], 0.0021)
    full = rectangle((0.010, 0.008), dx)
    holed = rectangle((0.010, 0.008), dx, holes=[hole])
    inside = np.linalg.norm(full.x - [0.005, 0.004], axis=1) <= 0.0021
    assert inside.sum() > 5
    np.testing.assert_array_equal(holed.x, full.x[~inside])
    np.testing.assert_array_equal(holed.volume, full.volume[~inside])

    left = Box([-np.inf, -np.inf], [0.0015, np.inf])
    ring = Ball([0.005, 0.004], 0.0035)
    tagged = full.with_node_sets(left=left, ring=ring, first=[0, 1, 2])
    cut = tagged.remove(hole)
    np.testing.assert_array_equal(cut.x, holed.x)
    for name in ("left", "ring", "first"):
        old = tagged.node_set(name)
        kept = old[~inside[old]]
        got = cut.node_set(name)
        assert np.all(np.diff(got) > 0)
        np.testing.assert_array_equal(cut.x[got], tagged.x[kept])
    assert len(cut.node_set("ring")) < len(tagged.node_set("ring"))
    np.testing.assert_array_equal(cut.node_set("left"), cut.select(left))
    with pytest.raises(KeyError, match="known sets"):
        cut.node_set("nope")
    with pytest.raises(ValueError, match="empty"):
        full.remove(Everywhere())


def test_point_cloud_validation():
    x = np.zeros((3, 2))
    x[:, 0] = [0, 1, 2]
    with pytest.raises(ValueError, match="plane"):
        PointCloud(x=x, volume=np.ones(3), spacing=1.0)
    with pytest.raises(ValueError, match="volume"):
        PointCloud(x=x, volume=np.ones(2), spacing=1.0, plane="stress")
    with pytest.raises(ValueError, match="volume"):
        PointCloud(x=x, volume=[1.0, 0.0, 1.0], spacing=1.0, plane="stress")
    with pytest.raises(ValueError, match="NaN"):
        PointCloud(x=x * np.nan, volume=np.ones(3), spacing=1.0, plane="stress")
    with pytest.raises(ValueError, match="outside"):
        PointCloud(x=x, volume=np.ones(3), spacing=1.0, plane="stress", node_sets={"a": [3]})
    c = PointCloud(x=[0.0, 1.0, 2.0], volume=np.ones(3), spacing=1.0)  # 1-D from a flat list
    assert c.dim == 1 and c.n_points == 3
    with pytest.raises(ValueError):  # frozen arrays
        c.x[0, 0] = 5.0


# -- mesh import -----------------------------------------------------------------------
def _quiet_from_mesh(*args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)  # from other libraries
        return from_mesh(*args, **kwargs)


def test_from_mesh_two_triangles():
    pts = np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0], [0.0, 1.0, 0.0]])
    mesh = meshio.Mesh(
        pts, [("triangle", np.array([[0, 1, 2], [0, 2, 3]])), ("line", np.array([[0, 1]]))]
    )
    c = _quiet_from_mesh(mesh, thickness=0.1)
    assert c.dim == 2 and c.plane == "stress"
    np.testing.assert_allclose(c.x, [[4 / 3, 1 / 3], [2 / 3, 2 / 3]], rtol=1e-14)
    np.testing.assert_allclose(c.volume, [0.1, 0.1], rtol=1e-14)  # area 1 each, h = 0.1
    assert c.spacing == pytest.approx(1.0)  # sqrt(mean area)
    assert c.cross_section == 0.1


def test_from_mesh_parallelogram_quad():
    pts = np.array([[0.0, 0.0], [2.0, 0.0], [2.5, 1.5], [0.5, 1.5]])
    c = _quiet_from_mesh(meshio.Mesh(pts, [("quad", np.array([[0, 1, 2, 3]]))]))
    np.testing.assert_allclose(c.volume, [3.0], rtol=1e-14)  # base 2, height 1.5
    np.testing.assert_allclose(c.x, [[1.25, 0.75]], rtol=1e-14)


def test_from_mesh_trapezoid_quad_centroid():
    pts = np.array([[0.0, 0.0], [2.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    c = _quiet_from_mesh(meshio.Mesh(pts, [("quad", np.array([[0, 1, 2, 3]]))]))
    np.testing.assert_allclose(c.volume, [1.5], rtol=1e-14)
    # unit square (centroid (1/2, 1/2), area 1) + triangle (centroid (4/3, 1/3), area 1/2)
    np.testing.assert_allclose(
        c.x, [[(0.5 + 0.5 * 4 / 3) / 1.5, (0.5 + 0.5 / 3) / 1.5]], rtol=1e-12
    )


def test_from_mesh_tetra_and_hexahedron():
    pts = np.array(
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [3.0, 3.0, 3.0]]
    )
    tet = meshio.Mesh(
        pts,
        [("tetra", np.array([[0, 1, 2, 3], [1, 2, 3, 4]])), ("triangle", np.array([[0, 1, 2]]))],
    )
    c = from_mesh(tet)
    assert c.dim == 3
    np.testing.assert_allclose(c.x, [[0.25, 0.25, 0.25], [1.0, 1.0, 1.0]], rtol=1e-14)
    # second tet: |det([p2-p1, p3-p1, p4-p1])| / 6 = |det([[-1,1,0],[-1,0,1],[2,3,3]])| / 6
    v2 = abs(np.linalg.det(np.array([[-1.0, 1, 0], [-1, 0, 1], [2, 3, 3]]))) / 6
    np.testing.assert_allclose(c.volume, [1 / 6, v2], rtol=1e-13)

    # a sheared brick (parallelepiped) in VTK ordering: volume = |det(edges)|
    a, b, h = np.array([2.0, 0, 0]), np.array([0.5, 1.0, 0]), np.array([0.3, 0.2, 1.5])
    base = [np.zeros(3), a, a + b, b]
    hpts = np.array(base + [p + h for p in base])
    hexm = meshio.Mesh(hpts, [("hexahedron", np.arange(8)[None, :])])
    ch = from_mesh(hexm)
    np.testing.assert_allclose(ch.volume, [abs(np.linalg.det(np.array([a, b, h])))], rtol=1e-13)
    np.testing.assert_allclose(ch.x, [(a + b + h) / 2], rtol=1e-14)
    # asking for the 2-D cloud of a mesh with volume cells uses its area cells
    c2 = _quiet_from_mesh(tet, dim=2)
    assert c2.n_points == 1 and c2.volume[0] == pytest.approx(0.5)
    with pytest.raises(ValueError, match="no"):
        from_mesh(meshio.Mesh(pts, [("line", np.array([[0, 1]]))]))


def test_from_mesh_reads_a_file(tmp_path):
    pts = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    path = tmp_path / "tet.vtu"
    meshio.write(path, meshio.Mesh(pts, [("tetra", np.array([[0, 1, 2, 3]]))]))
    c = from_mesh(path)
    np.testing.assert_allclose(c.volume, [1 / 6], rtol=1e-12)


def test_from_mesh_2d_uses_no_deprecated_numpy():
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)
        from_mesh(meshio.Mesh(pts, [("triangle", np.array([[0, 1, 2]]))]))
