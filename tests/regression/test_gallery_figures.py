"""The figure scripts of the gallery's bar wave, plate in tension and static fracture
(``examples/<folder>/make_figures.py``) at a small size: each writes its JSON and PNG, and
the numbers it derives agree with its reference.

``tests/regression/test_examples.py`` runs the decks themselves through the CLI; these
tests re-analyse the same runs (``--no-run`` on a copy of the session's shared run,
``example_run`` of ``tests/conftest.py``) and check what the scripts add: the analytic
and FEM references they compute (from the deck with its overrides), the quantities
derived from the probes and the figure.
Tolerances are set from the values measured at the same size (in the comments) with
margin.
"""

from __future__ import annotations

import json
import shutil
from collections.abc import Callable
from pathlib import Path
from types import ModuleType

import pytest

from tests.helpers import BAR_WAVE, EXAMPLES, PLATE, load_script


def _script(folder: str) -> ModuleType:
    return load_script(EXAMPLES / folder / "make_figures.py", f"gallery_{folder}")


def _run(tmp_path: Path, folder: str, case: str, *args: str) -> dict:
    assert _script(folder).main(["--out", str(tmp_path), *args]) == 0
    assert (tmp_path / f"{case}.png").stat().st_size > 1000
    return json.loads((tmp_path / f"{case}.json").read_text())


def _sets(overrides: tuple[str, ...]) -> list[str]:
    return [a for o in overrides for a in ("--set", o)]


@pytest.mark.long
def test_bar_wave_1d_figure(tmp_path: Path, example_run: Callable[..., Path]) -> None:
    # dx = 10 mm (101 points) with dt = 2 us: the shipped Courant number c dt / dx = 0.55
    out = shutil.copytree(example_run("bar_wave_1d", "deck.yaml", *BAR_WAVE), tmp_path / "run")
    res = _run(out, "bar_wave_1d", "bar_wave_1d", "--no-run", *_sets(BAR_WAVE))
    # the reference from the deck: c = sqrt(20 GPa / 2620) = 2762.9 m/s, v = 8.9 MPa / (rho c)
    assert res["wave_speed_m_per_s"] == pytest.approx(2762.8948, rel=1e-6)
    assert res["peak_velocity_reference_m_per_s"] == pytest.approx(1.229488, rel=1e-6)
    assert res["gauge_x_m"] == pytest.approx(0.5)
    # measured at this size: arrival (10 %) 3.0 us late (sampled every 2 us), half peak
    # 4.2 us late, peak 0.988 of p_m / (rho c) 7.0 us late, displacement at 300 us 1.008 of
    # the integral of the analytic velocity, L2 error of the velocity history 0.126
    assert 0.0 <= res["arrival_10pct_delay_s"] <= 6e-6
    assert 0.0 <= res["half_peak_delay_s"] <= 8e-6
    assert 0.97 < res["peak_velocity_ratio"] < 1.01
    assert 0.0 <= res["peak_time_delay_s"] <= 12e-6
    assert res["final_displacement_ratio"] == pytest.approx(1.0, abs=0.02)
    assert res["velocity_l2_error_relative"] < 0.2


