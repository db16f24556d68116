"""Geometry from files: closed surfaces filled with the grid (trimesh), Gmsh models with
physical groups (gmsh), images by grey level (Pillow), mesh groups (meshio); the deck
keys, their checks and the bodies a phase makes."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import meshio
import numpy as np
import pytest

from peridynamics.build.errors import SetupError
from peridynamics.geometry.image_phases import Phase, from_image
from peridynamics.geometry.mesh_groups import from_mesh_groups

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "geometry"


# ------------------------------------------------------------------ surfaces (trimesh)
def test_filled_sphere_volume_within_one_percent(tmp_path: Path) -> None:
    """An icosphere of radius 50 mm (20 480 faces, 0.05 % below the round sphere) filled
    at dx = 2.5 mm (r / dx = 20): the points' volume within 1 % of 4/3 pi r^3."""
    trimesh = pytest.importorskip("trimesh")
    from peridynamics.geometry.surface_fill import fill_surface

    r = 0.05
    trimesh.creation.icosphere(subdivisions=5, radius=r).export(tmp_path / "s.stl")
    cloud = fill_surface(tmp_path / "s.stl", 2.5e-3)
    exact = 4.0 / 3.0 * math.pi * r**3
    assert cloud.volume.sum() == pytest.approx(exact, rel=0.01)
    assert np.all(np.linalg.norm(cloud.x, axis=1) < r)
    assert cloud.dim == 3 and np.allclose(cloud.volume, 2.5e-3**3)


def test_box_fill_is_the_box_grid_and_scale_is_metres_per_unit(tmp_path: Path) -> None:
    """A box in mm whose faces are split along diagonals through lattice columns: every
    cell centre once (the offset columns), at the box generator's positions."""
    trimesh = pytest.importorskip("trimesh")
    from peridynamics.geometry import box
    from peridynamics.geometry.surface_fill import fill_surface

    b = trimesh.creation.box(extents=(20.0, 10.0, 30.0))
    b.apply_translation([10.0, 5.0, 15.0])
    b.export(tmp_path / "b.obj")
    cloud = fill_surface(tmp_path / "b.obj", 1e-3, scale=1e-3)
    ref = box((0.02, 0.01, 0.03), 1e-3)
    assert cloud.n_points == ref.n_points == 6000
    order = np.lexsort(cloud.x.T[::-1])
    ref_order = np.lexsort(ref.x.T[::-1])
    np.testing.assert_allclose(cloud.x[order], ref.x[ref_order], atol=1e-12)


def test_hollow_shells_and_ply(tmp_path: Path) -> None:
    """A tube (a hole through it) written as PLY: no point in the hole."""
    trimesh = pytest.importorskip("trimesh")
    from peridynamics.geometry.surface_fill import fill_surface

    trimesh.creation.annulus(0.005, 0.01, height=0.02, sections=64).export(tmp_path / "t.ply")
    cloud = fill_surface(tmp_path / "t.ply", 5e-4)
    rho = np.hypot(cloud.x[:, 0], cloud.x[:, 1])
    assert rho.min() > 0.005 and rho.max() < 0.01
    ring = math.pi * (0.01**2 - 0.005**2) * 0.02
    assert cloud.volume.sum() == pytest.approx(ring, rel=0.02)


def test_open_surface_is_an_error_naming_the_file(tmp_path: Path) -> None:
    trimesh = pytest.importorskip("trimesh")
    from peridynamics.geometry.surface_fill import fill_surface

    m = trimesh.creation.icosphere(subdivisions=2)
    m.update_faces(np.arange(len(m.faces)) > 0)  # one triangle less: a hole
    m.export(tmp_path / "open.stl")
    with pytest.raises(ValueError, match=r"open\.stl.*not closed \(watertight\)"):
        fill_surface(tmp_path / "open.stl", 0.1)


def test_missing_trimesh_names_the_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    from peridynamics.geometry.surface_fill import load_surface

    monkeypatch.setitem(sys.modules, "trimesh", None)
    with pytest.raises(ValueError, match=r'pip install "peridynamics\[geometry\]"'):
        load_surface("any.stl")


# ------------------------------------------------------------------------- gmsh models
GEO_2D = """SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 40, 20};
Rectangle(2) = {40, 0, 0, 20, 20};
Disk(3) = {20, 10, 0, 5};
BooleanFragments{ Surface{1, 2, 3}; Delete; }{}
"""


