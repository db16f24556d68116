"""Neighbour search and the directed CSR bond list, checked against brute force."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from peridynamics.bonds import brute_force_pairs, build_bonds, find_pairs
from peridynamics.bonds.search import bond_chunks, directed_bonds, directed_csr
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


# ------------------------------------------------- memory-bounded construction == oracle
# directed_bonds (cell grid, count then fill) must give the arrays of
# directed_csr(find_pairs(...)) bit for bit, ties at the radius included; build_bonds
# fills its per-bond arrays range by range and must not depend on the range size.


def oracle_csr(x: np.ndarray, radius: float):
    """Today's reference: cKDTree.query_pairs, then the global sort of directed_csr."""
    return directed_csr(find_pairs(x, radius), len(x))


def assert_same_csr(got, want) -> None:
    for g, w in zip(got, want, strict=True):
        assert g.dtype == w.dtype and g.shape == w.shape
        assert np.array_equal(g, w)


def _grid(dim: int, n: int) -> np.ndarray:
    axes = [np.arange(float(n))] * dim
    return np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, dim)


def _at_radius(x: np.ndarray, offsets, bond_i, bond_j, radius: float) -> int:
    """Bonds whose squared distance (summed left to right) is exactly radius**2."""
    d = x[bond_j] - x[bond_i]
    s = np.zeros(len(bond_i))
    for k in range(x.shape[1]):
        s = s + d[:, k] * d[:, k]
    return int(np.sum(s == radius * radius))


@pytest.mark.parametrize("dim", [1, 2, 3])
@pytest.mark.parametrize("scale", [1.0, 0.1, 1e-3])
@pytest.mark.parametrize("m", [1.0, 2.0, 3.0, 3.015, 2.5])
def test_directed_bonds_matches_oracle_on_grids_with_ties(dim, scale, m):
    """m = 1, 2, 3: lattice distances equal to the radius (exact ties); scale 0.1 and
    1e-3 make them ties of rounded values; 2.5 and 3.015 have no ties."""
    x = _grid(dim, {1: 40, 2: 14, 3: 8}[dim]) * scale
    radius = m * scale
    want = oracle_csr(x, radius)
    assert_same_csr(directed_bonds(x, radius), want)
    if scale == 1.0 and m in (1.0, 2.0, 3.0):
        assert _at_radius(x, *want, radius) > 0  # the case really has ties


@pytest.mark.parametrize("dim", [1, 2, 3])
def test_directed_bonds_matches_oracle_on_jittered_shuffled_and_duplicate_points(dim):
    rng = np.random.default_rng(dim)
    g = _grid(dim, {1: 60, 2: 16, 3: 9}[dim])
    for amp in (0.1, 0.3, 0.49):
        x = (g + rng.uniform(-amp, amp, g.shape)) * 1e-3
        for m in (1.0, 2.0, 3.015):
            assert_same_csr(directed_bonds(x, m * 1e-3), oracle_csr(x, m * 1e-3))
    # index order unrelated to the cells: rows are not presorted (insertion sort and,
    # for rows longer than 64, quicksort)
    perm = rng.permutation(len(g))
    for m in (1.0, 3.0, 4.5):
        assert_same_csr(directed_bonds(g[perm] * 0.1, m * 0.1), oracle_csr(g[perm] * 0.1, m * 0.1))
    # coincident points (distance 0) are neighbours, a point is never its own
    x = np.concatenate([g, g[:5]]) * 0.1
    got = directed_bonds(x, 0.1)
    assert_same_csr(got, oracle_csr(x, 0.1))
    assert not np.any(got[1] == got[2])


