"""Convergence of the micropolar cantilever (Zhou, Zhu & Li (n.d.), example 1) towards the
plane-stress FEM reference of ``examples/micropolar/fem_reference.py``.

The paper claims max |u_x| within 1 % of FEM at dx = 0.01 m; this model is 1.57 % low
there. The tests pin down why (``examples/micropolar/README.md``, cantilever section):
the bending curvature in the span is too small by a first-order surface-layer term (the
points within 2 delta of the top and bottom faces are stiff even with the surface
correction), so the error of max |u_x| falls with dx and is below 1 % at dx = 0.0025 m.

Measured (AMD EPYC, 2 cores), 3 clamping columns, delta = 3.015 dx, FEM at the particles:

======== ================== ========================== ======
dx (m)   max|u_x| error     curvature deficit 0.4-0.8  wall
======== ================== ========================== ======
0.01     -1.573 %           2.92 %                     6 s
0.005    -1.033 %           1.68 %                     14 s
0.0025   -0.581 %           0.88 %                     88 s, 5.4 GB
======== ================== ========================== ======

The bounds below are these numbers with margins of about 10 % of each; the solves are
direct (one Newton iteration of a linear model), so the numbers are deterministic up to
round-off.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.helpers import EXAMPLES

HERE = EXAMPLES / "micropolar"
LENGTH, HEIGHT = 1.0, 0.3


def _fem() -> Any:
    """The default-mesh FEM solution (within 1e-5 of its Richardson limit, README)."""
    spec = importlib.util.spec_from_file_location("fem_reference", HERE / "fem_reference.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod.solve_cantilever()


def _section_rotation(x: np.ndarray, ux: np.ndarray, column: float, dx: float) -> float:
    """Least-squares slope d u_x / d y of one column, over the rows more than delta from
    the faces (the section rotation of beam theory)."""
    sel = np.abs(x[:, 0] - column) < 1e-9
    y = x[sel, 1] - 0.5 * HEIGHT
    inner = np.abs(y) < 0.5 * HEIGHT - 3.015 * dx
    return float(np.polyfit(y[inner], ux[sel][inner], 1)[0])


def _run(tmp_path: Path, dx: float, fem: Any, columns: int = 3) -> dict[str, float]:
    """Run the deck at ``dx`` with ``columns`` clamping columns; errors against ``fem``."""
    from peridynamics.app.run import Simulation
    from peridynamics.deck import load_deck

    sets = [
        f"discretisation.spacing={dx}",
        f"geometry.size=[{round(LENGTH + columns * dx, 12)},{HEIGHT}]",
        f"geometry.origin=[{round(-columns * dx, 12)},0.0]",
    ]
    folder = tmp_path / f"dx{dx}_c{columns}"
    Simulation.from_deck(load_deck(HERE / "cantilever.yaml", overrides=sets)).run(folder)
    state = np.load(folder / "final_state.npz")
    body = state["x"][:, 0] > 0.0
    x, u = state["x"][body], state["u"][body]
    u_fem = fem.displacement(x)
    columns_x = np.unique(np.round(x[:, 0], 9))
    a, b = (float(columns_x[np.argmin(np.abs(columns_x - q))]) for q in (0.4, 0.8))
    kappa_pd = _section_rotation(x, u[:, 0], b, dx) - _section_rotation(x, u[:, 0], a, dx)
    kappa_fe = _section_rotation(x, u_fem[:, 0], b, dx) - _section_rotation(x, u_fem[:, 0], a, dx)
    return {
        "ux_error": float(np.abs(u[:, 0]).max() / np.abs(u_fem[:, 0]).max() - 1.0),
        "uy_error": float(np.abs(u[:, 1]).max() / np.abs(u_fem[:, 1]).max() - 1.0),
        "curvature_deficit": float(1.0 - kappa_pd / kappa_fe),
    }


@pytest.mark.long
def test_cantilever_converges_from_paper_resolution(tmp_path: Path) -> None:
    """dx = 0.01 and 0.005 m (about 20 s): max |u_x| is low at both, less so at the finer
    grid, and the span curvature deficit (the cause) nearly halves (first order)."""
    pytest.importorskip("skfem")
    fem = _fem()
    coarse, fine = _run(tmp_path, 0.01, fem), _run(tmp_path, 0.005, fem)
    # measured: -1.573 % and -1.033 % (ratio 1.52, observed order 0.61)
    assert -0.0175 < coarse["ux_error"] < -0.0140
    assert -0.0115 < fine["ux_error"] < -0.0090
    assert 1.35 < coarse["ux_error"] / fine["ux_error"] < 1.75
    # measured: -0.60 % and -0.51 % (u_y meets the paper's 1 % at both)
    assert -0.01 < coarse["uy_error"] < 0.0 and -0.01 < fine["uy_error"] < 0.0
    # measured: curvature 2.92 % and 1.68 % too small (ratio 1.74; 2 for first order)
    assert 0.026 < coarse["curvature_deficit"] < 0.032
    assert 1.55 < coarse["curvature_deficit"] / fine["curvature_deficit"] < 1.95


@pytest.mark.slow
def test_cantilever_within_one_percent_at_quarter_paper_spacing(tmp_path: Path) -> None:
    """dx = 0.005 and 0.0025 m (about 2 min, 5.4 GB): max |u_x| within 1 % of FEM at
    dx = 0.0025 m; the observed order of its error and of the curvature deficit."""
    pytest.importorskip("skfem")
    fem = _fem()
    coarse, fine = _run(tmp_path, 0.005, fem), _run(tmp_path, 0.0025, fem)
    # measured: -1.033 % and -0.581 % (observed order 0.83)
    assert -0.0065 < fine["ux_error"] < -0.0050
    order = np.log2(coarse["ux_error"] / fine["ux_error"])
    assert 0.70 < order < 0.95
    # measured: curvature deficit 1.68 % and 0.88 % (ratio 1.91: first order)
    assert 1.75 < coarse["curvature_deficit"] / fine["curvature_deficit"] < 2.1
