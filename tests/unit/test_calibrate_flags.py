"""The flag form of ``peridynamics calibrate`` (no calibration file): the flags build
the same calibration a file holds (parameters, one curve target, options), bounds
default to [0.5, 2] x the deck value, units in the CSV header become SI factors, and
bad flags exit 2 with a message naming the flag and the fix; end to end (long): E of a
static bar recovered from data made by the exact 1/E scaling of linear statics, and
the calibration file it wrote gives the same fit, every run read back."""

from __future__ import annotations

import argparse
import csv
import json
from pathlib import Path

import pytest

from peridynamics.app.calibrate_flags import spec_from_flags, unit_factor
from peridynamics.app.calibrate_spec import CalibrationError
from peridynamics.cli import main
from tests.helpers import TINY_STATIC_BAR

DECK = TINY_STATIC_BAR


@pytest.fixture
def files(tmp_path: Path) -> Path:
    (tmp_path / "deck.yaml").write_text(DECK)
    (tmp_path / "d.csv").write_text("load,tip [mm],sd\n0.5,0.006,0.001\n1.0,0.012,0.001\n")
    return tmp_path


def _args(tmp: Path, **kw) -> argparse.Namespace:
    base = {"data": str(tmp / "d.csv"), "fit": ["material.youngs_modulus"], "x": "time=load",
            "y": "tip", "sigma": None, "monotone": False, "set": [], "jobs": None,
            "method": None, "restarts": None, "max_runs": None}  # fmt: skip
    base.update(kw)
    return argparse.Namespace(**base)


def test_flags_build_the_calibration_a_file_holds(files):
    spec, data, notes = spec_from_flags(_args(files), files / "deck.yaml")
    (p,) = spec.parameters
    assert p.key == "material.youngs_modulus" and p.bounds == (10.0e9, 40.0e9)
    assert p.initial == 20.0e9 and p.scale == "linear"
    assert len(notes) == 1 and "[0.5, 2] x the deck value 2e+10" in notes[0]
    (t,) = spec.targets
    assert t.simulated is not None and t.measured is not None
    assert (t.simulated.x, t.simulated.y) == ("time", "tip")
    assert (t.measured.x, t.measured.y) == ("load", "tip")
    assert t.measured.x_factor == 1.0 and t.measured.y_factor == 1.0e-3  # [mm] -> m
    assert Path(t.measured.file).is_absolute()
    # explicit bounds, a log scale, comma-separated keys, a unit in the flag, options
    spec, _, notes = spec_from_flags(
        _args(files, fit=["material.youngs_modulus=1e9:1e11:log,material.density=2000:3000"],
              y="tip=tip [um]", sigma="sd", monotone=True, jobs=2, method="global"),
        files / "deck.yaml",
    )  # fmt: skip
    e, rho = spec.parameters
    assert e.scale == "log" and e.bounds == (1e9, 1e11) and e.initial == 20.0e9
    assert rho.bounds == (2000.0, 3000.0) and rho.initial == 2620.0 and notes == []
    t = spec.targets[0]
    assert t.measured.y_factor == 1.0e-6 and t.measured.sigma == "sd" and t.monotone
    assert spec.options.jobs == 2 and spec.options.method == "global"


def test_units_to_si():
    assert unit_factor("kN", "--y") == 1.0e3 and unit_factor("MPa", "--y") == 1.0e6
    assert unit_factor("mm", "--x") == 1.0e-3 and unit_factor("", "--x") == 1.0


@pytest.mark.parametrize(
    ("change", "needles"),
    [
        ({"fit": ["damage.G0"]}, ["--fit damage.G0", "unknown deck key", "fracture_energy"]),
        ({"fit": ["material.youngs_modulus=5e10:1e10"]}, ["--fit", "LOWER < UPPER"]),
        ({"fit": ["material.youngs_modulus=1e9"]}, ["--fit", "=LOWER:UPPER"]),
        ({"fit": ["material.youngs_modulus=-1:1:log"]}, ["--fit", "drop :log"]),
        ({"fit": ["material"]}, ["--fit material", "material.youngs_modulus"]),
        (
            {"fit": ["material.youngs_modulus"], "set": ["material.youngs_modulus=3e10"]},
            ["--fit material.youngs_modulus", "--set"],
        ),
        ({"x": "time=force"}, ["--x", "no column 'force'", "load"]),
        ({"y": "tip=tip [inch]"}, ["--y", "unknown unit [inch]", "mm"]),
        ({"sigma": "sdev"}, ["--sigma", "sdev"]),
        ({"y": None}, ["needs --y"]),
        ({"data": "missing.csv"}, ["--data missing.csv", "no such file"]),
    ],
)
def test_bad_flags_name_the_flag_and_the_fix(files, change, needles):
    with pytest.raises(CalibrationError) as info:
        spec_from_flags(_args(files, **change), files / "deck.yaml")
    text = str(info.value)
    assert all(n in text for n in needles), text


