"""Several bodies and rigid bodies resume bit for bit: the rigid bodies' pose, momenta,
reactions and the friction work live in the State, so a checkpoint holds them."""

from __future__ import annotations

import json

import numpy as np
import pytest
import yaml

from tests.helpers import EXAMPLES, cli

pytestmark = pytest.mark.long  # runs and resumes example decks (CI: pytest -m long)


def _same(a, b) -> None:
    sa = json.loads((a / "summary.json").read_text())
    sb = json.loads((b / "summary.json").read_text())
    assert sa["results"] == sb["results"]
    fa, fb = np.load(a / "final_state.npz"), np.load(b / "final_state.npz")
    for key in ("u", "v", "damage", "intact"):
        assert np.array_equal(fa[key], fb[key]), key


def _crash_and_resume(tmp_path, deck: str, args: list[str], crash_at: int) -> None:
    ref, crashed = tmp_path / "ref", tmp_path / "crashed"
    cli("run", deck, "--out", str(ref), *args, check=True)
    proc = cli(
        "run", deck, "--out", str(crashed), "--checkpoint-every", "20", *args,
        env={"PERIDYNAMICS_CRASH_AT_STEP": str(crash_at)},
    )  # fmt: skip
    assert proc.returncode == 137
    cli("run", deck, "--resume", str(crashed), *args, check=True)
    _same(ref, crashed)


def test_free_striker_with_friction_resumes_bit_for_bit(tmp_path) -> None:
    deck = str(EXAMPLES / "bodies" / "striker_plate.yaml")
    args = [
        "--set", "discretisation.spacing=2e-3", "--set", "solver.end_time=1.2e-5",
        "--set", "contact={friction_static: 0.3, friction_kinetic: 0.2}",
        "--set", "output.history_every=5", "--quiet",
    ]  # fmt: skip
    _crash_and_resume(tmp_path, deck, args, 45)


def test_two_materials_with_an_interface_resume_bit_for_bit(tmp_path) -> None:
    data = {
        "name": "two",
        "geometry": {"type": "rectangle", "size": [0.04, 0.02], "thickness": 0.01},
        "discretisation": {"spacing": 0.002, "horizon_factor": 3.015},
        "material": {"model": "pmb", "youngs_modulus": 30e9, "density": 2400},
        "damage": {"bond_law": "bilinear", "tensile_strength": 3e6, "fracture_energy": 50},
        "bodies": [{
            "name": "aggregate", "region": {"ball": {"center": [0.02, 0.01], "radius": 0.005}},
            "material": {"model": "lps", "youngs_modulus": 60e9, "poisson_ratio": 0.2,
                         "density": 2700},
            "damage": {"critical_stretch": 0.01},
        }],
        "interfaces": [{"bodies": ["main", "aggregate"], "critical_stretch": 0.0003}],
        "node_sets": {"left": {"edge": {"normal": [-1, 0]}},
                      "right": {"edge": {"normal": [1, 0]}}},
        "boundary_conditions": [
            {"type": "fixed", "set": "left"},
            {"type": "velocity", "set": "right", "components": {"x": 2.0}},
        ],
        "solver": {"steps": 120},
        "output": {"history_every": 5},
    }  # fmt: skip
    path = tmp_path / "two.yaml"
    path.write_text(yaml.safe_dump(data))
    _crash_and_resume(tmp_path, str(path), ["--quiet"], 70)
    final = np.load(tmp_path / "ref" / "final_state.npz")
    assert final["damage"].max() > 0  # the run breaks bonds (interface or matrix)
