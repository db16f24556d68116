"""Bond-based peridynamic heat conduction (docs/theory_thermal.md): kernels against
their NumPy twins, the micro-conductivity, the stable step, the 1-D and 2-D series
solutions, the energy balance, the steady state and the deck."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from peridynamics.bonds import build_bonds
from peridynamics.evaluation.heat import HeatConduction, micro_conductivity, point_conductivity
from peridynamics.geometry.cloud import PointCloud
from peridynamics.kernels import heat as kh
from peridynamics.kernels import reference_heat as ref
from peridynamics.loading.thermal import (
    MirroredTemperature,
    PrescribedTemperature,
    flux_as_source,
    mirror_points,
)
from peridynamics.solvers.base import run_solver
from peridynamics.solvers.heat import HeatSolver, SteadyHeatSolver


def grid(n: tuple[int, ...], dx: float, lo: int = 0, thick: float = 1e-3) -> PointCloud:
    """Points at i * dx, i = lo .. n_a - lo (a layer of -lo rows beyond [0, n dx])."""
    axes = [np.arange(lo, na - lo + 1) * dx for na in n]
    x = np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, len(n))
    dim = len(n)
    cs = {1: 1e-4, 2: thick, 3: 1.0}[dim]
    vol = dx**dim * (cs if dim < 3 else 1.0)
    return PointCloud(x=x, volume=np.full(len(x), vol), spacing=dx, cross_section=cs,
                      plane="stress" if dim == 2 else None)  # fmt: skip


def series_1d(x: np.ndarray, t: float, length: float, alpha: float) -> np.ndarray:
    """Carslaw & Jaeger (1959), sec. 3.3: theta = 1 - sum_odd 4/(n pi) sin(n pi x/L)
    exp(-n^2 pi^2 alpha t / L^2) for T(0) = 0, T = 1 on both ends."""
    n = np.arange(1, 4000, 2)[:, None]
    decay = np.exp(-((n * np.pi / length) ** 2) * alpha * t)
    return 1.0 - np.sum(4.0 / (n * np.pi) * np.sin(n * np.pi * x / length) * decay, axis=0)


def _step_problem(cloud: PointCloud, m: int, length: float, corr: bool, t_end: float) -> tuple:
    bonds = build_bonds(cloud, m * cloud.spacing * 1.005, "truncated")
    hc = HeatConduction(cloud, bonds, 1.0, 1.0, 1.0, correction="surface" if corr else "none")
    x = cloud.x
    eps = 1e-9 * length
    held = np.flatnonzero(np.any((x <= eps) | (x >= length - eps), axis=1))
    solver = HeatSolver(hc, None, 0.0, [PrescribedTemperature(held, 1.0)], end_time=t_end)
    s = run_solver(solver)
    free = np.setdiff1d(np.arange(len(x)), held)
    return s, free


def bar_error(n: int, m: int, corr: bool = False, t_end: float = 0.02) -> float:
    """Max error of the bar [0, 1] (a held layer of m points beyond each end)."""
    cloud = grid((n,), 1.0 / n, lo=-m)
    s, free = _step_problem(cloud, m, 1.0, corr, t_end)
    exact = series_1d(cloud.x[free, 0], s.t, 1.0, 1.0)
    return float(np.max(np.abs(s["T"][free] - exact)))


def mirrored_step(n: int, m: int, dim: int, t_end: float = 0.02) -> float:
    """Max error of the unit bar (dim 1) or square (dim 2) whose ends / edges are
    mirrored layers about T_b = 1 (a bulk-calibrated kappa), against the series."""
    cloud = grid((n,) * dim, 1.0 / n, lo=-m, thick=1.0)
    x, eps = cloud.x, 1e-9
    bonds = build_bonds(cloud, m * cloud.spacing * 1.005, "truncated")
    hc = HeatConduction(cloud, bonds, 1.0, 1.0, 1.0, correction="bulk")
    conds = []
    for a in range(dim):
        for side, sel in ((0.0, x[:, a] <= eps), (1.0, x[:, a] >= 1 - eps)):
            nodes = np.flatnonzero(sel)
            normal = np.eye(dim)[a] * (1 if side else -1)
            mirror = mirror_points(nodes, x, cloud.spacing, np.full(dim, side), normal)
            conds.append(MirroredTemperature(nodes, mirror, 1.0))
    s = run_solver(HeatSolver(hc, None, 0.0, conds, end_time=t_end))
    free = np.all((x > eps) & (x < 1 - eps), axis=1)
    theta = np.prod([1 - series_1d(x[free, a], s.t, 1.0, 1.0) for a in range(dim)], axis=0)
    return float(np.max(np.abs(s["T"][free] - (1 - theta))))


def test_kernels_match_numpy_twins() -> None:
    rng = np.random.default_rng(1)
    cloud = grid((7, 6), 1e-3)
    bonds = build_bonds(cloud, 3.015e-3)
    g = rng.random(bonds.n_bonds)
    mu = (rng.random(bonds.n_bonds) > 0.2).astype(np.uint8)
    t = rng.random(cloud.n_points) * 100
    out = np.empty(cloud.n_points)
    kh.heat_rate(t, bonds.offsets, bonds.bond_j, g, mu, out)
    np.testing.assert_allclose(
        out, ref.heat_rate(t, bonds.bond_i, bonds.bond_j, g, mu), rtol=1e-13, atol=1e-12
    )
    kh.conductance_row_sum(bonds.offsets, g, mu, out)
    np.testing.assert_allclose(
        out, ref.conductance_row_sum(cloud.n_points, bonds.bond_i, g, mu), rtol=1e-13
    )


@pytest.mark.parametrize("dim", [1, 2, 3])
def test_micro_conductivity_gives_k_in_the_bulk(dim: int) -> None:
    """The effective conductivity 1/2 sum G xi_x^2 of a full family tends to k as m =
    delta/dx grows (the quadrature of the constant kappa); the surface correction makes
    it k to round-off at every point, and then L (x^2) = 2 k exactly in the interior."""
    m = {1: 40, 2: 12, 3: 4}[dim]
    n = 4 * m + 2  # the centre's neighbours have whole families
    cloud = grid((n,) * dim, 1e-3)
    bonds = build_bonds(cloud, m * 1e-3 * 1.0001, "truncated")
    k = 3.0
    centre = int(np.argmin(np.linalg.norm(cloud.x - cloud.x.mean(axis=0), axis=1)))
    raw = HeatConduction(cloud, bonds, k, 1.0, 1.0, correction="none")
    k_raw = point_conductivity(bonds, raw.conductance, cloud.n_points, dim)[:, centre]
    assert k_raw == pytest.approx(np.full(dim, k), rel=0.15)  # 3-D, m = 4: -14 %
    hc = HeatConduction(cloud, bonds, k, 1.0, 1.0, correction="surface")
    k_pt = point_conductivity(bonds, hc.conductance, cloud.n_points, dim)
    assert k_pt[:, centre] == pytest.approx(np.full(dim, k), rel=1e-12)
    rate = hc.rate(np.sum(cloud.x**2, axis=1), bonds.bond_intact, np.empty(cloud.n_points))
    assert rate[centre] == pytest.approx(2 * k * dim, rel=1e-10)
    assert micro_conductivity(k, dim, 1.0, 1.0) == pytest.approx(
        {1: 2 * k, 2: 6 * k / np.pi, 3: 6 * k / np.pi}[dim]
    )


def test_stable_step_bounds_the_spectrum() -> None:
    cloud = grid((12, 9), 1e-3)
    bonds = build_bonds(cloud, 3.015e-3)
    hc = HeatConduction(cloud, bonds, 50.0, 7800.0, 450.0)
    a = (hc.matrix(bonds.bond_intact).toarray().T * hc.inv_capacity).T
    lam = np.linalg.eigvals(a)
    assert np.max(np.abs(lam.imag)) < 1e-9 * np.max(np.abs(lam.real))
    dt = hc.stable_time_step(bonds.bond_intact)
    assert dt * np.max(-lam.real) <= 2.0  # forward Euler is stable at dt
    assert dt * np.max(-lam.real) > 0.5  # and the bound is not far below the limit


def test_bar_with_mirrored_ends_converges_at_second_order() -> None:
    """delta = 3 dx, mirrored layers: errors 7.6e-3 .. 1.3e-4, rates 1.88, 1.92, 2.04."""
    errs = [mirrored_step(n, 3, 1) for n in (20, 40, 80, 160)]
    rates = np.log2(np.array(errs[:-1]) / errs[1:])
    assert errs[-1] < 2e-4
    assert np.all(rates > 1.8)


def test_plate_with_mirrored_edges_against_the_product_series() -> None:
    """The unit square, delta = 3 dx, against the product of two 1-D series: errors
    1.48e-2, 4.81e-3, 1.27e-3 at 12, 24, 48 spacings; rates 1.62, 1.92."""
    errs = [mirrored_step(n, 3, 2) for n in (12, 24, 48)]
    rates = np.log2(np.array(errs[:-1]) / errs[1:])
    assert errs[-1] < 1.5e-3
    assert np.all(rates > 1.5)


def test_bar_step_temperature_converges_to_the_series() -> None:
    """delta = 3 dx, a constant held layer: the error falls like dx (observed rate 0.99):
    constant data in the layer give an O(delta) boundary layer."""
    errs = [bar_error(n, 3) for n in (20, 40, 80, 160)]
    rates = np.log2(np.array(errs[:-1]) / errs[1:])
    assert errs[-1] < 0.012
    assert np.all(rates > 0.85)


@pytest.mark.slow
def test_bar_delta_convergence_at_fixed_dx_ratio_and_fixed_delta() -> None:
    """delta fixed, dx -> 0: the error tends to the nonlocal model's (no convergence to
    the local solution): constant layer 0.028, 0.040, 0.046, mirrored layers 9.9e-4,
    2.2e-4, 1.7e-4 (dx = 1/60, 1/120, 1/240; delta = 0.05)."""
    fixed = [bar_error(n, n // 20) for n in (60, 120, 240)]  # delta = 0.05
    assert fixed[2] > 0.03
    assert fixed[2] - fixed[1] < fixed[1] - fixed[0]  # tends to the nonlocal limit
    mirrored = [mirrored_step(n, n // 20, 1) for n in (60, 120, 240)]
    assert mirrored[-1] < 3e-4
    assert mirrored[1] / mirrored[2] < 1.5  # saturated at the nonlocal model's error


def test_plate_step_temperature_against_the_product_series() -> None:
    n, m, length, t_end = 24, 3, 1.0, 0.02
    cloud = grid((n, n), length / n, lo=-m, thick=1.0)
    s, free = _step_problem(cloud, m, length, False, t_end)
    x = cloud.x[free]
    theta = (1 - series_1d(x[:, 0], s.t, 1.0, 1.0)) * (1 - series_1d(x[:, 1], s.t, 1.0, 1.0))
    err = np.max(np.abs(s["T"][free] - (1 - theta)))
    assert err < 0.1  # measured 0.080 (the bar: 0.041 at n = 40, rate 1)


def test_energy_balance_with_prescribed_flux() -> None:
    """Heat in through the flux boundaries = heat stored, to round-off."""
    cloud = grid((20, 10), 1e-3)
    bonds = build_bonds(cloud, 3.015e-3)
    hc = HeatConduction(cloud, bonds, 40.0, 7800.0, 450.0)
    left = np.flatnonzero(cloud.x[:, 0] < 0.5e-3)
    right = np.flatnonzero(cloud.x[:, 0] > 19.5e-3)
    src = [flux_as_source(left, 2e5, cloud.x, 1e-3), flux_as_source(right, 5e4, cloud.x, 1e-3)]
    solver = HeatSolver(hc, None, 300.0, sources=src, steps=400)
    s = run_solver(solver)
    bal = solver.heat_balance(s)
    assert bal["heat_stored_J"] == pytest.approx(bal["heat_in_J"], rel=1e-10)
    area = 11 * 1e-3 * 1e-3  # face length (11 rows) x thickness
    assert bal["heat_in_J"] == pytest.approx((2e5 + 5e4) * area * s.t, rel=1e-12)


def test_steady_state_with_linear_boundary_is_linear() -> None:
    n, m = 20, 3
    cloud = grid((n, n), 1e-3, lo=-m)
    bonds = build_bonds(cloud, m * 1e-3 * 1.005)
    hc = HeatConduction(cloud, bonds, 10.0, 1.0, 1.0, correction="none")
    x = cloud.x
    held = np.flatnonzero(np.any((x <= 1e-9) | (x >= n * 1e-3 - 1e-9), axis=1))
    linear = 300.0 + 2e3 * x[:, 0] - 5e2 * x[:, 1]
    temps = [PrescribedTemperature(np.array([k]), float(linear[k])) for k in held]
    solver = SteadyHeatSolver(hc, None, 0.0, temps)
    s = run_solver(solver)
    assert np.max(np.abs(s["T"] - linear)) < 1e-9 * 300
    mirrored = []  # the constraint rows of mirrored layers: uniform 350 K
    for a in range(2):
        for side, sel in ((0.0, x[:, a] <= 1e-9), (n * 1e-3, x[:, a] >= n * 1e-3 - 1e-9)):
            nodes = np.flatnonzero(sel)
            normal = np.eye(2)[a] * (1 if side else -1)
            mirror = mirror_points(nodes, x, 1e-3, np.full(2, side), normal)
            mirrored.append(MirroredTemperature(nodes, mirror, 350.0))
    s = run_solver(SteadyHeatSolver(hc, None, 0.0, mirrored))
    assert np.max(np.abs(s["T"] - 350.0)) < 1e-9 * 350


def test_broken_bonds_do_not_conduct() -> None:
    cloud = grid((10, 4), 1e-3)
    bonds = build_bonds(cloud, 3.015e-3)
    hc = HeatConduction(cloud, bonds, 10.0, 1.0, 1.0)
    xi, xj = cloud.x[bonds.bond_i, 0], cloud.x[bonds.bond_j, 0]
    intact = ((xi - 4.5e-3) * (xj - 4.5e-3) > 0).astype(np.uint8)  # a crack at x = 4.5 mm
    t = np.where(cloud.x[:, 0] < 4.5e-3, 400.0, 300.0)
    out = hc.rate(t, intact, np.empty(cloud.n_points))
    assert np.all(out == 0.0)


def test_convection_cools_towards_the_ambient_and_bounds_the_step() -> None:
    """A plate at 400 K convecting on one edge to 300 K: the heat lost equals the
    integral of h (T - T_inf) over the face (the sources' bookkeeping), and the stable
    step includes h / l."""
    cloud = grid((10, 5), 1e-3)
    bonds = build_bonds(cloud, 3.015e-3)
    hc = HeatConduction(cloud, bonds, 40.0, 7800.0, 450.0)
    edge = np.flatnonzero(cloud.x[:, 0] > 9.5e-3)
    from peridynamics.loading.thermal import convection_on_layer

    cv = convection_on_layer(edge, 5e4, 300.0, cloud.x, 1e-3)
    assert cv.layer == pytest.approx(1e-3)
    solver = HeatSolver(hc, None, 400.0, convection=[cv], steps=300)
    assert solver.stable_time_step < hc.stable_time_step(bonds.bond_intact)
    s = run_solver(solver)
    bal = solver.heat_balance(s)
    assert bal["heat_in_J"] < 0
    assert bal["heat_stored_J"] == pytest.approx(bal["heat_in_J"], rel=1e-10)
    assert np.all((s["T"] > 300.0) & (s["T"] < 400.0 + 1e-9))


DECK = """
name: heat_deck
geometry: {type: rectangle, size: [0.02, 0.01], thickness: 1.0e-3, plane: stress}
discretisation: {spacing: 1.0e-3, horizon_factor: 3.015}
material: {youngs_modulus: 70.0e9, density: 2700.0}
node_sets:
  left: {edge: {normal: [-1.0, 0.0]}}
  right: {edge: {normal: [1.0, 0.0]}}
thermal:
  conductivity: 237.0
  specific_heat: 900.0
  initial_temperature: 300.0
  conditions:
    - {type: temperature, set: left, value: 400.0}
    - {type: convection, set: right, film: 100.0, ambient: 300.0}
solver: {type: heat_steady}
output: {fields: [temperature]}
"""


def test_deck_steady_run_and_refusals() -> None:
    """The deck builds a steady heat solve (T between the ambient and the hot edge);
    the Warp backend, a thermal section with a mechanical solver and mechanical
    conditions with a heat solver are refused by key."""
    from peridynamics.build.simulation import SimulationSetup
    from peridynamics.deck import DeckError, parse_deck, yaml_load

    def parse(text: str) -> Any:
        return parse_deck(yaml_load(text))

    deck = parse(DECK)
    setup = SimulationSetup.from_deck(deck)
    s = run_solver(setup.solver)
    assert s["T"].min() > 300.0 and s["T"].max() == pytest.approx(400.0)
    for text, key in (
        (DECK.replace("{type: heat_steady}", "{type: heat, steps: 5, backend: warp}"), "backend"),
        (DECK.replace("{type: heat_steady}", "{steps: 5}"), "thermal"),
        (
            DECK.replace(
                "solver: {type: heat_steady}",
                "boundary_conditions: [{type: fixed, set: left}]\nsolver: {type: heat_steady}",
            ),
            "boundary_conditions",
        ),
    ):
        with pytest.raises(DeckError, match=key):
            parse(text)