@pytest.mark.long
def test_plate_tension_2d_figure(tmp_path: Path, example_run: Callable[..., Path]) -> None:
    for name, deck in (("explicit", "deck.yaml"), ("adr", "adr.yaml")):
        shutil.copytree(example_run("plate_tension_2d", deck, *PLATE), tmp_path / name)
    res = _run(tmp_path, "plate_tension_2d", "plate_tension_2d", "--no-run", *_sets(PLATE))
    assert (tmp_path / "explicit" / "summary.json").exists()
    assert (tmp_path / "adr" / "summary.json").exists()
    # the gauges between the probed rows: L - dx and H - dx
    assert res["gauge_length_m"] == pytest.approx(0.049)
    assert res["gauge_height_m"] == pytest.approx(0.019)
    assert res["static_elongation_m"] == pytest.approx(10e6 * 0.049 / 70e9)
    # measured at dx = 1 mm (1000 points): explicit mean after the ramp 0.977 (elongation)
    # and 0.972 (lateral) of the static solution, oscillating by 1.2 % and 1.4 %; ADR
    # 0.979 and 0.974 in 446 iterations; explicit / ADR 0.998 (at dx = 0.5 mm: 0.990 and
    # 0.991, the deficit of the loaded edge rows halves with dx)
    assert res["explicit_records_after_ramp"] >= 5
    assert 0.95 < res["explicit_elongation_ratio"] < 1.0
    assert 0.95 < res["explicit_lateral_ratio"] < 1.0
    assert res["explicit_elongation_half_range_relative"] < 0.03
    assert res["adr_converged"] is True
    assert 0.96 < res["adr_elongation_ratio"] < 0.995
    assert 0.96 < res["adr_lateral_ratio"] < 0.995
    # the explicit run oscillates about the model's own static state
    assert res["explicit_over_adr_elongation"] == pytest.approx(1.0, abs=0.01)
    assert res["explicit_over_adr_lateral"] == pytest.approx(1.0, abs=0.01)


@pytest.mark.long
def test_static_fracture_figure(tmp_path: Path, example_run: Callable[..., Path]) -> None:
    pytest.importorskip("skfem")
    # the deck as shipped (450 points), the FEM reference on 1 mm elements (P2)
    run = example_run("static_fracture", "notched_plate_adr.yaml")
    out = shutil.copytree(run, tmp_path / "run")
    res = _run(out, "static_fracture", "notched_plate_adr", "--no-run", "--fem-h", "1e-3")
    # measured: PD 31.24 N/um, FEM 31.95 N/um (clamp faces at 1.5 mm; 31.65 on 0.5 mm
    # elements), band 30.6-32.8 for the faces at 1.0-2.0 mm; steps 1-5 proportional to
    # 2e-4; G0 = 151.2 J/m^2; LEFM growth load 343.5 N (341.2 on 0.5 mm elements); the
    # first bond breaks at 350.3 N (1.020 of LEFM); peak reaction 312.5 N at step 6,
    # 0.834 of the elastic line; below 1 % of the peak from step 8 on
    assert res["elastic_steps"] == 5 and res["first_damage_step"] == 6
    assert res["elastic_steps_stiffness_spread_relative"] < 1e-3
    assert 0.95 < res["pd_over_fem_stiffness"] < 1.02
    lo, hi = res["fem_stiffness_band_N_per_m"]
    assert lo < res["fem_stiffness_N_per_m"] < hi
    assert res["G0_from_critical_stretch_J_per_m2"] == pytest.approx(151.15, rel=1e-3)
    assert res["lefm_growth_load_N"] == pytest.approx(341.0, rel=0.02)
    # the PD initiation load lies between the last elastic reaction and the elastic line
    # at the first damaged step, and near LEFM
    assert res["pd_initiation_from_frame_step"] == 5
    assert res["last_elastic_reaction_N"] < res["pd_initiation_load_N"]
    assert res["pd_initiation_load_N"] < res["elastic_line_at_peak_step_N"]
    assert 0.95 < res["pd_initiation_over_lefm"] < 1.08
    assert res["peak_step"] == 6 and 0.75 < res["peak_over_elastic_line"] < 0.9
    assert res["first_step_below_1pct_of_peak"] == 8


def test_publish_refuses_overrides(tmp_path: Path) -> None:
    """The committed files come from the shipped decks: --publish with --set is an error."""
    for folder in ("bar_wave_1d", "plate_tension_2d", "static_fracture"):
        with pytest.raises(SystemExit) as err:
            _script(folder).main(
                ["--out", str(tmp_path), "--publish", "--set", "discretisation.spacing=1e-3"]
            )
        assert err.value.code == 2
