"""A deck from Python: every way of making one is validated as ``peridynamics check``
validates a file, with the same messages."""

from __future__ import annotations

import pytest
import yaml

import peridynamics as pd
from peridynamics.app.examples import list_examples
from peridynamics.cli import main


def test_file_dict_yaml_and_keywords_give_the_same_deck():
    path = list_examples()["plate_tension_2d"]
    from_file = pd.Deck.from_file(path)
    data = yaml.safe_load(path.read_text())
    assert pd.Deck.from_dict(data) == from_file
    assert pd.Deck.from_yaml(path.read_text()) == from_file
    assert pd.Deck(**data) == from_file
    assert pd.Deck.from_yaml(from_file.to_yaml()) == from_file
    assert isinstance(from_file, pd.Deck)


def test_overrides_are_the_command_lines(tmp_path):
    deck = pd.Deck.example("bar_wave_1d")
    a = deck.with_({"solver.end_time": 1e-4, "material.density": 2000.0})
    b = deck.with_(["solver.end_time=1e-4", "material.density=2000.0"])
    assert a == b and a.solver.end_time == 1e-4 and deck.solver.end_time == 3e-4


@pytest.mark.parametrize(
    "change",
    [
        {"material.density": -1.0},
        {"material.youngs_modulus": "soft"},
        {"geometry.lenght": 2.0},
        {"boundary_conditions.0.set": "nowhere"},
    ],
)
def test_errors_are_those_of_peridynamics_check(change, tmp_path, capsys):
    path = list_examples()["bar_wave_1d"]
    sets = [a for k, v in change.items() for a in ("--set", f"{k}={v}")]
    assert main(["check", str(path), *sets]) == 2
    said = capsys.readouterr().err
    with pytest.raises(pd.DeckError) as exc:
        pd.Deck.from_file(path, change)
    assert str(exc.value).splitlines()[1].strip() in said
    key = exc.value.errors[0][0]
    assert key.split(".")[0] == next(iter(change)).split(".")[0]
    with pytest.raises(pd.DeckError) as again:
        pd.Deck.from_dict(pd.Deck.example("bar_wave_1d").to_dict(), change)
    assert again.value.errors == exc.value.errors


def test_keyword_deck_errors_name_the_key():
    with pytest.raises(pd.DeckError, match="geometry"):
        pd.Deck(name="x")
    with pytest.raises(pd.DeckError, match="no example deck 'nope'"):
        pd.Deck.example("nope")
    with pytest.raises(pd.DeckError, match="mapping"):
        pd.Deck.from_yaml("- a\n- b\n")


def test_simulation_refuses_what_the_command_line_refuses():
    big = pd.Deck.example("crack_branching_2d", {"discretisation.spacing": 1e-6,
                                                 "discretisation.horizon": 4e-6})  # fmt: skip
    with pytest.raises(pd.SetupError, match="too large.*allow_large=True"):
        pd.Simulation(big)
    with pytest.raises(TypeError, match="Simulation"):
        pd.Simulation(3)
