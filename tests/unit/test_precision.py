"""solver.precision: float32 -- the float32 PMB pass against the float64 twin."""

from __future__ import annotations

import numpy as np
import pytest

from peridynamics import BondBasedMaterial, Evaluator, build_bonds
from peridynamics.damage import family_minimum
from peridynamics.geometry import PointCloud, box, rectangle
from peridynamics.kernels import reference
from peridynamics.kernels.bond_based_f32 import force_f32


def jittered(dim: int, offset: float, seed: int = 0):
    rng = np.random.default_rng(seed)
    dx = 1e-3
    cloud = rectangle((0.02, 0.015), dx, thickness=1e-3) if dim == 2 else box((0.008,) * 3, dx)
    x = cloud.x + rng.uniform(-0.2, 0.2, cloud.x.shape) * dx + offset
    return PointCloud(
        x=x, volume=cloud.volume, spacing=dx, cross_section=cloud.cross_section, plane=cloud.plane
    )


def f32_force(cloud, b, k, u, intact, s0=None):
    n, x = cloud.n_points, cloud.x
    s0 = np.full(n, np.inf) if s0 is None else s0
    out = np.zeros((n, cloud.dim), np.float32)
    nb = force_f32(
        np.ascontiguousarray(x - x.mean(0), dtype=np.float32), u.astype(np.float32), b.offsets,
        b.bond_j, k.astype(np.float32), intact, s0.astype(np.float32),
        family_minimum(b, s0).astype(np.float32), out, np.zeros(n, np.int64),
    )  # fmt: skip
    return out.astype(np.float64), nb


@pytest.mark.parametrize("dim", [2, 3])
def test_float32_pass_matches_the_float64_twin_far_from_the_origin(dim):
    # 0.5 m from the origin, u ~ 1e-8 m: x + u in float32 keeps no digit of u
    cloud = jittered(dim, offset=0.5)
    b = build_bonds(cloud, 3.015e-3)
    rng = np.random.default_rng(1)
    k = rng.uniform(0.5, 2.0, b.n_bonds) * 1e14
    u = rng.normal(0.0, 1e-8, cloud.x.shape)
    intact = (rng.random(b.n_bonds) > 0.1).astype(np.uint8)
    f, nb = f32_force(cloud, b, k, u, intact)
    ref = reference.force(cloud.x, u, b.bond_i, b.bond_j, b.bond_length, k, intact)
    err = np.abs(f - ref).max() / np.abs(ref).max()
    assert nb == 0
    assert err < 1e-5  # measured 1.4e-7 (2-D), 1.6e-7 (3-D)
    # the naive float32 stretch, (|x_j + u_j - x_i - u_i| - |xi|) / |xi|, has no digit left
    x32, u32 = cloud.x.astype(np.float32), u.astype(np.float32)
    e = (x32[b.bond_j] + u32[b.bond_j]) - (x32[b.bond_i] + u32[b.bond_i])
    d = x32[b.bond_j] - x32[b.bond_i]
    naive = np.linalg.norm(e, axis=1) / np.linalg.norm(d, axis=1) - 1
    exact = reference.stretch(cloud.x, u, b.bond_i, b.bond_j, b.bond_length)
    assert np.abs(naive - exact).max() >= 0.9 * np.abs(exact).max()  # naive: no digit


@pytest.mark.parametrize("dim", [2, 3])
def test_float32_breaking_is_symmetric_and_close_to_float64(dim):
    cloud = jittered(dim, offset=0.0, seed=3)
    b = build_bonds(cloud, 3.015e-3)
    rng = np.random.default_rng(4)
    u = rng.normal(0.0, 3e-5, cloud.x.shape)
    s = reference.stretch(cloud.x, u, b.bond_i, b.bond_j, b.bond_length)
    s0 = np.full(cloud.n_points, float(np.quantile(s, 0.9)))
    intact = np.ones(b.n_bonds, np.uint8)
    _, nb = f32_force(cloud, b, np.ones(b.n_bonds) * 1e14, u, intact, s0)
    broken = intact == 0
    assert nb == broken.sum() > 100
    assert np.array_equal(broken, broken[b.reverse_index()])  # (i, j) and (j, i) together
    expected = s >= s0[0]
    differ = np.count_nonzero(broken != expected)
    assert differ <= 0.01 * expected.sum()  # 2 of 698 here: at s0 within float32 rounding
    near = np.abs(s[broken != expected] - s0[0]) <= 1e-5 * s0[0]
    assert near.all()


def test_deck_precision_float32_runs_and_other_models_are_refused(tmp_path):
    from peridynamics.app.run import Simulation
    from peridynamics.build.errors import SetupError
    from peridynamics.deck import load_deck

    text = """
name: f32
geometry: {type: rectangle, size: [0.02, 0.01], thickness: 0.001}
discretisation: {spacing: 0.001, horizon_factor: 3.015}
material: {model: pmb, youngs_modulus: 70.0e9, density: 2500.0}
damage: {critical_stretch: 0.002}
boundary_conditions:
  - {type: initial_velocity, set: all, value: [0.0, 1.0]}
solver: {type: explicit, steps: 20, precision: float32}
"""
    deck = tmp_path / "d.yaml"
    deck.write_text(text)
    sim = Simulation.from_deck(load_deck(deck))
    assert sim.model.force_model.precision == "float32"
    assert sim.model.force_model.stiffness.dtype == np.float32
    deck.write_text(text.replace("model: pmb", "model: lps, poisson_ratio: 0.25"))
    with pytest.raises(SetupError, match="solver.precision"):
        Simulation.from_deck(load_deck(deck))


def test_float32_model_run_tracks_float64(tmp_path):
    from peridynamics.solvers import ExplicitSolver

    cloud = rectangle((0.03, 0.01), 5e-4, thickness=1e-3)
    runs = []
    for precision in ("float64", "float32"):
        model = Evaluator(cloud, build_bonds(cloud, 3.015 * 5e-4), BondBasedMaterial(70e9, 2500.0))
        if precision == "float32":
            model.force_model.set_precision("float32")
        solver = ExplicitSolver(model)
        s = solver.init()
        s.v[:, 0] = np.where(cloud.x[:, 0] > 0.015, 1.0, -1.0)
        solver.run(s, 200)
        runs.append(s.u.copy())
    err = np.abs(runs[1] - runs[0]).max() / np.abs(runs[0]).max()
    assert err < 2e-5  # measured 1.9e-6
