"""Point stress and strain: kernels vs NumPy twins, the families' pair forces against
their force passes, homogeneous strain in the interior, derived quantities, frame
fields."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from peridynamics.bonds import build_bonds
from peridynamics.evaluation import stress as st
from peridynamics.families.correspondence.material import CorrespondenceMaterial
from peridynamics.families.lps.force import LPSForceModel
from peridynamics.families.lps.material import LPSMaterial
from peridynamics.families.pmb.force import PMBForceModel
from peridynamics.families.pmb.material import BondBasedMaterial
from peridynamics.geometry import PointCloud, box, rectangle
from peridynamics.io.observers.point_fields import POINT_FIELDS, point_fields
from peridynamics.kernels import reference_stress as ref
from peridynamics.kernels import stress as kernels
from peridynamics.state import State

DX = 1e-3
E = 70e9


def _cloud(dim: int, seed: int = 0, size: float = 0.009) -> PointCloud:
    """A small jittered body with random volumes."""
    rng = np.random.default_rng(seed)
    if dim == 2:
        base = rectangle((size + 0.002, size), DX, thickness=1e-3, plane="stress")
    else:
        base = box((0.006, 0.005, 0.005), DX)
    x = base.x + rng.uniform(-0.15, 0.15, base.x.shape) * DX
    vol = base.volume * rng.uniform(0.7, 1.3, base.n_points)
    return PointCloud(x=x, volume=vol, spacing=DX, cross_section=base.cross_section,
                      plane=base.plane)  # fmt: skip


def _broken(bonds, fraction: float, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    intact = np.ones(bonds.n_bonds, dtype=np.uint8)
    hit = np.flatnonzero(rng.random(bonds.n_bonds) < fraction)
    intact[hit] = 0
    intact[bonds.reverse_index()[hit]] = 0
    return intact


def _state(x: np.ndarray, n_bonds: int, u: np.ndarray, intact: np.ndarray) -> State:
    n = len(x)
    return State(u=np.array(u, dtype=np.float64), v=np.zeros_like(x), force=np.zeros_like(x),
                 intact=np.array(intact, dtype=np.uint8), max_stretch=np.zeros(n))  # fmt: skip


@pytest.mark.parametrize("dim", [1, 2, 3])
def test_kernels_match_numpy_twins(dim: int) -> None:
    rng = np.random.default_rng(dim)
    if dim == 1:
        x = np.arange(12, dtype=float)[:, None] * DX
        cloud = PointCloud(x=x, volume=np.full(12, DX**3), spacing=DX)
    else:
        cloud = _cloud(dim, seed=dim)
    bonds = build_bonds(cloud, 3.015 * DX)
    x = cloud.x
    u = rng.normal(scale=1e-5, size=x.shape)
    g = rng.normal(size=bonds.n_bonds) * _broken(bonds, 0.2, 1)
    n = cloud.n_points
    out = np.empty((n, dim, dim))
    kernels.virial_stress(x, u, bonds.offsets, bonds.bond_j, g, out)
    want = ref.virial_stress(x, u, bonds.bond_i, bonds.bond_j, g, n)
    np.testing.assert_allclose(out, want, rtol=1e-12, atol=1e-12 * np.abs(want).max())
    intact = _broken(bonds, 0.3, 2)
    intact[bonds.offsets[3] : bonds.offsets[4]] = 0  # a family with no intact bond
    w = np.asarray(bonds.bond_volume, dtype=np.float64)
    fg = np.empty((n, dim, dim))
    kernels.deformation_gradient(x, u, bonds.offsets, bonds.bond_j, w, intact, fg)
    want_f = ref.deformation_gradient(x, u, bonds.bond_i, bonds.bond_j, w, intact, n)
    np.testing.assert_allclose(fg, want_f, rtol=1e-10, atol=1e-12)
    np.testing.assert_array_equal(fg[3], np.eye(dim))


@pytest.mark.parametrize("dim", [2, 3])
def test_deformation_gradient_is_exact_for_an_affine_field(dim: int) -> None:
    cloud = _cloud(dim, seed=5)
    bonds = build_bonds(cloud, 3.015 * DX)
    grad = np.random.default_rng(3).normal(scale=1e-3, size=(dim, dim))
    u = cloud.x @ grad.T
    n = cloud.n_points
    fg = np.empty((n, dim, dim))
    intact = _broken(bonds, 0.1, 4)
    kernels.deformation_gradient(cloud.x, u, bonds.offsets, bonds.bond_j,
                                 np.asarray(bonds.bond_volume), intact, fg)  # fmt: skip
    np.testing.assert_allclose(fg, np.broadcast_to(np.eye(dim) + grad, fg.shape), atol=1e-12)


def _lps(cloud, bonds):
    return LPSForceModel(cloud, bonds, LPSMaterial(E, 0.3, 2700.0, influence="constant"))


@pytest.mark.parametrize("family", ["pmb", "lps"])
@pytest.mark.parametrize("dim", [2, 3])
def test_pair_forces_sum_to_the_force_pass(family: str, dim: int) -> None:
    """sum_k g_k y_k is the family's own force density (broken bonds, jittered cloud)."""
    cloud = _cloud(dim, seed=7)
    bonds = build_bonds(cloud, 3.015 * DX)
    if family == "pmb":
        fm = PMBForceModel(cloud, bonds, BondBasedMaterial(E, 2700.0))
    else:
        fm = _lps(cloud, bonds)
    u = np.random.default_rng(8).normal(scale=2e-6, size=cloud.x.shape)
    s = _state(cloud.x, bonds.n_bonds, u, _broken(bonds, 0.2, 9))
    fm.prepass(s)
    fm.force(s)
    g = fm.pair_force_coefficients(s)
    y = bonds.bond_xi + u[bonds.bond_j] - u[bonds.bond_i]
    f = np.stack([np.bincount(bonds.bond_i, g * y[:, c], minlength=cloud.n_points)
                  for c in range(dim)], axis=1)  # fmt: skip
    np.testing.assert_allclose(f, s.force, rtol=1e-9, atol=1e-9 * np.abs(s.force).max())


