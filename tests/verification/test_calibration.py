"""Micromodulus and critical stretch against closed forms and direct quadrature.

The fracture energy G0 is the energy needed to break every bond crossing a unit area
of a crack surface: with the pair energy w(r) = c(r) s0^2 r / 2 (so that the strain
energy density is W = 1/2 int w dV_j), and points i below / j above the crack,

    G0 * (crack area) = int_{i below} int_{j above, |x_j - x_i| < delta} w dV_j dV_i.

The quadratures below are written in Cartesian (or axisymmetric) coordinates with
scipy, independent of the package's moment formulas.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate

from peridynamics import BondBasedMaterial

E, RHO = 72e9, 2440.0
H = 0.003  # thickness (2-D) / area (1-D)
OPTS = dict(epsabs=0.0, epsrel=1e-10)


def shape(profile: str, t):
    return 1.0 if profile == "constant" else (1.0 - t)


def c_profile(mat, dim, delta, plane, profile):
    c0 = mat.micromodulus_constant(dim, delta, H, plane)
    return (
        (lambda t: c0 * shape(profile, t))
        if profile == "constant"
        else (lambda t: (dim + 2) * c0 * shape(profile, t))
    )


def fracture_energy_quadrature(mat, dim, delta, plane, s0):
    """G0 from breaking all bonds across a crack, delta scaled to 1 for the quadrature."""
    c = c_profile(mat, dim, delta, plane, mat.profile)
    if dim == 1:
        # G0 A = int_0^1 A dz int_0^{1-z} A w(z + y) dy  (lengths in units of delta)
        val, _ = integrate.dblquad(
            lambda y, z: c(z + y) * (z + y) / 2, 0, 1, 0, lambda z: 1 - z, **OPTS
        )
        return H * s0**2 * val * delta**3
    if dim == 2:
        # G0 h = int_0^1 h dz int_0^{1-z} dy int_{-X}^{X} h w(r) dx, X = sqrt(1 - (y+z)^2)
        def f(x, y, z):
            r = math.hypot(x, y + z)
            return c(r) * r / 2 if r < 1 else 0.0

        val, _ = integrate.tplquad(
            f,
            0,
            1,
            0,
            lambda z: 1 - z,
            lambda z, y: -math.sqrt(max(0.0, 1 - (y + z) ** 2)),
            lambda z, y: math.sqrt(max(0.0, 1 - (y + z) ** 2)),
            epsabs=0.0,
            epsrel=1e-9,
        )
        return H * s0**2 * val * delta**4
    # 3-D, axisymmetric about the normal through i: dV_j = 2 pi rho d(rho) dy

    def f3(rho, y, z):
        r = math.hypot(rho, y + z)
        return 2 * math.pi * rho * c(r) * r / 2 if r < 1 else 0.0

    val, _ = integrate.tplquad(
        f3,
        0,
        1,
        0,
        lambda z: 1 - z,
        0,
        lambda z, y: math.sqrt(max(0.0, 1 - (y + z) ** 2)),
        epsabs=0.0,
        epsrel=1e-9,
    )
    return s0**2 * val * delta**5


CASES = [(1, None), (2, "stress"), (2, "strain"), (3, None)]


@pytest.mark.parametrize(("dim", "plane"), CASES)
@pytest.mark.parametrize("profile", ["constant", "conical"])
def test_critical_stretch_consistent_with_quadrature(dim, plane, profile):
    mat = BondBasedMaterial(E, RHO, profile=profile)
    delta, g0 = 1.7e-3, 135.0
    s0 = mat.critical_stretch(g0, dim=dim, horizon=delta, cross_section=H, plane=plane)
    assert fracture_energy_quadrature(mat, dim, delta, plane, s0) == pytest.approx(g0, rel=1e-7)


@pytest.mark.parametrize("delta", [1e-3, 4.5e-3])
@pytest.mark.parametrize("g0", [8.0, 3000.0])
def test_critical_stretch_closed_forms(delta, g0):
    mat = BondBasedMaterial(E, RHO)
    k_bulk = E / (3 * (1 - 2 * 0.25))
    cs = mat.critical_stretch
    assert cs(g0, 1, delta, H, None) == pytest.approx(math.sqrt(3 * g0 / (E * delta)), rel=1e-12)
    assert cs(g0, 2, delta, H, "stress") == pytest.approx(
        math.sqrt(4 * math.pi * g0 / (9 * E * delta)), rel=1e-12
    )
    assert cs(g0, 2, delta, H, "strain") == pytest.approx(
        math.sqrt(5 * math.pi * g0 / (12 * E * delta)), rel=1e-12
    )
    assert cs(g0, 3, delta, 1.0, None) == pytest.approx(
        math.sqrt(5 * g0 / (9 * k_bulk * delta)), rel=1e-12
    )
    # independent of the 2-D thickness / 1-D area (they cancel)
    assert cs(g0, 2, delta, 7 * H, "stress") == pytest.approx(
        cs(g0, 2, delta, H, "stress"), rel=1e-12
    )
    with pytest.raises(ValueError):
        cs(0.0, 2, delta, H, "stress")


@pytest.mark.parametrize(("dim", "plane"), CASES)
@pytest.mark.parametrize("profile", ["constant", "conical"])
def test_micromodulus_reproduces_classical_energy_by_quadrature(dim, plane, profile):
    """W = 1/4 int c(r) s^2 r dV with s = eps cos^2(theta) for uniaxial strain eps must be
    the classical E eps^2/2 (1-D), 9/16 E eps^2 (plane stress), 0.6 E eps^2 (else)."""
    mat = BondBasedMaterial(E, RHO, profile=profile)
    delta, eps = 2.3e-3, 1e-3
    c = c_profile(mat, dim, delta, plane, profile)
    if dim == 1:  # dV = A dx over both sides
        val = 2 * integrate.quad(lambda r: c(r) * r, 0, 1, **OPTS)[0] * H
        w = 0.25 * eps**2 * val * delta**2
    elif dim == 2:  # dV = h r dr dtheta
        val = (
            integrate.dblquad(
                lambda r, th: c(r) * math.cos(th) ** 4 * r * r, 0, 2 * math.pi, 0, 1, **OPTS
            )[0]
            * H
        )
        w = 0.25 * eps**2 * val * delta**3
    else:  # dV = r^2 sin(phi) dr dphi dtheta, theta integrated (2 pi)
        val = (
            2
            * math.pi
            * integrate.dblquad(
                lambda r, ph: c(r) * math.cos(ph) ** 4 * r**3 * math.sin(ph),
                0,
                math.pi,
                0,
                1,
                **OPTS,
            )[0]
        )
        w = 0.25 * eps**2 * val * delta**4
    classical = {1: 0.5, 2: 9 / 16 if plane == "stress" else 0.6, 3: 0.6}[dim] * E * eps**2
    assert w == pytest.approx(classical, rel=1e-9)
    # and the model's micromodulus at a few lengths has the expected profile
    r = np.array([0.0, 0.25, 0.5, 0.99]) * delta
    got = mat.micromodulus(r, dim, delta, H, plane)
    np.testing.assert_allclose(got, [c(t) for t in r / delta], rtol=1e-13)


def test_material_validation():
    for bad in [
        dict(youngs_modulus=0.0, density=1.0),
        dict(youngs_modulus=1.0, density=-1.0),
        dict(youngs_modulus=math.inf, density=1.0),
    ]:
        with pytest.raises(ValueError):
            BondBasedMaterial(**bad)
    with pytest.raises(ValueError, match="profile"):
        BondBasedMaterial(1.0, 1.0, profile="gaussian")  # type: ignore[arg-type]
    assert BondBasedMaterial(E, RHO).wave_speed() == pytest.approx(math.sqrt(E / RHO))


def test_micromodulus_constants():
    mat = BondBasedMaterial(E, RHO)
    d = 3e-3
    assert mat.micromodulus_constant(1, d, H, None) == pytest.approx(2 * E / (H * d**2))
    assert mat.micromodulus_constant(2, d, H, "stress") == pytest.approx(
        9 * E / (math.pi * H * d**3)
    )
    assert mat.micromodulus_constant(2, d, H, "strain") == pytest.approx(
        48 * E / (5 * math.pi * H * d**3)
    )
    assert mat.micromodulus_constant(3, d, 1.0, None) == pytest.approx(12 * E / (math.pi * d**4))
