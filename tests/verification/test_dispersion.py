"""Dispersion relations (issue 3): paper numbers, Bloch waves from real bond lists,
simulated waves, the FDM limit and the trends stated in Lu & Wang (2016) and PD wave
dispersion (n.d.) (references: docs/references.md)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from peridynamics.analysis import dispersion as dsp
from peridynamics.bonds import build_bonds
from peridynamics.evaluation import Evaluator
from peridynamics.families.pmb import BondBasedMaterial
from peridynamics.geometry import bar, rectangle
from peridynamics.solvers import ExplicitSolver
from tests.helpers import cli

E, RHO = 20e9, 2620.0
V0 = math.sqrt(E / RHO)


# ------------------------------------------------------------- the papers' numbers
def test_seed003_1d_numbers() -> None:  # PD wave dispersion (n.d.), eqs 17-21, Figs 2-3
    d = dsp.semi_discrete_1d([0.0, 0.2, 0.25, 0.5, 1.0, 1.5], 3.015)
    np.testing.assert_allclose(
        d.v_over_v0, [1.14896, 0.78270, 0.64508, 0.34481, 0.0, 0.11494], atol=6e-6
    )
    fine = dsp.semi_discrete_1d(np.linspace(0, 1, 20001), 3.015)
    k = int(np.argmax(fine.omega_over_omega0))
    assert fine.omega_over_omega0[k] == pytest.approx(1.08325, abs=5e-6)
    assert fine.N_h[k] == pytest.approx(0.5, abs=1e-4)
    crossing = fine.N_h[np.argmax(fine.v_over_v0 < 1.0)]
    assert crossing == pytest.approx(0.11892, abs=1e-4)  # the "critical point"
    np.testing.assert_allclose(
        dsp.zero_group_velocity_points_1d(3.015), [0.25, 1 / 3, 0.5, 2 / 3, 0.75], atol=1e-10
    )
    np.testing.assert_array_equal(dsp.zero_energy_points_1d(2), [1.0, 2.0])


@pytest.mark.parametrize(
    ("theta", "expected"),
    [
        (0.0, [0.81528, 0.39279, 0.0, 0.13093]),
        (30.0, [0.81906, 0.42212, 0.21088, 0.13439]),
        (45.0, [0.81772, 0.40065, 0.19870, 0.06742]),
    ],
)
def test_seed003_2d_numbers(theta: float, expected: list[float]) -> None:  # idem, eq. 32
    d = dsp.semi_discrete_2d([0.0, 0.25, 0.5, 1.0, 1.5], 3.015, theta)
    assert d.v_over_v0[0] == pytest.approx(1.24020, abs=5e-6)
    np.testing.assert_allclose(d.v_over_v0[1:], expected, atol=6e-6)
    assert len(dsp.lattice_family_2d(3.015)) == 28


def test_seed000_sample_table() -> None:  # Lu & Wang (2016), eq. 12; Hz, dx 5 mm, dt 1 us
    table = {
        100: [43653, 42976, 41874, 40387],
        200: [85346, 80179, 72417, 63186],
        400: [153938, 121915, 89097, 68645],
    }
    for k, row in table.items():
        f = [
            float(dsp.fully_discrete_1d(k, 0.005, m, 1e-6, E, RHO)) / (2 * np.pi)
            for m in (1, 2, 3, 4)
        ]
        np.testing.assert_allclose(f, row, atol=0.6)


def test_continuous_limit_of_the_discrete_relation() -> None:
    x = np.array([0.5, 2.0, 5.0, 10.0])  # kappa delta
    m = 400.0
    d = dsp.semi_discrete_1d(x / (2 * np.pi * m), m)
    np.testing.assert_allclose(d.v_over_v0, dsp.continuous_1d(x), rtol=5e-3)
    assert dsp.continuous_1d([1e-6])[0] == pytest.approx(1.0, abs=1e-6)


# ------------------------------------------------------------------ FDM limit, m = 1
def test_m1_equals_central_difference_fdm_exactly() -> None:
    k = np.linspace(1.0, np.pi / 0.005, 200)
    for dt in (1e-6, 5e-7, 1e-7):
        pd = dsp.fully_discrete_1d(k, 0.005, 1, dt, E, RHO)
        fd = dsp.fdm_1d(k, 0.005, dt, E, RHO)
        np.testing.assert_array_equal(pd, fd)


# ------------------------------------------------ Bloch waves from the engine's bonds
def _bar_model(dx: float, horizon: float, rule: str) -> Evaluator:
    cloud = bar(201 * dx, dx, area=1e-4)
    return Evaluator(cloud, build_bonds(cloud, horizon, rule), BondBasedMaterial(E, RHO))


def test_bloch_1d_equals_seed003_closed_form() -> None:
    h = 1e-3
    model = _bar_model(h, 3.015 * h, "none")
    nh = np.linspace(0.01, 2.0, 300)
    omega = dsp.bloch_dispersion(model, 100, (2 * np.pi * nh / h)[:, None])
    closed = dsp.semi_discrete_1d(nh, 3.015)
    np.testing.assert_allclose(omega * h / V0, closed.omega_over_omega0, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(
        omega / (2 * np.pi * nh / h) / V0, closed.v_over_v0, rtol=1e-10, atol=1e-12
    )  # atol: the zero-energy points are exact zeros


@pytest.mark.parametrize("m", [1, 2, 3, 4])
def test_bloch_1d_truncated_equals_seed000_stencil(m: int) -> None:
    dx = 5e-3
    model = _bar_model(dx, m * dx, "truncated")
    k = np.linspace(1.0, np.pi / dx, 200)
    omega = dsp.bloch_dispersion(model, 100, k[:, None])
    np.testing.assert_allclose(omega, dsp.semi_discrete_omega_1d(k, dx, m, E, RHO), rtol=1e-10)
    if m == 1:  # delta = dx: exactly the second-order finite-difference operator
        np.testing.assert_allclose(omega, 2 * V0 / dx * np.sin(k * dx / 2), rtol=1e-12)


@pytest.mark.parametrize("theta", [0.0, 30.0, 45.0, 77.0])
def test_bloch_2d_equals_seed003_eq32(theta: float) -> None:
    h = 1e-3
    cloud = rectangle((21 * h, 21 * h), h, thickness=2e-3)
    model = Evaluator(cloud, build_bonds(cloud, 3.015 * h, "none"), BondBasedMaterial(E, RHO))
    centre = int(np.argmin(np.sum((cloud.x - 10.5 * h) ** 2, axis=1)))
    nh = np.linspace(0.01, 2.0, 200)
    b = np.array([math.cos(math.radians(theta)), math.sin(math.radians(theta))])
    omega = dsp.bloch_dispersion(model, centre, np.outer(2 * np.pi * nh / h, b))
    closed = dsp.semi_discrete_2d(nh, 3.015, theta)
    np.testing.assert_allclose(omega * h / V0, closed.omega_over_omega0, rtol=1e-10, atol=1e-12)
    tensor = dsp.bloch_dispersion(model, centre, np.outer(2 * np.pi * nh[:3] / h, b), "tensor")
    assert tensor.shape == (3, 2)
    # long waves of the full bond-based operator: transverse sqrt(3/8), longitudinal
    # sqrt(9/8) of sqrt(E/rho) in plane stress (nu = 1/3); the discrete lattice family with
    # full volumes is 2-4 % stiffer than the continuum (see the patch tests)
    ratio = tensor[0] / (2 * np.pi * nh[0] / h) / V0
    np.testing.assert_allclose(ratio, [math.sqrt(3 / 8), math.sqrt(9 / 8)], rtol=0.03)


# -------------------------------------------------------------- a simulated wave
@pytest.mark.parametrize("n_h", [0.04, 0.08, 0.15])
def test_simulated_wave_travels_at_the_predicted_phase_velocity(n_h: float) -> None:
    h = 1e-3
    model = _bar_model(h, 3.015 * h, "none")
    x = model.cloud.x[:, 0]
    kappa = 2 * math.pi * n_h / h
    v_pred = float(dsp.semi_discrete_1d([n_h], 3.015).v_over_v0[0]) * V0
    omega = kappa * v_pred
    solver = ExplicitSolver(model, safety_factor=0.1)
    s = solver.init()
    amp = 1e-9
    s.u[:, 0] = amp * np.cos(kappa * x)  # u = a cos(kappa x - omega t)
    s.v[:, 0] = amp * omega * np.sin(kappa * x)
    model.internal_force(s.u, s.intact, s.force, s.max_stretch)
    centre = int(np.argmin(np.abs(x - x.mean())))
    # end effects reach the centre after ~ (L/2) / max group speed (1.15 v0); stop before
    n = int(0.8 * (x.mean() - x[0]) / (1.2 * V0) / solver.dt)
    t, u = [], []
    for st in solver.irun(s, n):
        t.append(st.t)
        u.append(st.u[centre, 0])
    t, u = np.array(t), np.array(u)

    # least-squares fit of the phase: u = a cos(kx_c) cos(wt) + a sin(kx_c) sin(wt)
    def misfit(w: float) -> float:
        basis = np.column_stack([np.cos(w * t), np.sin(w * t)])
        coef, res, *_ = np.linalg.lstsq(basis, u, rcond=None)
        return float(np.sum((basis @ coef - u) ** 2))

    ws = np.linspace(0.9 * omega, 1.1 * omega, 801)
    w_fit = ws[np.argmin([misfit(w) for w in ws])]
    assert ws[0] < w_fit < ws[-1]  # a real minimum, not the edge of the search window
    assert w_fit / kappa == pytest.approx(v_pred, rel=0.01)
    assert abs(v_pred / V0 - 1) > 0.05  # PD dispersion, not the local speed, is measured


def test_zero_energy_mode_does_not_propagate() -> None:
    h = 1e-3
    model = _bar_model(h, 3.015 * h, "none")
    x = model.cloud.x[:, 0]
    solver = ExplicitSolver(model)
    s = solver.init()
    interior = (x > 0.02) & (x < x.max() - 0.02)
    s.u[:, 0] = 1e-9 * np.where(interior, np.cos(2 * np.pi * x / h), 0.0)  # N_h = 1
    u0 = s.u.copy()
    model.internal_force(s.u, s.intact, s.force, s.max_stretch)
    deep = (x > 0.03) & (x < x.max() - 0.03)
    assert np.abs(s.force[deep]).max() < 1e-6 * np.abs(s.force).max()
    solver.run(s, 100)
    far = (x > 0.1) & (x < x.max() - 0.1)
    np.testing.assert_allclose(s.u[far], u0[far], rtol=0, atol=1e-6 * 1e-9)


# ----------------------------------------------------------------------- the trends
def _phase_error(k: float, dx: float, m: int, dt: float) -> float:
    return abs(float(dsp.fully_discrete_1d(k, dx, m, dt, E, RHO)) / k / V0 - 1)


def test_trends_of_seed000() -> None:
    k = 200.0
    at_fixed_dx = [_phase_error(k, 0.005, m, 1e-6) for m in (1, 2, 3, 4)]
    assert np.all(np.diff(at_fixed_dx) > 0)  # grows with m at fixed dx
    at_fixed_m = [_phase_error(k, dx, 3, 1e-6) for dx in (0.02, 0.015, 0.01, 0.005)]
    assert np.all(np.diff(at_fixed_m) < 0)  # shrinks as dx is refined at fixed m
    at_fixed_delta = [_phase_error(k, 0.02 / m, m, 1e-6) for m in (1, 2, 3, 4)]
    assert np.all(np.diff(at_fixed_delta) < 0)  # shrinks with m at fixed delta
    # nearly insensitive to dt below the stability limit (2.9 us here): from 1 to 0.1 us
    # the frequency at k = 200 rad/m moves by 0.7 % of the exact value (measured)
    by_dt = [
        float(dsp.fully_discrete_1d(k, 0.005, 3, dt, E, RHO)) for dt in (1e-6, 5e-7, 2e-7, 1e-7)
    ]
    assert (max(by_dt) - min(by_dt)) / (k * V0) < 0.01


def test_45_degree_symmetry_in_2d() -> None:
    nh = np.linspace(0, 2, 101)
    for theta in (5.0, 20.0, 33.0):
        ref = dsp.semi_discrete_2d(nh, 3.015, theta).v_over_v0
        for other in (90 - theta, -theta, 180 - theta, theta + 90):
            np.testing.assert_allclose(
                dsp.semi_discrete_2d(nh, 3.015, other).v_over_v0, ref, rtol=1e-12, atol=1e-14
            )
    idx = dsp.oscillation_index_2d(thetas_deg=np.arange(0, 360, 5.0), samples=401)
    k = np.arange(len(idx))
    np.testing.assert_allclose(idx, idx[(18 - k) % 72], rtol=1e-9)  # mirror about 45 deg
    np.testing.assert_allclose(idx, np.roll(idx, 18), rtol=1e-9)  # period 90 deg
    assert idx.max() > 1.2 * idx.min()  # the index does depend on the direction


def test_advice_meets_the_tolerance() -> None:
    adv = dsp.advise_1d(1e5, 0.01, E, RHO)
    assert adv.m == 3 and adv.max_phase_error <= 0.01
    dt = 0.8 * adv.spacing / V0 * dsp._stable_fraction_1d(adv.m)
    k = np.linspace(1.0, 2 * np.pi * 1e5 / V0, 200)
    err = np.abs(dsp.fully_discrete_1d(k, adv.spacing, adv.m, dt, E, RHO) / k / V0 - 1)
    assert err.max() <= 0.0101
    # a 5 % coarser grid breaks the tolerance (the advice is the coarsest)
    dx2 = 1.05 * adv.spacing
    dt2 = 0.8 * dx2 / V0 * dsp._stable_fraction_1d(adv.m)
    k2 = np.linspace(1.0, 1.05 * 2 * np.pi * 1e5 / V0, 400)
    err2 = np.abs(dsp.fully_discrete_1d(k2, dx2, adv.m, dt2, E, RHO) / k2 / V0 - 1)
    assert err2.max() > 0.01
    spacings = [row["spacing_m"] for row in adv.table]
    assert np.all(np.diff(spacings) < 0)  # more neighbours need finer grids


# ---------------------------------------------------------------------- CLI contract
def test_cli_dispersion_json_contract(tmp_path) -> None:
    proc = cli("dispersion", "--dim", "1", "--m", "3.015", "--n-points", "5", "--json", check=True)
    data = json.loads(proc.stdout)
    assert set(data) == {"N_h", "v_over_v0", "omega_over_omega0", "group_velocity_over_v0"}
    np.testing.assert_allclose(data["N_h"], [0, 0.5, 1, 1.5, 2])
    np.testing.assert_allclose(data["v_over_v0"], [1.14896, 0.34481, 0, 0.11494, 0], atol=6e-6)
    png = tmp_path / "d.png"
    cli("dispersion", "--dim", "2", "--theta", "30", "--plot", str(png), check=True)
    assert png.stat().st_size > 5000
    adv = json.loads(
        cli("dispersion", "--frequency", "1e5", "--tolerance", "0.01", "--json", check=True).stdout
    )
    assert adv["m"] == 3 and adv["spacing_m"] > 0
    bad = cli("dispersion", "--m", "0.5")
    assert bad.returncode == 2


def test_long_waves_keep_their_digits() -> None:
    """1 - cos(x) is evaluated without cancellation: tiny wavenumbers give the limit."""
    tiny = [1e-9, 1e-8, 1e-7]
    np.testing.assert_allclose(dsp.semi_discrete_1d(tiny).v_over_v0, 1.148955759581, rtol=1e-9)
    np.testing.assert_allclose(dsp.semi_discrete_2d(tiny).v_over_v0, 1.240201300, rtol=1e-8)
    np.testing.assert_allclose(dsp.continuous_1d([-5.0]), dsp.continuous_1d([5.0]))
    adv = dsp.advise_1d(50e3, 1e-5, E, RHO)  # a tight tolerance keeps every m
    assert [int(r["m"]) for r in adv.table] == [1, 2, 3, 4, 5, 6, 8, 10] and adv.m == 3
