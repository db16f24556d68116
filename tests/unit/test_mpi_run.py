"""``mpiexec -n 2 peridynamics run``: the decomposed run gives the serial run's fields bit
for bit (explicit dynamics: PMB crack branching; SED softening + Weibull + contact; LPS),
resumes after one rank dies (on another rank count: ``test_mpi_repartition``), and
refuses what it cannot do with the key to change.

``test_two_ranks_lps`` is the default selection's MPI smoke test; the others are in the
``mpi`` tier (``pytest -m mpi``, run by ``.ci/run``)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from peridynamics.io.final_state import read_final_state
from peridynamics.io.observers.bonds import read_bonds
from tests.helpers import EXAMPLES, cli, mpiexec

MPIEXEC, WHY = mpiexec()
pytestmark = pytest.mark.skipif(MPIEXEC is None, reason=WHY)

BRANCHING = [
    str(EXAMPLES / "crack_branching_2d" / "deck.yaml"),
    "--set", "discretisation.spacing=5e-4",
    "--set", "solver.end_time=16e-6",
    "--set", "output.plot=none",
]  # fmt: skip
ROCK = [
    str(EXAMPLES / "rock_compression" / "flaw45.yaml"),
    "--set", "discretisation.spacing=1e-3",
    "--set", "solver.steps=500",
    "--set", "output.plot=none",
]  # fmt: skip

LPS_DECK = """
name: lps_explicit
geometry: {type: rectangle, size: [0.02, 0.01], thickness: 1.0e-3, plane: stress}
discretisation: {spacing: 5.0e-4, horizon_factor: 3.015}
material: {model: lps, youngs_modulus: 70.0e9, density: 2700.0, poisson_ratio: 0.3}
damage: {model: critical_stretch, critical_stretch: 2.0e-3}
node_sets:
  left: {edge: {normal: [-1.0, 0.0]}}
  right: {edge: {normal: [1.0, 0.0]}}
boundary_conditions:
  - {type: velocity, set: right, components: {x: 5.0}}
  - {type: velocity, set: left, components: {x: -5.0}}
solver: {type: explicit, steps: 300, safety_factor: 0.8}
output:
  history_every: 20
  plot: none
  probes:
    - {name: right_ux, quantity: displacement, set: right, component: x}
    - {name: sxx, quantity: stress, set: all, component: xx}
    - {name: vm_max, quantity: von_mises, set: right, reduce: max}
"""


def _run(*args: str, ranks: int = 1, env: dict[str, str] | None = None, timeout: int = 180):
    """``[mpiexec -n RANKS] python -m peridynamics run ARGS`` on the source tree."""
    env = {"NUMBA_NUM_THREADS": "1", **(env or {})}
    return cli("run", *args, "--quiet", env=env, timeout=timeout, ranks=ranks)


def _close(a: object, b: object, path: str = "results") -> list[str]:
    """Entries of two results mappings that differ by more than 1e-12 (relative)."""
    if isinstance(a, dict) and isinstance(b, dict):
        out = [f"{path}.{k}: missing" for k in set(a) ^ set(b)]
        for k in set(a) & set(b):
            out += _close(a[k], b[k], f"{path}.{k}")
        return out
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{path}: lengths {len(a)} != {len(b)}"]
        return [
            d
            for k, (p, q) in enumerate(zip(a, b, strict=True))
            for d in _close(p, q, f"{path}[{k}]")
        ]
    if isinstance(a, float) and isinstance(b, (int, float)):
        ok = a == b or abs(a - b) <= 1e-12 * max(abs(a), abs(b))
        return [] if ok else [f"{path}: {a} != {b}"]
    return [] if a == b else [f"{path}: {a!r} != {b!r}"]


def _same_run(serial: Path, mpi: Path) -> None:
    fs, fm = read_final_state(serial), read_final_state(mpi)  # pieces joined
    for k in ("u", "v", "damage", "x", "intact"):  # intact: in the serial bond order
        np.testing.assert_array_equal(fm[k], fs[k], err_msg=k)  # bit for bit
    bs, bm = read_bonds(serial), read_bonds(mpi)  # one file; one per rank, joined
    assert not (mpi / "bonds.npz").exists()
    for k in ("i", "j", "length_m", "intact", "initially_intact", "x_m", "volume_m3"):
        np.testing.assert_array_equal(bm[k], bs[k], err_msg=k)
    rs = json.loads((serial / "summary.json").read_text())["results"]
    rm = json.loads((mpi / "summary.json").read_text())["results"]
    # sums over points and bonds (energies, crack length) add in another order: 1e-12
    assert _close(rs, rm) == []


SOFTENING = [
    *BRANCHING,
    "--set", "damage.bond_law=bilinear",
    "--set", "damage.tensile_strength=40e6",
]  # fmt: skip


@pytest.mark.mpi
@pytest.mark.parametrize("case", ["branching", "rock", "softening"])
def test_two_ranks_give_the_serial_run(tmp_path: Path, case: str) -> None:
    args = {"branching": BRANCHING, "rock": ROCK, "softening": SOFTENING}[case]
    serial = _run(*args, "--out", str(tmp_path / "s"))
    assert serial.returncode == 0, serial.stderr
    mpi = _run(*args, "--out", str(tmp_path / "m"), ranks=2)
    assert mpi.returncode == 0, mpi.stderr
    _same_run(tmp_path / "s", tmp_path / "m")
    summary = json.loads((tmp_path / "m" / "summary.json").read_text())
    assert summary["timing"]["ranks"] == 2
    # frames: one piece per rank joined by a .pvtu, listed in the .pvd series
    pvtu = sorted((tmp_path / "m").glob("frame_*.pvtu"))
    assert pvtu and len(list((tmp_path / "m").glob("frame_*_p000[01].vtu"))) == 2 * len(pvtu)
    pvd = next((tmp_path / "m").glob("*.pvd")).read_text()
    assert all(p.name in pvd for p in pvtu)


def test_two_ranks_lps(tmp_path: Path) -> None:
    """The default selection's MPI smoke test (the others are marked ``mpi``): a small
    LPS run with damage on two ranks gives the serial run's fields bit for bit."""
    deck = tmp_path / "lps.yaml"
    deck.write_text(LPS_DECK)
    assert _run(str(deck), "--out", str(tmp_path / "s")).returncode == 0
    mpi = _run(str(deck), "--out", str(tmp_path / "m"), ranks=2)
    assert mpi.returncode == 0, mpi.stderr
    _same_run(tmp_path / "s", tmp_path / "m")
    assert json.loads((tmp_path / "m" / "summary.json").read_text())["results"]["bonds_broken"] > 0


