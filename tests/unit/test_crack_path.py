"""Crack-path extraction on synthetic damage fields, tip speeds and Rayleigh speeds."""

from __future__ import annotations

import math

import numpy as np
import pytest

from peridynamics.analysis.crack_path import extract_crack_path, extract_crack_paths
from peridynamics.analysis.crack_polyline import polyline_angles
from peridynamics.analysis.crack_speed import rayleigh_speed, tip_speed_from_paths

H = 1.0e-3  # grid spacing, m


def _grid(nx: int, ny: int, x0: float = 0.0, y0: float = 0.0) -> np.ndarray:
    """Cell-centred grid of nx x ny points of spacing H with lower-left corner (x0, y0)."""
    i, j = np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij")
    return np.column_stack([x0 + (i.ravel() + 0.5) * H, y0 + (j.ravel() + 0.5) * H])


def _dist_to_segment(x: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    ab = b - a
    t = np.clip(((x - a) @ ab) / (ab @ ab), 0.0, 1.0)
    return np.linalg.norm(x - (a + t[:, None] * ab), axis=1)


def _damage(x: np.ndarray, polylines: list[np.ndarray], half_width: float = 2.0 * H):
    """Damage 0.6 within ``half_width`` of any segment of the polylines, a random
    0 ... 0.3 background elsewhere (seeded): a band like a PD crack's, 2 delta wide."""
    rng = np.random.default_rng(0)
    d = rng.uniform(0.0, 0.3, len(x))
    for pl in polylines:
        for a, b in zip(pl[:-1], pl[1:], strict=True):
            d[_dist_to_segment(x, a, b) <= half_width] = 0.6
    return d


def _ray(p: np.ndarray, angle_deg: float, length: float) -> np.ndarray:
    a = math.radians(angle_deg)
    return p + length * np.array([math.cos(a), math.sin(a)])


def test_straight_crack_at_30_degrees() -> None:
    x = _grid(80, 60, -0.01, -0.01)
    seed = np.array([0.0, 0.0])
    end = _ray(seed, 30.0, 0.05)
    path = extract_crack_path(x, _damage(x, [np.array([seed, end])]), seed, H)
    assert path.initial_angle_deg == pytest.approx(30.0, abs=2.0)
    # the band reaches half_width beyond the end: the tip is the farthest damaged point
    assert path.length == pytest.approx(0.05 + 2 * H, abs=2 * H)
    inner = (path.arc_length > 4 * H) & (path.arc_length < path.length - 4 * H)
    assert np.all(np.abs(path.angles_deg[inner] - 30.0) < 5.0)
    assert path.n_branches == 1
    assert np.linalg.norm(path.tip - end) < 3 * H
    # a longer initial length gives the same angle on a straight crack
    assert path.angle_over(0.03) == pytest.approx(30.0, abs=1.0)
    assert path.arc_length[-1] == pytest.approx(path.length)


def test_kinked_crack() -> None:
    x = _grid(80, 80, -0.01, -0.01)
    seed = np.array([0.0, 0.0])
    kink = _ray(seed, 0.0, 0.025)
    end = _ray(kink, 60.0, 0.03)
    path = extract_crack_path(x, _damage(x, [np.array([seed, kink, end])]), seed, H)
    assert path.initial_angle_deg == pytest.approx(0.0, abs=2.0)
    assert path.length == pytest.approx(0.055, abs=3 * H)  # a chord cuts the corner
    s = path.arc_length
    before = path.angles_deg[(s > 5 * H) & (s < 0.02)]
    after = path.angles_deg[(s > 0.032) & (s < path.length - 4 * H)]
    assert np.all(np.abs(before) < 5.0) and before.size >= 3
    assert np.all(np.abs(after - 60.0) < 5.0) and after.size >= 3


def test_only_the_seeds_crack_is_followed() -> None:
    """A longer crack nearby that does not touch the seed's crack is never followed
    (the fault of the farthest-damaged-point tip)."""
    x = _grid(120, 60, -0.01, -0.03)
    seed = np.array([0.0, 0.0])
    a = np.array([seed, _ray(seed, 70.0, 0.02)])
    other = np.array([[0.0, -0.015], [0.1, -0.02]])  # 10 spacings away, 5x longer
    d = _damage(x, [a, other])
    path = extract_crack_path(x, d, seed, H)
    assert path.length == pytest.approx(0.02 + 2 * H, abs=2 * H)
    assert path.initial_angle_deg == pytest.approx(70.0, abs=2.0)
    assert np.all(x[path.points, 1] > -0.01)  # no point of the other crack
    # seeded on the other crack, the same field gives the other crack
    other_path = extract_crack_path(x, d, other[0], H)
    assert other_path.length > 0.09
    assert np.all(x[other_path.points, 1] < -0.01)


def test_branched_crack_main_is_the_longest() -> None:
    x = _grid(110, 80, -0.01, -0.04)
    seed = np.array([0.0, 0.0])
    fork = _ray(seed, 0.0, 0.03)
    up = np.array([fork, _ray(fork, 25.0, 0.05)])
    down = np.array([fork, _ray(fork, -30.0, 0.03)])
    d = _damage(x, [np.array([seed, fork]), up, down])
    path = extract_crack_path(x, d, seed, H)
    assert path.n_branches == 2
    assert path.branch_lengths[0] == pytest.approx(0.08, abs=4 * H)
    assert path.branch_lengths[1] == pytest.approx(0.06, abs=4 * H)
    assert path.length == path.branch_lengths[0]
    assert np.linalg.norm(path.tip - up[1]) < 3 * H  # the main path ends on the long branch
    assert np.linalg.norm(path.branches[1][-1] - down[1]) < 3 * H
    assert path.initial_angle_deg == pytest.approx(0.0, abs=2.0)
    # each branch is a path from the seed: its last part follows its own direction
    br = path.branches[1]
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(br, axis=0), axis=1))])
    a, b = (
        np.array([np.interp(s, arc, br[:, j]) for j in (0, 1)]) for s in arc[-1] - [0.02, 0.003]
    )
    assert polyline_angles(np.array([a, b]))[0] == pytest.approx(-30.0, abs=3.0)


