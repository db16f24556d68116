"""The energy-method surface correction is the identity where a family is complete
(issue 35, item 3): in 1-D with delta = dx the corrected PMB bar is the finite-difference
scheme, and with delta = 3 dx a uniform strain puts no force on a complete point."""

from __future__ import annotations

import numpy as np
import pytest

import peridynamics as pd
from peridynamics.bonds import build_bonds
from peridynamics.deck.changed_defaults import notices
from peridynamics.evaluation import Evaluator
from peridynamics.families.pmb import BondBasedMaterial
from peridynamics.geometry import bar
from peridynamics.loading import TriangularPulse, traction_as_body_force
from peridynamics.solvers import ExplicitSolver
from peridynamics.solvers.fdm import FDMModel1D

E, RHO, DX = 20e9, 2620.0, 0.005


def _corrected(m: int) -> Evaluator:
    cloud = bar(1.0, DX, area=1e-4, nodes_on_boundary=True)
    bonds = build_bonds(cloud, m * DX, "truncated")
    return Evaluator(cloud, bonds, BondBasedMaterial(E, RHO), surface_correction=True)


def test_delta_dx_correction_is_the_identity() -> None:
    corr = _corrected(1).bonds.bond_correction
    assert np.abs(corr - 1.0).max() <= 1e-12  # measured 4.7e-15 (was 1.5 at the ends)


def test_delta_dx_corrected_pd_equals_fdm() -> None:
    cloud = bar(1.0, DX, area=1.0, nodes_on_boundary=True)
    load = traction_as_body_force(
        np.array([0]), np.array([8.9e6]), cloud.x, DX, function=TriangularPulse(1.0, 4e-5, 1.2e-4)
    )
    mat = BondBasedMaterial(E, RHO)
    pd_model = Evaluator(
        cloud, build_bonds(cloud, DX, "truncated"), mat, body_forces=[load],
        surface_correction=True,
    )  # fmt: skip
    fd_model = FDMModel1D(cloud, mat, [load])
    u = []
    for model in (pd_model, fd_model):
        solver = ExplicitSolver(model, time_step=1e-6, integrator="central_difference")
        s = solver.init()
        for _ in solver.irun(s, 400):
            pass
        u.append(s.u.copy())
    assert np.abs(u[0] - u[1]).max() <= 1e-12 * np.abs(u[1]).max()  # measured 2e-13


@pytest.mark.parametrize("m", [2, 3, 5])
def test_uniform_strain_puts_no_force_on_complete_points(m: int) -> None:
    model = _corrected(m)
    x = model.cloud.x
    u = 1e-6 * x  # a uniform strain
    f, ms = np.zeros_like(u), np.zeros(len(u))
    model.internal_force(u, model.bonds.bond_intact.copy(), f, ms)
    scale = E * 1e-6 / DX  # the end's force density, sigma / dx (N/m^3)
    inner = slice(m, len(x) - m)  # families complete
    assert np.abs(f[inner]).max() <= 1e-9 * scale
    corr = model.bonds.bond_correction
    assert corr.max() > 1.1  # the end points' bonds among themselves are still corrected


def test_bar_deck_gets_the_note() -> None:
    deck = pd.Deck.from_dict({
        "name": "bar",
        "geometry": {"type": "bar", "length": 0.1, "area": 1e-4},
        "discretisation": {"spacing": 0.01, "horizon_factor": 1.0},
        "material": {"youngs_modulus": E, "density": RHO},
        "solver": {"end_time": 1e-6},
    })  # fmt: skip
    assert any("complete" in n for n in notices(deck))
    off = deck.model_copy(update={"discretisation": deck.discretisation.model_copy(
        update={"surface_correction": False})})  # fmt: skip
    assert not any("complete" in n for n in notices(off))
