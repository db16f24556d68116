"""Closed-form beam references: Timoshenko & Goodier cantilever, beam theories, DCB (CBT)."""

import math

import numpy as np
import pytest

from peridynamics.analysis.beams import (
    euler_bernoulli_tip_deflection,
    timoshenko_beam_tip_deflection,
    timoshenko_goodier_cantilever,
    timoshenko_goodier_tip_deflection,
)
from peridynamics.analysis.dcb import dcb_chi, dcb_compliance, dcb_critical_load, dcb_lefm_curve

# Cantilever of the micropolar example: P (N), L, H, t (m), E (Pa), nu.
P, L, H, T, E, NU = 1000.0, 1.0, 0.3, 1.0, 200e9, 0.2
# DCB: arm height h, width B (m), fracture energy G_c (J/m^2).
DCB_H, DCB_B, GC = 0.02, 0.01, 962.8
REL = 1e-3


def test_timoshenko_goodier_tip_deflection_value() -> None:
    inertia = T * H**3 / 12.0
    expected = P * L**3 / (3 * E * inertia) + (4 + 5 * NU) * P * L / (2 * E * T * H)
    _, uy = timoshenko_goodier_cantilever(L, 0.0, P, L, H, T, E, NU)
    assert float(uy) == pytest.approx(expected, rel=1e-12)
    assert abs(float(uy)) == pytest.approx(7.824e-7, rel=REL)
    assert timoshenko_goodier_tip_deflection(P, L, H, T, E, NU) == pytest.approx(float(uy))


def test_timoshenko_goodier_signed_load_scales_linearly() -> None:
    x = np.linspace(0.0, L, 7)[:, None]
    y = np.linspace(-H / 2, H / 2, 5)[None, :]
    ux_up, uy_up = timoshenko_goodier_cantilever(x, y, P, L, H, T, E, NU)
    ux_dn, uy_dn = timoshenko_goodier_cantilever(x, y, -2.0 * P, L, H, T, E, NU)
    assert ux_up.shape == uy_up.shape == (7, 5)
    np.testing.assert_allclose(ux_dn, -2.0 * ux_up, rtol=1e-14, atol=0.0)
    np.testing.assert_allclose(uy_dn, -2.0 * uy_up, rtol=1e-14, atol=0.0)
    assert timoshenko_goodier_tip_deflection(-P, L, H, T, E, NU) < 0.0


def test_timoshenko_goodier_fixed_at_clamp_neutral_axis() -> None:
    ux, uy = timoshenko_goodier_cantilever(0.0, 0.0, P, L, H, T, E, NU)
    assert float(ux) == 0.0
    assert float(uy) == 0.0


def test_timoshenko_goodier_ux_antisymmetric_uy_symmetric_in_y() -> None:
    x = np.linspace(0.0, L, 11)
    for y in (0.03, 0.1, H / 2):
        ux_p, uy_p = timoshenko_goodier_cantilever(x, y, P, L, H, T, E, NU)
        ux_m, uy_m = timoshenko_goodier_cantilever(x, -y, P, L, H, T, E, NU)
        np.testing.assert_allclose(ux_m, -ux_p, rtol=1e-14, atol=0.0)
        np.testing.assert_allclose(uy_m, uy_p, rtol=1e-14, atol=0.0)
    # an upward load compresses the top fibre: u_x < 0 above the neutral axis
    assert float(timoshenko_goodier_cantilever(L, H / 2, P, L, H, T, E, NU)[0]) < 0.0


def test_timoshenko_goodier_stresses_by_finite_differences() -> None:
    """Strains of the displacement field: the stresses of Timoshenko & Goodier, section 21."""
    x, y, d = 0.37, 0.08, 1e-5
    inertia = T * H**3 / 12.0

    def u(xx: float, yy: float) -> np.ndarray:
        return np.array(timoshenko_goodier_cantilever(xx, yy, P, L, H, T, E, NU), dtype=float)

    du_dx = (u(x + d, y) - u(x - d, y)) / (2 * d)
    du_dy = (u(x, y + d) - u(x, y - d)) / (2 * d)
    eps_xx, eps_yy, gamma = du_dx[0], du_dy[1], du_dy[0] + du_dx[1]
    sxx = E / (1 - NU**2) * (eps_xx + NU * eps_yy)
    syy = E / (1 - NU**2) * (eps_yy + NU * eps_xx)
    txy = E / (2 * (1 + NU)) * gamma
    scale = P * L * H / inertia
    assert sxx == pytest.approx(-P * (L - x) * y / inertia, rel=1e-6)
    assert abs(syy) < 1e-6 * scale
    assert txy == pytest.approx(P * (H**2 / 4 - y**2) / (2 * inertia), rel=1e-6)


