"""1-D finite differences, the force-flux stress and hybrid solvers (issue 4, part)."""

from __future__ import annotations

import numpy as np
import pytest

from peridynamics.bonds import build_bonds
from peridynamics.damage import CriticalStretch
from peridynamics.evaluation import Evaluator
from peridynamics.families.pmb import BondBasedMaterial
from peridynamics.geometry import bar
from peridynamics.loading import TriangularPulse, traction_as_body_force
from peridynamics.solvers import ExplicitSolver
from peridynamics.solvers.fdm import FDMModel1D
from peridynamics.solvers.hybrid import HybridSolver, SwitchAtStretch

E, RHO, DX = 20e9, 2620.0, 0.005


def _pulse_bar(peak: float = 8.9e6):
    cloud = bar(1.0, DX, area=1.0, nodes_on_boundary=True)
    load = traction_as_body_force(
        np.array([0]), np.array([peak]), cloud.x, DX, function=TriangularPulse(1.0, 4e-5, 1.2e-4)
    )
    return cloud, BondBasedMaterial(E, RHO), load


def test_pd_with_delta_dx_equals_fdm_to_1e12() -> None:
    cloud, mat, load = _pulse_bar()
    pd = Evaluator(cloud, build_bonds(cloud, DX, "truncated"), mat, body_forces=[load])
    fd = FDMModel1D(cloud, mat, [load])
    runs = []
    for model in (pd, fd):
        solver = ExplicitSolver(model, time_step=1e-6, integrator="central_difference")
        s = solver.init()
        stress = []
        for st in solver.irun(s, 400):
            if st.step % 10 == 0:
                stress.append(model.section_stress(st.u, st.intact, 0.5 + DX / 2))
        runs.append((s.u.copy(), np.array(stress)))
    (u_pd, s_pd), (u_fd, s_fd) = runs
    assert np.abs(u_pd - u_fd).max() <= 1e-12 * np.abs(u_fd).max()  # measured 4.5e-13
    assert np.abs(s_pd - s_fd).max() <= 1e-11 * np.abs(s_fd).max()
    assert s_fd.min() < -7e6  # the compressive pulse passed the section


@pytest.mark.parametrize("m", [1, 2, 3, 5])
def test_section_stress_of_a_uniform_strain_is_e_eps(m: int) -> None:
    cloud = bar(1.0, DX, area=2.5e-3, nodes_on_boundary=True)
    model = Evaluator(cloud, build_bonds(cloud, m * DX, "truncated"), BondBasedMaterial(E, RHO))
    u = 1e-4 * cloud.x  # uniform strain 1e-4
    for pos in (0.3 + DX / 2, 0.5 + 0.3 * DX, 0.77 + DX / 2):
        sigma = model.section_stress(u, model.bonds.bond_intact, pos)
        assert sigma == pytest.approx(E * 1e-4, rel=1e-6)  # 1e-6: geometric nonlinearity


def test_fdm_refuses_non_uniform_or_higher_dimensional_grids() -> None:
    from peridynamics.geometry import PointCloud, rectangle

    with pytest.raises(ValueError, match="1-D"):
        FDMModel1D(rectangle((0.01, 0.01), 1e-3), BondBasedMaterial(E, RHO))
    x = np.array([[0.0], [1e-3], [2.5e-3]])
    with pytest.raises(ValueError, match="uniform"):
        FDMModel1D(
            PointCloud(x=x, volume=np.ones(3) * 1e-3, spacing=1e-3), BondBasedMaterial(E, RHO)
        )


@pytest.mark.parametrize("first_kind", ["fdm", "pd1"])
@pytest.mark.long
def test_hybrid_switches_at_the_stretch_and_transfers_exactly(first_kind: str) -> None:
    cloud, mat, load = _pulse_bar(peak=25e6)
    s0 = 9.5e-4
    second = Evaluator(
        cloud, build_bonds(cloud, 3 * DX, "truncated"), mat, CriticalStretch(s0), [load]
    )
    first = (
        FDMModel1D(cloud, mat, [load])
        if first_kind == "fdm"
        else Evaluator(cloud, build_bonds(cloud, DX, "truncated"), mat, body_forces=[load])
    )
    common = dict(time_step=1e-6, integrator="central_difference")
    hyb = HybridSolver(
        ExplicitSolver(first, **common), ExplicitSolver(second, **common), SwitchAtStretch(0.9)
    )
    s = hyb.init()
    assert s.intact.shape == second.bonds.bond_intact.shape
    before = None
    for _ in range(1000):
        before = (s.u.copy(), s.v.copy(), s.phase)
        hyb.step(s)
        if s.phase == 1:
            break
    assert s.phase == 1 and hyb.switch_time == pytest.approx(s.t)

    def first_stretch(u: np.ndarray) -> float:
        f, ms = np.zeros_like(u), np.zeros(len(u))
        first.internal_force(u, first.bonds.bond_intact.copy(), f, ms)
        return float(ms.max())

    # the switch happened at the first step where the first model's stretch reached 0.9 s0
    assert before is not None and before[2] == 0
    assert first_stretch(s.u) >= 0.9 * s0 > first_stretch(before[0])
    n_before = s.step
    for _ in range(1000):
        hyb.step(s)
    assert s.step == n_before + 1000
    assert s.bonds_broken > 0  # the PD model breaks bonds after the switch


def test_switching_rule_is_reusable() -> None:
    rule = SwitchAtStretch(0.5)
    with pytest.raises(ValueError):
        SwitchAtStretch(0.0)
    cloud, mat, _ = _pulse_bar()
    target = Evaluator(cloud, build_bonds(cloud, 3 * DX, "truncated"), mat, CriticalStretch(1e-3))
    st = target.new_state()
    assert not rule.should_switch(st, target, target)
    st.max_stretch[5] = 5e-4
    assert rule.should_switch(st, target, target)


def test_attenuation_fit_and_corrected_spall_strength() -> None:
    from peridynamics.analysis import corrected_strength, fit_attenuation

    # Lu & Wang (2016), eq. 19: 25.5 MPa corrected over 0.39 + 0.20 m with beta = 0.52 1/m
    assert corrected_strength(25.5e6, 0.52, 0.39 + 0.20) == pytest.approx(18.8e6, rel=3e-3)
    x = np.array([0.6, 1.58, 2.56, 3.54, 4.52])
    rng = np.random.default_rng(0)
    peaks = 30e6 * np.exp(-0.52 * x) * (1 + 0.01 * rng.standard_normal(5))
    sigma0, beta = fit_attenuation(x, -peaks)  # signs are ignored
    assert beta == pytest.approx(0.52, abs=0.01)
    assert sigma0 == pytest.approx(30e6, rel=0.03)
    with pytest.raises(ValueError):
        fit_attenuation([0.1], [1.0])


def test_fdm_numba_kernel_equals_numpy_twin() -> None:
    """The Numba FDM operator equals its NumPy reference (force and tensile strain)."""
    from peridynamics.kernels.fdm import fdm_force_1d
    from peridynamics.kernels.reference import fdm_force_1d as fdm_ref

    rng = np.random.default_rng(3)
    u = rng.normal(size=(257, 1)) * 1e-4
    force, ms = np.empty((257, 1)), np.empty(257)
    fdm_force_1d(u, 2.5e12, 100.0, force, ms)
    f_ref, ms_ref = fdm_ref(u, 2.5e12, 100.0)
    np.testing.assert_allclose(force, f_ref, rtol=1e-13, atol=1e-13 * np.abs(f_ref).max())
    np.testing.assert_array_equal(ms, ms_ref)
    assert ms.min() >= 0.0 and ms.max() > 0.0
