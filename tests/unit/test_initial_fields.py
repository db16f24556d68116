"""Initial velocity fields: expressions of x, y, z (parsed with `ast`, never `eval`) and
point values from .npy / .csv files, with deck errors that name the key."""

from __future__ import annotations

import copy

import numpy as np
import pytest
import yaml

from peridynamics.app.run import Simulation
from peridynamics.build.cloud import build_cloud
from peridynamics.build.errors import SetupError
from peridynamics.build.loads import build_conditions
from peridynamics.cli import main
from peridynamics.deck import DeckError, load_deck, parse_deck
from peridynamics.loading.initial_fields import FIELD_FUNCTIONS, FieldExpression

BASE = {
    "name": "fields",
    "geometry": {"type": "rectangle", "size": [0.01, 0.004], "thickness": 1e-3},
    "discretisation": {"spacing": 5e-4, "horizon_factor": 3.015},
    "material": {"youngs_modulus": 70e9, "density": 2700.0},
    "node_sets": {"right": {"half_space": {"point": [0.005, 0.0], "normal": [1.0, 0.0]}}},
    "solver": {"steps": 2},
}


def _deck(bc: dict, base: dict | None = None) -> dict:
    d = copy.deepcopy(base or BASE)
    d["boundary_conditions"] = [bc]
    return d


def _initial_v(deck_data: dict, base_dir=None) -> tuple[np.ndarray, np.ndarray]:
    deck = parse_deck(deck_data, base_dir)
    cloud = build_cloud(deck)
    _, _, init = build_conditions(deck, cloud)
    v = np.zeros_like(cloud.x)
    for iv in init:
        iv.apply_initial(v)
    return cloud.x, v


def test_expression_values_at_the_points() -> None:
    x = np.array([[0.0, 0.0], [0.0025, 0.001], [0.005, 0.003]])
    f = FieldExpression("-50.0 * sin(pi * x / 0.01) + where(y > 0.002, 1, 0) + t")
    expected = -50.0 * np.sin(np.pi * x[:, 0] / 0.01) + (x[:, 1] > 0.002)
    np.testing.assert_allclose(f(x), expected, rtol=1e-15)
    np.testing.assert_array_equal(FieldExpression("2 ** 3 - -1")(x), [9.0, 9.0, 9.0])
    np.testing.assert_allclose(FieldExpression("maximum(x, y) / e")(x), x.max(axis=1) / np.e)
    assert FieldExpression("sqrt(x*x + y*y)").names == {"x", "y"}
    for name in FIELD_FUNCTIONS:  # every documented function is callable
        args = ", ".join(["x"] * FIELD_FUNCTIONS[name][1])
        assert FieldExpression(f"{name}({args})")(x + 0.5).shape == (3,)


@pytest.mark.parametrize(
    ("text", "says"),
    [
        ("__import__('os').system('true')", "unknown function"),
        ("x.real", "attribute"),
        ("x[0]", "subscript"),
        ("(lambda: 1)()", "unknown function"),
        ("q * 2", "unknown name 'q'"),
        ("sin(x=1)", "positional"),
        ("sin(x, y)", "argument"),
        ("'abc'", "only numbers"),
        ("True", "only numbers"),
        ("[a for a in x]", "not allowed"),
        ("0 < x < 1", "chained"),
        ("x == 1", "comparisons"),
        ("x % 2", "operators"),
        ("sin", "is a function"),
        ("1 +", "not a valid expression"),
        ("x" * 2000, "longer than"),
    ],
)
def test_expression_refuses_anything_else(text: str, says: str) -> None:
    with pytest.raises(ValueError, match=says):
        FieldExpression(text)


def test_initial_velocity_expressions_reach_the_solver_state() -> None:
    bc = {
        "type": "initial_velocity",
        "set": "right",
        "value": [0.0, "-50.0 * sin(pi * x / 0.01) * (1 + y)"],
    }
    deck = parse_deck(_deck(bc))
    sim = Simulation.from_deck(deck)
    state = sim.solver.init()
    right = sim.cloud.node_set("right")
    x = sim.cloud.x[right]
    np.testing.assert_array_equal(state.v[right, 0], 0.0)
    expected = -50.0 * np.sin(np.pi * x[:, 0] / 0.01) * (1 + x[:, 1])
    np.testing.assert_allclose(state.v[right, 1], expected, rtol=1e-14)
    others = np.setdiff1d(np.arange(sim.cloud.n_points), right)
    assert np.all(state.v[others] == 0.0)
    # the validated deck keeps the expression text (summary.json inputs, fingerprint)
    dumped = deck.model_dump(mode="json")["boundary_conditions"][0]["value"]
    assert dumped == [0.0, "-50.0 * sin(pi * x / 0.01) * (1 + y)"]


