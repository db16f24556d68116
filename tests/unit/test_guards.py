"""Guards against silent mistakes: loads, post-processing and deck/CLI corner cases."""

from __future__ import annotations

import copy
import json

import numpy as np
import pytest
import yaml

from peridynamics.analysis.crack import branching, crack_tip
from peridynamics.bonds import make_crack
from peridynamics.build.cloud import build_cloud
from peridynamics.build.errors import SetupError
from peridynamics.build.loads import build_conditions
from peridynamics.deck import DeckError, load_deck, parse_deck
from peridynamics.geometry import NearestPoint, rectangle
from peridynamics.loading import traction_as_body_force
from tests.helpers import EXAMPLES, cli

BASE = {
    "name": "g",
    "geometry": {"type": "rectangle", "size": [0.01, 0.006], "thickness": 1e-3},
    "discretisation": {"spacing": 5e-4, "horizon_factor": 3.015},
    "material": {"youngs_modulus": 70e9, "density": 2700.0},
    "node_sets": {"top": {"edge": {"normal": [0, 1]}}, "left": {"edge": {"normal": [-1, 0]}}},
    "solver": {"steps": 5},
}


@pytest.mark.parametrize("value", [[1e6, 0.0], [0.0, 1e6], [1e6, 1e6], [-3e5, 2e5]])
def test_traction_total_force_is_traction_times_area(value) -> None:
    cloud = rectangle((0.01, 0.006), 5e-4, thickness=1e-3)
    top = np.flatnonzero(cloud.x[:, 1] > 0.006 - 5e-4)
    load = traction_as_body_force(top, np.asarray(value), cloud.x, cloud.spacing)
    b = np.zeros_like(cloud.x)
    load.add_to(b, 0.0)
    total = (b * cloud.volume[:, None]).sum(axis=0)
    np.testing.assert_allclose(total, np.asarray(value) * 0.01 * 1e-3, rtol=1e-12)


def _v_crack(direction: np.ndarray, dx: float = 5e-4):
    """Synthetic damage: a stem from the origin along ``direction``, then two arms."""
    cloud = rectangle((0.04, 0.04), dx)
    x = cloud.x - 0.02
    d = direction / np.linalg.norm(direction)
    a, b = x @ d, x @ np.array([-d[1], d[0]])
    stem = (a >= 0) & (a < 0.008) & (np.abs(b) < 0.6 * dx)
    arms = (a >= 0.008) & (np.abs(np.abs(b) - 0.5 * (a - 0.008)) < 0.6 * dx)
    return cloud.x, np.where(stem | arms, 1.0, 0.0)


@pytest.mark.parametrize("direction", [[1, 0], [-1, 0], [0, 1], [1, 1]])
def test_branching_follows_the_crack_direction(direction) -> None:
    d = np.asarray(direction, dtype=float)
    x, damage = _v_crack(d)
    n, dist = branching(x, damage, 5e-4, 0.5, np.array([0.02, 0.02]), d)
    assert n == 2
    assert dist is not None and 0.008 < dist < 0.0125


def test_crack_tip_ignores_pre_damaged_points() -> None:
    x = np.array([[0.0, 0.0], [0.01, 0.0], [0.02, 0.0]])
    damage = np.array([0.5, 0.5, 0.0])
    pre = np.array([True, True, False])
    assert crack_tip(x, damage, np.zeros(2), None, 0.35) == pytest.approx(0.01)
    assert crack_tip(x, damage, np.zeros(2), None, 0.35, ignore=pre) == 0.0


def test_conflicting_kinematic_conditions_are_refused() -> None:
    deck = copy.deepcopy(BASE)
    deck["boundary_conditions"] = [
        {"type": "fixed", "set": "left"},
        {"type": "displacement", "set": "all", "components": {"y": 1e-6}},
    ]
    d = parse_deck(deck)
    with pytest.raises(SetupError, match="boundary_conditions.1") as info:
        build_conditions(d, build_cloud(d))
    assert "boundary_conditions.0" in str(info.value)


def test_duplicate_yaml_keys_are_errors(tmp_path) -> None:
    path = tmp_path / "d.yaml"
    path.write_text(yaml.safe_dump(BASE) + "solver: {steps: 7}\n")
    with pytest.raises(DeckError, match="appears twice"):
        load_deck(path)


