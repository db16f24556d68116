"""Jittered grids, their Voronoi volumes, the deck keys, the moment correction and the
damage-anisotropy measure.

Oracles: the regular grid of the same call (bit for bit at jitter 0), the definition of
the offsets (uniform in [-jitter dx, jitter dx]^dim from default_rng(seed) in grid-point
order, recomputed here), the volume of the body (box-clipped Voronoi cells partition
the box), the continuum fourth moment of the ball, and synthetic damage fields whose
harmonics are known in closed form.
"""

from __future__ import annotations

import copy
import math

import meshio
import numpy as np
import pytest
from scipy.spatial import ConvexHull, Voronoi

from peridynamics import BondBasedMaterial, Evaluator, build_bonds
from peridynamics.analysis.anisotropy import damage_anisotropy
from peridynamics.bonds.surface import energy_correction_factors, moment_correction_factors
from peridynamics.build.cloud import build_cloud
from peridynamics.build.errors import SetupError
from peridynamics.deck import DeckError, parse_deck
from peridynamics.families.calibration import calibrate_influence
from peridynamics.geometry import Ball, box, cylinder, rectangle
from peridynamics.geometry.jitter import voronoi_volumes

DX = 1e-3


# -- jittered generators -----------------------------------------------------------------
GRIDS = {
    "rectangle": lambda **kw: rectangle((0.012, 0.007), DX, thickness=2e-3, **kw),
    "box": lambda **kw: box((0.006, 0.005, 0.004), DX, origin=(1.0, -2.0, 0.5), **kw),
    "cylinder": lambda **kw: cylinder(0.0035, 0.004, DX, origin=(0.1, 0.2, 0.3), **kw),
}


@pytest.mark.parametrize("kind", GRIDS)
def test_zero_jitter_is_the_regular_grid_bit_for_bit(kind: str) -> None:
    regular = GRIDS[kind]()
    for kw in ({"jitter": 0.0}, {"jitter": 0.0, "seed": 7}, {"jitter": 0, "volumes": "cell"}):
        same = GRIDS[kind](**kw)
        assert same.x.tobytes() == regular.x.tobytes()
        assert same.volume.tobytes() == regular.volume.tobytes()
        assert not same.irregular


@pytest.mark.parametrize("kind", ["rectangle", "box"])
@pytest.mark.parametrize("jitter", [0.1, 0.45])
def test_offsets_are_the_seeded_uniform_draw_and_bounded(kind: str, jitter: float) -> None:
    regular = GRIDS[kind]()
    moved = GRIDS[kind](jitter=jitter, seed=11)
    assert moved.irregular and moved.n_points == regular.n_points
    off = moved.x - regular.x
    want = np.random.default_rng(11).uniform(-jitter * DX, jitter * DX, regular.x.shape)
    np.testing.assert_allclose(off, want, rtol=0, atol=1e-15)
    assert np.abs(off).max() <= jitter * DX * (1 + 1e-12)
    assert np.abs(off).max() > 0.9 * jitter * DX  # the whole range is used
    # every point stays in its own grid cell, hence in the body
    lo, hi = regular.x.min(axis=0) - DX / 2, regular.x.max(axis=0) + DX / 2
    assert np.all((moved.x > lo) & (moved.x < hi))


@pytest.mark.parametrize("kind", GRIDS)
def test_jitter_is_reproducible_by_seed(kind: str) -> None:
    a, b, c = (GRIDS[kind](jitter=0.3, seed=s) for s in (4, 4, 5))
    assert a.x.tobytes() == b.x.tobytes() and a.volume.tobytes() == b.volume.tobytes()
    assert not np.array_equal(a.x, c.x)