def _mesh_geo(tmp_path: Path, geo: Path, size: float, dim: int) -> Path:
    """The model meshed by gmsh at element size ``size`` and written as a .msh."""
    gmsh = pytest.importorskip("gmsh")
    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(geo))
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        gmsh.model.mesh.generate(dim)
        out = tmp_path / "model.msh"
        gmsh.write(str(out))
    finally:
        gmsh.finalize()
    return out


def _group_nodes(msh: Path) -> dict[str, np.ndarray]:
    """Coordinates (n, 3) of the mesh nodes gmsh lists for every lower-dimensional
    physical group of ``msh``."""
    gmsh = pytest.importorskip("gmsh")
    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(msh))
        dim = gmsh.model.getDimension()
        out = {}
        for d, tag in gmsh.model.getPhysicalGroups():
            if d < dim:
                _, xyz = gmsh.model.mesh.getNodesForPhysicalGroup(d, tag)
                out[gmsh.model.getPhysicalName(d, tag)] = np.reshape(xyz, (-1, 3))
    finally:
        gmsh.finalize()
    return out


def test_gmsh_part_volume_and_node_sets_equal_gmsh_node_lists(tmp_path: Path) -> None:
    """examples/geometry/part.geo (a plate with a hole, CAD volume 7214.60 mm^3) meshed
    at 2 mm: the points' volume within 1 % of the CAD value; each face group is the set
    of points nearest to gmsh's nodes of that group (brute force here)."""
    pytest.importorskip("gmsh")
    from peridynamics.geometry.gmsh_model import from_gmsh

    msh = _mesh_geo(tmp_path, EXAMPLES / "part.geo", 2.0, 3)
    cloud = from_gmsh(msh, 1e-3, scale=1e-3)
    cad = (40 * 20 * 10 - math.pi * 5**2 * 10) * 1e-9
    assert cloud.volume.sum() == pytest.approx(cad, rel=0.01)
    assert cloud.node_sets["part"].size == cloud.n_points
    for name, xyz in _group_nodes(msh).items():
        d2 = ((xyz[:, None, :] * 1e-3 - cloud.x[None, :, :]) ** 2).sum(-1)
        expected = np.unique(np.argmin(d2, axis=1))
        np.testing.assert_array_equal(cloud.node_sets[name], expected)
    assert set(cloud.node_sets) == {"part", "left", "right"}


def test_gmsh_geo_is_meshed_at_the_spacing_and_groups_can_be_chosen(tmp_path: Path) -> None:
    pytest.importorskip("gmsh")
    from peridynamics.geometry.gmsh_model import from_gmsh

    cloud = from_gmsh(EXAMPLES / "part.geo", 2e-3, scale=1e-3, groups=["left"])
    cad = (40 * 20 * 10 - math.pi * 5**2 * 10) * 1e-9
    assert cloud.volume.sum() == pytest.approx(cad, rel=0.01)
    assert 0.3 < cad / cloud.n_points / (2e-3) ** 3 < 3.0  # cells of about dx^3
    assert set(cloud.node_sets) == {"left"}
    with pytest.raises(ValueError, match=r"no physical group 'nope'.*'left'"):
        from_gmsh(EXAMPLES / "part.geo", 2e-3, scale=1e-3, groups=["nope"])


def test_gmsh_2d_surfaces_partition_the_points(tmp_path: Path) -> None:
    """A 2-D model of three fragments, physical surfaces "matrix" (two) and "disc", a
    physical curve: the surface groups partition the points, areas within 1 %."""
    pytest.importorskip("gmsh")
    from peridynamics.geometry.gmsh_model import from_gmsh

    geo = tmp_path / "plate.geo"
    geo.write_text(
        GEO_2D
        + "d() = Surface In BoundingBox{14.9, 4.9, -1, 25.1, 15.1, 1};\n"
        + "m() = Surface{:};\nm() -= d();\n"
        + 'Physical Surface("disc") = {d()};\nPhysical Surface("matrix") = {m()};\n'
        + 'Physical Curve("left") = {Curve In BoundingBox{-1e-6, -1, -1, 1e-6, 21, 1}};\n'
    )
    cloud = from_gmsh(geo, 0.5, thickness=0.01)  # edges of 0.76: the disc 0.4 % short
    assert cloud.dim == 2 and cloud.plane == "stress"
    disc, matrix = cloud.node_sets["disc"], cloud.node_sets["matrix"]
    assert len(np.intersect1d(disc, matrix)) == 0 and len(disc) + len(matrix) == cloud.n_points
    assert cloud.volume[disc].sum() == pytest.approx(math.pi * 25 * 0.01, rel=0.01)
    assert cloud.volume.sum() == pytest.approx(60 * 20 * 0.01, rel=1e-9)
    assert np.all(cloud.x[cloud.node_sets["left"], 0] < 2.0)


