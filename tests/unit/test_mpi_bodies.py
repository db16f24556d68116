"""Several bodies with a bonded interface, decomposed (``mpiexec -n N peridynamics run``):
each rank owns points of one body (:mod:`peridynamics.parallel.bodies`), and the fields,
the broken bonds and the bond files are the serial run's bit for bit (``mpi`` tier). The
sharing of ranks among bodies is checked in the default selection without MPI."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from peridynamics.io.final_state import read_final_state
from peridynamics.io.observers.bonds import read_bonds
from peridynamics.parallel.bodies import body_partition, ranks_per_body
from tests.helpers import EXAMPLES, cli, mpiexec

MPIEXEC, WHY = mpiexec()

INCLUSIONS = [
    str(EXAMPLES / "bodies" / "inclusions.yaml"),
    "--set", "discretisation.spacing=1e-3",
    "--set", "solver.end_time=1e-3",
    "--set", "output.plot=none",
]  # fmt: skip
LPS_MAIN = ["--set", "material.model=lps", "--set", "material.poisson_ratio=0.25"]


def _run(*args: str, ranks: int = 1):
    env = {"NUMBA_NUM_THREADS": "1"}
    return cli("run", *args, "--quiet", env=env, timeout=240, ranks=ranks)


@pytest.mark.mpi
@pytest.mark.skipif(MPIEXEC is None, reason=WHY)
@pytest.mark.parametrize(("ranks", "extra"), [(2, []), (3, LPS_MAIN)], ids=["pmb-2", "lps-3"])
def test_mortar_and_aggregates_decomposed_give_the_serial_run(
    tmp_path: Path, ranks: int, extra: list[str]
) -> None:
    """The mortar plate with six aggregates and weak interface bonds (PMB everywhere, or
    an LPS mortar with PMB aggregates) pulled until the interfaces and the mortar crack:
    u, v, damage, bond flags and the joined bond files equal the serial run's."""
    args = [*INCLUSIONS, *extra]
    assert _run(*args, "--out", str(tmp_path / "s")).returncode == 0
    got = _run(*args, "--out", str(tmp_path / "m"), ranks=ranks)
    assert got.returncode == 0, got.stderr
    fs, fm = read_final_state(tmp_path / "s"), read_final_state(tmp_path / "m")
    for k in ("u", "v", "damage", "x", "intact"):
        np.testing.assert_array_equal(fm[k], fs[k], err_msg=k)
    bs, bm = read_bonds(tmp_path / "s"), read_bonds(tmp_path / "m")
    for k in ("i", "j", "intact", "initially_intact"):
        np.testing.assert_array_equal(bm[k], bs[k], err_msg=k)
    rs = json.loads((tmp_path / "s" / "summary.json").read_text())["results"]
    rm = json.loads((tmp_path / "m" / "summary.json").read_text())["results"]
    assert rs["bonds_broken"] > 1000  # interfaces and mortar cracked
    assert rm["bonds_broken"] == rs["bonds_broken"]
    assert rm["strain_energy_J"] == pytest.approx(rs["strain_energy_J"], rel=1e-12)


def test_ranks_are_shared_by_work_with_one_rank_at_least() -> None:
    assert ranks_per_body(np.array([77.0, 23.0]), 2).tolist() == [1, 1]
    assert ranks_per_body(np.array([77.0, 23.0]), 4).tolist() == [3, 1]
    assert ranks_per_body(np.array([98.0, 1.0, 1.0]), 3).tolist() == [1, 1, 1]
    assert ranks_per_body(np.array([50.0, 30.0, 20.0]), 10).tolist() == [5, 3, 2]
    assert ranks_per_body(np.array([1.0, 1.0, 1.0]), 7).sum() == 7
    with pytest.raises(ValueError, match="at least 3 ranks"):
        ranks_per_body(np.array([1.0, 1.0, 1.0]), 2)


def test_each_rank_owns_points_of_one_body() -> None:
    rng = np.random.default_rng(0)
    x = rng.random((400, 2))
    body = (x[:, 0] > 0.7).astype(np.int64)  # bodies need not be contiguous in space
    part = body_partition(x, np.ones(400), body, 5)
    assert sorted(set(part.tolist())) == [0, 1, 2, 3, 4]
    for r in range(5):
        assert len(set(body[part == r].tolist())) == 1


STATIC_BODIES = """
name: static_bodies
geometry: {type: rectangle, size: [0.02, 0.01], thickness: 1.0e-3, plane: stress}
discretisation: {spacing: 5.0e-4, horizon_factor: 3.015}
material: {youngs_modulus: 25.0e9, density: 2100.0}
bodies:
  - name: inclusion
    region: {ball: {center: [0.01, 0.005], radius: 0.003}}
    material: {model: lps, youngs_modulus: 60.0e9, poisson_ratio: 0.2, density: 2700.0}
interfaces:
  - {bodies: [main, inclusion], type: bonded, stiffness_factor: 0.5}
node_sets:
  left: {edge: {normal: [-1.0, 0.0], layers: 2}}
  right: {edge: {normal: [1.0, 0.0], layers: 2}}
boundary_conditions:
  - {type: fixed, set: left, components: [x, y]}
  - {type: displacement, set: right, components: {x: 2.0e-5}}
solver: {type: static, load_steps: 2}
output: {plot: none}
"""


@pytest.mark.mpi
@pytest.mark.skipif(MPIEXEC is None, reason=WHY)
def test_static_solve_of_bodies_on_two_ranks_gives_the_serial_displacements(
    tmp_path: Path,
) -> None:
    """A PMB plate with a stiffer LPS inclusion and a softer bonded interface, solved by
    the static solver (distributed CG on 2 ranks, a direct solve in one process): the
    displacements agree to 1e-10 of their largest value."""
    deck = tmp_path / "deck.yaml"
    deck.write_text(STATIC_BODIES)
    assert _run(str(deck), "--out", str(tmp_path / "s")).returncode == 0
    got = _run(str(deck), "--out", str(tmp_path / "m"), ranks=2)
    assert got.returncode == 0, got.stderr
    us, um = read_final_state(tmp_path / "s")["u"], read_final_state(tmp_path / "m")["u"]
    scale = float(np.abs(us).max())
    assert scale > 1e-6
    assert float(np.abs(um - us).max()) <= 1e-10 * scale
