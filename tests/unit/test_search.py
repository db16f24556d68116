"""Neighbour search and the directed CSR bond list, checked against brute force."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from peridynamics.bonds import brute_force_pairs, build_bonds, find_pairs
from peridynamics.bonds.search import directed_csr
from peridynamics.geometry import PointCloud, bar, box, rectangle


def naive_pairs(x: np.ndarray, radius: float) -> set[tuple[int, int]]:
    """All pairs i < j with |x_i - x_j| <= radius, by a plain double loop over i."""
    out = set()
    for i in range(len(x)):
        d = np.sqrt(np.sum((x[i + 1 :] - x[i]) ** 2, axis=1))
        for j in np.flatnonzero(d <= radius):
            out.add((i, i + 1 + int(j)))
    return out


def as_set(pairs: np.ndarray) -> set[tuple[int, int]]:
    assert pairs.ndim == 2 and pairs.shape[1] == 2
    s = {(int(a), int(b)) for a, b in pairs}
    assert len(s) == len(pairs), "duplicate pairs"
    return s


def check_csr(offsets, bond_i, bond_j, n_points):
    """Invariants of a directed CSR bond list sorted by (i, j)."""
    offsets = np.asarray(offsets)
    assert offsets.shape == (n_points + 1,)
    assert offsets[0] == 0 and offsets[-1] == len(bond_j) == len(bond_i)
    assert np.all(np.diff(offsets) >= 0)
    assert np.all(np.diff(bond_i.astype(np.int64)) >= 0)
    for i in range(n_points):
        fam_i = bond_i[offsets[i] : offsets[i + 1]]
        fam_j = bond_j[offsets[i] : offsets[i + 1]]
        assert np.all(fam_i == i)
        assert np.all(np.diff(fam_j.astype(np.int64)) > 0), "family not sorted / duplicates"
        assert not np.any(fam_j == i), "self bond"
    # every directed bond has its reverse
    fwd = set(zip(bond_i.tolist(), bond_j.tolist(), strict=True))
    assert fwd == {(j, i) for i, j in fwd}


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("radius", [0.05, 0.12, 0.3])
@pytest.mark.parametrize("seed", [0, 1])
def test_find_pairs_matches_brute_force(dim, radius, seed):
    rng = np.random.default_rng(seed)
    x = rng.random((250, dim))
    expected = naive_pairs(x, radius)
    got = find_pairs(x, radius)
    assert np.all(got[:, 0] < got[:, 1])
    assert as_set(got) == expected
    assert as_set(brute_force_pairs(x, radius)) == expected
    assert len(expected) > 0


def test_find_pairs_on_grid_includes_pairs_exactly_at_radius():
    # integer grid: distances 1 and sqrt(2) are exact ties with the radius
    g = np.stack(np.meshgrid(np.arange(6.0), np.arange(5.0), indexing="ij"), -1).reshape(-1, 2)
    for r in (1.0, 2.0, 3.0):
        assert as_set(find_pairs(g, r)) == naive_pairs(g, r)
    # radius 1: only the 4-neighbourhood -> 6*4 + 5*5 horizontal/vertical pairs
    assert len(find_pairs(g, 1.0)) == 5 * 5 + 6 * 4


@settings(max_examples=25, deadline=None)
@given(
    data=st.integers(1, 3).flatmap(
        lambda d: arrays(
            np.int64, st.tuples(st.integers(2, 40), st.just(d)), elements=st.integers(0, 12)
        )
    ),
    k=st.integers(0, 6),
)
def test_property_search_and_csr(data, k):
    """Integer coordinates and a half-integer radius: no ties, exact comparison."""
    x = data.astype(np.float64)
    radius = k + 0.5
    pairs = find_pairs(x, radius)
    assert as_set(pairs) == naive_pairs(x, radius)
    n = len(x)
    offsets, bond_i, bond_j = directed_csr(pairs, n)
    check_csr(offsets, bond_i, bond_j, n)
    assert len(bond_j) == 2 * len(pairs)
    assert np.array_equal(np.diff(offsets), np.bincount(pairs.ravel(), minlength=n))


def _beta(length, horizon, dx, rule):
    """Independent partial-volume factor (Lu & Wang (2016), eq. 9 / SED-PD (2021), eq. 11 /
    none)."""
    out = np.zeros_like(length)
    for k, L in enumerate(length):
        if rule == "none":
            out[k] = 1.0 if L <= horizon * (1 + 1e-9) else 0.0
        elif rule == "truncated":
            if L <= horizon - dx / 2:
                out[k] = 1.0
            elif L <= horizon * (1 + 1e-9):
                out[k] = (horizon - L) / dx + 0.5
        else:  # extended
            if L <= horizon - dx / 2:
                out[k] = 1.0
            elif L < horizon + dx / 2:
                out[k] = (horizon + dx / 2 - L) / dx
    return out


CLOUDS = {
    "bar": lambda: bar(0.02, 1e-3),
    "rect": lambda: rectangle((0.012, 0.008), 1e-3, thickness=0.01),
    "box": lambda: box((0.006, 0.005, 0.004), 1e-3),
    "jitter": lambda: _jittered(),
}


def _jittered():
    rng = np.random.default_rng(3)
    g = np.stack(np.meshgrid(np.arange(9.0), np.arange(7.0), indexing="ij"), -1).reshape(-1, 2)
    x = (g + rng.uniform(-0.3, 0.3, g.shape)) * 1e-3
    return PointCloud(
        x=x,
        volume=rng.uniform(0.5, 1.5, len(x)) * 1e-6,
        spacing=1e-3,
        cross_section=1e-3,
        plane="strain",
    )


# the jittered grid can leave a point alone with horizon = dx: not used there
CASES = [
    (name, m)
    for name in sorted(CLOUDS)
    for m in (1.0, 2.0, 3.015)
    if not (name == "jitter" and m == 1.0)
]


@pytest.mark.parametrize(("name", "m"), CASES)
@pytest.mark.parametrize("rule", ["truncated", "extended", "none"])
def test_build_bonds_csr_and_partial_volumes(name, m, rule):
    cloud = CLOUDS[name]()
    dx = cloud.spacing
    horizon = m * dx
    b = build_bonds(cloud, horizon, partial_volume=rule)
    n = cloud.n_points
    check_csr(b.offsets, b.bond_i, b.bond_j, n)
    assert b.n_points == n and b.horizon == horizon and b.partial_volume == rule

    # bond set == brute-force set of pairs with a non-zero partial volume
    reach = horizon + 0.5 * dx if rule == "extended" else horizon
    cand = np.array(sorted(naive_pairs(cloud.x, reach * (1 + 1e-9))), dtype=np.int64)
    cand = np.concatenate([cand, cand[:, ::-1]])
    lengths = np.linalg.norm(cloud.x[cand[:, 1]] - cloud.x[cand[:, 0]], axis=1)
    beta = _beta(lengths, horizon, dx, rule)
    want = {(int(i), int(j)): bt for (i, j), bt in zip(cand, beta, strict=True) if bt > 0}
    got = set(zip(b.bond_i.tolist(), b.bond_j.tolist(), strict=True))
    assert got == set(want)

    # geometry of each bond
    xi = cloud.x[b.bond_j] - cloud.x[b.bond_i]
    np.testing.assert_array_equal(b.bond_xi, xi)
    np.testing.assert_allclose(b.bond_length, np.linalg.norm(xi, axis=1), rtol=1e-15)
    beta_b = np.array(
        [want[(i, j)] for i, j in zip(b.bond_i.tolist(), b.bond_j.tolist(), strict=True)]
    )
    np.testing.assert_allclose(b.bond_volume, beta_b * cloud.volume[b.bond_j], rtol=1e-12)
    assert np.all(b.bond_correction == 1.0) and np.all(b.bond_intact == 1)

    # reverse index maps (i, j) -> (j, i) and is an involution
    r = b.reverse_index()
    assert np.array_equal(b.bond_i[r], b.bond_j)
    assert np.array_equal(b.bond_j[r], b.bond_i)
    assert np.array_equal(r[r], np.arange(b.n_bonds))
    np.testing.assert_array_equal(b.bond_xi[r], -b.bond_xi)


def test_truncated_partial_volume_in_1d_nearest_neighbour_gets_half():
    b = build_bonds(bar(0.01, 1e-3, area=2e-6), 1e-3, partial_volume="truncated")
    np.testing.assert_allclose(b.bond_volume, 0.5 * 2e-6 * 1e-3, rtol=1e-14)
    # end points have one bond, the others two
    fam = b.family_size
    assert fam[0] == fam[-1] == 1 and np.all(fam[1:-1] == 2)


def test_build_bonds_rejects_small_horizon_and_unknown_rule():
    c = bar(0.01, 1e-3)
    with pytest.raises(ValueError, match="spacing"):
        build_bonds(c, 0.5e-3)
    with pytest.raises(ValueError, match="partial_volume"):
        build_bonds(c, 3e-3, partial_volume="bogus")  # type: ignore[arg-type]


def test_build_bonds_rejects_isolated_point():
    x = np.array([[0.0, 0.0], [1e-3, 0.0], [10e-3, 0.0]])
    c = PointCloud(x=x, volume=np.full(3, 1e-6), spacing=1e-3, plane="stress")
    with pytest.raises(ValueError, match="no bond"):
        build_bonds(c, 1.5e-3)