def test_seed_mask_exclusion_and_reference_direction() -> None:
    """A notch modelled as pre-damaged points: excluded, the crack grows from a seed
    region at its tip; angles measured from the notch direction."""
    x = _grid(80, 80, -0.04, -0.01)
    notch = np.array([[-0.03, 0.0], [0.0, 0.0]])
    crack = np.array([[0.0, 0.0], _ray(np.zeros(2), 110.0, 0.03)])
    d = _damage(x, [notch, crack])
    pre = _dist_to_segment(x, notch[0], notch[1] - [2 * H, 0.0]) <= 2.0 * H  # at t = 0
    tip_zone = np.linalg.norm(x - notch[1], axis=1) <= 3 * H
    path = extract_crack_path(x, d, tip_zone, H, exclude=pre, initial_length=10 * H)
    assert path.initial_angle_deg == pytest.approx(110.0, abs=3.0)
    assert not np.any(pre[path.points])
    # measured from the direction (-1, 0) the same crack is at -70 degrees
    p2 = extract_crack_path(
        x, d, tip_zone, H, exclude=pre, initial_length=10 * H, reference_direction=[-1.0, 0.0]
    )
    assert p2.initial_angle_deg == pytest.approx(-70.0, abs=3.0)
    # without the exclusion the notch's points join the cluster
    p3 = extract_crack_path(x, d, tip_zone, H)
    assert p3.points.size > path.points.size


def test_two_seeds_split_a_joined_cluster() -> None:
    """Two notch cracks joined by a long crack between them (as in a Kalthoff-Winkler
    plate at high impact speed): one seed alone runs on along the bridge to the other
    crack; with both seeds each keeps its own crack."""
    x = _grid(100, 120, -0.01, -0.06)
    s_up, s_dn = np.array([0.0, 0.025]), np.array([0.0, -0.025])
    up = np.array([s_up, _ray(s_up, 65.0, 0.03)])
    dn = np.array([s_dn, _ray(s_dn, -65.0, 0.03)])
    bridge = np.array([s_up, [0.02, 0.0], [0.08, 0.0], [0.02, 0.0], s_dn])
    d = _damage(x, [up, dn, bridge])
    alone = extract_crack_path(x, d, s_up, H)
    assert alone.length > 0.08  # along the bridge: longer than its own 30 mm crack
    p_up, p_dn = extract_crack_paths(x, d, [s_up, s_dn], H, initial_length=10 * H)
    assert not np.intersect1d(p_up.points, p_dn.points).size
    assert np.all(x[p_up.points, 1] > -2 * H) and np.all(x[p_dn.points, 1] < 2 * H)
    # the bridge is split at y = 0: half of it (~ 32 + 60 mm) beats the 30 mm crack, so
    # the main path is the bridge; the 65-degree crack is a kept branch
    assert p_up.n_branches >= 2 and p_dn.n_branches >= 2
    # restricted to the far side of each notch, the main path is the notch's own crack
    q_up, q_dn = extract_crack_paths(
        x, d, [s_up, s_dn], H, initial_length=10 * H, within=np.abs(x[:, 1]) >= 0.025 - H
    )
    assert q_up.initial_angle_deg == pytest.approx(65.0, abs=3.0)
    assert q_dn.initial_angle_deg == pytest.approx(-65.0, abs=3.0)
    assert q_up.length == pytest.approx(0.032, abs=3 * H)


