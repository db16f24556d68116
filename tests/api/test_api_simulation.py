"""The Python API runs what the command line runs: the same bits, the same files; and
what only a script can do (step, callbacks, results as objects) keeps those bits."""

from __future__ import annotations

import gc
import os
import signal
from pathlib import Path

import numpy as np
import pytest

import peridynamics as pd
from peridynamics.app.examples import list_examples
from peridynamics.cli import main

#: the main job (README) at a size for the default selection
SMALL_MAIN = {
    "discretisation.spacing": 1.0e-3,
    "discretisation.horizon": 4.0e-3,
    "solver.end_time": 2.0e-5,
    "output.vtk_every": 20,
}


def _same_final(a: Path, b: Path) -> None:
    with np.load(a / "final_state.npz") as fa, np.load(b / "final_state.npz") as fb:
        assert sorted(fa.files) == sorted(fb.files)
        for key in fa.files:
            np.testing.assert_array_equal(fa[key], fb[key], err_msg=key)


def test_the_main_job_from_python_equals_the_command_line_bit_for_bit(tmp_path):
    deck_file = list_examples()["crack_branching_2d"]
    sets = [f"{k}={v}" for k, v in SMALL_MAIN.items()]
    cli_out = tmp_path / "cli"
    args = ["run", str(deck_file), "--out", str(cli_out), "--quiet"]
    assert main([*args, *[a for s in sets for a in ("--set", s)]]) == 0
    result = pd.Simulation(deck_file, SMALL_MAIN, out=tmp_path / "api").run()
    _same_final(cli_out, result.folder)
    cli = pd.Result.load(cli_out)
    assert result.results == cli.results
    assert result.results["bonds_broken"] > 0  # the pre-crack grows in this window
    assert result.history.equals(cli.history)
    assert sorted(p.name for p in cli_out.iterdir()) == sorted(
        p.name for p in result.folder.iterdir()
    )


def test_step_then_run_equals_a_plain_run(tmp_path):
    deck = pd.Deck.example("crack_branching_2d", SMALL_MAIN)
    plain = pd.Simulation(deck).run()
    sim = pd.Simulation(deck)
    state = sim.step(7)
    assert state.step == 7 and sim.state is state
    stepped = sim.run()
    for key in ("u", "v", "intact", "damage"):
        np.testing.assert_array_equal(stepped.final[key], plain.final[key], err_msg=key)
    assert stepped.results["steps"] == plain.results["steps"]
    with pytest.raises(RuntimeError, match="has run"):
        sim.step()


def test_callbacks_see_every_step_and_can_stop_the_run():
    seen: list[int] = []

    class Stopper(pd.Callback):
        def on_step(self, state, result):
            seen.append(state.step)
            return state.step >= 12

        def on_finish(self, state, results):
            results["my_peak_u_m"] = float(np.abs(state.u).max())

    deck = pd.Deck.example("bar_wave_1d")
    calls: list[float] = []
    result = pd.Simulation(deck, callbacks=[Stopper(every=3), lambda s: calls.append(s.t)]).run()
    assert seen == [3, 6, 9, 12]
    assert len(calls) == 12
    assert result.results["steps"] == 12 and result.results["stopped_by"] == "callback"
    assert result.results["my_peak_u_m"] == pytest.approx(np.abs(result.final["u"]).max())
    with pytest.raises(TypeError, match="callbacks"):
        pd.Simulation(deck, callbacks=[3])
    with pytest.raises(ValueError, match="every"):
        pd.Callback(every=0)


def test_interrupted_api_run_resumes_to_the_uninterrupted_result(tmp_path):
    deck = pd.Deck.example("bar_wave_1d", {"solver.end_time": 1.2e-4})
    whole = pd.Simulation(deck).run()

    def ctrl_c(state):
        if state.step == 40:
            os.kill(os.getpid(), signal.SIGINT)

    out = tmp_path / "run"
    with pytest.raises(pd.RunInterrupted) as stop:
        pd.Simulation(deck, out=out, callbacks=[ctrl_c]).run(checkpoint_every=25)
    assert stop.value.step == 40 and stop.value.checkpoint is not None
    assert pd.Result.load(out).status == "interrupted"
    resumed = pd.Simulation(deck, out=out).run(resume=True)
    assert resumed.status == "completed"
    for key in ("u", "v", "t", "step"):
        np.testing.assert_array_equal(resumed.final[key], whole.final[key], err_msg=key)
    with pytest.raises(pd.SetupError, match="resume=True"):
        pd.Simulation(deck).run(resume=True)


def test_a_run_without_out_leaves_no_files(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    sim = pd.Simulation(pd.Deck.example("bar_wave_1d", {"solver.end_time": 2e-5}))
    result = sim.run()
    folder = result.folder
    assert (folder / "summary.json").is_file() and list(tmp_path.iterdir()) == []
    kept = result.save(tmp_path / "kept")
    assert kept.results == result.results
    with pytest.raises(FileExistsError):
        result.save(tmp_path / "kept")
    del sim, result
    gc.collect()
    assert not folder.exists()
    assert (tmp_path / "kept" / "summary.json").is_file()


def test_results_as_objects(tmp_path):
    deck = pd.Deck.example("crack_branching_2d", SMALL_MAIN)
    result = pd.Simulation(deck, out=tmp_path / "r").run()
    table = result.history
    assert table["time"].iloc[-1] == pytest.approx(result.results["final_time_s"])
    assert result.units["strain_energy"] == "J" and result.units["crack_tip"] == "m"
    assert len(result.times) == len(list((tmp_path / "r").glob("frame_*.vtu")))
    last = result.fields()
    assert last["x"].shape == (result.results["n_points"], 2)
    np.testing.assert_allclose(last["damage"], result.damage, atol=1e-6)  # float32 frames
    np.testing.assert_allclose(last["displacement"], result.final["u"], rtol=1e-6, atol=1e-12)
    assert result.crack["bonds_broken"] == result.results["bonds_broken"]
    assert "<table>" in result._repr_html_() and "<table>" in deck._repr_html_()
    from matplotlib.figure import Figure

    assert isinstance(result.plot_damage(), Figure)
    assert isinstance(result.plot_history("strain_energy", "max_damage"), Figure)
    with pytest.raises(KeyError, match="no history column"):
        result.plot_history("nope")
    with pytest.raises(IndexError, match="frame 99"):
        result.fields(99)
    pytest.importorskip("pyvista")
    mesh = result.to_pyvista()
    assert mesh.n_points == result.results["n_points"]


def test_result_load_refuses_a_folder_that_is_no_run(tmp_path):
    with pytest.raises(FileNotFoundError, match="not a run folder"):
        pd.Result.load(tmp_path)
