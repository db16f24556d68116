"""Checkpoint / resume: a resumed run is bitwise identical to an uninterrupted one."""

from __future__ import annotations

import json
import signal
import time

import numpy as np
import pytest

from tests.helpers import EXAMPLES, cli, popen

DECK = str(EXAMPLES / "crack_branching_2d" / "deck.yaml")
SMALL = [
    "--set",
    "discretisation.spacing=1e-3",
    "--set",
    "discretisation.horizon=3e-3",
    "--set",
    "output.vtk_every=100",
    "--set",
    "output.history_every=7",
]


def _same_results(a, b) -> None:
    sa = json.loads((a / "summary.json").read_text())
    sb = json.loads((b / "summary.json").read_text())
    assert sa["results"] == sb["results"]  # exact equality of every recorded number
    fa, fb = np.load(a / "final_state.npz"), np.load(b / "final_state.npz")
    for key in ("u", "v", "damage", "intact", "t", "step"):
        assert np.array_equal(fa[key], fb[key]), key


@pytest.mark.long
def test_resume_after_crash_is_bitwise_identical(tmp_path) -> None:
    ref, crashed = tmp_path / "ref", tmp_path / "crashed"
    args = [*SMALL, "--set", "solver.end_time=40e-6", "--quiet"]
    cli("run", DECK, "--out", str(ref), *args, check=True)
    proc = cli(
        "run",
        DECK,
        "--out",
        str(crashed),
        "--checkpoint-every",
        "50",
        *args,
        env={"PERIDYNAMICS_CRASH_AT_STEP": "130"},
    )
    assert proc.returncode == 137  # died mid-run, after the checkpoint of step 100
    assert not (crashed / "summary.json").exists()
    cli("run", DECK, "--resume", str(crashed), *args, check=True)
    _same_results(ref, crashed)
    pvd = (crashed / "crack_branching_2d.pvd").read_text()
    assert pvd.count("<DataSet") == len(list(crashed.glob("frame_*.vtu")))


@pytest.mark.long
def test_resume_after_sigkill(tmp_path) -> None:
    ref, killed = tmp_path / "ref", tmp_path / "killed"
    deck = str(EXAMPLES / "plate_tension_2d" / "deck.yaml")
    args = ["--set", "solver.end_time=4e-4", "--set", "output.vtk_every=1000", "--quiet"]
    proc = popen("run", deck, "--out", str(killed), "--checkpoint-every", "200", *args)
    ckpt = killed / "checkpoint.npz"
    deadline = time.time() + 120
    while not ckpt.exists() and proc.poll() is None and time.time() < deadline:
        time.sleep(0.05)
    if proc.poll() is not None:
        pytest.fail("the run ended before it could be killed: make it longer")
    time.sleep(0.3)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert not (killed / "summary.json").exists()
    cli("run", deck, "--resume", str(killed), *args, check=True)
    cli("run", deck, "--out", str(ref), *args, check=True)
    _same_results(ref, killed)


def test_resume_refuses_other_deck(tmp_path) -> None:
    out = tmp_path / "run"
    args = [*SMALL, "--set", "solver.end_time=null", "--set", "solver.steps=40", "--quiet"]
    cli("run", DECK, "--out", str(out), "--checkpoint-every", "20", *args, check=True)
    other = cli("run", DECK, "--resume", str(out), *args, "--set", "material.density=2000")
    assert other.returncode == 2
    assert "different deck" in other.stderr


def test_resume_without_checkpoint_is_clear(tmp_path) -> None:
    proc = cli("run", DECK, "--resume", str(tmp_path), *SMALL, "--quiet")
    assert proc.returncode == 2
    assert "no checkpoint" in proc.stderr


@pytest.mark.long
def test_static_solver_resumes_after_crash(tmp_path) -> None:
    """A static run with bond breaking resumes from its checkpoint: the load level, the
    bonds and the pending break are restored, and the run ends where an uninterrupted
    one does (the factorisation is rebuilt, so agreement is to round-off: equal bond
    counts and loads, not bits)."""
    deck = str(EXAMPLES / "micropolar" / "dcb.yaml")
    args = [
        "--set", "discretisation.spacing=2.0e-3",
        "--set", "geometry.size=[0.206,0.04]",
        "--set", "boundary_conditions.1.components.y=0.45e-3",
        "--set", "boundary_conditions.2.components.y=-0.45e-3",
        "--set", "solver.load_steps=4",
        "--set", "output.crack_paths=[]",
        "--quiet",
    ]  # fmt: skip
    ref, crashed = tmp_path / "ref", tmp_path / "crashed"
    cli("run", deck, "--out", str(ref), *args, check=True)
    proc = cli(
        "run", deck, "--out", str(crashed), "--checkpoint-every", "5", *args,
        env={"PERIDYNAMICS_CRASH_AT_STEP": "12"},
    )  # fmt: skip
    assert proc.returncode == 137
    cli("run", deck, "--resume", str(crashed), *args, check=True)
    ra = json.loads((ref / "summary.json").read_text())["results"]
    rb = json.loads((crashed / "summary.json").read_text())["results"]
    assert ra["breaking_events"] > 5
    assert rb["load_factor"] == ra["load_factor"] == 1.0
    assert rb["bonds_broken"] == ra["bonds_broken"]
    pa, pb = ra["probes"]["load_N"]["values"], rb["probes"]["load_N"]["values"]
    assert len(pa) == len(pb)
    assert np.allclose(pa, pb, rtol=1e-8, atol=1e-9 * max(abs(np.asarray(pa))))
