"""The Warp step kernels (velocity Verlet, central difference, kinematic conditions,
body-force loads, mass damping, the broken-bond count) against their NumPy twins on
Warp's CPU device: the same bits (one operation order, no FMA)."""

from __future__ import annotations

import numpy as np
import pytest

wp = pytest.importorskip("warp", reason="warp-lang not installed (pip install '.[gpu]')")
pytestmark = pytest.mark.gpu  # the Warp tier (pytest -m gpu); the smoke test: test_warp_kernels.py

from peridynamics.backends import _warp_step_dsl as k  # noqa: E402

N, D = 57, 3
RNG = np.random.default_rng(7)


def _a(x: np.ndarray) -> object:
    return wp.array(np.ascontiguousarray(x, dtype=np.float64), dtype=wp.float64, device="cpu")


def _fields() -> tuple[np.ndarray, ...]:
    u, v, f, b, up = (RNG.normal(size=(N, D)) for _ in range(5))
    inv = 1.0 / RNG.uniform(1000.0, 3000.0, size=N)
    return u, v, f * 1e9, b * 1e8, up, inv


def test_velocity_verlet_halves() -> None:
    u, v, f, b, _, inv = _fields()
    dt = 3.7e-8
    du, dv = _a(u), _a(v)
    wp.launch(k.kick_drift, N, [du, dv, _a(f), _a(b), _a(inv), wp.float64(dt)], device="cpu")
    v1 = v + (0.5 * dt) * (f + b) * inv[:, None]
    u1 = u + dt * v1
    assert np.array_equal(dv.numpy(), v1) and np.array_equal(du.numpy(), u1)
    wp.launch(k.kick, N, [dv, _a(f), _a(b), _a(inv), wp.float64(dt)], device="cpu")
    assert np.array_equal(dv.numpy(), v1 + (0.5 * dt) * (f + b) * inv[:, None])


def test_central_difference_and_its_velocity() -> None:
    u, v, f, b, up, inv = _fields()
    dt = 2.1e-8
    du, dup, dv = _a(u), _a(up), _a(v)
    wp.launch(k.central_difference, N, [du, dup, dv, _a(f), _a(b), _a(inv), wp.float64(dt)],
              device="cpu")  # fmt: skip
    new = 2.0 * u - up + (dt * dt) * (f + b) * inv[:, None]
    assert np.array_equal(du.numpy(), new) and np.array_equal(dup.numpy(), u)
    assert np.array_equal(dv.numpy(), (new - u) / dt)
    wp.launch(k.end_of_step_velocity, N, [du, dup, dv, _a(f), _a(b), _a(inv), wp.float64(dt)],
              device="cpu")  # fmt: skip
    expect = (new - u) / dt + (0.5 * dt) * (f + b) * inv[:, None]
    assert np.array_equal(dv.numpy(), expect)


def test_conditions_loads_damping_count() -> None:
    u, v, f, b, _, _ = _fields()
    nodes = np.array([3, 9, 11, 40], dtype=np.int32)
    dn = wp.array(nodes, dtype=wp.int32, device="cpu")
    du, dv = _a(u), _a(v)
    wp.launch(k.set_displacement, len(nodes), [dn, 1, wp.float64(2.5e-6), wp.float64(-0.3),
              du, dv], device="cpu")  # fmt: skip
    u[nodes, 1], v[nodes, 1] = 2.5e-6, -0.3
    dt = 1e-7
    wp.launch(k.drive_velocity, len(nodes), [dn, 2, wp.float64(0.7), wp.float64(0.9),
              wp.float64(dt), du, dv], device="cpu")  # fmt: skip
    u[nodes, 2] += dt * (0.7 - v[nodes, 2])
    v[nodes, 2] = 0.9
    wp.launch(k.set_velocity, len(nodes), [dn, 0, wp.float64(-1.5), dv], device="cpu")
    v[nodes, 0] = -1.5
    assert np.array_equal(du.numpy(), u) and np.array_equal(dv.numpy(), v)
    value = RNG.normal(size=(len(nodes), D))
    db = _a(b)
    wp.launch(k.add_load, len(nodes), [dn, _a(value), wp.float64(0.37), db], device="cpu")
    b[nodes] += value * 0.37
    assert np.array_equal(db.numpy(), b)
    coef = RNG.uniform(1e5, 1e6, size=N)
    df = _a(f)
    wp.launch(k.mass_damping, N, [_a(coef), dv, df], device="cpu")
    assert np.array_equal(df.numpy(), f - coef[:, None] * v)
    broken = RNG.integers(0, 4, size=N).astype(np.int64)
    total = wp.zeros(1, dtype=wp.int64, device="cpu")
    wp.launch(k.count_broken, N, [wp.array(broken, dtype=wp.int64, device="cpu"), total],
              device="cpu")  # fmt: skip
    assert int(total.numpy()[0]) == int(broken.sum())


def test_first_bad_point_finds_each_kind() -> None:
    u, v, *_ = _fields()
    stretch = np.zeros(N)
    shift = np.zeros(D)

    def first(u: np.ndarray, v: np.ndarray, stretch: np.ndarray) -> int:
        out = wp.array(np.array([np.iinfo(np.int32).max], dtype=np.int32), device="cpu")
        wp.launch(k.first_bad_point, N, [_a(u), _a(v), _a(shift), wp.float64(10.0),
                  _a(stretch), wp.float64(1.0), out], device="cpu")  # fmt: skip
        return int(out.numpy()[0])

    assert first(u, v, stretch) == np.iinfo(np.int32).max  # all sound
    u2 = u.copy()
    u2[20, 1] = 11.0
    assert first(u2, v, stretch) == 20
    v2 = v.copy()
    v2[8, 0] = np.nan
    assert first(u2, v2, stretch) == 8
    s2 = stretch.copy()
    s2[5] = 1.5
    assert first(u, v, s2) == 5
