"""The direct backends of the static solver (SuperLU, MKL PARDISO when installed) and
the look-ahead columns of the Woodbury update (peridynamics.solvers.linear)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from peridynamics.solvers import linear as lin
from peridynamics.solvers import pardiso

needs_mkl = pytest.mark.skipif(not pardiso.available(), reason="MKL PARDISO not installed")


def _grid(
    n_side: int, seed: int = 0, ground: float = 0.1
) -> tuple[sp.csr_matrix, np.ndarray, np.ndarray]:
    """A 2-D grid of springs, each point tied to the ground by about ``ground`` (SPD when
    > 0), and its springs (i, j) with their stiffnesses."""
    rng = np.random.default_rng(seed)
    idx = np.arange(n_side * n_side).reshape(n_side, n_side)
    pairs = np.concatenate(
        [
            np.stack([idx[:, :-1].ravel(), idx[:, 1:].ravel()], axis=1),
            np.stack([idx[:-1, :].ravel(), idx[1:, :].ravel()], axis=1),
        ]
    )
    k = rng.uniform(1.0, 2.0, len(pairs))
    i, j = pairs[:, 0], pairs[:, 1]
    n = n_side * n_side
    rows = np.concatenate([i, j, i, j])
    cols = np.concatenate([i, j, j, i])
    vals = np.concatenate([k, k, -k, -k])
    mat = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
    mat = mat + sp.diags(ground * rng.uniform(1.0, 2.0, n))
    return sp.csr_matrix(mat), pairs, k


def _run_events(upd: lin.UpdatedDirect, k0: sp.csr_matrix, pairs, ks, order) -> None:
    """Remove half of the springs in ``order``; after each event the update solves as a
    fresh dense solve, with and without the ``negligible`` short cut."""
    k = k0.toarray()
    unit = np.array([[1.0, -1.0], [-1.0, 1.0]])
    rng = np.random.default_rng(1)
    for event, p in enumerate(order):
        dofs = pairs[p][None]
        blocks = (0.5 * ks[p] * unit)[None]
        upd.remove(dofs, blocks)
        k[np.ix_(dofs[0], dofs[0])] -= blocks[0]
        b = rng.normal(size=k.shape[0])
        assert np.allclose(upd.solve(b), np.linalg.solve(k, b), rtol=1e-9, atol=1e-12), event
        local = np.zeros(k.shape[0])
        local[dofs[0]] = [1.0, -1.0]  # a residual on the touched dofs only
        x = upd.solve(local, negligible=1e-300)
        assert np.allclose(x, np.linalg.solve(k, local), rtol=1e-9, atol=1e-12), event


def test_lookahead_columns_give_the_same_solution(monkeypatch) -> None:
    """Columns solved for in advance (forced on for SuperLU here) are used when their dof
    is touched, and the update still equals a fresh solve."""
    monkeypatch.setattr(lin, "PREFETCH_DOFS", 6)
    monkeypatch.setattr(lin, "CACHE_COLUMNS", 10)  # small: the ring drops old columns
    k0, pairs, ks = _grid(8)
    base = lin.DirectSolver(k0, backend="superlu")
    base.batch = True
    upd = lin.UpdatedDirect(base, k0.shape[0])
    assert upd.lookahead == 6
    # a crack advancing along a row of the grid: springs between rows 3 and 4
    order = [p for p, (i, j) in enumerate(pairs) if i // 8 == 3 and j // 8 == 4]
    _run_events(upd, k0, pairs, ks, order)
    assert upd.prefetched > 0 and upd.cache_hits > 0
    assert upd.column_solves == upd.rank == 2 * len(order)


def test_without_lookahead_every_column_is_solved_when_touched() -> None:
    k0, pairs, ks = _grid(6)
    upd = lin.UpdatedDirect(lin.DirectSolver(k0, backend="superlu"), k0.shape[0])
    assert upd.lookahead == 0
    _run_events(upd, k0, pairs, ks, [0, 7, 3, 20])
    assert upd.prefetched == 0 and upd.column_solves == upd.rank


def test_direct_backend_choice(monkeypatch) -> None:
    monkeypatch.setenv("PERIDYNAMICS_DIRECT_SOLVER", "superlu")
    assert lin.direct_backend() == "superlu"
    assert lin.direct_backend("pardiso") == "pardiso"
    monkeypatch.delenv("PERIDYNAMICS_DIRECT_SOLVER")
    assert lin.direct_backend() == ("pardiso" if pardiso.available() else "superlu")
    with pytest.raises(ValueError, match="pardiso or superlu"):
        lin.direct_backend("umfpack")


@needs_mkl
def test_pardiso_equals_superlu() -> None:
    k0, _, _ = _grid(12, seed=4)
    k0 = sp.csr_matrix(k0 @ sp.diags(np.linspace(1.0, 1e6, k0.shape[0])) @ k0.T)  # scales
    b = np.random.default_rng(2).normal(size=(k0.shape[0], 3))
    a = lin.DirectSolver(k0, backend="pardiso")
    s = lin.DirectSolver(k0, backend="superlu")
    assert a.backend == "pardiso" and a.batch and not s.batch
    assert np.allclose(a.solve(b), s.solve(b), rtol=1e-8)
    assert np.allclose(a.solve(b[:, 0]), s.solve(b[:, 0]), rtol=1e-8)
    assert 0 < a.fill


@needs_mkl
def test_pardiso_refuses_a_singular_matrix() -> None:
    free, _, _ = _grid(6, ground=0.0)  # a free-floating network: a rigid translation
    with pytest.raises(lin.SingularSystem):
        lin.DirectSolver(free, backend="pardiso")


def test_an_unknown_direct_solver_in_the_environment_is_a_clean_deck_error(tmp_path):
    """PERIDYNAMICS_DIRECT_SOLVER=foo: exit 2 naming the variable, no traceback."""
    from tests.helpers import EXAMPLES, cli

    deck = EXAMPLES / "micropolar" / "cantilever.yaml"
    r = cli("run", deck, "--set", "discretisation.spacing=0.02", "-o", tmp_path / "out",
            env={"PERIDYNAMICS_DIRECT_SOLVER": "foo"})  # fmt: skip
    assert r.returncode == 2, r.stdout + r.stderr
    assert "PERIDYNAMICS_DIRECT_SOLVER='foo'" in r.stderr and "Traceback" not in r.stderr
