"""The command line: `peridynamics check` exit codes and messages, `examples` list / copy.

Each test calls the command line in this process (``tests.helpers.cli``: ``cli.main``
with stdout and stderr captured, the exit status returned).
"""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from peridynamics.deck import load_deck
from tests.helpers import EXAMPLES, cli

NAMES = ("crack_branching_2d", "bar_wave_1d", "plate_tension_2d")


@pytest.mark.parametrize("name", NAMES)
def test_check_example_exits_0(name: str) -> None:
    deck = EXAMPLES / name / "deck.yaml"
    proc = cli("check", deck)
    assert proc.returncode == 0, proc.stderr
    assert "valid" in proc.stdout and "points" in proc.stdout
    # no warning; only the notes of changed defaults the example relies on
    assert all(line.startswith("note: ") for line in proc.stderr.splitlines()), proc.stderr


MALFORMED = """\
name: broken
geometry: {type: rectangle, size: [0.01, 0.005], thikness: 1.0e-3}
discretisation: {spacing: 5.0e-4, horizon_factor: 3.015}
material: {youngs_modulus: -70.0e9, density: 2700.0}
solver: {end_time: 1.0e-6}
"""


def test_check_malformed_deck_exits_2_with_key_paths(tmp_path: Path) -> None:
    deck = tmp_path / "deck.yaml"
    deck.write_text(MALFORMED)
    proc = cli("check", deck)
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert "invalid deck:" in proc.stderr
    assert "geometry.thikness: unknown key" in proc.stderr
    assert "material.youngs_modulus: Input should be greater than 0" in proc.stderr
    assert "Traceback" not in proc.stderr


def test_check_override_and_setup_errors(tmp_path: Path) -> None:
    """A bad ``--set`` is validated like the deck; an empty node set is a set-up error."""
    deck = tmp_path / "deck.yaml"
    data = yaml.safe_load(MALFORMED)
    del data["geometry"]["thikness"]
    data["material"]["youngs_modulus"] = 70.0e9
    data["node_sets"] = {"top": {"box": {"min": [0.0, 0.02], "max": [0.01, 0.03]}}}
    deck.write_text(yaml.safe_dump(data))
    proc = cli("check", deck, "--set", "solver.steps=10")
    assert proc.returncode == 2
    assert "solver.end_time: give exactly one of end_time (s) or steps" in proc.stderr
    proc = cli("check", deck)  # valid schema, but the node set selects no point
    assert proc.returncode == 2
    assert "node_sets.top: selects no point" in proc.stderr


def test_examples_lists_the_examples() -> None:
    proc = cli("examples")
    assert proc.returncode == 0, proc.stderr
    listed = {line.split()[0] for line in proc.stdout.splitlines() if line.strip()}
    assert set(NAMES) <= listed


def test_examples_copy(tmp_path: Path) -> None:
    dest = tmp_path / "mine"
    proc = cli("examples", "copy", "bar_wave_1d", dest)
    assert proc.returncode == 0, proc.stderr
    copied = dest / "bar_wave_1d" / "deck.yaml"
    assert copied.is_file()
    assert copied.read_text() == (EXAMPLES / "bar_wave_1d" / "deck.yaml").read_text()
    assert load_deck(copied).name == "bar_wave_1d"
    proc = cli("examples", "copy", "no_such_example", dest)
    assert proc.returncode == 2
    assert "unknown example" in proc.stderr


def test_a_static_solve_that_does_not_converge_warns_on_stderr(tmp_path, capsys) -> None:
    """Not converging is reported (results.converged false, exit 0), and said."""
    from peridynamics.cli import main

    deck = str(EXAMPLES / "plate_tension_2d" / "adr.yaml")
    sets = ["--set", "solver.max_iterations=20", "--set", "discretisation.spacing=1e-3"]
    assert main(["run", deck, *sets, "--out", str(tmp_path / "nc"), "--quiet"]) == 0
    err = capsys.readouterr().err
    assert "warning: the static solve did not converge in load steps [1]" in err
    assert main(["run", deck, sets[0], sets[1].replace("20", "200000"), *sets[2:],
                 "--out", str(tmp_path / "ok"), "--quiet"]) == 0  # fmt: skip
    assert "did not converge" not in capsys.readouterr().err
