"""Jittered grids made a window at a time (:mod:`peridynamics.geometry.jittered_lattice`):
the offsets of any window are the rows of the one draw, the Voronoi volumes computed in
blocks of slabs equal those of one diagram to round-off, and a window of the lattice is
the generator's cloud's rows bit for bit (positions, volumes, global ids)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import peridynamics.geometry.jitter as jit
from peridynamics.geometry import Ball, box, disc, rectangle
from peridynamics.geometry.jitter import grid_offsets
from peridynamics.geometry.jittered_lattice import jittered_lattice
from peridynamics.geometry.lattice import box_lattice, disc_lattice, rectangle_lattice

DX = 1e-3


def test_offsets_of_a_window_are_the_rows_of_the_one_draw() -> None:
    whole = np.random.default_rng(11).uniform(-0.3 * DX, 0.3 * DX, size=(500, 3))
    np.testing.assert_array_equal(grid_offsets(11, 0.3, DX, 123, 200, 3), whole[123:323])


CASES = {
    "rectangle": (
        lambda: rectangle((0.03, 0.02), DX, thickness=0.01, holes=[Ball((0.01, 0.01), 0.004)],
                          jitter=0.3, seed=3),
        lambda: rectangle_lattice((0.03, 0.02), DX, 0.01, (0.0, 0.0), "stress",
                                  [Ball((0.01, 0.01), 0.004)]),
        0.01,
    ),
    "disc": (
        lambda: disc(0.01, DX, thickness=0.01, jitter=0.4, seed=2),
        lambda: disc_lattice(0.01, DX, (0.0, 0.0), 0.01, "stress", []),
        0.01,
    ),
    "box": (
        lambda: box((0.012, 0.008, 0.006), DX, jitter=0.25, seed=5),
        lambda: box_lattice((0.012, 0.008, 0.006), DX, (0.0, 0.0, 0.0), []),
        1.0,
    ),
}  # fmt: skip


@pytest.mark.parametrize("kind", sorted(CASES))
def test_windows_are_the_rows_of_the_jittered_cloud(
    kind: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    make, lattice_of, thickness = CASES[kind]
    monkeypatch.setattr(jit, "BLOCK_POINTS", 100)  # blocks of 4 slabs: many blocks
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cloud = make()
        lat = lattice_of()
    seed, jitter = {"rectangle": (3, 0.3), "disc": (2, 0.4), "box": (5, 0.25)}[kind]
    jl = jittered_lattice(lat, jitter, seed, "voronoi", thickness)
    whole = jl.cloud()
    np.testing.assert_array_equal(whole.x, cloud.x)
    np.testing.assert_array_equal(whole.volume, cloud.volume)
    assert cloud.irregular and whole.irregular
    counts = jl.slab_counts(np.arange(jl.shape[0]))
    start = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    lo = [2] + [1] * (jl.dim - 1)
    hi = [jl.shape[0] - 3] + [n - 2 for n in jl.shape[1:]]
    x, ids, index = jl.window(lo, hi, start)
    assert len(ids) > 0
    np.testing.assert_array_equal(x, cloud.x[ids])
    np.testing.assert_array_equal(jl.volumes_at(index), cloud.volume[ids])


def test_block_volumes_equal_one_diagram_to_round_off(monkeypatch: pytest.MonkeyPatch) -> None:
    lat = jittered_lattice(
        rectangle_lattice((0.04, 0.02), DX, 1.0, (0.0, 0.0), "stress", []), 0.45, 9
    )
    one = lat.slab_volumes(0, lat.shape[0])  # 800 points: one block
    monkeypatch.setattr(jit, "BLOCK_POINTS", 60)
    blocks = lat.slab_volumes(0, lat.shape[0])
    np.testing.assert_allclose(blocks, one, rtol=1e-13, atol=0.0)
    assert abs(blocks.sum() / (0.04 * 0.02) - 1.0) < 1e-12  # the box's area
