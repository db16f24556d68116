"""Two points joined by one bond oscillate with the closed-form period.

Points 0 and 1 at distance L along the unit vector e. For motion along e the stretch is
s = r / L exactly, r = (u_1 - u_0) . e, and the force densities are
f_0 = k_01 s e and f_1 = -k_10 s e (k_ij the stiffness of bond i -> j, N/m^3). Hence

    rho r'' = (f_1 - f_0) . e = -(k_01 + k_10) r / L,   omega^2 = (k_01 + k_10) / (rho L),

a linear oscillator for any amplitude; with equal volumes k_01 = k_10 = k and
T = 2 pi sqrt(rho L / (2 k)).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from peridynamics import BondBasedMaterial, Evaluator, ExplicitSolver, PointCloud, build_bonds
from peridynamics.loading import InitialVelocity

E, RHO = 70e9, 2700.0
L = 1e-3
HORIZON = 3.015e-3
DIR = np.array([1.0, 2.0, 2.0]) / 3.0


def two_points(v0: float, v1: float) -> tuple[Evaluator, float]:
    x = np.array([[0.1, -0.2, 0.3], [0.1, -0.2, 0.3] + L * DIR])
    cloud = PointCloud(x=x, volume=np.array([v0, v1]), spacing=L)
    bonds = build_bonds(cloud, HORIZON)
    assert bonds.n_bonds == 2
    model = Evaluator(cloud, bonds, BondBasedMaterial(E, RHO))
    # independent stiffness: c = 12 E / (pi delta^4), beta = 1 (L <= delta - dx/2)
    c = 12 * E / (math.pi * HORIZON**4)
    np.testing.assert_allclose(model.stiffness, [c * v1, c * v0], rtol=1e-13)
    omega = math.sqrt((model.stiffness[0] + model.stiffness[1]) / (RHO * L))
    return model, 2 * math.pi / omega


def measured_period(times, r):
    """Mean spacing of the rising zero crossings of r(t) (linear interpolation)."""
    k = np.flatnonzero((r[:-1] < 0) & (r[1:] >= 0))
    t0 = times[k] - r[k] * (times[k + 1] - times[k]) / (r[k + 1] - r[k])
    assert len(t0) >= 3
    return float(np.mean(np.diff(t0)))


@pytest.mark.parametrize("integrator", ["velocity_verlet", "central_difference"])
@pytest.mark.parametrize("volumes", [(1e-9, 1e-9), (1e-9, 2.5e-9)])
def test_two_point_bond_period(integrator, volumes):
    model, period = two_points(*volumes)
    vel = 0.5  # m/s, equal and opposite: r'(0) = 2 vel
    ivs = [
        InitialVelocity(nodes=np.array([0]), value=tuple(-vel * DIR)),
        InitialVelocity(nodes=np.array([1]), value=tuple(vel * DIR)),
    ]
    dt = period / 300
    solver = ExplicitSolver(model, time_step=dt, integrator=integrator, initial_velocities=ivs)
    assert dt < solver.stable_time_step
    s = solver.init()
    n_steps = int(4.5 * period / dt)
    times, r = [0.0], [0.0]
    perp = []
    mom = []
    for st in solver.irun(s, n_steps):
        d = st.u[1] - st.u[0]
        times.append(st.t)
        r.append(float(d @ DIR))
        perp.append(float(np.linalg.norm(d - (d @ DIR) * DIR)))
        mom.append(model.cloud.volume @ st.u)  # centre-of-mass motion is uniform
    times, r = np.array(times), np.array(r)
    t_meas = measured_period(times, np.concatenate([[-1e-30], r[1:]]))
    print(f"two-point period: measured {t_meas:.6e} s, closed form {period:.6e} s")
    assert t_meas == pytest.approx(period, rel=5e-3)
    # amplitude 2 vel / omega, motion stays on the bond axis
    amp = 2 * vel * period / (2 * math.pi)
    assert np.max(np.abs(r)) == pytest.approx(amp, rel=5e-3)
    assert max(perp) < 1e-9 * amp
    # momentum sum rho V u: for equal volumes the centre of mass stays at rest;
    # in general it is V0 u0 + V1 u1 = t (V1 - V0) vel e
    vols = np.array(volumes)
    expect = np.outer(times[1:], (vols[1] - vols[0]) * vel * DIR)
    np.testing.assert_allclose(np.array(mom), expect, atol=1e-12 * vols.max() * amp)
