"""Lattices (:mod:`peridynamics.geometry.lattice`): the regular generators are a
lattice's cloud bit for bit, a window holds the rows of that cloud with their global ids,
block counts add up, and the regions that look at the whole body are told apart."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from peridynamics.geometry import Ball, Box, HalfSpace, Layer, NearestPoint, box, disc, rectangle
from peridynamics.geometry.generators import cylinder
from peridynamics.geometry.lattice import (
    box_lattice,
    cylinder_lattice,
    disc_lattice,
    rectangle_lattice,
)
from peridynamics.geometry.regions import is_pointwise, map_leaves
from peridynamics.parallel.grid_rcb import box_owner, mask_layer_counts, rcb_boxes

HOLE = [Ball((0.011, 0.006), 0.003)]
CASES = {
    "rectangle": (
        lambda: rectangle_lattice((0.025, 0.0133), 1e-3, 0.01, (0.0, 0.0), "strain", HOLE),
        lambda: rectangle((0.025, 0.0133), 1e-3, thickness=0.01, plane="strain", holes=HOLE),
    ),
    "disc": (
        lambda: disc_lattice(
            0.0093, 1e-3, (0.1, 0.2), 0.02, "stress", [Box((0.1, 0.2), (0.2, 0.3))]
        ),
        lambda: disc(0.0093, 1e-3, (0.1, 0.2), thickness=0.02, holes=[Box((0.1, 0.2), (0.2, 0.3))]),
    ),
    "box": (
        lambda: box_lattice((0.008, 0.0061, 0.005), 1e-3, (0.1, 0.0, -0.2)),
        lambda: box((0.008, 0.0061, 0.005), 1e-3, origin=(0.1, 0.0, -0.2)),
    ),
    "cylinder": (
        lambda: cylinder_lattice(0.0047, 0.0063, 1e-3, (0.1, 0.2, 0.3)),
        lambda: cylinder(0.0047, 0.0063, 1e-3, origin=(0.1, 0.2, 0.3)),
    ),
}


@pytest.mark.parametrize("kind", list(CASES))
def test_lattice_is_the_generator_and_windows_are_its_rows(kind: str) -> None:
    make_lattice, make_cloud = CASES[kind]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        lattice, ref = make_lattice(), make_cloud()
    got = lattice.cloud()
    np.testing.assert_array_equal(got.x, ref.x)
    np.testing.assert_array_equal(got.volume, ref.volume)
    assert (got.plane, got.cross_section, got.grid_fit) == (
        ref.plane,
        ref.cross_section,
        ref.grid_fit,
    )
    counts = lattice.slab_counts(np.arange(lattice.shape[0]))
    start = np.concatenate([[0], np.cumsum(counts)])
    assert start[-1] == ref.n_points
    lo = [2] * lattice.dim
    hi = [n - 1 for n in lattice.shape]
    x, ids, index = lattice.window(lo, hi, start)
    np.testing.assert_array_equal(x, ref.x[ids])  # the rows of the cloud, same bits
    assert np.all(np.diff(ids) > 0)
    assert np.all((index >= lo) & (index < hi))
    # every kept point of the index box, none else
    idx_all = np.round((ref.x - [a[0] for a in lattice.axes]) / lattice.spacing).astype(int)
    inside = np.all((idx_all >= lo) & (idx_all < hi), axis=1)
    np.testing.assert_array_equal(ids, np.flatnonzero(inside))
    # the bisection of the body into boxes from masks split between two "ranks"
    masks = np.stack(
        [lattice.kept(lattice.grid(i, i + 1)).reshape(lattice.shape[1:])
         for i in range(lattice.shape[0])]
    )  # fmt: skip
    half = lattice.shape[0] // 2

    def counts(requests):  # two ranks' counts, summed
        a = mask_layer_counts(masks[:half], 0, requests)
        b = mask_layer_counts(masks[half:], half, requests)
        return [p + q for p, q in zip(a, b, strict=True)]

    for parts in (2, 3, 5):
        boxes = rcb_boxes(lattice.shape, parts, counts)
        idx = np.argwhere(masks)  # grid index of every point, grid order
        owner = box_owner(boxes, idx)
        assert owner.min() == 0  # every point has one part
        load = np.bincount(owner, minlength=parts)
        layer = max(int(np.prod(lattice.shape)) // min(lattice.shape), 1)  # one layer
        assert np.all(np.abs(load - ref.n_points / parts) <= layer), (parts, load)


def test_empty_window_and_regions_that_see_the_whole_body() -> None:
    lattice = rectangle_lattice((0.01, 0.01), 1e-3)
    start = np.concatenate([[0], np.cumsum(lattice.slab_counts(np.arange(10)))])
    x, ids, index = lattice.window([5, 5], [5, 9], start)
    assert x.shape == (0, 2) and ids.size == 0 and index.shape == (0, 2)
    assert is_pointwise(Ball((0, 0), 1.0) & ~HalfSpace((0, 0), (1, 0)))
    assert not is_pointwise(Ball((0, 0), 1.0) | Layer((1, 0), 1e-3))
    assert not is_pointwise(~NearestPoint((0, 0)))
    with pytest.raises(ValueError, match="point-wise"):
        lattice.with_removed(Layer((1, 0), 1e-3))
    # a layer with the body's top given selects the same rows of any part of the body
    full = lattice.cloud().x
    layer = Layer((1, 0), 2e-3)
    part = full[full[:, 0] > 0.004]
    np.testing.assert_array_equal(
        Layer((1, 0), 2e-3, top=float(full[:, 0].max()))(part), layer(part)
    )
    swapped = map_leaves(
        Ball((0, 0), 1.0) & ~layer, lambda r: Box((0, 0), (1, 1)) if r is layer else r
    )
    assert is_pointwise(swapped)
