"""``peridynamics verify``: the registry's cases are valid decks with sourced references,
a case runs and is judged, a failed check fails the command, a rerun reuses finished
cases, and the reports hold the table."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import pytest

from peridynamics.app import verify_cases
from peridynamics.app.examples import list_examples
from peridynamics.app.verify import run_one
from peridynamics.app.verify_cases import CASES, Case, Check
from peridynamics.cli import main
from peridynamics.deck import load_deck

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.name)
def test_every_case_is_a_valid_deck_with_sourced_references(case):
    decks = list_examples()
    for tier in ("quick", "full"):
        sets = case.overrides(tier)
        if sets is not None:
            deck = load_deck(decks[case.deck], list(sets))
            inputs = deck.model_dump(mode="json", by_alias=True)
            for check in case.checks:
                assert check.reference(inputs) == pytest.approx(check.reference(inputs))
                assert check.rel >= 0 and check.abs >= 0 and check.source
    refs = (ROOT / "docs" / "references.md").read_text()
    for check in case.checks:
        for author, year in re.findall(r"([A-Z][a-z]+)(?: & [A-Z][a-z]+)? \((\d{4})\)",
                                       check.source + " " + case.title):  # fmt: skip
            assert f"{author}" in refs and year in refs, (author, year)


def test_a_check_judges_within_its_tolerance():
    c = Check("x", "m", lambda s: 0.0, lambda i: 1.0, "closed form", rel=0.1)
    assert c.judge(1.09, 1.0) and not c.judge(1.11, 1.0) and not c.judge(float("nan"), 1.0)
    bound = Check("v", "m/s", lambda s: 0.0, lambda i: 1.0, "bound", at_most=True)
    assert bound.judge(0.2, 1.0) and not bound.judge(1.01, 1.0)


def test_verify_one_case_then_reuse_it(tmp_path, capsys):
    out = tmp_path / "v"
    assert main(["verify", "--only", "bar_wave_1d", "--out", str(out)]) == 0
    report = json.loads((out / "verify.json").read_text())
    assert report["tier"] == "quick" and report["passed"] is True
    (case,) = report["cases"]
    assert case["case"] == "bar_wave_1d" and len(case["checks"]) == 2
    for check in case["checks"]:
        assert check["passed"] and check["source"] and check["measured"] != check["reference"]
    assert "| bar_wave_1d |" in (out / "verify.md").read_text()
    assert "<table>" in (out / "verify.html").read_text()
    assert case["figures"] and (out / "bar_wave_1d" / case["figures"][0]).is_file()
    assert report["machine"]["cores"] >= 1 and report["machine"]["cpu"]
    capsys.readouterr()
    assert main(["verify", "--only", "bar_wave_1d", "--out", str(out)]) == 0
    assert "(done before)" in capsys.readouterr().out
    # the reused case keeps the time of the run that made it, and the report says so
    again = json.loads((out / "verify.json").read_text())
    assert again["cases"][0]["reused"] is True
    assert again["cases"][0]["wall_s"] == case["wall_s"]
    assert again["case_wall_s"] == case["wall_s"]
    assert "(resumed; the cases' runs" in (out / "verify.md").read_text()


def test_a_failed_check_fails_the_command(tmp_path, monkeypatch, capsys):
    wrong = Case("bar_wrong", "the bar against a wrong reference", "bar_wave_1d",
                 quick=("discretisation.spacing=0.02", "solver.time_step=4e-6",
                        "solver.end_time=1e-4"),
                 checks=(Check("peak velocity", "m/s",
                               lambda s: abs(s["results"]["probes"]["gauge_velocity"]["peak"]),
                               lambda i: 1.0e3, "a wrong number", rel=0.01),))  # fmt: skip
    record = run_one(wrong, "quick", tmp_path)
    assert record["status"] == "completed" and record["passed"] is False
    monkeypatch.setattr(verify_cases, "CASES", (wrong,))
    assert main(["verify", "--out", str(tmp_path / "cmd")]) == 4
    assert "failed: bar_wrong" in capsys.readouterr().out
    report = json.loads((tmp_path / "cmd" / "verify.json").read_text())
    assert report["passed"] is False and "FAIL" in (tmp_path / "cmd" / "verify.md").read_text()


def test_a_series_case_runs_its_refinements_in_order(tmp_path):
    """A case with ``series`` (a convergence study) runs the deck once more per entry,
    with the entry's overrides added, into ``series_<k>/``; its checks read the runs in
    order, and a rerun reuses all of them."""
    bar = ("discretisation.spacing=0.02", "solver.time_step=4e-6", "solver.end_time=1e-4")
    finer = (
        ("discretisation.spacing=0.01", "solver.time_step=2e-6"),
        ("discretisation.spacing=0.005", "solver.time_step=1e-6"),
    )

    def spacing(k: int) -> Check:
        return Check(
            f"spacing of series run {k}", "m",
            lambda s: s["series"][k]["results"]["spacing_m"],
            lambda i: (0.01, 0.005)[k], "the overrides", rel=1e-12,
        )  # fmt: skip

    study = Case("bar_series", "the bar at three spacings", "bar_wave_1d", quick=bar,
                 series=finer, checks=(spacing(0), spacing(1)))  # fmt: skip
    record = run_one(study, "quick", tmp_path)
    assert record["status"] == "completed" and record["passed"], record
    assert (tmp_path / "bar_series" / "series_1" / "summary.json").is_file()
    again = run_one(study, "quick", tmp_path)
    assert again["reused"] is True and again["passed"]
    assert again["wall_s"] == record["wall_s"]  # all reused: the time that made them
    # a refinement added to a finished case (here: one removed) runs alone, and the
    # case's time is the earlier call's plus that run's, not the earlier call's only
    shutil.rmtree(tmp_path / "bar_series" / "series_1")
    extended = run_one(study, "quick", tmp_path)
    assert extended["reused"] is True and extended["passed"]
    assert extended["wall_s"] > record["wall_s"]
    assert run_one(study, "quick", tmp_path)["wall_s"] == extended["wall_s"]


def test_bad_arguments_name_the_option(tmp_path, capsys):
    assert main(["verify", "--only", "nothing*", "--out", str(tmp_path)]) == 2
    assert "--only 'nothing*' matches no case" in capsys.readouterr().err
    assert main(["verify", "--jobs", "0"]) == 2
    assert main(["verify", "--list"]) == 0
    assert "bar_wave_1d" in capsys.readouterr().out


@pytest.mark.long
def test_the_quick_tier_passes(tmp_path):
    """Every case of ``verify --quick`` (what the README's command runs), two at a time."""
    assert main(["verify", "--quick", "--jobs", "2", "--out", str(tmp_path)]) == 0