def test_voronoi_volumes_sum_to_the_body_and_match_convex_hulls() -> None:
    """Box-clipped Voronoi cells partition the box: sum = volume to 1e-12; each cell
    agrees with the convex hull of its vertices computed here (all points mirrored)."""
    r = rectangle((0.012, 0.007), DX, thickness=2e-3, jitter=0.4, seed=3)
    assert r.volume.sum() == pytest.approx(0.012 * 0.007 * 2e-3, rel=1e-12)
    b = GRIDS["box"](jitter=0.25, seed=2)
    assert b.volume.sum() == pytest.approx(0.006 * 0.005 * 0.004, rel=1e-12)
    lo, hi = np.array([1.0, -2.0, 0.5]), np.array([1.006, -1.995, 0.504])
    pts = [b.x]
    for k in range(3):
        for face in (lo[k], hi[k]):
            m = b.x.copy()
            m[:, k] = 2 * face - m[:, k]
            pts.append(m)
    vor = Voronoi(np.concatenate(pts))
    hull = [ConvexHull(vor.vertices[vor.regions[vor.point_region[i]]]).volume
            for i in range(b.n_points)]  # fmt: skip
    np.testing.assert_allclose(b.volume, hull, rtol=1e-9)
    # the cheap alternative: the grid cell of each point
    cell = GRIDS["box"](jitter=0.25, seed=2, volumes="cell")
    assert np.all(cell.volume == DX**3) and np.array_equal(cell.x, b.x)
    # volumes vary with the jitter (a Voronoi cell is not the grid cell)
    assert b.volume.std() / b.volume.mean() > 0.05


def test_holes_stay_empty_and_cylinder_points_stay_inside() -> None:
    hole = Ball([0.006, 0.0035], 0.002)
    r = rectangle((0.012, 0.007), DX, jitter=0.45, seed=1, holes=[hole])
    assert not np.any(hole(r.x))
    full = rectangle((0.012, 0.007), DX, jitter=0.45, seed=1)
    # the draw does not depend on the holes: the kept points are the same points
    keep = ~hole(full.x)
    np.testing.assert_array_equal(r.x, full.x[keep])
    np.testing.assert_array_equal(r.volume, full.volume[keep])
    # a hole of area A removes about A (the Voronoi cells of the removed points)
    removed = full.volume.sum() - r.volume.sum()
    assert removed == pytest.approx(math.pi * 0.002**2, rel=0.2)
    c = cylinder(0.0035, 0.004, DX, origin=(0.1, 0.2, 0.3), jitter=0.45, seed=2)
    radial = np.hypot(c.x[:, 0] - 0.1, c.x[:, 1] - 0.2)
    assert radial.max() <= 0.0035 * (1 + 1e-12)
    assert c.x[:, 2].min() > 0.3 and c.x[:, 2].max() < 0.304
    # volume: the cells of the kept points, within the grid's staircase error
    assert c.volume.sum() == pytest.approx(math.pi * 0.0035**2 * 0.004, rel=0.1)


@pytest.mark.parametrize("bad", [-0.1, 0.5, 0.7, math.nan, True])
def test_generators_reject_bad_jitter(bad: float) -> None:
    with pytest.raises(ValueError, match="0 <= jitter < 0.5"):
        rectangle((0.004, 0.004), DX, jitter=bad)


@pytest.mark.parametrize("bad", [-1, 1.5, "3", True])
def test_generators_reject_bad_seed(bad: object) -> None:
    with pytest.raises(ValueError, match="seed must be an integer >= 0"):
        box((0.003, 0.003, 0.003), DX, jitter=0.1, seed=bad)  # type: ignore[arg-type]


def test_voronoi_volumes_reject_points_outside_the_box() -> None:
    with pytest.raises(ValueError, match="strictly inside"):
        voronoi_volumes(np.array([[0.5, 0.5], [1.0, 0.2], [0.2, 0.7]]), [0, 0], [1, 1])


# -- deck keys ---------------------------------------------------------------------------
def _deck(geometry: dict | None = None, **disc: object) -> dict:
    return {
        "name": "jitter",
        "geometry": geometry or {"type": "rectangle", "size": [0.008, 0.004], "thickness": 1e-3},
        "discretisation": {"spacing": DX, "horizon_factor": 3.015, **disc},
        "material": {"youngs_modulus": 70e9, "density": 2700.0},
        "solver": {"steps": 1},
    }