@pytest.mark.parametrize("name", ["a/b", "..", ".", "a b", ""])
def test_name_must_be_a_file_stem(name) -> None:
    with pytest.raises(DeckError, match="name"):
        parse_deck({**BASE, "name": name})


@pytest.mark.parametrize("points", [[[0.0, 0.0], [0.0, 0.0]], [[0, 0, 0], [0, 0, 0], [0, 1e-3, 0]]])
def test_degenerate_cracks_are_refused(points) -> None:
    with pytest.raises(ValueError, match="zero"):
        make_crack(points)


def test_point_region_outside_the_body_is_an_error() -> None:
    cloud = rectangle((0.01, 0.006), 5e-4)
    assert NearestPoint([0.0, 0.0], max_distance=5e-4)(cloud.x).sum() == 1
    with pytest.raises(ValueError, match="outside"):
        NearestPoint([0.05, 0.0], max_distance=5e-4)(cloud.x)
    deck = copy.deepcopy(BASE)
    deck["node_sets"]["gauge"] = {"point": [0.05, 0.003]}
    with pytest.raises(SetupError, match="node_sets.gauge"):
        build_cloud(parse_deck(deck))


def test_unreadable_mesh_is_a_deck_error(tmp_path) -> None:
    (tmp_path / "bad.vtu").write_text("this is not a mesh")
    deck = {**BASE, "geometry": {"type": "mesh", "file": "bad.vtu"}, "node_sets": {}}
    (tmp_path / "d.yaml").write_text(yaml.safe_dump(deck))
    proc = cli("check", str(tmp_path / "d.yaml"))
    assert proc.returncode == 2 and "geometry.file" in proc.stderr


def test_cli_run_guards(tmp_path) -> None:
    deck = str(EXAMPLES / "bar_wave_1d" / "deck.yaml")
    a_file = tmp_path / "file"
    a_file.write_text("x")
    for args, expect in [
        (["--out", str(a_file)], "not a folder"),
        (["--resume", str(tmp_path / "missing")], "no run folder"),
        (["--resume", str(tmp_path), "--out", str(tmp_path)], "either --out"),
        (["--checkpoint-every", "-5"], "checkpoint-every"),
    ]:
        proc = cli("run", deck, "--quiet", *args)
        assert proc.returncode == 2 and expect in proc.stderr, (args, proc.stderr)
    assert not (tmp_path / "missing").exists()
    out = tmp_path / "done"
    # 60 steps without figures or frames: a finished run is all this needs
    quick = ["solver.end_time=null", "solver.steps=60", "output.plot=none", "output.vtk_every=0"]
    sets = [a for s in quick for a in ("--set", s)]
    cli("run", deck, "--out", str(out), "--quiet", "--checkpoint-every", "100", *sets, check=True)
    before = json.loads((out / "summary.json").read_text())
    proc = cli("run", deck, "--resume", str(out), "--quiet", *sets)
    assert proc.returncode == 2 and "already finished" in proc.stderr
    assert json.loads((out / "summary.json").read_text()) == before


def test_examples_copy_does_not_overwrite(tmp_path) -> None:
    cli("examples", "copy", "bar_wave_1d", str(tmp_path), check=True)
    deck = tmp_path / "bar_wave_1d" / "deck.yaml"
    deck.write_text(deck.read_text() + "# my edit\n")
    proc = cli("examples", "copy", "bar_wave_1d", str(tmp_path))
    assert proc.returncode == 2 and "--force" in proc.stderr
    assert deck.read_text().endswith("# my edit\n")
    cli("examples", "copy", "bar_wave_1d", str(tmp_path), "--force", check=True)
    assert not deck.read_text().endswith("# my edit\n")


@pytest.mark.parametrize("args", [["--dims", "4"], ["--dims", "x"], ["--steps", "0"]])
def test_bench_argument_errors(args) -> None:
    proc = cli("bench", "--size", "quick", *args)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr


def test_check_with_bonds_checks_the_time_step(tmp_path) -> None:
    deck = str(EXAMPLES / "plate_tension_2d" / "deck.yaml")
    ok = cli("check", deck, "--bonds", "--set", "discretisation.spacing=1e-3")
    assert ok.returncode == 0 and "stable limit" in ok.stdout
    bad = cli(
        "check",
        deck,
        "--bonds",
        "--set",
        "discretisation.spacing=1e-3",
        "--set",
        "solver.time_step=1e-6",
    )
    assert bad.returncode == 2 and "solver.time_step" in bad.stderr
