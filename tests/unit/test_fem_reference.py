"""FE reference of the micropolar cantilever (examples/micropolar/fem_reference.py)."""

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

from peridynamics.analysis.beams import timoshenko_goodier_cantilever

pytest.importorskip("skfem")

SCRIPT = Path(__file__).resolve().parents[2] / "examples" / "micropolar" / "fem_reference.py"
TG_TIP = 7.824e-7  # |u_y(L, 0)| of Timoshenko & Goodier for F = 1000 N (m)
COARSE = {"refine": 0, "corner_levels": 4}  # 2802 unknowns, < 0.1 s


@pytest.fixture(scope="module")
def fem() -> ModuleType:
    spec = importlib.util.spec_from_file_location("micropolar_fem_reference", SCRIPT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    try:
        spec.loader.exec_module(module)
    finally:
        sys.modules.pop(spec.name, None)
    return module


def test_clamped_cantilever_close_to_timoshenko_goodier(fem: ModuleType) -> None:
    sol = fem.solve_cantilever(**COARSE)
    rel = sol.max_abs_uy / TG_TIP - 1.0
    print(f"max|u_y| = {sol.max_abs_uy:.6e} m, {rel:+.3%} from Timoshenko-Goodier")
    # Measured: coarse 7.88253e-7 m (+0.75 %), converged 7.88401e-7 m (+0.77 %): the fully
    # clamped edge and the uniform (not parabolic) end shear make the FE model slightly softer
    # at the loaded corner, where max |u_y| lies. Neutral-axis tip: -7.8566e-7 m (+0.42 %).
    assert 0.0 < rel < 0.02
    assert sol.tip_uy < 0.0
    assert abs(sol.tip_uy) / TG_TIP - 1.0 == pytest.approx(0.0042, abs=0.002)
    # coarse mesh vs the converged default (7.884010e-7 m, 1.687958e-7 m; measured -2e-4)
    assert sol.max_abs_uy == pytest.approx(7.88401e-7, rel=1e-3)
    assert sol.max_abs_ux == pytest.approx(1.68796e-7, rel=2e-3)


def test_clamped_edge_and_point_evaluation(fem: ModuleType) -> None:
    sol = fem.solve_cantilever(**COARSE)
    y = np.linspace(0.0, 0.3, 7)
    u_clamp = sol.displacement(np.column_stack([np.zeros_like(y), y]))
    assert np.max(np.abs(u_clamp)) < 1e-12 * sol.max_abs_uy
    u = sol.displacement([[1.0, 0.15], [1.0, 0.3], [1.0, 0.0]])
    assert u.shape == (3, 2)
    assert u[0, 1] == pytest.approx(sol.tip_uy)
    # antisymmetry of the bending about the neutral axis (up to the mesh, whose diagonals are
    # not mirror-symmetric: measured 4e-5 relative on the coarse mesh)
    assert u[1, 0] == pytest.approx(-u[2, 0], rel=1e-3)
    assert u[1, 1] == pytest.approx(u[2, 1], rel=1e-3)
    with pytest.raises(ValueError, match="inside"):
        sol.displacement([[1.1, 0.1]])


def test_thickness_scaling(fem: ModuleType) -> None:
    thick = fem.solve_cantilever(**COARSE)
    thin = fem.solve_cantilever(thickness=0.01, **COARSE)
    assert thin.max_abs_uy == pytest.approx(100.0 * thick.max_abs_uy, rel=1e-9)


def test_timoshenko_goodier_conditions_reproduce_closed_form(fem: ModuleType) -> None:
    """With the exact boundary conditions the FE model reproduces the elasticity solution."""
    length, height, thickness, E, nu, force = 1.0, 0.3, 1.0, 200e9, 0.2, -1000.0
    # uniform cells of H / 6, no corner refinement (the solution is smooth): measured 2.1e-5
    # (2.3e-4 with cells of H / 3, 2.0e-6 with H / 12)
    sol = fem.solve_cantilever(bc="timoshenko", refine=1, corner_levels=0)
    gx, gy = np.meshgrid(np.linspace(0.0, length, 11), np.linspace(0.0, height, 7))
    pts = np.column_stack([gx.ravel(), gy.ravel()])
    exact = np.column_stack(
        timoshenko_goodier_cantilever(
            pts[:, 0], pts[:, 1] - 0.5 * height, force, length, height, thickness, E, nu
        )
    )
    err = np.max(np.abs(sol.displacement(pts) - exact)) / np.max(np.abs(exact))
    print(f"max |u_FE - u_TG| / max |u_TG| = {err:.1e}")
    assert err < 1e-4