def _uniaxial(model, eps: float = 1e-4) -> tuple[State, np.ndarray]:
    """The affine field of a uniaxial stress E eps along x (lateral strain -nu eps)."""
    x = model.cloud.x
    dim = x.shape[1]
    nu = st.poisson_ratio(model)
    grad = np.diag([eps] + [-nu * eps] * (dim - 1))
    b = model.bonds
    s = _state(x, b.n_bonds, (x - x.mean(axis=0)) @ grad.T, np.ones(b.n_bonds, np.uint8))
    return s, grad


def _model(family: str, dim: int, size: float = 0.016) -> SimpleNamespace:
    if dim == 2:
        cloud = rectangle((size, size), 5e-4, thickness=1e-3, plane="stress")
    else:
        cloud = box((0.008, 0.008, 0.008), 5e-4)
    bonds = build_bonds(cloud, 3.015 * 5e-4)
    mat: object
    if family == "pmb":
        mat = BondBasedMaterial(E, 2700.0)
        fm = PMBForceModel(cloud, bonds, mat, surface_correction=True)
    elif family == "lps":
        mat = LPSMaterial(E, 0.3, 2700.0, influence="constant")
        fm = LPSForceModel(cloud, bonds, mat, surface_correction=True)
    else:
        mat = CorrespondenceMaterial(E, 0.3, 2700.0)
        fm = mat.force_model(cloud, bonds)  # type: ignore[attr-defined]
    return SimpleNamespace(cloud=cloud, bonds=bonds, material=mat, force_model=fm)


#: sigma_xx / (E eps) - 1 and the largest |sigma_yy|, |sigma_zz| / (E eps) at least two
#: horizons from the surfaces under the affine field of a uniaxial stress (dx = 0.5 mm,
#: delta = 3.015 dx, surface correction on), measured: PMB 2-D -8e-4, 2.6e-3; LPS 2-D
#: and 3-D 1e-4, 1e-5; correspondence 2e-4 (its geometric nonlinearity), 0; PMB 3-D
#: 5.6e-5, 3.5e-6 with the default isotropic family (-0.021, 0.031 with
#: discretisation.isotropic_family: false: the cubic lattice); see docs/stress.md
_AFFINE_TOL = {("pmb", 2): (2e-3, 5e-3), ("lps", 2): (1e-3, 1e-3),
               ("correspondence", 2): (1e-3, 1e-3), ("pmb", 3): (1e-3, 1e-3),
               ("lps", 3): (1e-3, 1e-3), ("correspondence", 3): (1e-3, 1e-3)}  # fmt: skip


