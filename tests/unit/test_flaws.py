"""Crack-initiation direction and coalescence counting on synthetic damage fields."""

from __future__ import annotations

import numpy as np
import pytest

from peridynamics.analysis.flaws import angle_between_lines, bridges, initiation_direction


def grid(n: int = 60, h: float = 1.0):
    g = (np.arange(n) + 0.5) * h
    X, Y = np.meshgrid(g, g, indexing="ij")
    return np.column_stack([X.ravel(), Y.ravel()])


@pytest.mark.parametrize("angle", [0.0, 37.0, 90.0, 135.0, -60.0])
def test_initiation_direction_of_a_straight_damage_line(angle: float) -> None:
    x = grid()
    tip = np.array([30.0, 30.0])
    d = np.array([np.cos(np.radians(angle)), np.sin(np.radians(angle))])
    rel = x - tip
    along = rel @ d
    across = np.abs(rel @ np.array([-d[1], d[0]]))
    phi = np.where((along > 0.5) & (along < 8) & (across < 0.8), 0.5, 0.0)
    got = initiation_direction(x, phi, np.zeros(len(x)), tip, radius=10.0)
    assert got is not None
    assert angle_between_lines(got, angle) < 6.0
    assert abs(((got - angle) + 180) % 360 - 180) < 6.0  # pointing away from the tip
    assert initiation_direction(x, np.zeros(len(x)), np.zeros(len(x)), tip, 10.0) is None


def test_angle_between_lines() -> None:
    assert angle_between_lines(10, 190) == pytest.approx(0)
    assert angle_between_lines(0, 100) == pytest.approx(80)
    assert angle_between_lines(-45, 45) == pytest.approx(90)


def test_bridges_counts_independent_links() -> None:
    x = grid()
    near_a = np.linalg.norm(x - [15, 30], axis=1) < 4
    near_b = np.linalg.norm(x - [45, 30], axis=1) < 4
    phi0 = np.zeros(len(x))
    phi = np.zeros(len(x))
    assert bridges(x, phi, phi0, near_a, near_b, 1.0) == 0
    band1 = (np.abs(x[:, 1] - 30) < 0.6) & (x[:, 0] > 12) & (x[:, 0] < 48)
    phi[band1] = 0.6
    assert bridges(x, phi, phi0, near_a, near_b, 1.0) == 1
    # a second, separate band between the two zones: two independent links
    touching = (np.abs(x[:, 1] - 31.5) < 0.6) & (x[:, 0] > 12) & (x[:, 0] < 48)
    phi[touching] = 0.6
    assert bridges(x, phi, phi0, near_a, near_b, 1.0) == 1  # adjacent rows: one cluster
    phi[touching] = 0.0
    band3 = (np.abs(x[:, 1] - 33.5) < 0.6) & (x[:, 0] > 12) & (x[:, 0] < 48)
    phi[band3] = 0.6
    assert bridges(x, phi, phi0, near_a, near_b, 1.0) == 2
    # damage that was there at t = 0 does not count
    assert bridges(x, phi, phi, near_a, near_b, 1.0) == 0
