"""Checkpoints you can trust (issue "Nothing lost", item 4): a checksum in every
checkpoint, two generations kept (``checkpoint.npz``, ``checkpoint.prev.npz``; the MPI
marker names the previous step too), and ``--resume`` falling back to the previous one
with a warning, or exit 2 naming each file when none is usable: never a traceback.

The byte-level mutations (hypothesis, bounded) are checked twice: many of them on the
reader alone (each reads back the same arrays or raises DamagedCheckpoint), a few
through ``peridynamics run --resume`` (each resumes to the uninterrupted run's fields).
"""

from __future__ import annotations

import json
import shutil
import signal
import tempfile
import zipfile
from collections.abc import Iterator
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from peridynamics.app.run import RunInterrupted, Simulation
from peridynamics.deck import load_deck
from peridynamics.io.checkpoint import (
    CHECKPOINT_NAME,
    PREVIOUS_NAME,
    DamagedCheckpoint,
    load_checkpoint,
    read_checkpoint,
    write_checkpoint,
)
from tests.helpers import EXAMPLES, cli, mpiexec, same_final_fields, sigint_at

BAR = EXAMPLES / "bar_wave_1d" / "deck.yaml"
# 60 steps of the 1-D bar (201 points), as QUICK_BAR of test_faults.py
QUICK_BAR = [
    "solver.end_time=null",
    "solver.steps=60",
    "output.vtk_every=20",
    "output.plot=none",
    "output.history_every=5",
]
SETS = [a for s in QUICK_BAR for a in ("--set", s)]


def _interrupted_at(step: int, out: Path) -> None:
    """Run the quick bar with checkpoints every 20 steps and a Ctrl-C (a real SIGINT)
    while it computes ``step``: checkpoints of steps 40 (previous) and ``step`` (newest)."""
    sim = Simulation.from_deck(load_deck(BAR, QUICK_BAR))
    sigint_at(sim, step)
    saved = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(RunInterrupted):
            sim.run(out, quiet=True, checkpoint_every=20)
    finally:
        signal.signal(signal.SIGINT, saved)


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> SimpleNamespace:
    """The reference run (no checkpoints), a finished run with checkpoints (newest step
    60 marked finished, previous 40) and a run interrupted at step 50 (newest 50,
    previous 40). Copy them to change them."""
    base = tmp_path_factory.mktemp("checkpoints")
    ref, fin, cut = base / "ref", base / "finished", base / "interrupted"
    cli("run", BAR, "--out", ref, "--quiet", *SETS, check=True)
    cli("run", BAR, "--out", fin, "--quiet", "--checkpoint-every", "20", *SETS, check=True)
    _interrupted_at(50, cut)
    return SimpleNamespace(ref=ref, finished=fin, interrupted=cut)


def _copy(src: Path, dst: Path, looks_interrupted: bool = False) -> Path:
    """A copy of a run folder (without its summary.json: a run that looks interrupted)."""
    shutil.copytree(src, dst)
    if looks_interrupted:
        (dst / "summary.json").unlink()
    return dst


def _resume(folder: Path):  # noqa: ANN202
    return cli("run", BAR, "--resume", folder, "--quiet", *SETS)


def _same_fields(ref: Path, got: Path) -> None:
    same_final_fields(ref, got, ("u", "v", "damage"))


def _fallback_line(folder: Path) -> str:
    return f"; resuming from the previous one {folder / PREVIOUS_NAME}\n"


# ------------------------------------------------------------------ write and read
def test_round_trip_keeps_every_field_and_a_checksum(tmp_path: Path) -> None:
    sim = Simulation.from_deck(load_deck(BAR, QUICK_BAR))
    state = sim.solver.init()
    for _ in range(3):
        sim.solver.step(state)
    records = {"history": [1.0, 2.0], "checkpoint_every": 7}
    path = write_checkpoint(tmp_path, state, records, "fp", {"finished": False})
    ck = load_checkpoint(path)
    assert (ck.records, ck.fingerprint, ck.meta) == (records, "fp", {"finished": False})
    got, want = ck.state.to_arrays(), state.to_arrays()
    assert got.keys() == want.keys()
    for key in want:
        np.testing.assert_array_equal(got[key], want[key], err_msg=key)
        assert np.asarray(got[key]).dtype == np.asarray(want[key]).dtype, key
    with np.load(path) as data:  # a plain npz (no pickles), with the checksum in it
        assert data["checksum"].shape == (32,)
    assert not (tmp_path / PREVIOUS_NAME).exists()
    sim.solver.step(state)
    write_checkpoint(tmp_path, state, records, "fp")
    assert read_checkpoint(tmp_path)[0].step == 4
    assert load_checkpoint(tmp_path / PREVIOUS_NAME).state.step == 3