# ---------------------------------------------------------------------------- images
def _png(tmp_path: Path, grey: np.ndarray) -> Path:
    from PIL import Image

    path = tmp_path / "img.png"
    Image.fromarray(grey.astype(np.uint8), mode="L").save(path)
    return path


def test_image_phases_become_node_sets_and_pores_go(tmp_path: Path) -> None:
    """A 10 x 4 pixel image: left half aggregate (200), right half mortar (120), one
    pore pixel (0); at dx = pixel size one point per pixel, the first row at the top."""
    g = np.full((4, 10), 120)
    g[:, :5] = 200
    g[0, 9] = 0  # top-right pixel
    phases = [Phase("aggregate", 0.6, 1.0), Phase("mortar", 0.3, 0.6), Phase("pore", 0, 0.1, True)]
    cloud = from_image(_png(tmp_path, g), 1e-3, 1e-3, phases, thickness=0.01)
    assert cloud.n_points == 39
    assert len(cloud.node_sets["aggregate"]) == 20 and len(cloud.node_sets["mortar"]) == 19
    assert "pore" not in cloud.node_sets
    xa = cloud.x[cloud.node_sets["aggregate"]]
    assert xa[:, 0].max() < 5e-3
    assert not np.any(np.all(np.isclose(cloud.x, [9.5e-3, 3.5e-3]), axis=1))  # the pore
    half = from_image(_png(tmp_path, g), 1e-3, 2e-3, phases)  # coarser grid samples
    assert half.n_points == 9 and np.allclose(half.volume, 4e-6)  # (9, 3) mm: the pore


def test_image_grey_in_no_phase_is_an_error(tmp_path: Path) -> None:
    path = _png(tmp_path, np.full((3, 3), 128))
    with pytest.raises(ValueError, match=r"grey levels 0\.502 \.\. 0\.502 in no phase"):
        from_image(path, 1e-3, 1e-3, [Phase("a", 0.6, 1.0)])


# ----------------------------------------------------------------------- mesh groups
def _two_blocks() -> meshio.Mesh:
    """Two unit squares of two triangles each (blocks), an element set and a node set."""
    pts = np.array([[0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]], dtype=float)
    a = np.array([[0, 1, 4], [0, 4, 3]])
    b = np.array([[1, 2, 5], [1, 5, 4]])
    return meshio.Mesh(
        pts, [("triangle", a), ("triangle", b)],
        cell_sets={"right": [np.array([], dtype=int), np.array([0, 1])]},
        point_sets={"edge": np.array([2, 5])},
    )  # fmt: skip


def test_abaqus_blocks_element_sets_and_node_sets(tmp_path: Path) -> None:
    path = tmp_path / "m.inp"
    meshio.write(path, _two_blocks())
    cloud = from_mesh_groups(path, dim=2, spacing=0.5)
    assert cloud.n_points == 4
    assert set(cloud.node_sets) >= {"right", "edge"}
    np.testing.assert_array_equal(cloud.node_sets["right"], [2, 3])
    assert np.all(cloud.x[cloud.node_sets["edge"], 0] > 1.0)
    with pytest.raises(ValueError, match=r"no group 'nope'"):
        from_mesh_groups(path, dim=2, spacing=0.5, groups=["nope"])


def test_exodus_blocks_and_node_sets(tmp_path: Path) -> None:
    pytest.importorskip("netCDF4")
    path = tmp_path / "m.exo"
    mesh = _two_blocks()
    mesh.points = np.column_stack([mesh.points, np.zeros(len(mesh.points))])
    mesh.cell_sets = {}
    meshio.write(path, mesh)
    cloud = from_mesh_groups(path, dim=2, spacing=0.5)
    np.testing.assert_array_equal(cloud.node_sets["block_1"], [0, 1])
    np.testing.assert_array_equal(cloud.node_sets["block_2"], [2, 3])
    assert np.all(cloud.x[cloud.node_sets["edge"], 0] > 1.0)