def test_deck_jitter_and_seed_reach_the_generator() -> None:
    deck = parse_deck(_deck(jitter=0.3, seed=9))
    assert deck.discretisation.jitter == 0.3 and deck.discretisation.seed == 9
    cloud = build_cloud(deck)
    want = rectangle((0.008, 0.004), DX, thickness=1e-3, jitter=0.3, seed=9)
    assert cloud.x.tobytes() == want.x.tobytes()
    assert cloud.volume.tobytes() == want.volume.tobytes()
    default = parse_deck(_deck())
    assert default.discretisation.jitter == 0.0 and default.discretisation.seed == 0
    assert build_cloud(default).x.tobytes() == rectangle((0.008, 0.004), DX).x.tobytes()
    b = build_cloud(parse_deck(_deck({"type": "box", "size": [0.004, 0.003, 0.003]},
                                     jitter=0.2, seed=1)))  # fmt: skip
    assert b.x.tobytes() == box((0.004, 0.003, 0.003), DX, jitter=0.2, seed=1).x.tobytes()


@pytest.mark.parametrize(
    ("key", "value", "message"),
    [
        ("jitter", 0.5, "0 <= jitter < 0.5"),
        ("jitter", -0.01, "0 <= jitter < 0.5"),
        ("jitter", ".nan", "finite number"),
        ("jitter", True, "not true/false"),
        ("seed", -3, "greater than or equal to 0"),
        ("seed", 2.5, "integer"),
    ],
)
def test_deck_rejects_bad_jitter_and_seed(key: str, value: object, message: str) -> None:
    raw = _deck(**{key: value})
    if value == ".nan":
        raw["discretisation"][key] = math.nan
    with pytest.raises(DeckError) as info:
        parse_deck(raw)
    paths = [p for p, _ in info.value.errors]
    assert f"discretisation.{key}" in paths, info.value.errors
    assert message in str(info.value)


@pytest.mark.parametrize("kind", ["bar", "mesh"])
def test_jitter_with_a_bar_or_mesh_geometry_is_a_setup_error(kind: str, tmp_path) -> None:
    if kind == "bar":
        geometry = {"type": "bar", "length": 0.01, "area": 1e-6}
    else:
        pts = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=float) * 0.004
        path = tmp_path / "square.vtu"
        meshio.write(path, meshio.Mesh(pts, [("triangle", np.array([[0, 1, 2], [0, 2, 3]]))]))
        geometry = {"type": "mesh", "file": str(path)}
    raw = _deck(geometry, jitter=0.2)
    with pytest.raises(SetupError, match=r"discretisation\.jitter = 0\.2 needs a rectangle"):
        build_cloud(parse_deck(raw))
    no_jitter = copy.deepcopy(raw)
    no_jitter["discretisation"]["jitter"] = 0.0
    build_cloud(parse_deck(no_jitter))  # fine without jitter


