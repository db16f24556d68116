"""Micropolar fracture energy with the surface correction (``corrected_critical_stretch``).

The critical stretch l_c = sqrt(G_c / (4 kappa beta)) is calibrated with the continuum
axial spring k_n. The surface correction multiplies a bond's springs by g_k, so at l_c the
bond stores g_k times the calibrated energy. With ``corrected_critical_stretch`` the model
reports sqrt(g_k) l as the bond's stretch, so it breaks at l_c / sqrt(g_k) and stores the
uncorrected energy. Oracle: the energy 1/2 w_k k_n xi l_break^2 V_i of the bonds crossing
a line, per unit crack area, summed in NumPy from the bond arrays.
"""

from __future__ import annotations

import numpy as np
import pytest

from peridynamics.bonds.bonds import build_bonds
from peridynamics.deck import parse_deck
from peridynamics.evaluation import Evaluator
from peridynamics.families.micropolar.material import MicropolarMaterial
from peridynamics.geometry.generators import rectangle

E, NU, RHO, GC = 200e9, 0.2, 7850.0, 962.8
DX, M, T = 1.0e-3, 3.015, 0.01


def _model(surface_correction: bool, corrected: bool) -> Evaluator:
    cloud = rectangle((0.03, 0.02), DX, thickness=T, plane="stress")
    bonds = build_bonds(cloud, M * DX)
    mat = MicropolarMaterial(E, NU, RHO, corrected_critical_stretch=corrected)
    return Evaluator(cloud, bonds, mat, surface_correction=surface_correction)


def _crack_energy(model: Evaluator) -> tuple[float, float]:
    """(G, max |reported/raw - 1|): the energy (J/m^2) the bonds crossing the line
    y = y_mid inside the central third in x store when each reaches its breaking
    stretch, per unit crack area; the breaking stretch l_c l / r from the raw stretch l
    (NumPy) and the reported one r (the model's ``pair_stretch``) under u = (0, eps y)."""
    fm = model.force_model
    b, x = fm.bonds, model.cloud.x
    mat = fm.material
    lc = mat.critical_stretch(GC, 2, b.horizon, plane="stress")
    state = model.new_state()
    eps = 1e-4
    state.u[:, 1] = eps * x[:, 1]
    xi, length = b.bond_xi, b.bond_length
    raw = eps * (xi[:, 1] / length) ** 2
    y_mid = 0.5 * (x[:, 1].min() + x[:, 1].max())
    xc = 0.5 * (x[:, 0].min() + x[:, 0].max())
    yi, yj = x[b.bond_i, 1], x[b.bond_j, 1]
    crossing = (yi < y_mid) & (yj > y_mid) & (np.abs(x[b.bond_i, 0] - xc) < 0.005)
    index = np.flatnonzero(crossing)
    reported = fm.pair_stretch(state, index)
    l_break = lc * raw[index] / reported
    vol = model.cloud.volume[b.bond_i[index]]
    w = fm.weight[index]  # g_k V_j beta_k
    energy = 0.5 * fm.springs.axial * w * vol * length[index] * l_break**2  # J per bond
    area = 0.01 * T  # the central third (10 mm) times the thickness
    return float(energy.sum() / area), float(np.abs(reported / raw[index] - 1).max())


def test_rupture_energy_follows_the_correction():
    g_plain, dev_plain = _crack_energy(_model(False, False))
    g_corr, _ = _crack_energy(_model(True, False))
    g_fixed, dev_fixed = _crack_energy(_model(True, True))
    assert dev_plain < 1e-12  # without the correction the option is the raw stretch
    assert dev_fixed > 0.01  # the interior factors differ from 1
    # with the option the corrected model breaks with the uncorrected model's energy
    assert g_fixed == pytest.approx(g_plain, rel=1e-10)
    # without it the corrected model needs g ~ 1.16 times more (measured 1.16, dx = 1 mm)
    assert 1.08 < g_corr / g_plain < 1.25
    # the discrete crack energy is G_c up to the quadrature of the family sum
    assert 0.7 < g_plain / GC < 1.1


def test_option_without_correction_is_inert():
    model = _model(False, True)
    assert model.force_model.stretch_scale is None


def _deck(solver: dict) -> dict:
    return {
        "name": "mp",
        "geometry": {"type": "rectangle", "size": [0.02, 0.01], "thickness": 0.01},
        "discretisation": {"spacing": 1.0e-3, "horizon_factor": 3.015},
        "material": {
            "model": "micropolar",
            "youngs_modulus": 200e9,
            "poisson_ratio": 0.2,
            "density": 7850.0,
            "corrected_critical_stretch": True,
        },
        "damage": {"model": "critical_stretch", "fracture_energy": GC},
        "solver": solver,
    }


def test_option_needs_the_static_solver():
    with pytest.raises(ValueError, match="material.corrected_critical_stretch"):
        parse_deck(_deck({"steps": 10}))
    parse_deck(_deck({"type": "static", "load_steps": 2}))