@pytest.mark.parametrize("dim", [1, 2, 3])
def test_directed_bonds_matches_oracle_at_ulp_level_ties(dim):
    """Radius equal to a computed pair distance and its neighbouring floats: which pairs
    are in depends on the last bit of the squared distance."""
    rng = np.random.default_rng(10 + dim)
    x = rng.random((600 // dim, dim))
    for _ in range(10):
        a, c = rng.integers(0, len(x), 2)
        d = x[a] - x[c]
        s = 0.0
        for t in d:
            s += t * t
        base = float(np.sqrt(s))
        for r in (base, float(np.nextafter(base, 0.0)), float(np.nextafter(base, 2.0))):
            assert_same_csr(directed_bonds(x, r), oracle_csr(x, r))


@pytest.mark.parametrize("dim", [1, 2, 3])
def test_directed_bonds_sparse_and_degenerate_clouds(dim):
    rng = np.random.default_rng(20 + dim)
    x = rng.random((200, dim)) * 1e6  # huge extent: the grid widens its cells
    x[:6] = x[6] + rng.random((6, dim)) * 1e-3
    for r in (2e-3, 3e5):
        assert_same_csr(directed_bonds(x, r), oracle_csr(x, r))
    g = _grid(dim, 4)
    for pts, r in ((g[:1], 1.0), (g[:2], 1.0), (np.concatenate([g, g[:2]]), 0.0)):
        assert_same_csr(directed_bonds(pts, r), oracle_csr(pts, r))
    line = np.outer(np.arange(30.0), np.ones(dim)) * 0.1  # collinear: thin grid
    assert_same_csr(directed_bonds(line, 0.3 * np.sqrt(dim)), oracle_csr(line, 0.3 * np.sqrt(dim)))


@settings(max_examples=40, deadline=None)
@given(
    data=st.integers(1, 3).flatmap(
        lambda d: arrays(
            np.int64, st.tuples(st.integers(1, 60), st.just(d)), elements=st.integers(0, 9)
        )
    ),
    r=st.sampled_from([0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 5.0, 13.0]),
    scale=st.sampled_from([1.0, 0.1, 0.3]),
)
def test_property_directed_bonds_equals_oracle(data, r, scale):
    """Integer coordinates (many exact ties, duplicates) at several scales."""
    x = data.astype(np.float64) * scale
    assert_same_csr(directed_bonds(x, r * scale), oracle_csr(x, r * scale))


def test_bond_chunks_cover_whole_rows():
    offsets = np.array([0, 3, 3, 10, 12, 12, 20])
    for m in (1, 2, 3, 5, 7, 8, 12, 100):
        ranges = bond_chunks(offsets, m)
        assert ranges[0][0] == 0 and ranges[-1][1] == 20
        assert all(b == c for (_, b), (c, _) in itertools.pairwise(ranges))
        assert all(a < b and a in offsets and b in offsets for a, b in ranges)
        assert all(b - a <= m or np.sum((offsets > a) & (offsets < b)) == 0 for a, b in ranges)
    assert bond_chunks(np.zeros(4, dtype=np.int64), 5) == []


def reference_build(cloud: PointCloud, horizon: float, rule: str) -> dict[str, np.ndarray]:
    """build_bonds as it was before the memory-bounded construction (the oracle)."""
    from peridynamics.bonds.partial_volume import partial_volume_factor, search_radius

    x, dx = cloud.x, cloud.spacing
    offsets, bond_i, bond_j = oracle_csr(x, search_radius(horizon, dx, rule))  # type: ignore[arg-type]
    xi = x[bond_j] - x[bond_i]
    # squares summed in component order (the kernels' order; einsum pairs x and z first)
    sq = xi[:, 0] * xi[:, 0]
    for c in range(1, xi.shape[1]):
        sq = sq + xi[:, c] * xi[:, c]
    length = np.sqrt(sq)
    beta = partial_volume_factor(length, horizon, dx, rule)  # type: ignore[arg-type]
    keep = beta > 0
    if not np.all(keep):
        bond_i, bond_j = bond_i[keep], bond_j[keep]
        xi, length, beta = xi[keep], length[keep], beta[keep]
        offsets = np.zeros(cloud.n_points + 1, dtype=np.int64)
        np.cumsum(np.bincount(bond_i, minlength=cloud.n_points), out=offsets[1:])
    return {
        "offsets": offsets,
        "bond_i": bond_i,
        "bond_j": bond_j,
        "bond_xi": xi,
        "bond_length": length,
        "bond_volume": beta * cloud.volume[bond_j],
    }


BUILD_CASES = [
    ("bar", 3.015, "truncated"),
    ("rect", 3.0, "truncated"),
    ("rect", 2.5, "extended"),  # lattice bonds at exactly delta + dx/2 are dropped
    ("box", 3.015, "truncated"),
    ("box", 2.0, "none"),
    ("box", 1.5, "extended"),
    ("jitter", 3.015, "extended"),
]


@pytest.mark.parametrize(("name", "m", "rule"), BUILD_CASES)
@pytest.mark.parametrize("chunk_bytes", [1, 3000, 2**40])
def test_build_bonds_equals_reference_for_any_range_size(monkeypatch, name, m, rule, chunk_bytes):
    """Ranges of one row, of a few rows (not aligned with family sizes) and of all bonds
    give the arrays of the old one-shot construction bit for bit."""
    import peridynamics.bonds.bonds as bonds_module
    from peridynamics.bonds.partial_volume import search_radius

    monkeypatch.setattr(bonds_module, "SETUP_CHUNK_BYTES", chunk_bytes)
    monkeypatch.setattr(bonds_module, "CELL_SEARCH_MIN_POINTS", 0)  # the cell-grid search
    cloud = CLOUDS[name]()
    b = build_bonds(cloud, m * cloud.spacing, partial_volume=rule)  # type: ignore[arg-type]
    want = reference_build(cloud, m * cloud.spacing, rule)
    if rule == "extended" and m == 2.5:  # the dropping path is exercised
        reach = search_radius(m * cloud.spacing, cloud.spacing, "extended")
        assert len(want["bond_j"]) < 2 * len(find_pairs(cloud.x, reach))
    for key, arr in want.items():
        got = getattr(b, key)
        assert got.dtype == arr.dtype and np.array_equal(got, arr), key
        assert got.tobytes() == arr.tobytes(), key


@pytest.mark.parametrize("dim", [2, 3])
def test_cuts_and_surface_correction_do_not_depend_on_the_range_size(monkeypatch, dim):
    """Crack cuts and the energy-method factors (per-point sums over whole rows) are the
    same bits with ranges of one bond/row as with one range."""
    import peridynamics.bonds.bonds as bonds_module
    import peridynamics.bonds.precrack as precrack_module
    from peridynamics import BondBasedMaterial, Evaluator
    from peridynamics.bonds import make_crack

    if dim == 2:
        cloud = rectangle((0.02, 0.012), 1e-3, thickness=1e-3)
        crack = make_crack([(0.0045, 0.0), (0.0045, 0.006)])
    else:
        cloud = box((0.009, 0.008, 0.007), 1e-3)
        crack = make_crack([(0.0035, 0.0, 0.0), (0.0035, 0.004, 0.0), (0.0035, 0.0, 0.007)])

    def built() -> tuple[np.ndarray, np.ndarray]:
        b = build_bonds(cloud, 3.015e-3, cracks=[crack])
        m = Evaluator(cloud, b, BondBasedMaterial(70e9, 2700.0), surface_correction=True)
        return b.bond_intact, m.bonds.bond_correction

    intact, corr = built()  # k-d tree search (small cloud), one range
    assert np.any(intact == 0)
    monkeypatch.setattr(bonds_module, "CELL_SEARCH_MIN_POINTS", 0)
    monkeypatch.setattr(bonds_module, "SETUP_CHUNK_BYTES", 1)
    monkeypatch.setattr(precrack_module, "CHUNK_BONDS", 7)
    intact_small, corr_small = built()
    assert np.array_equal(intact, intact_small)
    assert corr.tobytes() == corr_small.tobytes()
