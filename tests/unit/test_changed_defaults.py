"""The notes of changed defaults agree with the model that is built: a deck gets the
note of the PMB Lanczos step exactly when its built model takes the Lanczos estimate
(two independent implementations: one reads the deck, one the built model)."""

from __future__ import annotations

import pytest

import peridynamics as pd
from peridynamics.deck.changed_defaults import notices

BASE = {
    "name": "plate",
    "geometry": {"type": "rectangle", "size": [0.01, 0.004], "thickness": 1e-3},
    "discretisation": {"spacing": 1e-3, "horizon_factor": 3.015, "surface_correction": True},
    "material": {"youngs_modulus": 70e9, "density": 2700.0},
    "solver": {"end_time": 1e-7},
}
PLATEN = {
    "name": "platen",
    "shape": {"box": {"min": [0.002, 0.004], "max": [0.008, 0.005]}},
    "velocity": [0.0, -0.01],
    "touch": True,
}


def _deck(**sections: object) -> pd.Deck:
    data = {**BASE, **sections}
    return pd.Deck.from_dict(data)


def _notes(deck: pd.Deck, text: str) -> list[str]:
    return [n for n in notices(deck) if text in n]


CASES = [
    ("pmb", {}, True),
    ("pmb, contact", {"contact": {}}, False),
    ("pmb, rigid platen", {"rigid_bodies": [PLATEN]}, False),
    ("lps", {"material": {"model": "lps", "youngs_modulus": 70e9, "poisson_ratio": 0.25,
                          "density": 2700.0}}, True),
]  # fmt: skip


@pytest.mark.parametrize(("label", "sections", "spectral"), CASES, ids=[c[0] for c in CASES])
def test_note_follows_the_built_model(label: str, sections: dict, spectral: bool) -> None:
    deck = _deck(**sections)
    sim = pd.Simulation(deck)
    assert sim.model.spectral_applies is spectral
    pmb_note = _notes(deck, "automatic step of a PMB deck")
    assert bool(pmb_note) is (spectral and label == "pmb")
    lps_back = _notes(deck, "again the per-point bound")
    assert not lps_back  # single-body PMB or LPS without contact


def test_a_given_time_step_gets_no_note() -> None:
    deck = _deck(solver={"end_time": 1e-7, "time_step": 1e-8})
    assert not _notes(deck, "automatic step")


def test_lps_with_a_platen_is_told_its_step_is_the_per_point_bound_again() -> None:
    lps = {"model": "lps", "youngs_modulus": 70e9, "poisson_ratio": 0.25, "density": 2700.0}
    deck = _deck(material=lps, rigid_bodies=[PLATEN])
    assert _notes(deck, "again the per-point bound")
    assert not pd.Simulation(deck).model.spectral_applies