@pytest.mark.parametrize("family", ["pmb", "lps", "correspondence"])
@pytest.mark.parametrize("dim", [2, 3])
def test_homogeneous_strain_gives_the_applied_stress_inside(family: str, dim: int) -> None:
    model = _model(family, dim)
    s, grad = _uniaxial(model)
    sigma = st.point_stress(model, s)
    eps = st.point_strain(model, s)
    x, delta = model.cloud.x, model.bonds.horizon
    lo, hi = x.min(axis=0), x.max(axis=0)
    inner = np.all((x > lo + 2 * delta) & (x < hi - 2 * delta), axis=1)
    ratio = sigma[inner, 0, 0] / (E * grad[0, 0])
    tol_xx, tol_lateral = _AFFINE_TOL[(family, dim)]
    assert np.abs(ratio - 1.0).max() < tol_xx
    assert np.abs(sigma[inner][:, 1:, 1:]).max() / (E * grad[0, 0]) < tol_lateral
    np.testing.assert_allclose(eps[:, :dim, :dim], np.broadcast_to(grad, (len(x), dim, dim)),
                               atol=1e-12)  # fmt: skip
    if dim == 2:  # plane stress: eps_zz = -nu / (1 - nu) (eps_xx + eps_yy)
        nu = st.poisson_ratio(model)
        assert eps[0, 2, 2] == pytest.approx(-nu / (1 - nu) * np.trace(grad), rel=1e-9)


def test_derived_quantities_of_known_tensors() -> None:
    sig = np.zeros((3, 3, 3))
    sig[0, 0, 0] = 5.0  # uniaxial
    sig[1] = -2.0 * np.eye(3)  # hydrostatic compression
    sig[2, 0, 1] = sig[2, 1, 0] = 3.0  # pure shear
    np.testing.assert_allclose(st.von_mises(sig), [5.0, 0.0, 3.0 * np.sqrt(3.0)], atol=1e-12)
    np.testing.assert_allclose(st.pressure(sig), [-5.0 / 3.0, 2.0, 0.0], atol=1e-12)
    w, v = st.principal_stresses(sig)
    np.testing.assert_allclose(w[2], [3.0, 0.0, -3.0], atol=1e-12)
    np.testing.assert_allclose(np.abs(v[2][:, 0]), [np.sqrt(0.5), np.sqrt(0.5), 0.0], atol=1e-12)
    np.testing.assert_allclose(w[0], [5.0, 0.0, 0.0], atol=1e-12)


def test_plane_strain_out_of_plane_stress() -> None:
    cloud = rectangle((0.006, 0.006), 5e-4, thickness=1e-3, plane="strain")
    bonds = build_bonds(cloud, 3.015 * 5e-4)
    mat = LPSMaterial(E, 0.3, 2700.0, influence="constant")
    model = SimpleNamespace(cloud=cloud, bonds=bonds, material=mat,
                            force_model=LPSForceModel(cloud, bonds, mat))  # fmt: skip
    s, _ = _uniaxial(model)
    sig = st.point_stress(model, s)
    np.testing.assert_allclose(sig[:, 2, 2], 0.3 * (sig[:, 0, 0] + sig[:, 1, 1]), rtol=1e-12)


def test_frame_point_fields_shapes_and_registry() -> None:
    model = _model("lps", 2, size=0.006)
    s, _ = _uniaxial(model)
    data = point_fields(list(POINT_FIELDS) + ["displacement"], model, s)
    n = model.cloud.n_points
    assert set(data) == set(POINT_FIELDS)
    assert data["stress"].shape == (n, 9) and data["strain"].shape == (n, 9)
    assert data["principal_stress"].shape == (n, 3)
    assert data["principal_direction"].shape == (n, 3)
    np.testing.assert_allclose(data["von_mises"], st.von_mises(data["stress"].reshape(n, 3, 3)))


def test_a_family_without_stress_is_named() -> None:
    model = SimpleNamespace(force_model=SimpleNamespace(point_stress=lambda s: None, name="x"))
    with pytest.raises(ValueError, match="'x' model gives no point stress"):
        st.point_stress(model, None)  # type: ignore[arg-type]


def test_frames_carry_the_stress_fields_and_result_reads_them_back(tmp_path) -> None:
    import peridynamics as pd

    deck = {
        "name": "stress_frame",
        "geometry": {"type": "rectangle", "size": [0.006, 0.004], "thickness": 1e-3,
                     "plane": "strain"},
        "discretisation": {"spacing": 5e-4, "horizon_factor": 3.015},
        "material": {"model": "lps", "youngs_modulus": E, "poisson_ratio": 0.3,
                     "density": 2700.0},
        "damage": {"model": "none"},
        "initial_conditions": [],
        "solver": {"end_time": 2e-7},
        "output": {"fields": ["displacement", "stress", "strain", "von_mises", "pressure",
                              "principal_stress", "principal_direction"]},
    }  # fmt: skip
    deck.pop("initial_conditions")
    sim = pd.Simulation(deck, out=tmp_path)
    sim.state.u[:] = sim.model.cloud.x * 1e-4  # a uniform expansion before the run
    res = sim.run()
    got = res.fields()
    n = sim.n_points
    assert got["stress"].shape == (n, 3, 3) and got["strain"].shape == (n, 3, 3)
    assert got["von_mises"].shape == (n,) and got["principal_direction"].shape == (n, 3)
    now = sim.field("stress")
    np.testing.assert_allclose(got["stress"], now, rtol=1e-5, atol=1e-6 * np.abs(now).max())
    np.testing.assert_allclose(got["pressure"], st.pressure(now), rtol=1e-5, atol=1.0)
    with pytest.raises(KeyError, match="not a computed point field"):
        sim.field("damage")