def test_the_previous_generation_is_kept_and_only_a_good_one(tmp_path: Path) -> None:
    state = Simulation.from_deck(load_deck(BAR, QUICK_BAR)).solver.init()
    for step in (1, 2):
        state.step = step
        write_checkpoint(tmp_path, state, {}, "fp")
    (tmp_path / CHECKPOINT_NAME).write_bytes(b"damaged")  # step 2 lost
    state.step = 3
    write_checkpoint(tmp_path, state, {}, "fp")  # the damaged one is not rotated
    assert load_checkpoint(tmp_path / PREVIOUS_NAME).state.step == 1
    assert load_checkpoint(tmp_path / CHECKPOINT_NAME).state.step == 3
    state.step = 1  # a new run of another deck in this folder: both old ones go
    write_checkpoint(tmp_path, state, {}, "other")
    assert not (tmp_path / PREVIOUS_NAME).exists()


def test_a_finished_run_keeps_two_generations(runs: SimpleNamespace) -> None:
    newest = load_checkpoint(runs.finished / CHECKPOINT_NAME)
    previous = load_checkpoint(runs.finished / PREVIOUS_NAME)
    assert (newest.state.step, newest.meta) == (60, {"finished": True})
    assert (previous.state.step, previous.meta) == (40, {})
    assert load_checkpoint(runs.interrupted / CHECKPOINT_NAME).state.step == 50


# ------------------------------------------------------------------ byte mutations
def _mutate(raw: bytes, kind: str, where: int, value: int) -> bytes:
    """``raw`` truncated at ``where``, with the byte at ``where`` XORed with ``value``
    (1..255), or replaced by ``where`` seeded random bytes."""
    if kind == "truncate":
        return raw[: where % len(raw)]
    if kind == "flip":
        i = where % len(raw)
        return raw[:i] + bytes([raw[i] ^ value]) + raw[i + 1 :]
    return np.random.default_rng(value).integers(0, 256, where, dtype=np.uint8).tobytes()


def _structure(path: Path) -> list[int]:
    """Byte offsets of a checkpoint's structure: each member's zip and .npy headers and
    the central directory at the end (where a flipped byte is not in array data)."""
    with zipfile.ZipFile(path) as zf:
        infos = zf.infolist()
    size = path.stat().st_size
    heads = [o for i in infos for o in range(i.header_offset, i.header_offset + 200)]
    return sorted({o for o in heads if o < size} | set(range(size - 80 * len(infos), size)))


MUTATION = st.tuples(
    st.sampled_from(["truncate", "flip", "garbage"]),
    st.integers(0, 1 << 20),
    st.integers(1, 255),
)


@pytest.fixture(scope="module")
def newest(runs: SimpleNamespace) -> SimpleNamespace:
    path = runs.interrupted / CHECKPOINT_NAME
    arrays = load_checkpoint(path).state.to_arrays()
    return SimpleNamespace(raw=path.read_bytes(), arrays=arrays, structure=_structure(path))


@settings(max_examples=300, deadline=None, database=None)
@given(mutation=MUTATION, data=st.data())
def test_mutated_bytes_read_back_the_same_or_are_damaged(
    newest: SimpleNamespace, mutation: tuple[str, int, int], data: st.DataObject
) -> None:
    kind, where, value = mutation
    if kind == "flip" and data.draw(st.booleans()):  # half the flips in the structure
        where = data.draw(st.sampled_from(newest.structure))
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / CHECKPOINT_NAME
        path.write_bytes(_mutate(newest.raw, kind, where, value))
        try:
            got = load_checkpoint(path).state.to_arrays()
        except DamagedCheckpoint as exc:
            assert str(path) in str(exc) and "is damaged (" in str(exc)
            return
    for key, want in newest.arrays.items():  # a harmless byte (a zip time stamp)
        np.testing.assert_array_equal(got[key], want, err_msg=key)