@pytest.mark.parametrize(
    ("value", "path", "says"),
    [
        ([0.0, "q * 2"], "boundary_conditions.0.value.1", "unknown name 'q'"),
        ([0.0, "z"], "boundary_conditions.0.value.1", "'z': no such axis in 2-D"),
        (["os.system('x')", 0.0], "boundary_conditions.0.value.0", "unknown function"),
        ([0.0, True], "boundary_conditions.0.value.1", "true/false"),
    ],
)
def test_bad_expressions_are_deck_errors_naming_the_key(value, path, says) -> None:
    with pytest.raises(DeckError) as info:
        parse_deck(_deck({"type": "initial_velocity", "set": "right", "value": value}))
    assert any(p == path and says in m for p, m in info.value.errors), info.value.errors


def test_non_finite_field_is_a_setup_error_naming_the_key() -> None:
    bc = {"type": "initial_velocity", "set": "all", "value": ["1 / (x - x)", 0.0]}
    with pytest.raises(SetupError, match="not finite") as info:
        _initial_v(_deck(bc))
    assert info.value.path == "boundary_conditions.0.value.0"


def test_value_and_file_are_exclusive() -> None:
    with pytest.raises(DeckError, match="exactly one of value"):
        parse_deck(_deck({"type": "initial_velocity", "set": "all"}))
    bc = {"type": "initial_velocity", "set": "all", "value": [0, 0], "file": "v.npy"}
    with pytest.raises(DeckError, match="exactly one of value"):
        parse_deck(_deck(bc))
    with pytest.raises(DeckError, match=r"\.npy or a \.csv"):
        parse_deck(_deck({"type": "initial_velocity", "set": "all", "file": "v.txt"}))


def test_point_values_from_files_per_set_and_per_body(tmp_path) -> None:
    deck = parse_deck(_deck({"type": "initial_velocity", "set": "right", "value": [0, 0]}))
    cloud = build_cloud(deck)
    right = cloud.node_set("right")
    body = np.column_stack([cloud.x[:, 0] * 100.0, -cloud.x[:, 1] * 10.0])
    np.save(tmp_path / "body.npy", body)
    np.savetxt(tmp_path / "set.csv", body[right], delimiter=",", header="vx,vy")
    for name in ("body.npy", "set.csv"):  # relative to the deck's folder
        bc = {"type": "initial_velocity", "set": "right", "file": name}
        x, v = _initial_v(_deck(bc), base_dir=tmp_path)
        np.testing.assert_allclose(v[right], body[right], rtol=1e-15)
        assert np.all(v[np.setdiff1d(np.arange(len(x)), right)] == 0.0)


def test_bad_files_are_errors_naming_the_key(tmp_path) -> None:
    bc = {"type": "initial_velocity", "set": "right", "file": "missing.npy"}
    with pytest.raises(DeckError) as info:
        parse_deck(_deck(bc), base_dir=tmp_path)
    assert info.value.errors[0][0] == "boundary_conditions.0.file"
    np.save(tmp_path / "short.npy", np.zeros((3, 2)))
    np.save(tmp_path / "wide.npy", np.zeros((3, 3)))
    body = build_cloud(parse_deck(BASE)).n_points
    bad = np.zeros((body, 2))
    bad[5, 1] = np.nan
    np.save(tmp_path / "nan.npy", bad)
    for name, says in [
        ("short.npy", "has 3 rows; it needs one per point of the node set"),
        ("wide.npy", r"one row of 2 value\(s\) per point"),
        ("nan.npy", "non-finite"),
    ]:
        bc = {"type": "initial_velocity", "set": "right", "file": name}
        with pytest.raises(SetupError, match=says) as err:
            _initial_v(_deck(bc), base_dir=tmp_path)
        assert err.value.path == "boundary_conditions.0.file"


def test_bad_expression_exits_2_from_the_command_line(tmp_path, capsys) -> None:
    path = tmp_path / "deck.yaml"
    bc = {"type": "initial_velocity", "set": "all", "value": ["open('x')", 0.0]}
    path.write_text(yaml.safe_dump(_deck(bc)))
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert "boundary_conditions.0.value.0" in err and "unknown function 'open'" in err
    assert load_deck(path, ["boundary_conditions.0.value.0=x * 2"]).boundary_conditions
