"""The static solver's fast paths give the numbers of the paths they replace, bit for
bit: the micropolar tangent kernel (against the NumPy 6 x 6 pair blocks and their
family sum), the candidates' stretch, the pairwise family sum, the intact counts of a
few families, and the BLAS thread control restores what it changed."""

from __future__ import annotations

import numpy as np
import pytest

from peridynamics.bonds.bonds import build_bonds
from peridynamics.evaluation import Evaluator
from peridynamics.families.assembly import block_csr, family_sum
from peridynamics.families.micropolar.material import MicropolarMaterial
from peridynamics.geometry.generators import rectangle
from peridynamics.kernels.micropolar import _pairwise
from peridynamics.solvers.blas_threads import blas_threads, openblas_controls
from peridynamics.solvers.tangent_system import _intact_count


@pytest.fixture(scope="module")
def model() -> Evaluator:
    cloud = rectangle((0.12, 0.09), 0.01, thickness=1.0, plane="stress")
    bonds = build_bonds(cloud, 5.015 * 0.01)  # families above 8 terms: the 8-way sums
    material = MicropolarMaterial(25e9, 0.2, 2400.0)
    return Evaluator(cloud, bonds, material, surface_correction=True)


def test_tangent_kernel_has_the_bits_of_the_numpy_blocks(model: Evaluator) -> None:
    fm = model.force_model
    b = fm.bonds
    s = model.new_state()
    rng = np.random.default_rng(0)
    s.intact[rng.random(b.n_bonds) < 0.2] = 0
    pair = fm.bond_blocks(s.intact)
    diag = family_sum(b.offsets, pair[:, 0:3, 0:3])
    keep = (s.intact != 0) & (fm.weight != 0)
    old = block_csr(b.offsets, b.bond_j, diag, pair[:, 0:3, 3:6], keep, fm.n_points)
    new = fm.tangent(s)
    assert np.array_equal(old.indptr, new.indptr)
    assert np.array_equal(old.indices, new.indices)
    assert np.array_equal(old.data, new.data)


def test_pair_stretch_is_bond_stretch_at_those_bonds(model: Evaluator) -> None:
    fm = model.force_model
    s = model.new_state()
    rng = np.random.default_rng(1)
    s.u[...] = rng.normal(size=s.u.shape) * 1e-5
    index = np.flatnonzero(fm.bonds.bond_i < fm.bonds.bond_j)
    assert np.array_equal(fm.pair_stretch(s, index), fm.bond_stretch(s)[index])


@pytest.mark.parametrize("m", [1, 2, 7, 8, 9, 17, 128, 129, 300, 1031])
def test_pairwise_sum_is_numpys_reduceat(m: int) -> None:
    rng = np.random.default_rng(m)
    a = rng.normal(size=(m, 9)) * 10.0 ** rng.normal(size=(m, 1))
    want = np.add.reduceat(a, [0], axis=0)[0]
    got = np.array([a[0, q] + _pairwise(a, q, 1, m - 1) for q in range(9)])
    assert np.array_equal(got, want)


def test_intact_count_of_a_few_families() -> None:
    rng = np.random.default_rng(2)
    offsets = np.concatenate([[0], np.cumsum(rng.integers(0, 6, 40))])
    intact = (rng.random(offsets[-1]) < 0.5).astype(np.uint8)
    points = np.array([0, 5, 17, 39])
    want = [int(intact[offsets[p] : offsets[p + 1]].sum()) for p in points]
    assert _intact_count(offsets, intact, points).tolist() == want


def test_blas_threads_restores_the_counts() -> None:
    controls = openblas_controls()
    before = [get() for get, _ in controls]
    with blas_threads(1):
        assert all(get() == 1 for get, _ in controls)
    assert [get() for get, _ in controls] == before
