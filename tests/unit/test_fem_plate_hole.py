"""FE reference of the plate with a hole (examples/correspondence/fem_reference.py)."""

import importlib.util
import json
import sys
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np
import pytest

pytest.importorskip("skfem")

SCRIPT = Path(__file__).resolve().parents[2] / "examples" / "correspondence" / "fem_reference.py"
CX, CY, RADIUS, LENGTH, WIDTH = 0.075, 0.025, 0.010, 0.150, 0.050


@pytest.fixture(scope="module")
def fem() -> ModuleType:
    spec = importlib.util.spec_from_file_location("correspondence_fem_reference", SCRIPT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    try:
        spec.loader.exec_module(module)
    finally:
        sys.modules.pop(spec.name, None)
    return module


@pytest.fixture(scope="module")
def coarse(fem: ModuleType) -> Any:
    return fem.solve_plate(refine=1)  # 12464 unknowns, 0.3 s


@pytest.fixture(scope="module")
def default(fem: ModuleType) -> Any:
    return fem.solve_plate()  # refine = 2: 39040 unknowns, about 1 s


def _lower_half_points(n: int = 400) -> np.ndarray:
    rng = np.random.default_rng(7)
    pts = rng.uniform([0.0, 0.0], [LENGTH, CY], size=(n, 2))
    return pts[np.hypot(pts[:, 0] - CX, pts[:, 1] - CY) > RADIUS]


def test_handbook_factors(fem: ModuleType) -> None:
    # Pilkey & Pilkey (2008) chart 4.1 (Howland fit) and Heywood (1952) at d / W = 0.4
    assert round(fem.peterson_gross_factor(0.4), 2) == 3.73
    assert fem.peterson_gross_factor(0.4) == pytest.approx(2.23952 / 0.6, rel=1e-12)
    assert round(fem.heywood_gross_factor(0.4), 2) == 3.69
    assert fem.heywood_gross_factor(0.4) == pytest.approx(2.216 / 0.6, rel=1e-12)
    # small holes: both tend to the infinite-plate value 3
    assert fem.peterson_gross_factor(1e-9) == pytest.approx(3.004, abs=1e-6)
    assert fem.heywood_gross_factor(1e-9) == pytest.approx(3.0, abs=1e-6)
    assert fem.nominal_gross_stress(1000.0, 0.05, 1e-3) == pytest.approx(2e7)


def test_equilibrium_strips_and_pin(coarse: Any) -> None:
    assert coarse.reaction > 0.0
    assert coarse.reaction_left == pytest.approx(-coarse.reaction, rel=1e-8)
    # the pin carries no force: the problem is symmetric about y = W / 2
    assert abs(coarse.reaction_pin) < 1e-8 * coarse.reaction
    y = np.linspace(0.0, WIDTH, 11)
    for x, ux in ((0.0, 0.0), (0.003, 0.0), (0.147, coarse.U), (0.150, coarse.U)):
        u = coarse.displacement(np.column_stack([np.full_like(y, x), y]))
        assert np.max(np.abs(u[:, 0] - ux)) < 1e-12 * coarse.U
    assert np.max(np.abs(coarse.displacement([[0.0015, 0.025]]))) < 1e-12 * coarse.U


def test_mirror_symmetries(coarse: Any) -> None:
    """Symmetric about y = W / 2; about x = L / 2, u_x -> U - u_x (the mesh is symmetric)."""
    pts = _lower_half_points()
    u = coarse.displacement(pts)
    up = coarse.displacement(np.column_stack([pts[:, 0], WIDTH - pts[:, 1]]))
    scale_y = np.max(np.abs(u[:, 1]))
    # measured 1e-11 (solver round-off)
    assert np.max(np.abs(up[:, 1] + u[:, 1])) < 1e-8 * scale_y
    assert np.max(np.abs(up[:, 0] - u[:, 0])) < 1e-8 * coarse.U
    ur = coarse.displacement(np.column_stack([LENGTH - pts[:, 0], pts[:, 1]]))
    assert np.max(np.abs(ur[:, 0] - (coarse.U - u[:, 0]))) < 1e-8 * coarse.U
    assert np.max(np.abs(ur[:, 1] - u[:, 1])) < 1e-8 * scale_y
    s = coarse.stress(pts)
    sp = coarse.stress(np.column_stack([pts[:, 0], WIDTH - pts[:, 1]]))
    scale_s = np.max(np.abs(s))
    assert np.max(np.abs(sp[:, :2] - s[:, :2])) < 1e-8 * scale_s
    assert np.max(np.abs(sp[:, 2] + s[:, 2])) < 1e-8 * scale_s


def test_hole_is_traction_free_and_peak_at_top(default: Any) -> None:
    theta, sig = default.hole_stress(720)
    n = np.column_stack([np.cos(theta), np.sin(theta)])
    tx = sig[:, 0] * n[:, 0] + sig[:, 2] * n[:, 1]
    ty = sig[:, 2] * n[:, 0] + sig[:, 1] * n[:, 1]
    peak = default.max_hole_stress()
    # the traction of the P2 gradient on the hole: measured 4.8e-3 of the peak
    assert np.max(np.hypot(tx, ty)) < 1e-2 * peak
    i = np.argmax(sig[:, 0])
    assert abs(np.sin(theta[i])) > np.cos(np.radians(1.0))  # within 1 degree of 90 / 270
    top = default.stress([[CX, CY + RADIUS], [CX, CY - RADIUS]])[:, 0]
    assert top == pytest.approx([peak, peak], rel=1e-4)


def test_gross_factor_close_to_handbook(fem: ModuleType, default: Any) -> None:
    """FE gross factor max sigma_xx / (reaction / (W t)) against the handbook (d/W = 0.4).

    Measured 3.7478 on the default mesh (3.7480 converged): +0.41 % from Peterson's 3.7325,
    +1.47 % from Heywood's 3.6933. The strip loading (u_x prescribed 1.24 W from the hole's
    edge on a plate 3 W long) is not the uniform remote stress of the handbook, which may
    explain part of the difference; the two handbook fits themselves differ by 1.1 %.
    """
    factor = default.max_hole_stress() / fem.nominal_gross_stress(default.reaction)
    assert factor == pytest.approx(default.gross_factor)
    peterson = fem.peterson_gross_factor(0.4)
    assert abs(factor / peterson - 1.0) < 0.03
    assert factor == pytest.approx(3.7480, rel=1e-3)
    assert default.reaction == pytest.approx(12607.02, rel=1e-5)
    assert default.max_hole_stress() == pytest.approx(945.03e6, rel=1e-3)


@pytest.mark.long
def test_convergence_of_default_mesh(fem: ModuleType, default: Any) -> None:
    """Default (refine = 2) against refine = 3: peak hole stress and sample displacements."""
    fine = fem.solve_plate(refine=3)  # 144288 unknowns, about 6 s
    rel = default.max_hole_stress() / fine.max_hole_stress() - 1.0
    print(f"peak hole stress, refine 2 vs 3: {rel:+.1e}")
    assert abs(rel) < 5e-3  # measured -4.8e-5
    pts = [[0.0375, 0.025], [0.1125, 0.025], [0.075, 0.035], [0.075, 0.05]]
    u, uf = default.displacement(pts), fine.displacement(pts)
    for value, ref in ((u[:2, 0], uf[:2, 0]), (u[2:, 1], uf[2:, 1])):
        assert np.max(np.abs(value / ref - 1.0)) < 1e-4  # measured 6.0e-5 (u_y at the hole)
    assert default.reaction == pytest.approx(fine.reaction, rel=1e-5)  # measured 1.3e-6


def test_linearity_in_load_and_thickness(fem: ModuleType, coarse: Any) -> None:
    other = fem.solve_plate(refine=1, U=0.1e-3, thickness=2e-3, E=105e9)
    pts = _lower_half_points(50)
    assert other.displacement(pts) == pytest.approx(0.5 * coarse.displacement(pts), rel=1e-9)
    assert other.reaction == pytest.approx(0.5 * coarse.reaction, rel=1e-9)
    assert other.max_hole_stress() == pytest.approx(0.25 * coarse.max_hole_stress(), rel=1e-9)


def test_points_outside_the_body_rejected(coarse: Any) -> None:
    with pytest.raises(ValueError, match="inside"):
        coarse.displacement([[CX, CY + 0.5 * RADIUS]])
    with pytest.raises(ValueError, match="inside"):
        coarse.stress([[0.16, 0.01]])
    with pytest.raises(ValueError, match="shape"):
        coarse.displacement(np.zeros((2, 3)))


def test_cli_writes_json(fem: ModuleType, tmp_path: Path) -> None:
    out = tmp_path / "ref.json"
    result = fem.main(["--refine", "0", "--out", str(out)])
    data = json.loads(out.read_text())
    assert data["default"]["refine"] == 0
    assert [row["refine"] for row in data["convergence"]] == [0, 1]
    line = data["profiles"]["y=0.025"]
    assert len(line["x_m"]) == 130 and len(line["ux_m"]) == 130  # 20 points in the hole
    assert len(data["profiles"]["x=0.075"]["uy_m"]) == 30
    assert data["handbook"]["peterson_gross_factor"] == pytest.approx(3.7325, abs=1e-4)
    assert result["default"]["reaction_N"] == pytest.approx(data["default"]["reaction_N"])
