"""The calibration against a real published test (examples/calibration/real_gregoire/):
the digitised load-CMOD band of Gregoire et al. (2013), beam D = 50 mm, parses, keeps
its provenance header and is consistent; the calibration file and the deck validate;
the calibrations themselves (slow: 64 runs of the 360-point beam, 335 s
on 2 shared cores) land on the published values within 2 %."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from peridynamics.app.calibrate_data import load_targets
from peridynamics.app.calibrate_spec import load_spec
from peridynamics.deck import load_deck

FOLDER = Path(__file__).resolve().parents[2] / "examples" / "calibration" / "real_gregoire"


def test_data_file_parses_and_names_its_source():
    text = (FOLDER / "gregoire2013_d50_load_cmod.csv").read_text()
    head = "\n".join(ln for ln in text.splitlines() if ln.startswith("#"))
    for needed in ("Gregoire", "1434-1452", "mark-hobbs/pypd", "61b1323340782a657b5f6c5b"):
        assert needed in head
    rows = [ln for ln in text.splitlines() if ln and not ln.startswith("#")]
    assert rows[0] == "cmod,load_min,load_max,load_mid"
    vals = np.array([[float(v) for v in r.split(",")] for r in rows[1:]])
    assert vals.shape == (142, 4)
    assert np.all(np.diff(vals[:, 0]) > 0)  # CMOD increases
    assert np.all(vals[:, 1] <= vals[:, 2])  # the band's lower edge under its upper
    assert np.allclose(vals[:, 3], 0.5 * (vals[:, 1] + vals[:, 2]), atol=1e-3)
    assert 900.0 < vals[:, 3].max() < 1100.0  # N: the peak of the band's middle


def test_calibration_file_and_deck_validate():
    spec = load_spec(FOLDER / "calibration.yml")
    assert [p.name for p in spec.parameters] == ["E", "f_t", "G_F"]
    (target,) = load_targets(spec.targets, FOLDER)
    assert target.size == 142 and target.x.max() == pytest.approx(2.0215e-4, rel=1e-3)
    deck = load_deck(FOLDER / "beam_d50.yaml")
    assert deck.damage is not None and deck.damage.bond_law == "bilinear"


@pytest.mark.slow
def test_real_calibration_reproduces_published_values(tmp_path):
    """fit_gregoire.py end to end: the fitted E, f_t and G_F of fits A and B within 2 %
    of the values committed in gregoire_d50.json (same deck, data and settings)."""
    from tests.helpers import load_script

    mod = load_script(FOLDER / "fit_gregoire.py", "fit_gregoire")
    numbers = mod.run(tmp_path, 2)
    published = json.loads((FOLDER / "gregoire_d50.json").read_text())
    for fit in ("fit_A", "fit_B"):
        for name, row in published[fit]["parameters"].items():
            got = numbers[fit]["parameters"][name]["fitted"]
            assert got == pytest.approx(row["fitted"], rel=0.02), (fit, name)
        assert numbers[fit]["misfit_rms"] < 1.1 * published[fit]["misfit_rms"]