def test_no_crack_gives_an_empty_path() -> None:
    x = _grid(20, 20)
    path = extract_crack_path(x, np.zeros(len(x)), np.array([0.01, 0.01]), H)
    assert path.empty and path.length == 0.0 and math.isnan(path.initial_angle_deg)
    assert path.vertices.shape == (1, 2) and path.n_branches == 0


def test_three_dimensional_crack() -> None:
    i, j, k = np.meshgrid(np.arange(40), np.arange(12), np.arange(12), indexing="ij")
    x = (np.column_stack([i.ravel(), j.ravel(), k.ravel()]) + 0.5) * H
    d = np.where(np.linalg.norm(x[:, 1:] - 0.006, axis=1) <= 1.5 * H, 0.6, 0.0)
    path = extract_crack_path(x, d, np.array([0.0, 0.006, 0.006]), H)
    assert path.length == pytest.approx(0.04, abs=2 * H)
    assert path.initial_angle_deg == pytest.approx(0.0, abs=2.0)


def test_tip_speed_from_linear_growth_and_flags() -> None:
    t = np.linspace(0.0, 50e-6, 51)
    rng = np.random.default_rng(1)
    lengths = 1500.0 * t + rng.uniform(-0.25, 0.25, t.size) * H  # grid-scale jitter
    speeds, flagged = tip_speed_from_paths(t, lengths, rayleigh_speed=2800.0, window=9)
    assert np.all(np.abs(speeds - 1500.0) < 150.0)
    assert not flagged.any()
    exact, _ = tip_speed_from_paths(t, 1500.0 * t, window=5)
    assert np.allclose(exact, 1500.0, rtol=1e-9)
    _, above = tip_speed_from_paths(t, 3000.0 * t, rayleigh_speed=2800.0)
    assert above.all()
    # a jump (another crack counted) shows up as flagged records around it, not clipped
    jump = np.where(t > 25e-6, 1500.0 * t + 0.03, 1500.0 * t)
    s_jump, f_jump = tip_speed_from_paths(t, jump, rayleigh_speed=2800.0)
    assert f_jump.any() and s_jump.max() > 2800.0
    assert not f_jump[:20].any()


def test_rayleigh_speed() -> None:
    E, rho = 190e9, 8000.0
    c_s = math.sqrt(E / (2 * (1 + 1 / 3)) / rho)
    # plane stress, nu = 1/3: the in-plane equations of plane strain with nu* = 1/4
    assert rayleigh_speed(E, None, rho, "stress") / c_s == pytest.approx(0.9176, abs=1e-4)
    assert rayleigh_speed(E, 1 / 3, rho, "stress", "exact") / c_s == pytest.approx(0.9194, abs=1e-4)
    c_s4 = math.sqrt(E / (2 * 1.25) / rho)
    assert rayleigh_speed(E, None, rho, "strain", "exact") / c_s4 == pytest.approx(0.9194, abs=1e-4)
    # nu = 1/3 in plane strain / 3-D: eta = 0.9325
    assert rayleigh_speed(E, 1 / 3, rho, "3d", "exact") / c_s == pytest.approx(0.9325, abs=1e-4)
    # Viktorov's fit: within 0.3 % for nu >= 0.2, 1.4 % at nu = 0
    for nu, tol in ((0.0, 0.015), (0.2, 0.003), (0.25, 0.003), (0.4, 0.003), (0.49, 0.003)):
        v = rayleigh_speed(E, nu, rho, "strain")
        assert v == pytest.approx(rayleigh_speed(E, nu, rho, "strain", "exact"), rel=tol)