DISC = [
    str(EXAMPLES / "bodies" / "brazilian_disc.yaml"),
    "--set", "discretisation.spacing=2.5e-3",
    "--set", "solver.end_time=2e-4",
    "--set", "output.plot=none",
]  # fmt: skip


@pytest.mark.mpi
def test_rigid_platens_on_three_ranks_give_the_serial_run(tmp_path: Path) -> None:
    """The Brazilian disc between two rigid platens (seated by ``touch``, prescribed
    motion): every rank holds the platens, each presses its owned points, the reactions
    are summed over the ranks: the fields are the serial run's bit for bit and the
    reaction history agrees to round-off."""
    assert _run(*DISC, "--out", str(tmp_path / "s")).returncode == 0
    mpi = _run(*DISC, "--out", str(tmp_path / "m"), ranks=3)
    assert mpi.returncode == 0, mpi.stderr
    fs, fm = read_final_state(tmp_path / "s"), read_final_state(tmp_path / "m")
    for k in ("u", "v", "damage", "intact"):
        np.testing.assert_array_equal(fm[k], fs[k], err_msg=k)
    assert np.abs(fs["u"]).max() > 0  # the platens pressed the disc
    rs = json.loads((tmp_path / "s" / "summary.json").read_text())["results"]
    rm = json.loads((tmp_path / "m" / "summary.json").read_text())["results"]
    assert _close(rs, rm) == []


@pytest.mark.mpi
def test_micropolar_explicit_on_three_ranks_gives_the_serial_run(tmp_path: Path) -> None:
    """A micropolar cantilever in explicit dynamics: rotations are exchanged with the
    displacements, the surface-correction ratios of the ghosts come from their owners:
    u, v, theta and the moments are the serial run's bit for bit."""
    args = [
        str(EXAMPLES / "micropolar" / "cantilever.yaml"),
        "--set", "discretisation.spacing=0.02",
        "--set", "geometry.size=[1.04, 0.3]",
        "--set", "geometry.origin=[-0.04, 0.0]",
        "--set", "solver={type: explicit, steps: 200}",
        "--set", "output.plot=none",
    ]  # fmt: skip
    assert _run(*args, "--out", str(tmp_path / "s")).returncode == 0
    mpi = _run(*args, "--out", str(tmp_path / "m"), ranks=3)
    assert mpi.returncode == 0, mpi.stderr
    assert "warning" not in mpi.stderr
    fs, fm = read_final_state(tmp_path / "s"), read_final_state(tmp_path / "m")
    for k in ("u", "v", "theta", "moment"):
        np.testing.assert_array_equal(fm[k], fs[k], err_msg=k)
    assert np.abs(fs["theta"]).max() > 0


