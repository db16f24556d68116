"""Wave speed in a bar and energy conservation of velocity Verlet without damage."""

from __future__ import annotations

import math

import numpy as np
import pytest

from peridynamics import BondBasedMaterial, Evaluator, ExplicitSolver, build_bonds
from peridynamics.geometry import bar, rectangle


@pytest.mark.long
def test_long_wave_speed_in_a_bar():
    """A Gaussian displacement of width 20 horizons splits into two pulses travelling at
    +-sqrt(E / rho). With delta = 3 dx and the truncated rule the long-wave modulus is
    exactly E (c A dx^2 (1 + 2 + 3/2) = E), and dispersion at k delta ~ 0.05 is ~1e-4."""
    E, rho, dx = 200e9, 7850.0, 1e-3
    c0 = math.sqrt(E / rho)
    cloud = bar(1.0, dx, area=1e-4)
    model = Evaluator(cloud, build_bonds(cloud, 3 * dx), BondBasedMaterial(E, rho))
    solver = ExplicitSolver(model)
    s = solver.init()
    x = cloud.x[:, 0]
    x0, width = 0.3, 0.02
    s.u[:, 0] = 1e-6 * np.exp(-0.5 * ((x - x0) / width) ** 2)
    model.internal_force(s.u, s.intact, s.force, s.max_stretch)
    right = x > x0

    def centroid(u):  # energy-like centroid of the right-going pulse
        w = u[right, 0] ** 2
        return float(np.sum(x[right] * w) / np.sum(w))

    def peak(u):  # parabola through the largest sample on the right
        k = int(np.argmax(u[right, 0])) + int(np.argmax(right))
        y0, y1, y2 = u[k - 1, 0], u[k, 0], u[k + 1, 0]
        return x[k] + 0.5 * dx * (y0 - y2) / (y0 - 2 * y1 + y2)

    times, cents, peaks = [], [], []
    for st in solver.irun(s, solver.steps_for(0.45 / c0)):
        if st.step % 10 == 0 and st.t > 6 * width / c0:  # the two pulses have separated
            times.append(st.t)
            cents.append(centroid(st.u))
            peaks.append(peak(st.u))
    assert len(times) > 10
    # the pulse really travelled (about 0.15 m) and is still far from the end
    assert peaks[-1] - peaks[0] > 0.1 and peaks[-1] < 0.9
    speed_c = np.polyfit(times, cents, 1)[0]
    speed_p = np.polyfit(times, peaks, 1)[0]
    print(f"bar wave speed: {speed_c:.2f} (centroid), {speed_p:.2f} (peak) vs {c0:.2f} m/s")
    assert speed_c == pytest.approx(c0, rel=1e-2)
    assert speed_p == pytest.approx(c0, rel=1e-2)
    # half the amplitude goes each way
    assert s.u[right, 0].max() == pytest.approx(0.5e-6, rel=2e-2)


def _plate_with_smooth_velocity(correction: bool, seed: int = 0):
    E, rho, dx = 70e9, 2700.0, 1e-3
    lx, ly = 0.02, 0.016
    cloud = rectangle((lx, ly), dx)
    model = Evaluator(
        cloud,
        build_bonds(cloud, 3.015 * dx),
        BondBasedMaterial(E, rho),
        surface_correction=correction,
    )
    solver = ExplicitSolver(model)  # 0.8 x stable
    s = solver.init()
    rng = np.random.default_rng(seed)
    x, y = cloud.x[:, 0] / lx, cloud.x[:, 1] / ly
    for comp in range(2):
        for m in range(3):
            for n in range(3):
                s.v[:, comp] += (
                    rng.normal()
                    * np.cos(m * np.pi * x + rng.uniform(0, 6))
                    * np.cos(n * np.pi * y + rng.uniform(0, 6))
                )
    s.v *= 0.1  # m/s: strains of order 1e-5, linear regime
    return model, solver, s


@pytest.mark.parametrize("correction", [False, True])
def test_velocity_verlet_conserves_energy_without_damage(correction):
    """Velocity Verlet conserves, for a linear system, exactly the 'shadow' energy
    1/2 sum rho V v_{n-1/2} . v_{n+1/2} + U(u_n) = K(v_n) - dt^2/8 sum rho V |a_n|^2 + U(u_n);
    the ordinary K + U oscillates by O((omega dt)^2) around a constant with no drift."""
    model, solver, s = _plate_with_smooth_velocity(correction)
    rho_v = model.density * model.cloud.volume
    dt = solver.dt

    def energies(st):
        k = model.kinetic_energy(st.v)
        u = model.strain_energy(st.u, st.intact)
        a = st.force / model.density[:, None]
        return k + u, k + u - dt**2 / 8 * np.sum(rho_v * np.sum(a * a, axis=1))

    e0, sh0 = energies(s)
    total, shadow = [], []
    for st in solver.irun(s, 2000):  # every step: no aliasing of the O(dt^2) oscillation
        t, sh = energies(st)
        total.append(t)
        shadow.append(sh)
    total, shadow = np.array(total) / e0, np.array(shadow) / sh0
    assert np.abs(shadow - 1).max() < 1e-4  # measured ~1e-6 (geometric nonlinearity)
    assert np.abs(total - 1).max() < 3e-2  # bounded O((omega dt)^2) oscillation
    q = len(total) // 4
    # no secular drift: window means and the least-squares trend of K + U over the 2000
    # steps both move by < 1e-4 of the energy (measured 2e-5..4e-5)
    assert abs(total[-q:].mean() - total[:q].mean()) < 1e-4
    trend = np.polyfit(np.linspace(0.0, 1.0, len(total)), total, 1)[0]
    assert abs(trend) < 1e-4
    assert s.bonds_broken == 0
    # momentum: the initial field has a net momentum that must be kept exactly
    p0 = rho_v @ _plate_with_smooth_velocity(correction)[2].v
    np.testing.assert_allclose(rho_v @ s.v, p0, rtol=1e-9, atol=1e-12 * np.abs(p0).max())