# ----------------------------------------------------------------------------- decks
def _concrete_deck(tmp_path: Path, **extra: object) -> dict:
    g = np.full((20, 40), 120)
    g[5:15, 5:15] = 200
    g[2, 30] = 0
    _png(tmp_path, g)
    deck = {
        "name": "img",
        "geometry": {
            "type": "image", "file": "img.png", "pixel_size": 1e-3, "thickness": 0.01,
            "phases": [{"name": "aggregate", "grey": [0.6, 1.0]},
                       {"name": "mortar", "grey": [0.25, 0.6]},
                       {"name": "pores", "grey": [0.0, 0.25], "remove": True}],
        },
        "discretisation": {"spacing": 1e-3, "horizon_factor": 3.015},
        "material": {"youngs_modulus": 25e9, "density": 2100.0},
        "bodies": [{"name": "stones", "region": {"set": "aggregate"},
                    "material": {"youngs_modulus": 60e9, "density": 2700.0}}],
        "boundary_conditions": [{"type": "fixed", "set": "mortar", "components": ["x"]}],
        "solver": {"type": "explicit", "steps": 2},
    }  # fmt: skip
    deck.update(extra)
    return deck


def test_image_deck_phase_becomes_a_body(tmp_path: Path) -> None:
    """A body whose region is an image phase: its own material, the phase sets kept
    through the reordering of the points, the size estimated from the image."""
    from peridynamics.build.cloud import build_cloud
    from peridynamics.build.estimates import estimate_size
    from peridynamics.deck import parse_deck

    deck = parse_deck(_concrete_deck(tmp_path), base_dir=tmp_path)
    assert Path(deck.geometry.file).is_absolute()
    est = estimate_size(deck)
    assert est is not None and est.points == 800
    cloud = build_cloud(deck)
    assert cloud.n_points == 799
    np.testing.assert_array_equal(cloud.node_sets["stones"], cloud.node_sets["aggregate"])
    assert len(cloud.node_sets["stones"]) == 100
    assert len(cloud.node_sets["mortar"]) == 699
    assert cloud.node_sets["stones"][0] == 699  # the body after main


def test_deck_checks_of_file_geometries(tmp_path: Path) -> None:
    from peridynamics.deck import DeckError, parse_deck

    bad = _concrete_deck(tmp_path)
    bad["boundary_conditions"][0]["set"] = "pores"  # removed: not a node set
    with pytest.raises(DeckError, match="unknown node set 'pores'"):
        parse_deck(bad, base_dir=tmp_path)
    ref = _concrete_deck(tmp_path, node_sets={"stone_top": {"set": "aggregate"}})
    parse_deck(ref, base_dir=tmp_path)  # a deck node set may name the geometry's sets
    missing = _concrete_deck(tmp_path)
    missing["geometry"]["file"] = "none.png"
    with pytest.raises(DeckError, match=r"image file .*none\.png' does not exist"):
        parse_deck(missing, base_dir=tmp_path)
    order = _concrete_deck(tmp_path)
    order["geometry"]["phases"][0]["grey"] = [1.0, 0.6]
    with pytest.raises(DeckError, match="must be <= hi"):
        parse_deck(order, base_dir=tmp_path)


def test_jitter_and_unreadable_files_are_setup_errors(tmp_path: Path) -> None:
    from peridynamics.build.cloud import build_cloud
    from peridynamics.deck import parse_deck

    deck = _concrete_deck(tmp_path)
    deck["discretisation"]["jitter"] = 0.2
    with pytest.raises(SetupError, match=r"jitter = 0\.2 needs a rectangle.*not a image"):
        build_cloud(parse_deck(deck, base_dir=tmp_path))
    (tmp_path / "bad.stl").write_text("not a surface")
    surf = {**_concrete_deck(tmp_path), "geometry": {"type": "surface", "file": "bad.stl"}}
    surf.pop("bodies")
    surf["boundary_conditions"] = []
    if pytest.importorskip("trimesh"):
        with pytest.raises(SetupError, match=r"geometry: .*bad\.stl"):
            build_cloud(parse_deck(surf, base_dir=tmp_path))