def test_beam_theory_tip_deflections() -> None:
    assert timoshenko_beam_tip_deflection(P, L, H, T, E, NU) == pytest.approx(7.887e-7, rel=REL)
    assert euler_bernoulli_tip_deflection(P, L, H, T, E) == pytest.approx(7.407e-7, rel=REL)
    assert timoshenko_beam_tip_deflection(-P, L, H, T, E, NU, shear_factor=1.0) < 0.0


def test_dcb_chi_value() -> None:
    assert dcb_chi(E, 0.2) == pytest.approx(0.645, rel=REL)


def test_dcb_reference_numbers() -> None:
    k1 = DCB_B * math.sqrt(E * GC * DCB_H**3 / 12.0)
    assert k1 == pytest.approx(113.30, rel=REL)
    pc = float(dcb_critical_load(0.1, DCB_H, DCB_B, E, NU, GC))
    assert pc == pytest.approx(1003.0, rel=REL)
    delta_c = float(dcb_compliance(0.1, DCB_H, DCB_B, E, NU)) * pc
    assert delta_c == pytest.approx(0.722e-3, rel=REL)


def test_dcb_compliance_formula_and_plane_strain() -> None:
    a = np.array([0.05, 0.1, 0.2])
    a_e = a + dcb_chi(E, NU) * DCB_H
    stress = dcb_compliance(a, DCB_H, DCB_B, E, NU, plane="stress")
    np.testing.assert_allclose(stress, 8 * a_e**3 / (E * DCB_B * DCB_H**3), rtol=1e-14)
    strain = dcb_compliance(a, DCB_H, DCB_B, E, NU, plane="strain")
    np.testing.assert_allclose(strain, stress * (1 - NU**2), rtol=1e-14)
    with pytest.raises(ValueError, match="plane"):
        dcb_compliance(0.1, DCB_H, DCB_B, E, NU, plane="membrane")  # type: ignore[arg-type]


def test_dcb_energy_release_rate_at_critical_load() -> None:
    """G = P^2 / (2 B) dC/da equals G_c at P_c (dC/da by central differences)."""
    for plane in ("stress", "strain"):
        a, da = 0.1, 1e-6
        dc_da = (
            dcb_compliance(a + da, DCB_H, DCB_B, E, NU, plane)
            - dcb_compliance(a - da, DCB_H, DCB_B, E, NU, plane)
        ) / (2 * da)
        pc = dcb_critical_load(a, DCB_H, DCB_B, E, NU, GC, plane)
        assert float(pc**2 / (2 * DCB_B) * dc_da) == pytest.approx(GC, rel=1e-6)


@pytest.mark.parametrize("plane", ["stress", "strain"])
@pytest.mark.parametrize("a", [0.02, 0.05, 0.1 - 0.00025, 0.1, 0.3])
def test_dcb_lefm_curve_passes_through_critical_point(a: float, plane: str) -> None:
    pc = float(dcb_critical_load(a, DCB_H, DCB_B, E, NU, GC, plane))
    delta_c = float(dcb_compliance(a, DCB_H, DCB_B, E, NU, plane)) * pc
    p = float(dcb_lefm_curve(delta_c, DCB_H, DCB_B, E, NU, GC, plane))
    assert p == pytest.approx(pc, rel=1e-12)


def test_dcb_lefm_curve_with_initial_crack() -> None:
    a0 = 0.1
    c0 = float(dcb_compliance(a0, DCB_H, DCB_B, E, NU))
    pc = float(dcb_critical_load(a0, DCB_H, DCB_B, E, NU, GC))
    delta_c = c0 * pc
    delta = np.array([0.0, 0.5, 1.0, 2.0, 4.0]) * delta_c
    full = dcb_lefm_curve(delta, DCB_H, DCB_B, E, NU, GC, crack_length=a0)
    branch = dcb_lefm_curve(delta, DCB_H, DCB_B, E, NU, GC)
    np.testing.assert_allclose(full[:3], delta[:3] / c0, rtol=1e-12)
    np.testing.assert_allclose(full[2:], branch[2:], rtol=1e-12)
    assert np.isinf(branch[0])
    # propagation branch: P ~ Delta^(-1/2)
    assert branch[4] / branch[3] == pytest.approx(2**-0.5, rel=1e-12)
    with pytest.raises(ValueError, match="delta"):
        dcb_lefm_curve(-1e-3, DCB_H, DCB_B, E, NU, GC)
