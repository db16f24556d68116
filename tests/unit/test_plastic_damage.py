"""Damage at a critical equivalent plastic strain (``damage.model: plastic_strain``):
the strain at which a J2 bar in uniaxial stress breaks against the closed form, the
locality of the criterion, the proposal against a loop over bonds, and the deck keys."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from peridynamics.app.run import Simulation
from peridynamics.damage.plastic_strain import PlasticStrainLaw, plastic_strain_proposal
from peridynamics.deck import DeckError, parse_deck
from peridynamics.families.correspondence.plastic_force import HISTORY, TRIAL

E, NU, SY, H = 200e9, 0.3, 200e6, 5e9
ALPHA_C = 2e-3

DECK = {
    "name": "plastic_damage",
    "geometry": {"type": "box", "size": [0.006, 0.006, 0.006]},
    "discretisation": {"spacing": 1e-3, "horizon_factor": 2.015},
    "material": {
        "model": "correspondence",
        "youngs_modulus": E,
        "poisson_ratio": NU,
        "density": 7800.0,
        "plasticity": {"type": "j2", "yield_stress": SY, "hardening_modulus": H},
    },
    "damage": {"model": "plastic_strain", "critical_plastic_strain": ALPHA_C},
    "solver": {"steps": 5},
    "output": {"plot": "none", "vtk_every": 0},
}  # fmt: skip


def _model(deck: dict | None = None):
    return Simulation.from_deck(parse_deck(copy.deepcopy(deck or DECK))).model


def _uniaxial(eps: float) -> tuple[float, float]:
    """Lateral strain and alpha of J2 with linear isotropic hardening under uniaxial
    stress at axial strain eps (monotone): sigma = sy + Et (eps - ey), alpha = eps_p =
    eps - sigma/E, lateral = -nu sigma/E - eps_p/2."""
    ey = SY / E
    if eps <= ey:
        return -NU * eps, 0.0
    sig = SY + E * H / (E + H) * (eps - ey)
    ep = eps - sig / E
    return -NU * sig / E - ep / 2.0, ep


def _load(model, s, eps: float) -> int:
    """Homogeneous uniaxial-stress deformation at eps, an accepted load step (the
    evaluation, then the damage and history commit of dynamic relaxation)."""
    lat, _ = _uniaxial(eps)
    s.u[...] = model.cloud.x @ np.diag([eps, lat, lat])
    model.evaluate(s, commit=False)
    return model.commit_damage(s)


def test_bar_breaks_where_alpha_reaches_the_critical_value_and_not_before() -> None:
    model = _model()
    law = model.damage_law
    assert isinstance(law, PlasticStrainLaw) and law.column == 18
    # alpha = (eps - ey) E/(E + H) reaches alpha_c at eps*
    eps_star = SY / E + ALPHA_C * (E + H) / E
    s = model.new_state()
    n_bonds = int(s.intact.sum())
    for eps in (0.5 * eps_star, 0.9 * eps_star, eps_star * (1 - 1e-6)):
        assert _load(model, s, eps) == 0
        want = _uniaxial(eps)[1]
        assert np.allclose(s[HISTORY][:, 18], want, rtol=1e-9, atol=1e-15)
    assert s.intact.all()
    assert _load(model, s, eps_star * (1 + 1e-6)) == n_bonds
    assert not s.intact.any() and s.bonds_broken == n_bonds


def test_only_the_bonds_of_points_past_the_critical_value_break() -> None:
    model = _model()
    s = model.new_state()
    b = model.bonds
    x = model.cloud.x
    hot = int(np.argmin(np.linalg.norm(x - x.mean(axis=0), axis=1)))  # an interior point
    alpha = np.zeros(len(x))
    alpha[hot] = ALPHA_C  # committed plastic strain, then an elastic step
    s[HISTORY][:, 18] = alpha
    s.u[...] = x @ np.diag([1e-5, 0.0, 0.0])
    model.evaluate(s, commit=False)
    assert np.array_equal(s[TRIAL][:, 18], alpha)
    broken = model.commit_damage(s)
    bi = np.repeat(np.arange(len(x)), np.diff(b.offsets))
    pairs = zip(bi, b.bond_j, strict=True)
    want = [bool(alpha[i] >= ALPHA_C or alpha[j] >= ALPHA_C) for i, j in pairs]
    assert np.array_equal(s.intact == 0, np.array(want))
    assert broken == sum(want) > 0


def test_proposal_is_the_loop_over_bonds() -> None:
    rng = np.random.default_rng(7)
    n, nb = 40, 600
    alpha = rng.uniform(0, 2, n)
    bi, bj = rng.integers(0, n, nb), rng.integers(0, n, nb)
    intact = rng.random(nb) < 0.8
    protected = rng.random(nb) < 0.1
    got = plastic_strain_proposal(alpha, 1.5, bi, bj, intact, protected)
    want = np.zeros(nb, dtype=bool)
    for k in range(nb):
        hit = alpha[bi[k]] >= 1.5 or alpha[bj[k]] >= 1.5
        want[k] = intact[k] and not protected[k] and hit
    assert np.array_equal(got, want) and want.any()


def test_drucker_prager_reads_its_alpha_column() -> None:
    d = copy.deepcopy(DECK)
    d["material"]["plasticity"] = {"type": "drucker_prager", "cohesion": 40e6,
                                   "friction_angle": 20.0}  # fmt: skip
    assert _model(d).damage_law.column == 9


@pytest.mark.parametrize(
    ("change", "key"),
    [
        ({"material": {"plasticity": None}}, "damage.model"),
        ({"solver": {"type": "static"}}, "damage.model"),
        ({"damage": {"model": "plastic_strain"}}, "critical_plastic_strain"),
        ({"damage": {"model": "critical_stretch", "critical_stretch": 0.01,
                     "critical_plastic_strain": 0.1}}, "critical_plastic_strain"),
        ({"damage": {"model": "plastic_strain", "critical_plastic_strain": 0.1,
                     "critical_stretch": 0.01, "fracture_energy": 10.0}}, "critical_stretch"),
        ({"damage": {"model": "plastic_strain", "critical_plastic_strain": 0.1,
                     "weibull": {"shape": 4.0}}}, "model"),
    ],
)  # fmt: skip
def test_bad_keys_name_the_key(change: dict, key: str) -> None:
    d = copy.deepcopy(DECK)
    for section, values in change.items():
        if section == "material":
            del d["material"]["plasticity"]
        else:
            d[section] = values
    with pytest.raises(DeckError) as err:
        parse_deck(d)
    assert key in str(err.value)
