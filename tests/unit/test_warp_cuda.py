"""The Warp kernels build for CUDA without a GPU (Warp's NVRTC, PTX for sm_90, no FMA
contraction, so the CUDA device can give the CPU device's bits); on a machine with a
CUDA device a short run gives the CPU device's fields bit for bit. The one-command GPU
measurement script runs at small size on the CPU device."""

from __future__ import annotations

import importlib
import json
import sys
from pathlib import Path

import numpy as np
import pytest

from peridynamics.app.run import Simulation
from peridynamics.deck import load_deck
from tests.helpers import EXAMPLES

wp = pytest.importorskip("warp", reason="warp-lang not installed (pip install '.[gpu]')")
pytestmark = pytest.mark.gpu  # the Warp tier (pytest -m gpu); the smoke test: test_warp_kernels.py

MODULES = [
    "_warp_dsl", "_warp_step_dsl", "_warp_damage_dsl", "_warp_lps_dsl",
    "_warp_correspondence_prepass_dsl", "_warp_correspondence_dsl", "_warp_extras_dsl",
    "_warp_short_range_contact_dsl", "_warp_energy_dsl", "_warp_halo_dsl",
]  # fmt: skip
ROOT = Path(__file__).resolve().parents[2]


def _nvrtc_archs() -> list[int]:
    wp.init()
    get = getattr(wp, "get_cuda_supported_archs", None)
    return list(get()) if get is not None else []


@pytest.mark.skipif(not _nvrtc_archs(), reason="Warp has no NVRTC here (cannot build PTX)")
@pytest.mark.parametrize("name", MODULES)
def test_kernels_build_for_sm90_without_fma(name: str, tmp_path: Path) -> None:
    mod = importlib.import_module(f"peridynamics.backends.{name}")
    paths = wp.compile_aot_module(mod, arch=90, use_ptx=True, module_dir=tmp_path)
    ptx = [p for p in map(Path, paths) if p.suffix == ".ptx"]
    assert ptx, paths
    text = ptx[0].read_text()
    assert ".entry" in text  # kernels were emitted
    assert "fma.rn.f64" not in text  # contraction off: the CPU device's rounding


@pytest.mark.skipif(
    wp.get_cuda_device_count() == 0, reason="no CUDA device on this machine (GPU-only test)"
)
def test_cuda_device_gives_the_cpu_device_bits(tmp_path: Path) -> None:
    deck = EXAMPLES / "crack_branching_2d" / "deck.yaml"
    over = ["discretisation.spacing=5e-4", "solver.end_time=22e-6", "output.plot=none",
            "output.vtk_every=0", "solver.backend=warp"]  # fmt: skip
    fields = []
    for device in ("cpu", "cuda"):
        sim = Simulation.from_deck(load_deck(deck, overrides=[*over, f"solver.device={device}"]))
        sim.run(tmp_path / device, quiet=True)
        fields.append(np.load(tmp_path / device / "final_state.npz"))
    for name in ("u", "v", "intact", "damage"):
        assert np.array_equal(fields[0][name], fields[1][name]), name


def test_measurement_script_small_on_cpu(tmp_path: Path) -> None:
    sys.path.insert(0, str(ROOT / "benchmarks"))
    try:
        gm = importlib.import_module("gpu_measure")
    finally:
        sys.path.pop(0)
    out = tmp_path / "m.json"
    gm.main(["--device", "cpu", "--sizes", "2d:30,3d:8", "--steps", "2", "--cpu-steps", "1",
             "--main-spacing", "1e-3", "--out", str(out)])  # fmt: skip
    res = json.loads(out.read_text())
    assert res["machine"]["device"] == "cpu"
    assert [c["dim"] for c in res["cases"]] == [2, 3]
    for c in res["cases"]:
        assert c["warp_bond_updates_per_s"] > 0 and c["numba_bond_updates_per_s"] > 0
    mj = res["main_job"]
    assert mj["bonds_broken_numba"] == mj["bonds_broken_warp"]
    assert mj["bond_flags_differing"] == 0