# -- the moment correction -----------------------------------------------------------------
@pytest.mark.parametrize("dim", [2, pytest.param(3, marks=pytest.mark.long)])
def test_moment_correction_gives_every_interior_point_the_continuum_energy(dim: int) -> None:
    """Under any homogeneous strain the corrected energy of an interior point of a
    jittered cloud is the continuum one, W = 1/2 eps : C : eps with C the isotropic
    stiffness of the bond-based solid (nu = 1/3 plane stress, 1/4 in 3-D), on average
    over the interior to 1 % (each point exactly before the two ends are averaged);
    the axis energy method is not (shear is off by 2.5 %)."""
    if dim == 2:
        cloud = rectangle((0.024, 0.024), DX, thickness=1e-3, jitter=0.3, seed=5)
        size = 0.024
    else:
        cloud = box((0.014, 0.014, 0.014), DX, jitter=0.3, seed=5)
        size = 0.014
    e_mod = 70e9
    mat = BondBasedMaterial(e_mod, 2700.0)
    bonds = build_bonds(cloud, 3.015 * DX)
    raw = mat.bond_stiffness(cloud, bonds, corrected=False)
    w_inf = mat.uniaxial_energy_density(1e-6, dim, bonds.horizon, cloud.cross_section,
                                        cloud.plane)  # fmt: skip
    g = moment_correction_factors(cloud.x, bonds, raw, w_inf, 1e-6, calibrate=calibrate_influence)
    np.testing.assert_allclose(g, g[bonds.reverse_index()], rtol=1e-14)  # pair forces
    assert g.min() > 0
    model = Evaluator(cloud, bonds.with_correction(g), mat)
    nu = 1 / 3 if dim == 2 else 0.25
    lam = e_mod * nu / ((1 + nu) * (1 - (dim - 1) * nu))  # plane stress / 3-D
    mu = e_mod / (2 * (1 + nu))
    inner = np.all((cloud.x > 2 * bonds.horizon) & (cloud.x < size - 2 * bonds.horizon), axis=1)
    assert inner.sum() >= 8
    # the axis energy method (what surface_correction gives on a regular grid)
    axes = Evaluator(
        cloud,
        bonds.with_correction(energy_correction_factors(cloud.x, bonds, raw, w_inf, 1e-6)),
        mat,
    )
    deck_path = Evaluator(cloud, bonds, mat, surface_correction=True)  # irregular: moments
    assert np.array_equal(deck_path.bonds.bond_correction, g)
    errors = []
    # uniaxial, simple shear, equibiaxial, pure shear in the x-y plane
    for a, b, c in [(1, 0, 0), (0, 1, 0), (1, 0, 1), (1, 0, -1)]:
        eps = np.zeros((dim, dim))
        eps[0, 0], eps[0, 1], eps[1, 0], eps[1, 1] = a, b, b, c
        eps *= 1e-6
        w_c = 0.5 * lam * np.trace(eps) ** 2 + mu * np.sum(eps * eps)
        w = model.strain_energy_density(cloud.x @ eps.T, model.bonds.bond_intact)
        assert w[inner].mean() == pytest.approx(w_c, rel=0.01)  # measured <= 0.7 %
        w_axes = axes.strain_energy_density(cloud.x @ eps.T, axes.bonds.bond_intact)
        errors.append(abs(w_axes[inner].mean() / w_c - 1))
    # the axis method calibrates uniaxial strain along the axes only: shear is 2.5 % stiff
    assert max(errors) > 0.02


# -- damage anisotropy -----------------------------------------------------------------------
CLOUD = rectangle((0.1, 0.1), 5e-4, jitter=0.3, seed=1)
CENTRE = np.array([0.05, 0.05])


def _polar() -> tuple[np.ndarray, np.ndarray]:
    rel = CLOUD.x - CENTRE
    return np.hypot(rel[:, 0], rel[:, 1]), np.arctan2(rel[:, 1], rel[:, 0])


def test_isotropic_disc_has_no_harmonic_and_round_extent() -> None:
    r, _ = _polar()
    a = damage_anisotropy(CLOUD.x, np.where(r < 0.03, 1.0, 0.1), CENTRE, 0.01, 0.04)
    assert a.angles.shape == a.mean_damage.shape == a.extent.shape == (72,)
    assert a.harmonic_4 < 0.01 and a.harmonic_8 < 0.01
    assert a.extent_ratio < 1.05  # every direction reaches r = 0.03 - dx


def test_axis_cross_has_a_strong_4_fold_harmonic_along_the_axes() -> None:
    x = CLOUD.x - CENTRE
    d = ((np.abs(x[:, 0]) < 2e-3) | (np.abs(x[:, 1]) < 2e-3)).astype(float)
    a = damage_anisotropy(CLOUD.x, d, CENTRE, 0.01, 0.04)
    assert a.harmonic_4 > 1.0 and a.harmonic_8 > 0.5
    assert abs(a.phase_4) < 0.05  # along the axes, not the diagonals
    assert a.extent_ratio > 3.5  # 0.04 along the arms, r_min = 0.01 between them
    # the same cross along the diagonals: the same amplitude, phase pi/4
    rot = np.array([[1, -1], [1, 1]]) / math.sqrt(2)
    xr = x @ rot
    dr = ((np.abs(xr[:, 0]) < 2e-3) | (np.abs(xr[:, 1]) < 2e-3)).astype(float)
    b = damage_anisotropy(CLOUD.x, dr, CENTRE, 0.01, 0.04)
    assert b.harmonic_4 == pytest.approx(a.harmonic_4, rel=0.1)
    assert abs(abs(b.phase_4) - math.pi / 4) < 0.05


