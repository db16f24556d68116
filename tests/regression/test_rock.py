"""SED-PD (2021) rock compression: deck contract, ensemble command, flaw analysis, contact in
a model, and (slow) the Weibull-shape trend at paper scale."""

from __future__ import annotations

import importlib.util
import json

import numpy as np
import pytest

from peridynamics import BondBasedMaterial, Evaluator, build_bonds
from peridynamics.evaluation.short_range_contact import ShortRangeContact
from peridynamics.geometry import rectangle
from peridynamics.geometry.regions import Box
from peridynamics.solvers.explicit import ExplicitSolver
from tests.helpers import EXAMPLES, cli

RC = EXAMPLES / "rock_compression"
# half the resolution of the paper (dx = 1 mm, 5 000 points), same duration
COARSE = [
    "--set", "discretisation.spacing=0.001",
    "--set", "solver.time_step=5.74e-7",
    "--set", "solver.steps=700",
]  # fmt: skip


def _load(name: str):
    spec = importlib.util.spec_from_file_location(name, RC / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.long
def test_contract_through_the_cli(tmp_path) -> None:
    cli("run", str(RC / "flaw30_m10.yaml"), "--out", str(tmp_path), *COARSE, check=True)
    summary = json.loads((tmp_path / "summary.json").read_text())
    r = summary["results"]
    # Measured values of this deck (Weibull seed 1) at the COARSE size. Spread over
    # default threads (2), NUMBA_NUM_THREADS=1 and NUMBA_CPU_NAME=generic (another
    # vectorisation of the fast-math sums, as on another platform): given per line;
    # the spread was 0 (discrete) or <= 1e-13 (continuous). Tolerances: rel 1e-6 for
    # elastic quantities; for quantities that follow bond breaking, a margin for a bond
    # decision that flips on other hardware (+-25 damaged points, 0.2 % of a peak, one
    # record of 20 steps, 5 degrees) - still 10-1000x tighter than the old ranges.
    # 507 of 5000 points damaged (phi >= 0.3), identical in all three runs
    assert r["damaged_area_fraction"] == pytest.approx(0.1014, abs=0.005)  # +-25 points
    assert summary["timing"]["wall_s"] > 0
    # peak compressive stress 9.0709 MPa; spread rel 7.6e-15 (seeds 2 and 3 give 8.884
    # and 8.698 MPa: this pins the seed-1 specimen, not a seed-free property)
    assert r["peak_stress_Pa"] == pytest.approx(9070877.866882922, rel=2e-3)
    strain, stress = np.array(r["stress_strain"]["strain"]), r["stress_strain"]["stress_Pa"]
    # final platen strain, closed form v (t_end - t_ramp / 2) / L for the linear ramp to
    # v = 1.25 m/s over t_ramp = 100 us: measured 4.3975010e-3, rel 2.2e-7 above it
    # (spread over threads / CPU rel 5.9e-16)
    assert np.all(np.diff(strain) >= -1e-12) and strain[-1] == pytest.approx(
        1.25 * (700 * 5.74e-7 - 0.5e-4) / 0.1, rel=1e-6
    )
    # secant modulus stress / strain at the first record above 30 % of the peak (record
    # 8, still elastic): measured 5.3030 GPa = 1.1259 E, bitwise the same for Weibull
    # seeds 1, 2 and 3; spread over threads / CPU rel 1.0e-13
    k = int(np.argmax(np.asarray(stress) > 0.3 * r["peak_stress_Pa"]))
    assert k == 8
    assert stress[k] / strain[k] == pytest.approx(5303023577.922685, rel=1e-6)
    # 0.49634, bitwise the same for seeds 1, 2, 3; spread over threads / CPU rel 1.2e-14
    assert r["max_kinetic_to_strain_energy"] == pytest.approx(0.4963443899140499, rel=1e-2)
    assert (tmp_path / "flaw30_m10_damage.png").exists()


@pytest.mark.long
def test_ensemble_command(tmp_path) -> None:
    cli("ensemble", str(RC / "flaw30_m2.yaml"), "--n", "2", "--seed0", "3", "--out",
        str(tmp_path), "--quiet", *COARSE, "--set", "output.plot=none", check=True)  # fmt: skip
    rep = json.loads((tmp_path / "ensemble.json").read_text())
    assert rep["n"] == 2 and rep["seeds"] == [3, 4]
    peaks = [run["peak_stress_Pa"] for run in rep["runs"]]
    # each member is the run of its seed: 7.5268 and 7.8275 MPa, damaged area fractions
    # 0.1130 and 0.1178 (measured with Simulation and the same overrides; spread over
    # default threads, NUMBA_NUM_THREADS=1 and NUMBA_CPU_NAME=generic rel 1.1e-14 and
    # 1.4e-14 for the peaks, none for the areas)
    assert peaks == pytest.approx([7526811.823789242, 7827456.449681662], rel=2e-3)
    areas = [run["damaged_area_fraction"] for run in rep["runs"]]
    assert areas == pytest.approx([0.113, 0.1178], abs=0.005)
    assert rep["peak_stress_Pa"]["mean"] == pytest.approx(np.mean(peaks), rel=1e-12)
    assert rep["peak_stress_Pa"]["min"] == min(peaks) and rep["peak_stress_Pa"]["max"] == max(peaks)
    assert rep["peak_stress_Pa"]["std"] == pytest.approx(np.std(peaks, ddof=1), rel=1e-12)
    assert (tmp_path / "seed_3" / "summary.json").exists()
    bad = cli("ensemble", str(EXAMPLES / "waves" / "pulse_sine_plain.yaml"), "--n", "1")
    assert bad.returncode == 2 and "weibull" in bad.stderr


@pytest.mark.long
def test_flaw_analysis_script_small(tmp_path) -> None:
    mod = _load("analyse")
    sets = [COARSE[i + 1] for i in range(0, len(COARSE), 2)]
    args = ["--decks", "double_flaw45", "--out", str(tmp_path), "--every", "20"]
    for s in sets:
        args += ["--set", s]
    assert mod.main(args) == 0
    res = json.loads((tmp_path / "flaw_results.json").read_text())["double_flaw45"]
    assert len(res["tips"]) == 4
    # Measured (every 20 steps); identical with default threads, NUMBA_NUM_THREADS=1 and
    # NUMBA_CPU_NAME=generic (all discrete: steps, point counts, grid positions; the
    # directions are means of grid positions, spread 0).
    # New damage first appears at step 380 as one point 1.02 mm (< 2 delta) from a tip:
    first = res["first_new_damage"]
    assert first is not None, res  # the run must damage something
    assert abs(first["step"] - 380) <= 20 and first["at_tips"]  # +-1 record
    assert first["max_distance_to_nearest_tip_m"] == pytest.approx(1.0232702477840463e-3, abs=5e-4)
    # initiation at every tip (flaw 0 lower, upper; flaw 1 lower, upper) and the first
    # mean crack direction (degrees from +x)
    assert [t["initiation_step"] for t in res["tips"]] == pytest.approx(
        [440, 480, 420, 400], abs=20
    )
    assert [t["direction_step"] for t in res["tips"]] == pytest.approx([520, 500, 460, 460], abs=20)
    assert [t["direction_deg"] for t in res["tips"]] == pytest.approx(
        [-106.98393569880774, 97.3881781721371, -145.89145843982968, 59.58742161683445], abs=5.0
    )
    # at half the paper's resolution and 700 steps no damaged cluster bridges the flaws
    assert res["first_coalescence_step"] is None and res["second_coalescence_step"] is None
    assert (tmp_path / "double_flaw45_stages.png").exists()


@pytest.mark.long
def test_contact_stops_two_blocks_interpenetrating_in_a_model() -> None:
    """Two plates 2 mm apart (no bonds across: gap > delta) fly at each other at 20 m/s:
    with contact they never come closer than half the contact distance, momentum is
    conserved and they bounce apart; without it they pass into each other."""
    dx = 5e-4
    cloud = rectangle((0.02, 0.01), dx, thickness=1e-3,
                      holes=[Box((0.009, -1.0), (0.011, 1.0), 1e-12)])  # fmt: skip
    bonds = build_bonds(cloud, 3.015 * dx)
    left = cloud.x[:, 0] < 0.01
    material = BondBasedMaterial(70e9, 2700.0)

    def run(with_contact: bool):
        c0 = material.micromodulus_constant(2, bonds.horizon, 1e-3, "stress")
        d_c = 0.9 * dx
        contact = (
            ShortRangeContact(cloud.x, cloud.volume, bonds, d_c,
                              ShortRangeContact.parks_stiffness(c0, d_c, bonds.horizon))
            if with_contact else None
        )  # fmt: skip
        model = Evaluator(cloud, bonds, material, contact=contact)
        solver = ExplicitSolver(model, safety_factor=0.5)
        s = solver.init()
        s.v[:, 0] = np.where(left, 20.0, -20.0)
        p0 = np.sum(model.density * cloud.volume * s.v[:, 0])
        gap = []
        for _ in range(int(1.0e-4 / solver.dt)):  # contact after ~51 us
            solver.step(s)
            y = cloud.x + s.u
            gap.append(y[~left, 0].min() - y[left, 0].max())
        p1 = np.sum(model.density[:, None] * cloud.volume[:, None] * s.v, axis=0)
        return np.array(gap), p0, p1, s

    # Measured (1746 steps); spread over default threads, NUMBA_NUM_THREADS=1 and
    # NUMBA_CPU_NAME=generic given per line, tolerances rel 1e-9 (the floor).
    gap, p0, p1, s = run(True)
    assert gap.min() > 0.5 * 0.9 * dx
    # closest approach 0.4441 mm = 0.987 d_c at step 932; spread rel 2.0e-14
    assert gap.min() == pytest.approx(4.44056695954086e-4, rel=1e-6)
    # momentum: measured errors <= 3.7e-16 of the total
    assert abs(p1[0] - p0) < 1e-9 * np.sum(2700 * cloud.volume * 20.0)
    assert abs(p1[1]) < 1e-9 * np.sum(2700 * cloud.volume * 20.0)
    # bounced: each plate leaves at 17.226 m/s (86 % of 20 m/s); spread rel 3.7e-15
    assert s.v[left, 0].mean() == pytest.approx(-17.226130658119462, rel=1e-6)
    assert s.v[~left, 0].mean() == pytest.approx(17.226130658119466, rel=1e-6)
    gap_free, *_ = run(False)
    # without contact they interpenetrate, by up to 1.4974 mm (the Lanczos step applies
    # without contact; 1.4997 mm with 0.2.0's per-point bound); spread rel 6.4e-14
    assert gap_free.min() == pytest.approx(-1.4974369064227819e-3, rel=1e-6)


@pytest.mark.slow
def test_weibull_shape_trend_at_paper_scale() -> None:
    """SED-PD (2021), section 3.2: at the same load step the damaged area falls as m grows.
    One realisation per m is not enough to see it (the seed-to-seed spread at m = 10 is
    0.3 % of the area, as large as the step from m = 20 to 100): compare the means of
    three Weibull fields each for m = 2, 10 and 100."""
    from peridynamics.app.run import Simulation
    from peridynamics.deck import load_deck

    means = []
    for m in (2, 10, 100):
        areas = []
        for seed in (1, 2, 3):
            deck = load_deck(RC / f"flaw30_m{m}.yaml", [f"damage.weibull.seed={seed}"])
            sim = Simulation.from_deck(deck)
            s = sim.solver.init()
            sim.solver.run(s, sim.n_steps)
            areas.append(float(np.mean(sim.model.point_damage(s.intact) >= 0.3)))
        means.append(np.mean(areas))
    assert means[0] > means[1] > means[2], means
