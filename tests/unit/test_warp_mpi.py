"""``mpiexec -n 2 peridynamics run`` with ``solver.backend: warp`` on Warp's CPU device:
every rank steps its part on its own device, the ghost rows of u and v are exchanged
before each force evaluation, and the fields are the serial Warp run's bit for bit
(PMB with critical stretch, velocity Verlet; LPS with critical stretch, central
difference), with the same number of bonds broken: in the ``mpi`` tier (``.ci/run``),
skipped without mpi4py and mpiexec or without warp-lang. The device of rank r
(``pick_device``) is checked in the default selection on a stand-in for Warp (no GPU,
no warp-lang needed)."""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from peridynamics.backends import warp_device
from peridynamics.io.final_state import read_final_state
from tests.helpers import cli, mpiexec

MPIEXEC, WHY = mpiexec()
HAS_WARP = importlib.util.find_spec("warp") is not None

DECK = """
name: warp_mpi
geometry: {{type: rectangle, size: [0.02, 0.01], thickness: 1.0e-3, plane: stress}}
discretisation: {{spacing: 5.0e-4, horizon_factor: 3.015}}
material: {{model: {model}, youngs_modulus: 70.0e9, density: 2700.0{extra}}}
damage: {{model: critical_stretch, critical_stretch: 2.0e-3}}
node_sets:
  left: {{edge: {{normal: [-1.0, 0.0]}}}}
  right: {{edge: {{normal: [1.0, 0.0]}}}}
boundary_conditions:
  - {{type: velocity, set: right, components: {{x: 5.0}}}}
  - {{type: velocity, set: left, components: {{x: -5.0}}}}
solver:
  type: explicit
  steps: 300
  safety_factor: 0.8
  integrator: {integrator}
  backend: warp
  device: cpu
output: {{history_every: 20, plot: none, vtk_every: 0}}
"""


def _run(deck: Path, out: Path, ranks: int = 1) -> None:
    env = {"NUMBA_NUM_THREADS": "1"}
    got = cli("run", str(deck), "--out", str(out), "--quiet", env=env, ranks=ranks, timeout=180)
    assert got.returncode == 0, got.stderr


@pytest.mark.mpi  # one tier per test (tests/conftest.py): it needs mpiexec and Warp
@pytest.mark.skipif(MPIEXEC is None, reason=WHY)
@pytest.mark.skipif(not HAS_WARP, reason="warp-lang not installed (pip install '.[gpu]')")
@pytest.mark.parametrize(
    ("model", "integrator"), [("pmb", "velocity_verlet"), ("lps", "central_difference")]
)
def test_two_ranks_on_warp_give_the_serial_warp_run(
    tmp_path: Path, model: str, integrator: str
) -> None:
    deck = tmp_path / "deck.yaml"
    extra = ", poisson_ratio: 0.25" if model == "lps" else ""  # bond-based: none
    deck.write_text(DECK.format(model=model, integrator=integrator, extra=extra))
    _run(deck, tmp_path / "s")
    _run(deck, tmp_path / "m", ranks=2)
    fs, fm = read_final_state(tmp_path / "s"), read_final_state(tmp_path / "m")
    for k in ("u", "v", "damage", "intact"):
        np.testing.assert_array_equal(fm[k], fs[k], err_msg=k)  # bit for bit
    rs = json.loads((tmp_path / "s" / "summary.json").read_text())
    rm = json.loads((tmp_path / "m" / "summary.json").read_text())
    assert rs["results"]["bonds_broken"] > 0
    assert rm["results"]["bonds_broken"] == rs["results"]["bonds_broken"]
    assert rm["results"]["backend"] == "warp"
    assert rm["results"]["devices_per_rank"] == ["cpu", "cpu"]
    for key in ("kinetic_energy_J", "strain_energy_J"):  # sums over ranks: round-off
        assert rm["results"][key] == pytest.approx(rs["results"][key], rel=1e-12, abs=0.0)
    assert rm["timing"]["ranks"] == 2 and rm["timing"]["halo_exchanges"] >= 300


@pytest.mark.parametrize(
    ("cuda", "requested", "rank", "expected"),
    [
        (2, "auto", 0, "cuda:0"),
        (2, "auto", 3, "cuda:1"),
        (4, "cuda", 6, "cuda:2"),
        (1, "auto", 5, "cuda:0"),
        (2, "cpu", 1, "cpu"),
        (0, "auto", 1, "cpu"),
    ],
)
def test_rank_r_drives_cuda_device_r_mod_count(
    monkeypatch: pytest.MonkeyPatch, cuda: int, requested: str, rank: int, expected: str
) -> None:
    fake = SimpleNamespace(get_cuda_device_count=lambda: cuda)
    monkeypatch.setattr(warp_device, "require_warp", lambda: fake)
    assert warp_device.pick_device(requested, rank) == expected


def test_cuda_without_a_cuda_device_is_refused_on_every_rank(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    fake = SimpleNamespace(get_cuda_device_count=lambda: 0)
    monkeypatch.setattr(warp_device, "require_warp", lambda: fake)
    with pytest.raises(ValueError, match="solver.device: cuda"):
        warp_device.pick_device("cuda", 1)


@pytest.mark.mpi
@pytest.mark.skipif(MPIEXEC is None, reason=WHY)
@pytest.mark.skipif(not HAS_WARP, reason="warp-lang not installed (pip install '.[gpu]')")
def test_the_ranks_check_script_finds_the_serial_bits(tmp_path: Path) -> None:
    """``benchmarks/gpu_ranks_check.py`` (what was run on the H200) on Warp's CPU device:
    two ranks against one process, the main job at 0.5 mm, bit for bit (exit 0)."""
    import os
    import subprocess
    import sys

    from tests.helpers import ROOT, subprocess_env

    out = tmp_path / "check.json"
    env = subprocess_env({"NUMBA_NUM_THREADS": "1"})
    env["PATH"] = f"{Path(str(MPIEXEC)).parent}{os.pathsep}{env.get('PATH', '')}"
    got = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / "gpu_ranks_check.py"), "--device", "cpu",
         "--ranks", "2", "--set", "discretisation.spacing=5e-4", "--out", str(out)],
        env=env, capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip
    assert got.returncode == 0, got.stderr[-3000:]
    res = json.loads(out.read_text())
    assert res["devices_ranks"] == ["cpu", "cpu"]
    assert all(res[f"{k}_identical"] for k in ("u", "v", "damage", "intact"))
    assert res["bonds_broken_ranks"] == res["bonds_broken_one"] > 0