@pytest.mark.mpi
def test_a_killed_rank_resumes_to_the_same_result(tmp_path: Path) -> None:
    deck = [a if a != "solver.steps=500" else "solver.steps=300" for a in ROCK]
    whole = _run(*deck, "--out", str(tmp_path / "whole"), ranks=2)
    assert whole.returncode == 0, whole.stderr
    out = str(tmp_path / "cut")
    crash = {"PERIDYNAMICS_CRASH_AT_STEP": "130", "PERIDYNAMICS_CRASH_RANK": "1"}
    died = _run(*deck, "--out", out, "--checkpoint-every", "50", ranks=2, env=crash)
    assert died.returncode != 0
    marker = json.loads((tmp_path / "cut" / "checkpoint_mpi.json").read_text())
    assert marker["step"] == 100 and marker["ranks"] == 2
    info = json.loads((tmp_path / "cut" / "checkpoint_mpi.json").read_text())
    del info["owned_boxes"]  # as written before the partition was stored
    (tmp_path / "cut" / "checkpoint_mpi.json").write_text(json.dumps(info))
    other = _run(*deck, "--resume", out, ranks=3)  # cannot repartition: refused
    assert other.returncode == 2 and "mpiexec -n 2" in other.stderr
    resumed = _run(*deck, "--resume", out, ranks=2)
    assert resumed.returncode == 0, resumed.stderr
    a = read_final_state(tmp_path / "whole")
    b = read_final_state(tmp_path / "cut")
    for k in ("u", "v", "damage"):
        np.testing.assert_array_equal(b[k], a[k], err_msg=k)


@pytest.mark.mpi
def test_two_ranks_static_solver_breaks_the_same_bonds(tmp_path: Path) -> None:
    """The static Newton solver decomposed (distributed CG with block AMG): the same
    solves, Newton iterations, breaking events and broken bonds as one process, the
    displacements and the reaction to the Newton tolerance (docs/mpi.md)."""
    args = [
        str(EXAMPLES / "static_fracture" / "notched_plate_adr.yaml"),
        "--set", "solver.type=static",
        "--set", "solver.tolerance=1e-8",
        "--set", "output.vtk_every=0",
    ]  # fmt: skip
    assert _run(*args, "--out", str(tmp_path / "s")).returncode == 0
    mpi = _run(*args, "--out", str(tmp_path / "m"), ranks=2)
    assert mpi.returncode == 0, mpi.stderr
    fs, fm = read_final_state(tmp_path / "s"), read_final_state(tmp_path / "m")
    np.testing.assert_array_equal(fm["intact"], fs["intact"])
    # measured 1.5e-14 of the largest displacement (tolerance 1e-8, CG to 1e-10)
    assert np.abs(fm["u"] - fs["u"]).max() <= 1e-9 * np.abs(fs["u"]).max()
    rs = json.loads((tmp_path / "s" / "summary.json").read_text())["results"]
    rm = json.loads((tmp_path / "m" / "summary.json").read_text())["results"]
    for key in ("solves", "newton_iterations", "breaking_events", "bonds_broken"):
        assert rm[key] == rs[key], key
    assert rm["breaking_events"] > 10 and rm["ranks"] == 2 and rm["cg_iterations"] > 0
    assert rm["first_break_m"] == pytest.approx(rs["first_break_m"])
    ps = np.asarray(rs["probes"]["reaction"]["values"])
    pm = np.asarray(rm["probes"]["reaction"]["values"])
    assert np.abs(pm - ps).max() <= 1e-9 * np.abs(ps).max()


@pytest.mark.mpi
def test_two_ranks_adr_agree_to_the_tolerance(tmp_path: Path) -> None:
    """Dynamic relaxation sums its norms over ranks in another order than one process:
    the iterations may differ, the equilibrium agrees to the residual tolerance."""
    args = [
        str(EXAMPLES / "lps" / "plate_hole.yaml"),
        "--set", "discretisation.spacing=2e-3",
        "--set", "solver.tolerance=1e-6",
    ]  # fmt: skip
    assert _run(*args, "--out", str(tmp_path / "s")).returncode == 0
    mpi = _run(*args, "--out", str(tmp_path / "m"), ranks=2)
    assert mpi.returncode == 0, mpi.stderr
    us = read_final_state(tmp_path / "s")["u"]
    um = read_final_state(tmp_path / "m")["u"]
    # measured 2.7e-7 of the largest displacement at tolerance 1e-6 (spacing 1 mm)
    assert np.abs(um - us).max() <= 1e-5 * np.abs(us).max()
    rm = json.loads((tmp_path / "m" / "summary.json").read_text())["results"]
    assert rm["residual"] <= 1e-6