def _tension_deck(family: str, dim: int) -> dict:
    """A plate (2-D, 40 x 20 mm, dx 0.5 mm) or a box (3-D, 24 x 16 x 16 mm, dx 1 mm)
    pulled by 10 MPa on x = L, held by a roller on x = 0 and pins, static solver."""
    mat: dict = {"youngs_modulus": E, "density": 2700.0}
    if family != "pmb":
        mat.update(model=family, poisson_ratio=0.3)
    if dim == 2:
        size, dx = [0.04, 0.02], 5e-4
        pins = {"pin": ({"point": [0.0, 0.01]}, ["y"])}
    else:
        size, dx = [0.024, 0.016, 0.016], 1e-3
        pins = {"pin": ({"point": [0.0, 0.008, 0.008]}, ["y", "z"]),
                "pin2": ({"point": [0.0, 0.016, 0.008]}, ["z"])}  # fmt: skip
    normal = [-1.0] + [0.0] * (dim - 1)
    sets = {"left": {"edge": {"normal": normal}},
            "right": {"edge": {"normal": [1.0] + [0.0] * (dim - 1)}}}  # fmt: skip
    sets.update({k: v[0] for k, v in pins.items()})
    bcs = [{"type": "fixed", "set": "left", "components": ["x"]},
           {"type": "traction", "set": "right", "value": [10e6] + [0.0] * (dim - 1)}]  # fmt: skip
    bcs += [{"type": "fixed", "set": k, "components": v[1]} for k, v in pins.items()]
    geo = ({"type": "rectangle", "size": size, "thickness": 1e-3, "plane": "stress"}
           if dim == 2 else {"type": "box", "size": size})  # fmt: skip
    solver = {"type": "static", "load_steps": 1, "tolerance": 1e-8}
    if dim == 3:
        solver["linear_solver"] = "iterative"
    deck = {"name": f"tension_{family}", "geometry": geo,
            "discretisation": {"spacing": dx, "horizon_factor": 3.015}, "material": mat,
            "node_sets": sets, "boundary_conditions": bcs, "solver": solver,
            "output": {"fields": ["displacement"], "plot": "none"}}  # fmt: skip
    if family != "pmb":
        deck["damage"] = {"model": "none"}
    return deck


#: measured sigma_xx / sigma at least two horizons from every surface (min, max) and the
#: section integral of sigma_xx at mid-length over the load (docs/stress.md)
_SOLVED = {("pmb", 2): (0.9897, 1.0036), ("lps", 2): (0.9992, 1.0014),
           ("correspondence", 2): (0.9917, 1.0013), ("pmb", 3): (0.9731, 0.9922),
           ("lps", 3): (0.9960, 1.0025)}  # fmt: skip


@pytest.mark.slow
@pytest.mark.parametrize(("family", "dim"), list(_SOLVED))
def test_uniaxial_tension_solved_interior_stress(family: str, dim: int, tmp_path) -> None:
    import peridynamics as pd

    sim = pd.Simulation(_tension_deck(family, dim), out=tmp_path)
    sim.run()
    sigma = sim.field("stress")[:, 0, 0] / 10e6
    x, delta = sim.model.cloud.x, sim.model.bonds.horizon
    lo, hi = x.min(axis=0), x.max(axis=0)
    inner = np.all((x > lo + 2 * delta) & (x < hi - 2 * delta), axis=1)
    low, high = _SOLVED[(family, dim)]
    assert low - 1e-3 < sigma[inner].min() and sigma[inner].max() < high + 1e-3
    dx = sim.model.cloud.spacing
    mid = np.abs(x[:, 0] - (lo[0] + hi[0]) / 2) < 0.5 * dx + 1e-12
    columns = len(np.unique(np.round(x[mid, 0] / dx, 6)))
    area = (hi[1] - lo[1] + dx) * (1e-3 if dim == 2 else hi[2] - lo[2] + dx)
    force = np.sum(sigma[mid] * sim.model.cloud.volume[mid]) / (columns * dx)
    assert force / area == pytest.approx(1.0, abs=1e-4)