@pytest.fixture(scope="module")
def scratch(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    yield tmp_path_factory.mktemp("mutated")


@settings(max_examples=12, deadline=None, database=None)
@given(mutation=MUTATION)
def test_resume_after_any_mutation_of_the_newest_gives_the_uninterrupted_run(
    runs: SimpleNamespace, scratch: Path, mutation: tuple[str, int, int]
) -> None:
    folder = _copy(runs.interrupted, Path(tempfile.mkdtemp(dir=scratch)) / "run")
    newest = folder / CHECKPOINT_NAME
    newest.write_bytes(_mutate(newest.read_bytes(), *mutation))
    proc = _resume(folder)
    assert proc.returncode == 0 and "Traceback" not in proc.stderr, proc.stderr
    if "warning:" in proc.stderr:
        assert f"warning: checkpoint {newest} is damaged (" in proc.stderr
        assert _fallback_line(folder) in proc.stderr
    _same_fields(runs.ref, folder)


def _drop_member(path: Path, member: str) -> None:
    """Rewrite the zip at ``path`` without ``member`` (a zip with an array missing)."""
    with zipfile.ZipFile(path) as zf:
        kept = {i.filename: zf.read(i) for i in zf.infolist() if i.filename != member}
    with zipfile.ZipFile(path, "w") as zf:
        for name, raw in kept.items():
            zf.writestr(name, raw)


DAMAGES = {
    "truncated_to_nothing": lambda p: p.write_bytes(b""),
    "truncated_half": lambda p: p.write_bytes(p.read_bytes()[: p.stat().st_size // 2]),
    "truncated_last_byte": lambda p: p.write_bytes(p.read_bytes()[:-1]),
    "random_garbage": lambda p: p.write_bytes(_mutate(b"", "garbage", 4096, 7)),
    "array_missing": lambda p: _drop_member(p, "state_v.npy"),
    "checksum_missing": lambda p: _drop_member(p, "checksum.npy"),
}


@pytest.mark.parametrize("which", ["finished", "interrupted"])
@pytest.mark.parametrize("damage", sorted(DAMAGES))
def test_a_damaged_newest_resumes_from_the_previous_one(
    runs: SimpleNamespace, tmp_path: Path, which: str, damage: str
) -> None:
    """A finished run whose summary.json is gone (it looks interrupted: its newest is
    the final checkpoint) and an interrupted one both continue from step 40."""
    folder = _copy(getattr(runs, which), tmp_path / "run", looks_interrupted=True)
    DAMAGES[damage](folder / CHECKPOINT_NAME)
    proc = _resume(folder)
    assert proc.returncode == 0 and "Traceback" not in proc.stderr, proc.stderr
    line = next(s for s in proc.stderr.splitlines() if s.startswith("warning:"))
    assert line.startswith(f"warning: checkpoint {folder / CHECKPOINT_NAME} is damaged (")
    assert line.endswith(_fallback_line(folder).strip())
    _same_fields(runs.ref, folder)
    assert load_checkpoint(folder / CHECKPOINT_NAME).state.step == 60  # written anew
    assert load_checkpoint(folder / PREVIOUS_NAME).state.step == 40


@pytest.mark.parametrize("which", ["finished", "interrupted"])
def test_no_usable_checkpoint_is_exit_2_naming_each_file(
    runs: SimpleNamespace, tmp_path: Path, which: str
) -> None:
    folder = _copy(getattr(runs, which), tmp_path / "run")
    DAMAGES["truncated_half"](folder / CHECKPOINT_NAME)
    DAMAGES["random_garbage"](folder / PREVIOUS_NAME)
    proc = _resume(folder)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr, proc.stderr
    assert f"checkpoint {folder / CHECKPOINT_NAME} is damaged (" in proc.stderr
    assert f"checkpoint {folder / PREVIOUS_NAME} is damaged (" in proc.stderr
    assert "no usable checkpoint in" in proc.stderr
    assert "start a new run with --out" in proc.stderr


def test_a_finished_run_with_a_damaged_final_checkpoint_is_still_refused(
    runs: SimpleNamespace, tmp_path: Path
) -> None:
    folder = _copy(runs.finished, tmp_path / "run")
    before = (folder / "final_state.npz").read_bytes()
    DAMAGES["truncated_half"](folder / CHECKPOINT_NAME)
    proc = _resume(folder)
    assert proc.returncode == 2 and "already finished" in proc.stderr, proc.stderr
    assert (folder / "final_state.npz").read_bytes() == before  # nothing overwritten


def test_a_missing_newest_resumes_from_the_previous_one(
    runs: SimpleNamespace, tmp_path: Path
) -> None:
    folder = _copy(runs.interrupted, tmp_path / "run")
    (folder / CHECKPOINT_NAME).unlink()  # a crash between the two renames
    proc = _resume(folder)
    assert proc.returncode == 0, proc.stderr
    assert f"checkpoint {folder / CHECKPOINT_NAME} is missing" in proc.stderr
    _same_fields(runs.ref, folder)
    (folder / CHECKPOINT_NAME).unlink()
    (folder / PREVIOUS_NAME).unlink()
    proc = _resume(folder)
    assert proc.returncode == 2 and "no checkpoint in" in proc.stderr


# ------------------------------------------------------------------ MPI
MPIEXEC, WHY = mpiexec()

PLATE_DECK = """
name: plate_checkpoints
geometry: {type: rectangle, size: [0.02, 0.01], thickness: 1.0e-3, plane: stress}
discretisation: {spacing: 1.0e-3, horizon_factor: 3.015}
material: {model: pmb, youngs_modulus: 70.0e9, density: 2700.0}
damage: {model: critical_stretch, critical_stretch: 2.0e-3}
node_sets:
  left: {edge: {normal: [-1.0, 0.0]}}
  right: {edge: {normal: [1.0, 0.0]}}
boundary_conditions:
  - {type: velocity, set: right, components: {x: 5.0}}
  - {type: velocity, set: left, components: {x: -5.0}}
solver: {type: explicit, steps: 60, safety_factor: 0.8}
output: {history_every: 20, plot: none}
"""


@pytest.mark.mpi
@pytest.mark.skipif(MPIEXEC is None, reason=WHY)
def test_ranks_fall_back_together_to_the_previous_step(tmp_path: Path) -> None:
    deck = tmp_path / "plate.yaml"
    deck.write_text(PLATE_DECK)
    env = {"NUMBA_NUM_THREADS": "1"}
    whole, out = tmp_path / "whole", tmp_path / "cut"
    cli("run", deck, "--out", whole, "--quiet", env=env, ranks=2, check=True)
    cli("run", deck, "--out", out, "--quiet", "--checkpoint-every", "20",
        env=env, ranks=2, check=True)  # fmt: skip
    marker = json.loads((out / "checkpoint_mpi.json").read_text())
    assert (marker["step"], marker["previous"]["step"], marker["finished"]) == (60, 40, True)
    kept = sorted(p.name for p in (out / "ranks" / "rank0001").glob("checkpoint_*.npz"))
    assert kept == ["checkpoint_000000040.npz", "checkpoint_000000060.npz"]
    (out / "summary.json").unlink()  # it looks interrupted
    damaged = out / "ranks" / "rank0001" / "checkpoint_000000060.npz"
    damaged.write_bytes(damaged.read_bytes()[:500])  # one rank's newest file only
    proc = cli("run", deck, "--resume", out, "--quiet", env=env, ranks=2)
    assert proc.returncode == 0 and "Traceback" not in proc.stderr, proc.stderr
    assert proc.stderr.count("warning:") == 1  # rank 0 speaks for both
    assert f"warning: checkpoint {damaged} is damaged (" in proc.stderr
    assert "checkpoint_000000040.npz" in proc.stderr
    _same_fields(whole, out)
    # both steps damaged on some rank: exit 2 naming the files, on every rank alike
    (out / "summary.json").unlink()
    damaged.write_bytes(b"")
    (out / "ranks" / "rank0000" / "checkpoint_000000040.npz").write_bytes(b"x" * 64)
    proc = cli("run", deck, "--resume", out, "--quiet", env=env, ranks=2)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr, proc.stderr
    assert str(damaged) in proc.stderr and "rank0000/checkpoint_000000040.npz" in proc.stderr
    assert "no usable checkpoint" in proc.stderr