def test_cli_flag_form_bad_input_exits_2(files, capsys):
    deck, data = str(files / "deck.yaml"), str(files / "d.csv")
    out = str(files / "o")
    assert main(["calibrate", deck, "--data", data, "--fit", "damage.G0", "--x", "time=load",
                 "--y", "tip", "--out", out]) == 2  # fmt: skip
    assert "--fit damage.G0" in capsys.readouterr().err
    assert main(["calibrate", deck, str(files / "c.yml"), "--data", data, "--out", out]) == 2
    assert "not both" in capsys.readouterr().err
    assert main(["calibrate", deck, "--out", out]) == 2
    assert "--data CSV --fit KEY" in capsys.readouterr().err
    assert not (files / "o" / "runs").exists()


@pytest.mark.long  # about 14 runs of a tiny deck, 2 min on 2 shared cores
def test_flag_run_recovers_e_and_its_file_reruns_at_no_cost(files):
    """Linear statics: u is exactly proportional to 1/E, so a run at the deck's 20 GPa
    scaled by 20/30 is the data of E = 30 GPa."""
    deck = files / "deck.yaml"
    assert main(["run", str(deck), "-o", str(files / "fwd"), "--quiet"]) == 0
    rows = list(csv.reader((files / "fwd" / "history.csv").open()))
    head = [h.split("[")[0].strip() for h in rows[0]]
    it, iu = head.index("time"), head.index("tip")
    lines = [f"{r[it]},{float(r[iu]) * 1e3 * 20.0 / 30.0!r}" for r in rows[1:]]
    (files / "d.csv").write_text("load,tip [mm]\n" + "\n".join(lines) + "\n")
    cal = files / "cal"
    args = ["calibrate", str(deck), "--data", str(files / "d.csv"), "--fit",
            "material.youngs_modulus", "--x", "time=load", "--y", "tip", "--jobs", "2",
            "--out", str(cal), "--quiet"]  # fmt: skip
    assert main(args) == 0
    first = json.loads((cal / "report.json").read_text())
    e = first["parameters"]["material.youngs_modulus"]
    assert abs(e / 30.0e9 - 1.0) < 1e-4, e
    assert main(["calibrate", str(deck), str(cal / "calibration.yml"), "--out", str(cal),
                 "--quiet"]) == 0  # fmt: skip
    again = json.loads((cal / "report.json").read_text())
    assert again["runs"]["runs"] == 0 and again["parameters"] == first["parameters"]


def test_flags_give_the_real_example_s_calibration_file():
    """The flags of docs/calibration.md build the parameters and the target of
    examples/calibration/real_gregoire/calibration.yml (only the path differs)."""
    from peridynamics.app.calibrate_spec import load_spec
    from tests.helpers import EXAMPLES

    folder = EXAMPLES / "calibration" / "real_gregoire"
    args = _args(
        folder,
        data=str(folder / "gregoire2013_d50_load_cmod.csv"),
        fit=["material.youngs_modulus=10e9:80e9:log",
             "damage.tensile_strength=1e6:8e6:log,damage.fracture_energy=30:600:log"],
        x="mouth_right_ux - mouth_left_ux=cmod [mm]", y="-1 * reaction=load_mid [N]",
    )  # fmt: skip
    spec, _, _ = spec_from_flags(args, folder / "beam_d50.yaml")
    ref = load_spec(folder / "calibration.yml")
    key = lambda p: (p.key, p.bounds, p.scale, p.initial)  # noqa: E731
    assert list(map(key, spec.parameters)) == list(map(key, ref.parameters))
    got, want = spec.targets[0], ref.targets[0]
    assert got.simulated == want.simulated
    assert got.measured.model_dump(exclude={"file"}) == want.measured.model_dump(exclude={"file"})
    assert Path(got.measured.file) == folder / want.measured.file