@pytest.mark.parametrize(("m", "amp"), [(4, 0.3), (8, 0.15)])
def test_harmonic_amplitude_of_a_cosine_field(m: int, amp: float) -> None:
    _, th = _polar()
    a = damage_anisotropy(CLOUD.x, 0.5 * (1 + amp * np.cos(m * th)), CENTRE, 0.01, 0.04)
    assert a.harmonic(m) == pytest.approx(amp, rel=0.01)
    assert (a.harmonic_4 if m == 4 else a.harmonic_8) == pytest.approx(amp, rel=0.01)
    assert a.harmonic(12 - m) < 0.01
    assert a.mean == pytest.approx(0.5, rel=0.01)


def test_plane_of_a_3d_cloud_and_bad_input() -> None:
    b = box((0.02, 0.004, 0.02), 1e-3, jitter=0.2, seed=0)  # plate in x-z
    rel = b.x - [0.01, 0.002, 0.01]
    d = (np.abs(rel[:, 0]) < 1.5e-3).astype(float)  # a band along z
    a = damage_anisotropy(b.x, d, [0.01, 0.002, 0.01], 0.002, 0.009, n_bins=24, axes=(0, 2))
    assert a.harmonic(2) > 0.8 and a.extent_ratio > 2
    with pytest.raises(ValueError, match="angular bins hold no point"):
        damage_anisotropy(b.x, d, [0.01, 0.01], 0.002, 0.003, n_bins=360, axes=(0, 2))
    with pytest.raises(ValueError, match="r_min < r_max"):
        damage_anisotropy(b.x, d, [0.01, 0.01], 0.004, 0.003, axes=(0, 2))
    with pytest.raises(ValueError, match="two distinct axes"):
        damage_anisotropy(b.x, d, [0.01, 0.01], 0.002, 0.009, axes=(1, 1))
    with pytest.raises(ValueError, match="damage must have shape"):
        damage_anisotropy(b.x, d[:-1], [0.01, 0.01], 0.002, 0.009)


@pytest.mark.parametrize(
    ("jitter", "layers", "dim"), [(0.1, 1, 2), (0.25, 2, 2), (0.4, 1, 2), (0.25, 1, 3)]
)
def test_traction_on_a_jittered_edge_applies_traction_times_area(jitter, layers, dim):
    """The layer's body force totals traction x face area although the jittered rows are
    not flat (extent + dx would be up to (1 + 2 jitter) dx)."""
    from peridynamics import deck as dk
    from peridynamics.build.cloud import build_cloud
    from peridynamics.build.loads import build_conditions

    size = [0.05, 0.02] if dim == 2 else [0.02, 0.01, 0.01]
    geom = {"type": "rectangle", "size": size, "thickness": 0.01} if dim == 2 else {
        "type": "box", "size": size}  # fmt: skip
    normal = [1.0] + [0.0] * (dim - 1)
    d = dk.parse_deck({
        "name": "t", "geometry": geom,
        "discretisation": {"spacing": 0.001, "horizon_factor": 3.015, "jitter": jitter,
                           "seed": 3},
        "material": {"youngs_modulus": 1e9, "density": 1000.0},
        "node_sets": {"right": {"edge": {"normal": normal, "layers": layers}}},
        "boundary_conditions": [{"type": "traction", "set": "right",
                                 "value": [1e6] + [0.0] * (dim - 1), "normal": normal}],
        "solver": {"steps": 1},
    })  # fmt: skip
    cloud = build_cloud(d)
    body, _, _ = build_conditions(d, cloud)
    out = np.zeros((cloud.n_points, dim))
    body[0].add_to(out, 0.0)
    area = size[1] * (0.01 if dim == 2 else size[2])
    assert float(np.sum(out[:, 0] * cloud.volume)) == pytest.approx(1e6 * area, rel=1e-12)
