"""Lengths that are not whole multiples of the spacing, the disc geometry and notches."""

from __future__ import annotations

import copy
import json
import math
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from peridynamics.app.run import Simulation
from peridynamics.bonds import build_bonds
from peridynamics.bonds.precrack import crossing_bonds
from peridynamics.build.cloud import build_cloud
from peridynamics.build.errors import SetupError
from peridynamics.build.loads import build_conditions
from peridynamics.deck import DeckError, parse_deck
from peridynamics.geometry import (
    GeometryFitWarning,
    Notch,
    bar,
    box,
    cylinder,
    disc,
    rectangle,
)
from peridynamics.geometry.generators import fit_cells
from peridynamics.geometry.regions import Ball

DX = 1.0e-3


def old_centres(lo: float, length: float, dx: float) -> np.ndarray:
    """The rule before fitting: L / dx cells from ``lo``, centres lo + (k + 1/2) dx."""
    n = int(round(length / dx))
    return np.asarray(lo + (np.arange(n) + 0.5) * dx, dtype=np.float64)


@contextmanager
def no_fit_warning() -> Iterator[None]:
    """A GeometryFitWarning inside is an error (every length is a whole multiple)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", GeometryFitWarning)
        yield


# ------------------------------------------------------------------ fitting rule
def test_fit_cells_rule() -> None:
    assert fit_cells(0.01, DX, "L") == (10, None)
    assert fit_cells(0.3, 0.1, "L") == (3, None)  # 0.3 / 0.1 = 2.9999999999999996
    n, fit = fit_cells(0.0103, DX, "size[0]")
    assert n == 10 and fit is not None
    assert fit.key == "size[0]" and fit.cells == 10
    assert fit.grid_length == pytest.approx(0.010)
    assert fit.margin == pytest.approx(0.00015)
    assert fit_cells(0.0109999, DX, "L")[0] == 10  # floor, not round
    with pytest.raises(ValueError, match="shorter than the spacing"):
        fit_cells(0.0004, DX, "size[1]")


def test_rectangle_non_multiple_is_centred_with_cell_volumes() -> None:
    with pytest.warns(GeometryFitWarning, match=r"size\[0\] = 0.0103 m .* 10 cells"):
        c = rectangle((0.0103, 0.005), DX, thickness=2e-3, origin=(1.0, -1.0))
    assert c.n_points == 10 * 5
    xs, ys = np.unique(c.x[:, 0]), np.unique(c.x[:, 1])
    np.testing.assert_allclose(xs, 1.0 + 0.00015 + (np.arange(10) + 0.5) * DX, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(ys, old_centres(-1.0, 0.005, DX))  # exact side: unchanged
    # equal margins at both ends of the nominal length
    assert xs[0] - 0.5 * DX - 1.0 == pytest.approx(1.0103 - (xs[-1] + 0.5 * DX), abs=1e-15)
    np.testing.assert_array_equal(c.volume, np.full(50, DX * DX * 2e-3))
    assert [f.key for f in c.grid_fit] == ["size[0]"]
    assert c.grid_fit[0].as_dict()["grid_m"] == pytest.approx(0.01)


def test_box_bar_cylinder_non_multiple() -> None:
    with pytest.warns(GeometryFitWarning):
        b = box((0.0041, 0.0035, 0.0029), DX, origin=(0.0, 0.0, 0.0))
    assert b.n_points == 4 * 3 * 2
    for k, (length, n) in enumerate([(0.0041, 4), (0.0035, 3), (0.0029, 2)]):
        axis = np.unique(b.x[:, k])
        margin = 0.5 * (length - n * DX)
        np.testing.assert_allclose(axis, margin + (np.arange(n) + 0.5) * DX, atol=1e-15)
    np.testing.assert_array_equal(b.volume, DX**3)
    assert [f.key for f in b.grid_fit] == ["size[0]", "size[1]", "size[2]"]

    with pytest.warns(GeometryFitWarning, match="length"):
        r = bar(1.05, 0.1, area=2.0, origin=0.0)
    np.testing.assert_allclose(r.x[:, 0], 0.025 + (np.arange(10) + 0.5) * 0.1, atol=1e-14)
    np.testing.assert_array_equal(r.volume, 2.0 * 0.1)
    with pytest.warns(GeometryFitWarning):
        rb = bar(1.05, 0.1, nodes_on_boundary=True)
    np.testing.assert_allclose(rb.x[:, 0], 0.025 + np.arange(11) * 0.1, atol=1e-14)

    with pytest.warns(GeometryFitWarning, match="length"):
        cy = cylinder(0.0023, 0.0043, 0.0005, origin=(0.0, 0.0, 1.0))
    z = np.unique(cy.x[:, 2])
    np.testing.assert_allclose(z, 1.0 + 0.00015 + (np.arange(8) + 0.5) * 0.0005, atol=1e-15)
    ref = cylinder(0.0023, 0.004, 0.0005, origin=(0.0, 0.0, 1.00015))  # the same 8 layers
    np.testing.assert_allclose(cy.x, ref.x, atol=1e-15)
    assert [f.key for f in cy.grid_fit] == ["length"]


@pytest.mark.parametrize(
    ("size", "dx", "origin"),
    [
        ((0.01, 0.005), 5e-4, (0.0, 0.0)),
        ((0.3, 0.7), 0.1, (0.1, -0.2)),
        ((0.0103, 0.0051), 1e-4, (1.0, 2.0)),
    ],
)
def test_exact_multiples_unchanged(size: tuple, dx: float, origin: tuple) -> None:
    with no_fit_warning():
        c = rectangle(size, dx, origin=origin)
        b = bar(size[1], dx, origin=origin[0])
        bj = box((3 * dx, 2 * dx, size[1]), dx, origin=(*origin, 0.5))
        j = rectangle(size, dx, origin=origin, jitter=0.2, seed=4)
    gx, gy = np.meshgrid(
        *(old_centres(o, s, dx) for o, s in zip(origin, size, strict=True)), indexing="ij"
    )
    assert c.x.tobytes() == np.column_stack([gx.ravel(), gy.ravel()]).tobytes()
    assert b.x[:, 0].tobytes() == old_centres(origin[0], size[1], dx).tobytes()
    assert np.unique(bj.x[:, 2]).tobytes() == old_centres(0.5, size[1], dx).tobytes()
    assert c.grid_fit == () and b.grid_fit == () and bj.grid_fit == ()
    rng = np.random.default_rng(4)
    moved = c.x + rng.uniform(-0.2 * dx, 0.2 * dx, size=c.x.shape)
    assert j.x.tobytes() == moved.tobytes()


def test_jittered_non_multiple_stays_in_the_fitted_grid() -> None:
    with pytest.warns(GeometryFitWarning):
        c = rectangle((0.0103, 0.0052), DX, thickness=1e-3, jitter=0.3, seed=2)
    lo = np.array([0.00015, 0.0001])
    hi = lo + np.array([10, 5]) * DX
    assert np.all(c.x > lo) and np.all(c.x < hi)
    assert c.volume.sum() == pytest.approx(10 * 5 * DX * DX * 1e-3, rel=1e-12)
    assert c.irregular and len(c.grid_fit) == 2


# --------------------------------------------------------------------------- disc
@pytest.mark.parametrize("r_over_dx", [2.0, 5.0, 7.3, 10.0, 15.7, 40.0])
def test_disc_symmetric_with_cell_volumes(r_over_dx: float) -> None:
    radius = r_over_dx * DX
    c = disc(radius, DX, center=(0.0, 0.0), thickness=3e-3)
    x = c.x
    key = {tuple(p) for p in np.round(x / DX * 2).astype(int).tolist()}
    for flip in ([-1, 1], [1, -1], [-1, -1]):
        assert {tuple(p) for p in np.round(x * flip / DX * 2).astype(int).tolist()} == key
    assert {(q, p) for p, q in key} == key  # quarter turn
    assert np.all(np.abs(x / DX - np.round(x / DX - 0.5) - 0.5) < 1e-9)  # cell corner at 0
    assert np.all(np.sum(x * x, axis=1) <= radius**2 * (1 + 1e-12))
    np.testing.assert_array_equal(c.volume, DX * DX * 3e-3)
    ratio = c.n_points * DX * DX / (math.pi * radius**2)
    assert abs(ratio - 1.0) <= 0.66 / r_over_dx  # measured bound (docs/deck.md)


def test_disc_counts_and_legacy_rectangle() -> None:
    assert [disc(r * DX, DX).n_points for r in (1.0, 2.0, 10.0, 40.0)] == [4, 12, 316, 5024]
    d = disc(0.025, 0.000625, center=(0.025, 0.025), thickness=0.025)
    hole = ~Ball((0.025, 0.025), 0.025)
    r = rectangle((0.05, 0.05), 0.000625, thickness=0.025, holes=[hole])
    np.testing.assert_allclose(d.x, r.x, rtol=0, atol=1e-15)
    np.testing.assert_array_equal(d.volume, r.volume)
    with pytest.raises(ValueError, match="no grid point lies inside"):
        disc(0.6 * DX, DX)


def test_disc_jitter() -> None:
    c = disc(10 * DX, DX, center=(0.1, 0.2), jitter=0.25, seed=1)
    assert c.irregular and np.all(c.volume > 0)
    assert np.all(np.sum((c.x - [0.1, 0.2]) ** 2, axis=1) <= (10 * DX) ** 2 * (1 + 1e-12))
    assert c.volume.sum() == pytest.approx(math.pi * (10 * DX) ** 2, rel=0.02)


# ----------------------------------------------------------------------- notches
def _cloud_2d() -> Any:
    return rectangle((0.02, 0.01), DX, thickness=1e-3)


def test_notch_removes_points_and_cuts_crossing_bonds() -> None:
    c = _cloud_2d()
    notch = Notch([-0.001, 0.005], [0.008, 0.005], width=2 * DX)
    removed = notch.region()(c.x)
    # two rows (y = 4.5 and 5.5 mm) strictly inside, x = 0.5 .. 7.5 mm
    assert removed.sum() == 2 * 8
    assert np.all(np.abs(c.x[removed, 1] - 0.005) < DX)
    assert np.all(c.x[removed, 0] < 0.008)
    cut = c.remove(notch.region())
    bonds = build_bonds(cut, 3.015 * DX, "truncated", [notch.crack()])
    a, b = cut.x[bonds.bond_i], cut.x[bonds.bond_j]
    across = (a[:, 1] < 0.005) & (b[:, 1] > 0.005)
    x_cross = a[:, 0] + (0.005 - a[:, 1]) / (b[:, 1] - a[:, 1] + 1e-300) * (b[:, 0] - a[:, 0])
    assert np.all(bonds.bond_intact[across & (x_cross < 0.008 - 1e-12)] == 0)
    assert np.all(bonds.bond_intact[across & (x_cross > 0.008 + 1e-12)] == 1)
    assert np.all(bonds.bond_intact[(a[:, 0] > 0.012) & (b[:, 0] > 0.012)] == 1)


def test_narrow_notch_removes_nothing_but_still_cuts() -> None:
    c = _cloud_2d()
    notch = Notch([-0.001, 0.005], [0.008, 0.005], width=0.3 * DX)
    assert not np.any(notch.region()(c.x))
    bonds = build_bonds(c, 3.015 * DX, "truncated", [notch.crack()])
    hit = crossing_bonds(c.x, bonds.bond_i, bonds.bond_j, [notch.crack()])
    assert hit.sum() > 0
    np.testing.assert_array_equal(bonds.bond_intact == 0, hit)
    # the two faces are separated: no intact bond joins y < 5 mm and y > 5 mm left of 7.5 mm
    a, b = c.x[bonds.bond_i], c.x[bonds.bond_j]
    joins = (a[:, 1] < 0.005) & (b[:, 1] > 0.005) & (np.maximum(a[:, 0], b[:, 0]) < 0.0075)
    assert joins.sum() > 0 and np.all(bonds.bond_intact[joins] == 0)


def test_round_tip() -> None:
    c = _cloud_2d()
    flat = Notch([-0.001, 0.0055], [0.008, 0.0055], width=2.2 * DX)
    round_ = Notch([-0.001, 0.0055], [0.008, 0.0055], width=2.2 * DX, tip="round")
    extra = round_.region()(c.x) & ~flat.region()(c.x)
    np.testing.assert_allclose(c.x[extra], [[0.0085, 0.0055]])
    np.testing.assert_allclose(round_.tip_point, [0.0091, 0.0055])
    np.testing.assert_allclose(round_.crack().end, [0.0091, 0.0055])


def test_notch_3d_through_and_z_range() -> None:
    b = box((0.006, 0.004, 0.004), DX)
    through = Notch([-0.001, 0.002], [0.003, 0.002], width=0.5 * DX)
    part = Notch([-0.001, 0.002], [0.003, 0.002], width=0.5 * DX, z=(0.0, 0.002))
    bounds = (-DX, 0.004 + DX)
    full = build_bonds(b, 2.015 * DX, "truncated", [through.crack(bounds)])
    half = build_bonds(b, 2.015 * DX, "truncated", [part.crack(bounds)])
    a, c = b.x[full.bond_i], b.x[full.bond_j]
    across = (a[:, 1] < 0.002) & (c[:, 1] > 0.002) & (np.maximum(a[:, 0], c[:, 0]) < 0.003)
    assert np.all(full.bond_intact[across] == 0)
    upper = across & (a[:, 2] > 0.002) & (c[:, 2] > 0.002)
    lower = across & (a[:, 2] < 0.002) & (c[:, 2] < 0.002)
    assert np.all(half.bond_intact[upper] == 1) and np.all(half.bond_intact[lower] == 0)
    wide = Notch([-0.001, 0.002], [0.003, 0.002], width=2 * DX, z=(0.0, 0.002))
    gone = wide.region()(b.x)
    assert gone.sum() == 3 * 2 * 2 and np.all(b.x[gone, 2] < 0.002)


# ------------------------------------------------------------------------ decks
def deck_2d() -> dict[str, Any]:
    return {
        "name": "fit",
        "geometry": {"type": "rectangle", "size": [0.0103, 0.0052], "thickness": 1e-3},
        "discretisation": {"spacing": 5e-4, "horizon_factor": 3.015},
        "material": {"youngs_modulus": 70e9, "density": 2700.0},
        "damage": {"critical_stretch": 0.01},
        "notches": [{"start": [-0.001, 0.0026], "end": [0.004, 0.0026], "width": 1e-4}],
        "node_sets": {
            "top": {"edge": {"normal": [0, 1]}},
            "bottom": {"edge": {"normal": [0, -1]}},
        },
        "boundary_conditions": [
            {"type": "fixed", "set": "bottom"},
            {"type": "traction", "set": "top", "value": [0.0, 1.0e6]},
        ],
        "solver": {"steps": 3},
    }


def deck_errors(data: dict[str, Any]) -> dict[str, str]:
    with pytest.raises(DeckError) as info:
        parse_deck(data)
    return dict(info.value.errors)


def test_deck_errors_name_the_key() -> None:
    d = deck_2d()
    d["notches"][0]["width"] = -1e-4
    assert "greater than 0" in deck_errors(d)["notches.0.width"]
    d = deck_2d()
    d["notches"][0]["end"] = [0.004, 0.0026, 0.0]
    assert "[x, y]" in deck_errors(d)["notches.0.end"]
    d = deck_2d()
    d["notches"][0]["end"] = d["notches"][0]["start"]
    assert "length" in deck_errors(d)["notches.0.end"]
    d = deck_2d()
    d["notches"][0]["z"] = [0.0, 1.0]
    assert "3-D" in deck_errors(d)["notches.0.z"]
    d = deck_2d()
    d["notches"][0]["tip"] = "pointy"
    assert "notches.0.tip" in deck_errors(d)
    d = deck_2d()
    d["geometry"] = {"type": "bar", "length": 0.01}
    d["node_sets"], d["boundary_conditions"] = {}, []
    assert "2-D or 3-D" in deck_errors(d)["notches.0"]
    d = deck_2d()
    d["geometry"] = {"type": "disc", "radius": 0.005, "center": [0.0, 0.0, 0.0]}
    assert "geometry.center" in deck_errors(d)
    d = deck_2d()
    d["geometry"] = {"type": "disc", "radius": 0.005, "hole": []}
    assert "unknown key" in deck_errors(d)["geometry.hole"]
    d = deck_2d()
    d["geometry"] = {"type": "disk", "radius": 0.005}
    assert "disc" in deck_errors(d)["geometry.type"]
    d = deck_2d()
    d["notches"][0]["z"] = [1.0, 0.0]
    d["geometry"] = {"type": "box", "size": [0.01, 0.005, 0.002]}
    d["node_sets"], d["boundary_conditions"] = {}, []
    assert "z_min < z_max" in deck_errors(d)["notches.0.z"]
    d["notches"][0]["z"] = None
    d["notches"][0]["start"] = [0.0, 0.0, 0.0]
    assert "runs along z" in deck_errors(d)["notches.0.start"]


def test_side_below_spacing_is_a_setup_error() -> None:
    d = deck_2d()
    d["geometry"]["size"] = [0.0103, 0.0004]
    d["notches"], d["node_sets"], d["boundary_conditions"] = [], {}, []
    with pytest.raises(SetupError, match=r"size\[1\] = 0.0004 m is shorter") as info:
        build_cloud(parse_deck(d))
    assert info.value.path == "geometry"


def test_traction_force_uses_the_fitted_face() -> None:
    d = deck_2d()
    with pytest.warns(GeometryFitWarning):
        cloud = build_cloud(parse_deck(d))
    body, _, _ = build_conditions(parse_deck(d), cloud)
    top = cloud.node_set("top")
    force = np.asarray(body[0].value)[1] * cloud.volume[top].sum()
    n_face = 20  # floor(10.3 / 0.5) cells along x
    assert top.size == n_face
    assert force == pytest.approx(1.0e6 * n_face * 5e-4 * 1e-3, rel=1e-12)  # not 10.3 mm


def test_deck_with_fit_and_notch_runs(tmp_path: Path) -> None:
    d = deck_2d()
    with pytest.warns(GeometryFitWarning):
        sim = Simulation.from_deck(parse_deck(d))
    assert sim.cloud.n_points == 20 * 10  # a 0.1 mm notch between rows removes no point
    cut = int(np.sum(sim.model.bonds.bond_intact == 0))
    assert cut > 0
    summary = sim.run(tmp_path, quiet=True, progress=False)
    assert summary["results"]["steps"] == 3
    assert summary["results"]["bonds_broken"] == 0  # notch bonds start broken: no growth
    fits = json.loads((tmp_path / "summary.json").read_text())["results"]["geometry_fit"]
    assert [(f["key"], f["cells"]) for f in fits] == [("size[0]", 20), ("size[1]", 10)]
    assert fits[0]["grid_m"] == pytest.approx(0.01)


def test_disc_deck_runs_with_edge_sets() -> None:
    d = copy.deepcopy(deck_2d())
    d["geometry"] = {"type": "disc", "radius": 0.004, "center": [0.01, 0.02], "thickness": 1e-3}
    d["notches"] = [{"start": [0.005, 0.02], "end": [0.01, 0.02], "width": 1e-3, "tip": "round"}]
    with no_fit_warning():
        sim = Simulation.from_deck(parse_deck(d))
    cloud = sim.cloud
    # rows y = 19.75 and 20.25 mm lose x = 6.25 .. 9.75 mm and, for the round tip, 10.25 mm
    assert cloud.n_points == disc(0.004, 5e-4).n_points - 2 * 9
    top = cloud.x[cloud.node_set("top")]
    np.testing.assert_allclose(top[:, 1], 0.02 + 0.00375)  # the topmost grid row
    np.testing.assert_allclose(np.sort(top[:, 0]) - 0.01, -np.sort(top[:, 0])[::-1] + 0.01)
    state = sim.solver.init()
    for _ in range(3):
        sim.solver.step(state)
    assert np.all(np.isfinite(state.u)) and state.bonds_broken == 0


def test_help_lists_disc_and_notches() -> None:
    from peridynamics.deck.reference import deck_reference

    geo = deck_reference("geometry")
    assert "type: disc" in geo and "center: [number, number]" in geo
    assert "whole cells that fit" in geo
    notches = deck_reference("notches")
    for key in ("start", "end", "width", "tip: flat | round", "z:"):
        assert key in notches
