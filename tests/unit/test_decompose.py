"""Domain decomposition without MPI: the partition, the ghosts, a rank's bond families
(the serial families in the serial order) and loads built on the global cloud."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import cKDTree

from peridynamics.bonds import build_bonds
from peridynamics.bonds.partial_volume import search_radius
from peridynamics.bonds.search import neighbour_counts
from peridynamics.geometry import rectangle
from peridynamics.geometry.cloud import PointCloud
from peridynamics.loading.conditions import traction_as_body_force
from peridynamics.parallel.decompose import Layout, ghost_points, rcb_partition
from peridynamics.parallel.local import local_cloud, localize_condition, own_families


def _cloud() -> PointCloud:
    c = rectangle((0.03, 0.02), 1e-3, thickness=1e-3, plane="stress")
    top = np.flatnonzero(c.x[:, 1] > c.x[:, 1].max() - 2.5e-3)  # three rows
    return c.with_node_sets(top=top)


@pytest.mark.parametrize("parts", [2, 3, 4, 7])
def test_rcb_balances_bonds_and_cuts_boxes(parts: int) -> None:
    c = _cloud()
    w = neighbour_counts(c.x, 3e-3).astype(float) + 1.0
    part = rcb_partition(c.x, w, parts)
    assert set(np.unique(part)) == set(range(parts))
    load = np.bincount(part, weights=w, minlength=parts)
    # cuts fall between grid rows: at most one row of points off the even share
    row = w.sum() / min(len(np.unique(c.x[:, 0])), len(np.unique(c.x[:, 1]))) * 1.0
    assert np.all(np.abs(load - w.sum() / parts) <= row * 1.05)
    np.testing.assert_array_equal(part, rcb_partition(c.x, w, parts))  # deterministic
    # parts are boxes: no point of another part inside a part's bounding box
    for p in range(parts):
        lo, hi = c.x[part == p].min(axis=0), c.x[part == p].max(axis=0)
        inside = np.all((c.x >= lo) & (c.x <= hi), axis=1)
        assert np.all(part[inside] == p)


def test_rcb_refuses_more_parts_than_points() -> None:
    with pytest.raises(ValueError, match="fewer ranks"):
        rcb_partition(np.zeros((3, 2)), np.ones(3), 4)


def test_ghosts_are_the_points_within_the_radius() -> None:
    c = _cloud()
    part = rcb_partition(c.x, np.ones(c.n_points), 3)
    owned = np.flatnonzero(part == 1)
    got = ghost_points(c.x, owned, 2.2e-3)
    d, _ = cKDTree(c.x[owned]).query(c.x, k=1)
    want = np.flatnonzero((d <= 2.2e-3) & (part != 1))
    np.testing.assert_array_equal(got, want)


def _rank_layout(c: PointCloud, part: np.ndarray, rank: int, radius: float) -> tuple[Layout, int]:
    owned = np.flatnonzero(part == rank)
    ghosts = ghost_points(c.x, owned, 2 * radius)
    first = np.isin(ghosts, ghost_points(c.x, owned, radius))
    ghosts = np.concatenate([ghosts[first], ghosts[~first]])
    ids = np.concatenate([owned, ghosts])
    return Layout(rank, int(part.max()) + 1, len(part), ids, len(owned), {}, {}), len(owned) + int(
        first.sum()
    )


@pytest.mark.parametrize("rule", ["truncated", "extended"])
def test_rank_families_are_the_serial_families_in_order(rule: str) -> None:
    c = _cloud()
    horizon = 3.015e-3
    serial = build_bonds(c, horizon, rule)
    radius = search_radius(horizon, c.spacing, rule)
    part = rcb_partition(c.x, np.ones(c.n_points), 3)
    for rank in range(3):
        layout, n_family = _rank_layout(c, part, rank, radius)
        local = local_cloud(c, layout)
        bonds = own_families(build_bonds(local, horizon, rule), local, n_family)
        gid = local.global_ids
        assert gid is not None
        for k in range(n_family):  # owned points and the first ghost layer
            g = gid[k]
            want = serial.bond_j[serial.offsets[g] : serial.offsets[g + 1]]
            got = gid[bonds.bond_j[bonds.offsets[k] : bonds.offsets[k + 1]]]
            np.testing.assert_array_equal(got, want)
        assert np.all(np.diff(bonds.offsets[n_family:]) == 0)  # second layer: no family
        # node sets keep every member held here (ghosts too), in local numbering
        top = local.node_set("top")
        want = np.intersect1d(c.node_set("top"), layout.local_ids)
        np.testing.assert_array_equal(np.sort(gid[top]), want)


def test_loads_built_on_the_global_cloud_keep_the_layer_thickness() -> None:
    c = _cloud()
    nodes = c.node_set("top")
    load = traction_as_body_force(nodes, np.array([0.0, 1e6]), c.x, c.spacing)
    part = rcb_partition(c.x, np.ones(c.n_points), 4)
    total = np.zeros(2)
    for rank in range(4):
        owned = np.flatnonzero(part == rank)
        mine = localize_condition(load, owned)
        assert np.all(owned[mine.nodes] >= 0)
        assert mine.value == load.value  # the thickness of the whole layer
        total += len(mine.nodes) * np.asarray(mine.value)
    np.testing.assert_allclose(total, len(nodes) * np.asarray(load.value))


def test_reverse_index_of_a_rank_list() -> None:
    c = _cloud()
    part = rcb_partition(c.x, np.ones(c.n_points), 2)
    radius = search_radius(3.015e-3, c.spacing, "truncated")
    layout, n_family = _rank_layout(c, part, 0, radius)
    local = local_cloud(c, layout)
    b = own_families(build_bonds(local, 3.015e-3), local, n_family)
    rev = b.reverse_index()
    end = int(b.offsets[layout.n_owned])
    # every owned bond's reverse is held (its far end has a family here) and is (j, i)
    np.testing.assert_array_equal(b.bond_i[rev[:end]], b.bond_j[:end])
    np.testing.assert_array_equal(b.bond_j[rev[:end]], b.bond_i[:end])
