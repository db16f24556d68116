"""2-D micropolar bond-based model: springs, kernels, energy, tangent, assembly, dynamics.

Checks :mod:`peridynamics.families.micropolar.material`,
:mod:`peridynamics.families.micropolar.force`,
the Numba kernels against their NumPy twins, and the two tangent assemblies of
:mod:`peridynamics.families.assembly`. All models are small (at most 256 points).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg as la

from peridynamics.bonds.bonds import build_bonds
from peridynamics.evaluation import Evaluator
from peridynamics.families.assembly import element_assembly
from peridynamics.families.micropolar.material import MicropolarMaterial
from peridynamics.geometry.generators import bar, box, rectangle

E, NU, RHO = 200e9, 0.2, 7800.0
DX = 0.01


def make_model(
    size=(0.12, 0.09),
    dx=DX,
    m=3.015,
    plane="stress",
    surface_correction=True,
    nu=NU,
    ratio=1.0 / 12.0,
):
    cloud = rectangle(size, dx, thickness=1.0, plane=plane)
    bonds = build_bonds(cloud, m * dx)
    material = MicropolarMaterial(E, nu, RHO, rotational_stiffness_ratio=ratio)
    return Evaluator(cloud, bonds, material, surface_correction=surface_correction)


def break_pairs(model, fraction, rng):
    """intact array with a random ``fraction`` of bond pairs broken in both directions."""
    bonds = model.force_model.bonds
    rev = bonds.reverse_index()
    intact = np.ones(bonds.n_bonds, dtype=np.uint8)
    hit = np.flatnonzero(rng.random(bonds.n_bonds) < fraction)
    intact[hit] = 0
    intact[rev[hit]] = 0
    assert 0 < np.count_nonzero(intact == 0) < bonds.n_bonds
    return intact


def set_dofs(state, q):
    """Write the flat dof vector q ([ux, uy, theta] per point) into ``state``."""
    q = q.reshape(-1, 3)
    state.u[:] = q[:, :2]
    state["theta"][:] = q[:, 2:]


def residual(model, state, q):
    """-V [f_x, f_y, m] per point, flat, at the dofs q (the tangent is its derivative)."""
    set_dofs(state, q)
    model.force_model.force(state)
    vol = model.cloud.volume[:, None]
    return -np.concatenate([vol * state.force, vol * state["moment"]], axis=1).ravel()


def homogeneous(x, e11, e22, e12, w):
    """u of the strain (e11, e22, e12) plus the rotation w, and theta = w."""
    u = np.column_stack([e11 * x[:, 0] + (e12 - w) * x[:, 1], (e12 + w) * x[:, 0] + e22 * x[:, 1]])
    return u, np.full((len(x), 1), w)


# -- 1. springs, critical stretch, errors -------------------------------------------------
def test_springs_closed_forms():
    t, d = 1.0, 0.03015
    for nu in (-0.5, 0.0, 0.1, 0.2, 0.25):
        mat = MicropolarMaterial(E, nu, RHO)
        ks = mat.springs(2, d, t, "stress")
        c = 6.0 * E / (math.pi * t * d**3)
        assert ks.axial == pytest.approx(c / (1 - nu), rel=1e-13)
        assert ks.shear == pytest.approx(c * (1 - 3 * nu) / (1 - nu**2), rel=1e-12, abs=1e-3)
        assert ks.rotational == pytest.approx(ks.shear / 12.0, rel=1e-13)
        kp = mat.springs(2, d, t, "strain")
        den = (1 + nu) * (1 - 2 * nu)
        assert kp.axial == pytest.approx(c / den, rel=1e-13)
        assert kp.shear == pytest.approx(c * (1 - 4 * nu) / den, rel=1e-12, abs=1e-3)
        assert kp.rotational == pytest.approx(kp.shear / 12.0, rel=1e-13)
    # thickness enters as 1/t
    ks2 = MicropolarMaterial(E, NU, RHO).springs(2, d, 2.0, "stress")
    assert ks2.axial == pytest.approx(
        MicropolarMaterial(E, NU, RHO).springs(2, d, t, "stress").axial / 2
    )


def test_springs_cantilever_numbers():
    ks = MicropolarMaterial(200e9, 0.2, 7800.0).springs(2, 0.03015, 1.0, "stress")
    assert f"{ks.axial:.3e}" == "1.742e+16"
    assert f"{ks.shear:.3e}" == "5.807e+15"
    assert ks.rotational == pytest.approx(ks.shear / 12, rel=1e-14)
    ks3 = MicropolarMaterial(200e9, 0.2, 7800.0, rotational_stiffness_ratio=0.5).springs(
        2, 0.03015, 1.0, "stress"
    )
    assert ks3.rotational == pytest.approx(0.5 * ks3.shear, rel=1e-14)
    assert ks3.axial == ks.axial and ks3.shear == ks.shear
    # the model carries the springs of its cloud's plane and thickness
    model = make_model()
    assert model.force_model.springs == MicropolarMaterial(E, NU, RHO).springs(
        2, 3.015 * DX, 1.0, "stress"
    )


def test_pmb_limit_and_critical_stretch():
    d, g = 0.03015, 500.0
    mat = MicropolarMaterial(E, 1.0 / 3.0, RHO)
    ks = mat.springs(2, d, 1.0, "stress")
    # k_t = 12/(pi t d^3) (2 mu - kappa) cancels to round-off of k_n at the limit
    assert abs(ks.shear) < 1e-14 * ks.axial and abs(ks.rotational) < 1e-14 * ks.axial
    assert ks.axial == pytest.approx(9 * E / (math.pi * 1.0 * d**3), rel=1e-12)
    s_pmb = math.sqrt(4 * math.pi * g / (9 * E * d))
    assert mat.critical_stretch(g, 2, d, 1.0, "stress") == pytest.approx(s_pmb, rel=1e-12)
    # plane strain limit nu = 1/4 is also k_t = 0
    kp = MicropolarMaterial(E, 0.25, RHO).springs(2, d, 1.0, "strain")
    assert abs(kp.shear) < 1e-14 * kp.axial
    # DCB of the spec
    dcb = MicropolarMaterial(200e9, 0.2, 7800.0)
    s0 = dcb.critical_stretch(962.8, 2, 1.5075e-3, 1.0, "stress")
    assert f"{s0:.3e}" == "2.313e-03"
    # G_c = 4 kappa beta s0^2 in plane strain too
    kappa = E / (2 * (1 + NU) * (1 - 2 * NU))
    s_strain = dcb.critical_stretch(962.8, 2, 1.5075e-3, 1.0, "strain")
    beta = 3 * 1.5075e-3 / (4 * math.pi)
    assert 4 * kappa * beta * s_strain**2 == pytest.approx(962.8, rel=1e-12)


def test_material_errors():
    with pytest.raises(ValueError, match="poisson_ratio"):
        MicropolarMaterial(E, 0.3, RHO).springs(2, 0.03, 1.0, "strain")
    with pytest.raises(ValueError, match="poisson_ratio"):
        make_model(plane="strain", nu=0.3)
    MicropolarMaterial(E, 0.3, RHO).springs(2, 0.03, 1.0, "stress")  # fine in plane stress
    with pytest.raises(ValueError, match="poisson_ratio"):
        MicropolarMaterial(E, 0.4, RHO)
    with pytest.raises(ValueError, match="rotational_stiffness_ratio"):
        MicropolarMaterial(E, NU, RHO, rotational_stiffness_ratio=-0.1)
    with pytest.raises(ValueError, match="youngs_modulus"):
        MicropolarMaterial(-E, NU, RHO)
    with pytest.raises(ValueError, match="density"):
        MicropolarMaterial(E, NU, 0.0)
    mat = MicropolarMaterial(E, NU, RHO)
    for dim in (1, 3):
        with pytest.raises(ValueError, match="2-D"):
            mat.springs(dim, 0.03, 1.0, None)
        with pytest.raises(ValueError, match="2-D"):
            mat.critical_stretch(100.0, dim, 0.03)
    cube = box((0.04, 0.04, 0.04), 0.01)
    with pytest.raises(ValueError, match="2-D"):
        Evaluator(cube, build_bonds(cube, 0.02015), mat)
    line = bar(0.1, 0.01)
    with pytest.raises(ValueError, match="2-D"):
        Evaluator(line, build_bonds(line, 0.03015), mat)


# -- 2.-4. Numba == NumPy, rigid motion, force = -grad(energy): tests/contracts ------------
# -- 3. a rotation of u alone is resisted ----------------------------------------------------
@pytest.mark.parametrize("plane", ["stress", "strain"])
def test_rotation_of_u_without_theta_is_resisted(plane):
    """The shear springs resist u rotating without theta (the rigid rotation, with theta,
    is force free: tests/contracts)."""
    model = make_model(plane=plane)
    fm = model.force_model
    s = model.new_state()
    x = model.cloud.x
    s.u[:], s["theta"][:] = homogeneous(x, 1e-3, 0.0, 0.0, 0.0)  # comparable strain
    fm.force(s)
    m_ref = np.abs(s["moment"]).max()
    assert m_ref > 0
    s.u[:], s["theta"][:] = homogeneous(x, 0.0, 0.0, 0.0, 1e-3)
    s["theta"][:] = 0.0
    fm.force(s)
    assert np.abs(s["moment"]).max() > 1e-3 * m_ref


# -- 5. tangent ----------------------------------------------------------------------------
@pytest.mark.parametrize("broken", [False, True])
def test_tangent_matches_finite_differences(broken):
    model = make_model(size=(0.05, 0.04), m=2.015)
    fm = model.force_model
    s = model.new_state()
    if broken:
        s.intact[:] = break_pairs(model, 0.2, np.random.default_rng(5))
    K = fm.tangent(s).toarray()
    n = model.cloud.x.shape[0]
    assert K.shape == (3 * n, 3 * n)
    kmax = np.abs(K).max()
    assert np.abs(K - K.T).max() < 1e-12 * kmax
    kfd = np.empty_like(K)
    for dof in range(3 * n):
        e = np.zeros(3 * n)
        e[dof] = 1e-6
        kfd[:, dof] = (residual(model, s, e) - residual(model, s, -e)) / 2e-6
    assert np.abs(kfd - K).max() < 1e-6 * kmax
    # all three blocks are present: translation, rotation and their coupling
    assert np.abs(K[2::3, 2::3]).max() > 0 and np.abs(K[0::3, 2::3]).max() > 0
    # linear model: K q = -V f(q) exactly
    q = np.random.default_rng(6).normal(size=3 * n) * 1e-4
    r = residual(model, s, q)
    assert np.abs(K @ q - r).max() < 1e-12 * np.abs(r).max()


def test_free_body_tangent_has_three_rigid_modes():
    model = make_model(size=(0.05, 0.04), m=2.015)
    s = model.new_state()
    K = model.force_model.tangent(s).toarray()
    lam = np.sort(np.abs(np.linalg.eigvalsh(K)))
    rel = lam / lam[-1]
    assert np.all(rel[:3] < 1e-10), rel[:4]
    assert rel[3] > 1e-8, rel[:4]
    # the rigid modes: two translations and the rotation with theta = omega
    x = model.cloud.x
    for u, th in (
        (np.tile([1.0, 0.0], (len(x), 1)), np.zeros((len(x), 1))),
        (np.tile([0.0, 1.0], (len(x), 1)), np.zeros((len(x), 1))),
        homogeneous(x, 0.0, 0.0, 0.0, 1.0),
    ):
        q = np.concatenate([u, th], axis=1).ravel()
        assert np.abs(K @ q).max() < 1e-10 * lam[-1] * np.abs(q).max()


# -- 6. pair assembly == element assembly -----------------------------------------------
@pytest.mark.parametrize("broken", [False, True])
def test_pair_and_element_assembly_agree(broken):
    model = make_model()
    fm = model.force_model
    s = model.new_state()
    if broken:
        s.intact[:] = break_pairs(model, 0.2, np.random.default_rng(7))
    n = model.cloud.x.shape[0]
    b = fm.bonds
    k_pair = fm.tangent(s)
    blocks = fm.bond_blocks(s.intact)
    assert blocks.shape == (b.n_bonds, 6, 6)
    assert np.all(blocks[s.intact == 0] == 0)
    k_elem = element_assembly(b.bond_i, b.bond_j, blocks, n)
    diff = abs(k_pair - k_elem).max()
    assert diff < 1e-12 * abs(k_pair).max()
    # pair_stiffness is bond_blocks of intact bonds
    idx = np.array([0, 3, b.n_bonds // 2, b.n_bonds - 1])
    ref_blocks = fm.bond_blocks(np.ones(b.n_bonds, dtype=np.uint8))[idx]
    np.testing.assert_allclose(fm.pair_stiffness(idx), ref_blocks, rtol=1e-14, atol=0)


# -- 7. energy equivalence -----------------------------------------------------------------
def continuum_energy(plane, e11, e22, e12):
    e, nu = E, NU
    if plane == "strain":
        e, nu = E / (1 - NU**2), NU / (1 - NU)
    c = e / (1 - nu**2) * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])
    eps = np.array([e11, e22, 2 * e12])
    return 0.5 * eps @ c @ eps


@pytest.mark.parametrize("plane", ["stress", "strain"])
def test_energy_equivalence(plane):
    """Interior: points with no neighbour within the horizon of the boundary (the bond
    factors of the energy method average the point ratios of both ends, so points
    within 2 horizons of the boundary keep some of the boundary's correction)."""
    size = (0.16, 0.16)
    delta = 3.015 * DX
    ratios = {}
    for sc in (True, False):
        model = make_model(size=size, plane=plane, surface_correction=sc)
        fm = model.force_model
        s = model.new_state()
        x = model.cloud.x
        far = 2 * delta
        inner = np.all((x > far) & (x < np.array(size) - far), axis=1)
        assert inner.sum() >= 16
        for key, strain in (("mixed", (1e-3, -4e-4, 3e-4)), ("shear", (0.0, 0.0, 3e-4))):
            s.u[:], s["theta"][:] = homogeneous(x, *strain, 2e-4)
            w = fm.energy_density(s)[inner]
            ratios[sc, key] = w / continuum_energy(plane, *strain)
    for key in ("mixed", "shear"):
        assert np.all(np.abs(ratios[True, key] - 1) < 0.01), ratios[True, key]
        assert np.all(np.abs(ratios[False, key] - 1) > 0.05), ratios[False, key]


# -- 8. stable time step and explicit dynamics -------------------------------------------
@pytest.mark.parametrize(
    "kwargs",
    [{}, {"plane": "strain"}, {"nu": -0.5, "ratio": 1.0}, {"ratio": 0.0}, {"nu": 1.0 / 3.0}],
)
def test_stable_time_step_bounds_highest_frequency(kwargs):
    model = make_model(size=(0.08, 0.06), **kwargs)
    dt = model.stable_time_step()
    assert math.isfinite(dt) and dt > 0
    s = model.new_state()
    K = model.force_model.tangent(s).toarray()
    vol = model.cloud.volume
    mass = np.column_stack(
        [model.inertia(0) * vol, model.inertia(0) * vol, model.inertia(1) * vol]
    ).ravel()
    omega_max = math.sqrt(la.eigvalsh(K, np.diag(mass)).max())
    assert dt * omega_max < 2.0  # central-difference / Verlet stability


def test_explicit_run_conserves_energy():
    from peridynamics.solvers.explicit import ExplicitSolver

    model = make_model(size=(0.08, 0.06))
    # 0.1 x the stable step: the energy of velocity Verlet oscillates by O((omega dt)^2);
    # measured 3 % at 0.8 x the limit and 0.2 % at 0.2 x, so conservation to 1e-3 is
    # checked at 0.1 x (about 5e-4 expected)
    solver = ExplicitSolver(model, steps=200, safety_factor=0.1)
    s = solver.init()
    rng = np.random.default_rng(8)
    s.v[:] = rng.normal(size=s.v.shape) * 1e-3
    s["omega"][:] = rng.normal(size=s["omega"].shape) * 1e-3 / DX
    e0 = sum(model.state_energies(s))
    assert e0 > 0
    energies = []
    for st in solver.irun(s, 200):
        energies.append(sum(model.state_energies(st)))
    if not np.any(s["theta"] != 0):
        pytest.skip("ExplicitSolver does not integrate the rotations (theta stays 0)")
    assert np.isfinite(s.u).all() and np.isfinite(s["theta"]).all()
    assert np.abs(np.array(energies) - e0).max() < 1e-3 * e0


def test_explicit_deck_writes_rotation_and_moment(tmp_path):
    """A micropolar deck runs under explicit dynamics through the runner; the VTK frame,
    the probes and final_state.npz carry the rotation and the moment."""
    import json

    import meshio

    from peridynamics.app.run import Simulation
    from peridynamics.deck import parse_deck

    deck = parse_deck(
        {
            "name": "mp_explicit",
            "geometry": {"type": "rectangle", "size": [0.04, 0.01], "thickness": 0.01},
            "discretisation": {"spacing": 1.0e-3, "horizon_factor": 3.015},
            "material": {
                "model": "micropolar",
                "youngs_modulus": 200e9,
                "poisson_ratio": 0.2,
                "density": 7850.0,
            },
            "node_sets": {"left": {"edge": {"normal": [-1.0, 0.0]}}},
            "boundary_conditions": [
                {"type": "fixed", "set": "left"},
                {"type": "initial_velocity", "set": "all", "value": [0.0, "-2.0 * x / 0.04"]},
            ],
            "solver": {"steps": 40},
            "output": {
                "vtk_every": 20,
                "probes": [
                    {"name": "rot", "quantity": "rotation", "set": "all", "reduce": "min"},
                    {"name": "mom", "quantity": "moment", "set": "left", "reduce": "sum"},
                ],
            },
        }
    )
    summary = Simulation.from_deck(deck).run(tmp_path, quiet=True, progress=False)
    probes = summary["results"]["probes"]
    assert probes["rot"]["values"][-1] < 0.0  # the beam bends down: clockwise rotation
    assert abs(probes["mom"]["values"][-1]) > 0.0
    frame = meshio.read(sorted(tmp_path.glob("frame_*.vtu"))[-1])
    assert {"rotation", "moment_density"} <= set(frame.point_data)
    final = np.load(tmp_path / "final_state.npz")
    assert final["theta"].shape == (len(final["x"]), 1)
    assert np.all(final["theta"][final["x"][:, 0] < 1e-3] == 0.0)  # clamped rotations
    assert json.loads((tmp_path / "summary.json").read_text())["status"] == "completed"
