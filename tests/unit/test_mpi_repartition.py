"""Resuming a decomposed run on another number of ranks (:mod:`peridynamics.io.repartition`):
a run killed after bonds broke, resumed on more or fewer ranks, ends with the serial
run's fields bit for bit; what cannot be repartitioned is refused with the count to use.

The runs are in the ``mpi`` tier (``pytest -m mpi``); the field classification is
checked without MPI."""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from peridynamics.families.base import FieldSpec
from peridynamics.io.final_state import read_final_state
from peridynamics.io.observers.bonds import read_bonds
from peridynamics.io.repartition import field_kinds, needed_ranks, same_partition
from peridynamics.state import State
from tests.helpers import cli, mpiexec

MPIEXEC, WHY = mpiexec()

PLATE_DECK = """
name: plate_repartition
geometry: {type: rectangle, size: [0.02, 0.01], thickness: 1.0e-3, plane: stress}
discretisation: {spacing: 1.0e-3, horizon_factor: 3.015}
material: {model: MODEL, youngs_modulus: 70.0e9, density: 2700.0}
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
#: rank 1 dies after step 50: the marker names step 40 (bonds break from step 10 on)
CRASH = {"PERIDYNAMICS_CRASH_AT_STEP": "50", "PERIDYNAMICS_CRASH_RANK": "1"}
ENV = {"NUMBA_NUM_THREADS": "1"}


@pytest.fixture(scope="module")
def serial(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """The decks (PMB; LPS: two ghost layers with families) and their serial runs."""
    root = tmp_path_factory.mktemp("repartition")
    out = {}
    for model in ("pmb", "lps"):
        deck = root / f"{model}.yaml"
        deck.write_text(PLATE_DECK.replace("MODEL", model))
        cli("run", deck, "--out", root / model, "--quiet", env=ENV, check=True)
        out[model], out[f"{model}_deck"] = root / model, deck
    return out


def _kill_then_resume(
    deck: Path, out: Path, before: int, after: int, damage: bool = False
) -> tuple[object, float]:
    """A run on ``before`` ranks killed after step 50 (checkpoints every 20 steps), then
    resumed on ``after`` ranks (``damage``: rank 1's file of step 40 cut short first);
    the resumed process and the bonds broken at the checkpoint."""
    args = ("run", deck, "--quiet")
    died = cli(*args, "--out", out, "--checkpoint-every", "20", env={**ENV, **CRASH},
               ranks=before)  # fmt: skip
    assert died.returncode != 0
    marker = json.loads((out / "checkpoint_mpi.json").read_text())
    assert (marker["step"], marker["ranks"], len(marker["owned_boxes"])) == (40, before, before)
    files = sorted(out.glob("ranks/rank*/checkpoint_000000040.npz"))
    assert len(files) == before
    broken = sum(int(np.load(f)["state_bonds_broken"]) for f in files)
    if damage:
        files[1].write_bytes(files[1].read_bytes()[:500])
    if before > after:  # as an interrupted run's outputs would leave it
        (files[-1].parent / "bonds.npz").write_bytes(b"stale")
    return cli(*args, "--resume", out, env=ENV, ranks=after), broken


def _same_fields(a: Path, b: Path) -> None:
    """``final_state.npz`` and the bonds broken of two runs: the same bits."""
    fa, fb = read_final_state(a), read_final_state(b)
    for key in ("u", "v", "damage", "intact"):  # intact: in the serial bond order
        np.testing.assert_array_equal(fb[key], fa[key], err_msg=key)
    ra = json.loads((a / "summary.json").read_text())["results"]
    rb = json.loads((b / "summary.json").read_text())["results"]
    assert ra["bonds_broken"] == rb["bonds_broken"] > 0


@pytest.mark.mpi
@pytest.mark.skipif(MPIEXEC is None, reason=WHY)
@pytest.mark.parametrize(
    ("model", "before", "after", "damage"),
    [("pmb", 2, 3, False), ("pmb", 3, 2, True), ("pmb", 4, 2, False), ("lps", 2, 3, False)],
)
def test_resume_on_another_rank_count_gives_the_same_bits(
    serial: dict[str, Path], tmp_path: Path, model: str, before: int, after: int, damage: bool
) -> None:
    out = tmp_path / "cut"
    proc, broken = _kill_then_resume(serial[f"{model}_deck"], out, before, after, damage)
    assert proc.returncode == 0 and "Traceback" not in proc.stderr, proc.stderr
    assert broken > 0  # bonds broke before the checkpoint the resume starts from
    if damage:  # every new rank falls back to step 20, rank 0 says so once
        assert proc.stderr.count("is damaged") == 1
        assert "rank0001/checkpoint_000000040.npz is damaged" in proc.stderr
        assert "resuming from the previous one (step 20" in proc.stderr
    _same_fields(serial[model], out)
    marker = json.loads((out / "checkpoint_mpi.json").read_text())
    assert marker["ranks"] == after and marker["finished"]
    left = {p.parent.name for p in out.glob("ranks/rank*/*.npz")}
    assert left == {f"rank{r:04d}" for r in range(after)}  # no stale files of the old run
    a, b = read_bonds(serial[model]), read_bonds(out)
    for key in ("i", "j", "intact"):
        np.testing.assert_array_equal(b[key], a[key], err_msg=key)


@pytest.mark.mpi
@pytest.mark.skipif(MPIEXEC is None, reason=WHY)
def test_a_checkpoint_without_its_partition_is_refused(
    serial: dict[str, Path], tmp_path: Path
) -> None:
    """A marker of a version that stored no partition: refused on every rank alike."""
    out = tmp_path / "cut"
    deck = serial["pmb_deck"]
    died = cli("run", deck, "--quiet", "--out", out, "--checkpoint-every", "20",
               env={**ENV, **CRASH}, ranks=2)  # fmt: skip
    assert died.returncode != 0
    marker = json.loads((out / "checkpoint_mpi.json").read_text())
    del marker["owned_boxes"]
    (out / "checkpoint_mpi.json").write_text(json.dumps(marker))
    proc = cli("run", deck, "--quiet", "--resume", out, env=ENV, ranks=3)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr, proc.stderr
    assert "written by 2 MPI ranks without their partition" in proc.stderr
    assert "resume with mpiexec -n 2" in proc.stderr
    assert proc.stderr.count("without their partition") == 1  # rank 0 speaks once


def test_fields_of_other_kinds_are_refused() -> None:
    """Interface bonds (``where="interface"``) and unknown fields cannot be
    repartitioned; per-point, per-bond and summed fields can."""
    n, nb = 5, 12
    specs = (FieldSpec("dilatation"), FieldSpec("bond_kappa", where="bond", history=True),
             FieldSpec("interface_intact", "interface", 0, "uint8", True, rows=3))  # fmt: skip
    force_model = SimpleNamespace(dofs=lambda: (None,), state_fields=lambda: specs)
    s = State(u=np.zeros((n, 2)), v=np.zeros((n, 2)), intact=np.ones(nb, np.uint8),
              dilatation=np.zeros(n), bond_kappa=np.zeros(nb), friction_work=np.zeros(1),
              interface_intact=np.ones(3, np.uint8), rigid_x=np.zeros(2))  # fmt: skip
    kinds, refused = field_kinds(SimpleNamespace(force_model=force_model), s)
    assert kinds == {"u": "point", "v": "point", "intact": "bond", "dilatation": "point",
                     "bond_kappa": "bond", "friction_work": "sum"}  # fmt: skip
    assert refused == ["interface_intact (interface)", "rigid_x (unknown)"]


def test_a_rank_reads_the_old_ranks_whose_box_holds_its_points() -> None:
    boxes = [[[0.0, 0.0], [1.0, 1.0]], [[2.0, 0.0], [3.0, 1.0]], [[4.0, 0.0], [5.0, 1.0]]]
    x = np.array([[0.5, 0.5], [2.0, 1.0]])  # on the edge of box 1 counts
    assert needed_ranks(x, boxes, root=False) == [0, 1]
    assert needed_ranks(x + 4.0 * np.array([1.0, 0.0]), boxes, root=True) == [0, 2]


def test_a_changed_partition_is_told_apart() -> None:
    """Same rank count, other rows or bonds (another version's bisection): repartitioned."""
    a = {"global_ids": np.arange(4), "n_owned": np.array(2), "offsets": np.array([0, 1, 2]),
         "bond_j": np.array([1, 0], np.int32)}  # fmt: skip
    assert same_partition(a, {k: v.copy() for k, v in a.items()})
    assert not same_partition(a, {**a, "global_ids": np.array([0, 1, 3, 2])})
    assert not same_partition(a, {**a, "bond_j": np.array([1, 2], np.int32)})
    assert not same_partition(a, {k: v for k, v in a.items() if k != "offsets"})


def test_one_process_resume_of_a_decomposed_run_names_mpiexec(tmp_path: Path) -> None:
    deck = tmp_path / "plate.yaml"
    deck.write_text(PLATE_DECK.replace("MODEL", "pmb"))
    out = tmp_path / "cut"
    out.mkdir()
    (out / "checkpoint_mpi.json").write_text(json.dumps({"step": 40, "ranks": 2}))
    proc = cli("run", deck, "--quiet", "--resume", out)
    assert proc.returncode == 2
    assert "written by a decomposed run" in proc.stderr and "mpiexec -n 2" in proc.stderr
