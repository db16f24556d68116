"""``peridynamics calibrate``: the calibration file's schema and messages, the targets
(CSV data, column expressions, the monotone cut, residuals), the optimisers and the
uncertainty against the closed form of linear regression, the budget, the run cache
(a run made once is read back), Sobol' indices (long: SALib), the example's synthetic
recovery of E and nu from data with 1 % noise, resumed at no cost (long), and the
three-parameter recovery of softening bonds (slow)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from peridynamics.app.calibrate_data import cut_monotone, expression_terms, load_targets
from peridynamics.app.calibrate_fit import Objective, optimise, uncertainty
from peridynamics.app.calibrate_runs import Runner, run_folder
from peridynamics.app.calibrate_spec import CalibrationError, Options, Parameter, parse_spec
from peridynamics.cli import main
from tests.helpers import TINY_STATIC_BAR

BASE = {
    "parameters": [{"key": "material.youngs_modulus", "bounds": [1.0e9, 1.0e11], "scale": "log"}],
    "targets": [{"name": "peak", "scalar": "max_displacement_m", "value": 1.0e-5}],
}


def _with(path: str, value):
    data = json.loads(json.dumps(BASE))
    node = data
    *head, last = path.split(".")
    for part in head:
        node = node[int(part)] if part.isdigit() else node[part]
    node[last] = value
    return data


@pytest.mark.parametrize(
    ("path", "value", "where", "fix"),
    [
        ("parameters.0.bounds", [2.0, 1.0], "parameters.0", "lower < upper"),
        ("parameters.0.bounds", [-1.0, 1.0], "parameters.0", "use linear"),
        ("parameters.0.initial", 1.0e12, "parameters.0", "outside bounds"),
        ("parameters.0.scael", "log", "parameters.0.scael", "Extra inputs"),
        ("targets.0.scalar", None, "targets.0", "give a curve"),
        ("options", {"method": "newton"}, "options.method", "least_squares"),
        ("set", ["material.youngs_modulus=1e9"], "", "both fitted"),
    ],
)
def test_bad_calibration_file_names_the_key(path, value, where, fix):
    with pytest.raises(CalibrationError) as info:
        parse_spec(_with(path, value))
    text = str(info.value)
    assert where in text and fix in text, text


def test_scales_round_trip_and_derivative():
    lin = Parameter(key="a", bounds=(2.0, 6.0))
    log = Parameter(key="b", bounds=(1.0e9, 1.0e11), scale="log")
    for p, v in ((lin, 3.5), (log, 7.0e9)):
        z = p.to_unit(v)
        assert 0 <= z <= 1 and p.from_unit(z) == pytest.approx(v, rel=1e-14)
        h = 1e-6
        fd = (p.from_unit(z + h) - p.from_unit(z - h)) / (2 * h)
        assert p.dvalue_dunit(v) == pytest.approx(fd, rel=1e-6)


def test_expressions_monotone_cut_and_data(tmp_path):
    assert expression_terms("mouth_right_ux - mouth_left_ux", "x") == [
        (1.0, "mouth_right_ux"), (-1.0, "mouth_left_ux"),
    ]  # fmt: skip
    assert expression_terms("-1e-3 * load [N]", "y") == [(-1e-3, "load [N]")]
    with pytest.raises(CalibrationError, match="joined by"):
        expression_terms("a * * b", "x")
    x, y = cut_monotone(np.array([0.0, 1.0, 2.0, 1.5, 3.0]), np.arange(5.0))
    assert x.tolist() == [0.0, 1.0, 2.0] and y.tolist() == [0.0, 1.0, 2.0]
    (tmp_path / "d.csv").write_text("# a comment\nCMOD [mm],F [kN]\n0.1,1\n0.2,2\n0.15,1.5\n")
    spec = parse_spec({
        "parameters": BASE["parameters"],
        "targets": [{"name": "c", "monotone": True,
                     "simulated": {"x": "cmod", "y": "load"},
                     "measured": {"file": "d.csv", "x": "CMOD", "y": "F [kN]",
                                  "x_factor": 1e-3, "y_factor": 1e3}}],
    })  # fmt: skip
    (td,) = load_targets(spec.targets, tmp_path)
    assert td.x.tolist() == pytest.approx([1e-4, 2e-4]) and td.y.tolist() == [1e3, 2e3]
    assert td.sigma.tolist() == [2e3, 2e3]  # default: the largest |measured y|
    bad = spec.model_dump()
    bad["targets"][0]["measured"]["y"] = "G"
    with pytest.raises(CalibrationError, match=r"targets.0 \(c\).measured.y: no column 'G'"):
        load_targets(parse_spec(bad).targets, tmp_path)


def _line_problem(noise: float, seed: int = 3):
    """y = a + b x with Gaussian noise: the closed-form least-squares oracle."""
    rng = np.random.default_rng(seed)
    x = np.linspace(0.0, 1.0, 25)
    y = 2.0 + 3.0 * x + noise * rng.normal(size=x.size)
    params = [Parameter(key="a", bounds=(0.0, 5.0)), Parameter(key="b", bounds=(0.5, 10.0),
                                                              scale="log")]  # fmt: skip

    def batch(points):
        return [(p[0] + p[1] * x) - y for p in points]

    return x, y, params, batch


def test_least_squares_and_intervals_match_linear_regression():
    x, y, params, batch = _line_problem(0.05)
    obj = Objective(params, batch, max_runs=500)
    opts = Options(tolerance=1e-12)
    z, info = optimise(obj, opts)
    values = obj.physical(z)
    design = np.column_stack([np.ones_like(x), x])
    coef, *_ = np.linalg.lstsq(design, y, rcond=None)
    assert values == pytest.approx(coef, rel=1e-7)
    res = obj.one(z)
    unc = uncertainty(params, values, obj.jacobian(z, 1e-6), res, 0.95)
    s2 = float(res @ res) / (x.size - 2)
    cov = s2 * np.linalg.inv(design.T @ design)
    np.testing.assert_allclose(unc["covariance"], cov, rtol=1e-5)
    corr = cov[0, 1] / np.sqrt(cov[0, 0] * cov[1, 1])
    assert unc["correlation"][0][1] == pytest.approx(corr, rel=1e-5)
    lo, hi = unc["parameters"][1]["interval"]
    assert lo < 3.0 < hi and info["stopped"] == "converged"
    assert unc["t_quantile"] == pytest.approx(2.0687, abs=1e-4)  # t_{0.975, 23}


def test_global_search_restarts_and_budget():
    # two minima: near 0.2 (cost ~0.029) and near 0.8 (cost ~0.002, the global one)
    params = [Parameter(key="p", bounds=(0.0, 1.0), initial=0.15)]

    def batch(points):
        return [np.array([5.0 * (p - 0.2) * (p - 0.8), 0.3 * (1.0 - p)]) for (p,) in points]

    local = Objective(params, batch, 500)
    z_local, _ = optimise(local, Options())
    glob = Objective(params, batch, 500)
    z_glob, info = optimise(glob, Options(method="global", population=6, generations=8))
    assert glob.best is not None and local.best is not None
    assert z_local[0] < 0.5 < z_glob[0] and glob.best[0] < 0.2 * local.best[0]
    assert "global_best" in info
    restarted = Objective(params, batch, 500)
    _, info = optimise(restarted, Options(restarts=3))
    assert len(info["starts"]) == 4
    capped = Objective(params, batch, 3)
    _, info = optimise(capped, Options())
    assert "max_runs (3)" in info["stopped"] and len(capped.memo) <= 3


DECK = TINY_STATIC_BAR


def test_a_run_is_made_once_and_read_back(tmp_path):
    """The cache: a second calibration over the same folder reads the run back."""
    deck = tmp_path / "deck.yaml"
    deck.write_text(DECK)
    params = [Parameter(key="material.youngs_modulus", bounds=(1e9, 1e11), scale="log")]
    first = Runner(deck, [], params, tmp_path / "cal", quiet=True)
    (rec,) = first.run([[3.0e10]])
    assert rec.status == "completed" and not rec.cached and first.runs == 1
    assert rec.folder == run_folder(params, [3.0e10])
    again = Runner(deck, [], params, tmp_path / "cal", quiet=True)
    (rec2,) = again.run([[3.0e10]])
    assert rec2.status == "skipped-done" and rec2.cached and again.runs == 0
    with pytest.raises(CalibrationError, match="material.youngs_modulus"):
        Runner(deck, [], params, tmp_path / "cal").run([[-1.0]])


def test_cli_bad_input_exits_2(tmp_path, capsys):
    (tmp_path / "deck.yaml").write_text(DECK)
    (tmp_path / "cal.yaml").write_text("parameters: []\ntargets: []\n")
    assert main(["calibrate", str(tmp_path / "deck.yaml"), str(tmp_path / "cal.yaml")]) == 2
    assert "parameters" in capsys.readouterr().err
    (tmp_path / "cal.yaml").write_text(json.dumps(BASE))
    code = main(["calibrate", str(tmp_path / "deck.yaml"), str(tmp_path / "cal.yaml"),
                 "--restarts", "-1", "--out", str(tmp_path / "o")])  # fmt: skip
    assert code == 2 and "options.restarts" in capsys.readouterr().err
    assert not Path(tmp_path / "o" / "runs").exists()


@pytest.mark.long
def test_example_runs(tmp_path):
    """examples/calibration/make_figures.py end to end (E and nu of an LPS plate from
    its own curves with 1 % noise, through the command line): both values within 2 %,
    the 95 % intervals contain the truth; the same command again makes no run."""
    from tests.helpers import EXAMPLES, load_script

    mod = load_script(EXAMPLES / "calibration" / "make_figures.py", "calibration_example")
    numbers = mod.run(tmp_path, [], 2)
    for row in numbers["parameters"].values():
        assert abs(row["relative_error"]) < 0.02 and row["interval_contains_truth"], row
    assert numbers["runs"] > 0
    cal = tmp_path / "calibration"
    for name in ("report.md", "fit.png", "fit_axial.csv", "fitted_deck.yaml", "runs.csv"):
        assert (cal / name).is_file(), name
    first = json.loads((cal / "report.json").read_text())
    # the same command again: every run is read back, none is made, the same result
    args = ["calibrate", str(EXAMPLES / "calibration" / "plate.yaml"),
            str(tmp_path / "calibration.yml"), "--out", str(cal), "--quiet"]  # fmt: skip
    assert main(args) == 0
    again = json.loads((cal / "report.json").read_text())
    assert again["runs"]["runs"] == 0 and again["runs"]["runs_read_back"] > 0
    assert again["parameters"] == first["parameters"]


@pytest.mark.long  # importing SALib alone takes 2-8 s on 2 shared cores
def test_sobol_indices_of_an_additive_function():
    """y = a + 2 b with a, b uniform on [0, 1]: S1 = ST = 1/5 and 4/5 (variances 1/12 and
    4/12); a log-scaled parameter that y ignores gets zero."""
    pytest.importorskip("SALib")
    from peridynamics.app.calibrate_sobol import sobol_from

    params = [Parameter(key="a", bounds=(0.0, 1.0)), Parameter(key="b", bounds=(0.0, 1.0)),
              Parameter(key="c", bounds=(1.0, 100.0), scale="log")]  # fmt: skip

    def outputs(points):
        return np.array([[p[0] + 2.0 * p[1], p[1]] for p in points])

    res = sobol_from(params, outputs, ["y", "b"], 256)
    assert res["samples"] == 256 * 5
    y = res["outputs"]["y"]
    for lab, want in (("a", 0.2), ("b", 0.8), ("c", 0.0)):
        assert y[lab]["S1"] == pytest.approx(want, abs=0.03), lab
        assert y[lab]["ST"] == pytest.approx(want, abs=0.03), lab
    again = sobol_from(params, outputs, ["y", "b"], 256)  # bootstrap seeded: the
    assert again == res  # intervals too (SALib reads seed 0 as none: they differed)
    with pytest.raises(CalibrationError, match="power of 2"):
        sobol_from(params, outputs, ["y", "b"], 100)


@pytest.mark.slow
def test_three_parameter_recovery_of_softening_bonds(tmp_path):
    """E, f_t and G_F of the notched plate with bilinear softening bonds from its
    load-displacement curve with 1 % noise (examples/calibration/recovery_softening.py):
    each within 2 %, inside its 95 % interval."""
    from tests.helpers import EXAMPLES, load_script

    mod = load_script(EXAMPLES / "calibration" / "recovery_softening.py", "recovery_softening")
    numbers = mod.run(tmp_path, 2)
    for row in numbers["parameters"].values():
        assert abs(row["relative_error"]) < 0.02 and row["interval_contains_truth"], row


def test_api_names_bad_input(tmp_path):
    import peridynamics as pd

    with pytest.raises(pd.CalibrationError, match="no deck file"):
        pd.calibrate(tmp_path / "missing.yaml", BASE, out=tmp_path / "o")
    with pytest.raises(pd.CalibrationError, match="parameters.0.bounds"):
        pd.calibrate(tmp_path / "missing.yaml", _with("parameters.0.bounds", [1.0]))
