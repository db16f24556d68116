"""Crack outputs that need no damage threshold: the crack length (2-D) or area (3-D) of
the bonds broken during the run (:mod:`peridynamics.analysis.crack_length`), as a
history, in total and per tracked crack; and the warning raised when a threshold-based
crack tracker (``output.crack_tip``, ``output.crack_paths``) has its threshold at the
damage the crack leaves (a straight crack at m = 2 leaves phi = 0.350 beside it)."""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.analysis.crack_attribution import attribute_to_polylines
from peridynamics.analysis.crack_length import CrackMeter
from peridynamics.io import deck as dk
from peridynamics.io.observers import Observer, RunContext
from peridynamics.solvers.base import StepResult
from peridynamics.state import State

if TYPE_CHECKING:
    from peridynamics.model import Model

#: half-width of the damage band around a threshold that counts as "at the threshold"
THRESHOLD_BAND = 0.03
#: share of the crack's ridge points inside the band (or below it) that warns
THRESHOLD_SHARE = 0.5
#: fewest ridge points for the rule to judge (a crack of a few bonds proves nothing)
THRESHOLD_MIN_POINTS = 8
#: a ridge point's damage is within this of the largest across its broken bonds
RIDGE_TOLERANCE = 0.05


class CrackThresholdWarning(UserWarning):
    """A crack tracker's damage threshold sits at the damage the crack leaves."""


def can_break_bonds(deck: dk.Deck) -> bool:
    """True when some bond of the deck's model can break: a damage model other than
    ``none`` for the deck or a body, or a bonded interface."""
    if deck.damage.model != "none":
        return True
    if any(b.damage is not None and b.damage.model != "none" for b in deck.bodies):
        return True
    return any(
        i.type == "bonded" and (i.critical_stretch is not None or i.fracture_energy is not None)
        for i in deck.interfaces
    )


def _interfaces(model: Model) -> tuple[Any, ...]:
    """Bonded interfaces of a model with several bodies (their own bond lists)."""
    return tuple(getattr(model.force_model, "interfaces", ()) or ())


def all_intact(model: Model, s: State) -> NDArray[np.uint8]:
    """Bond flags of ``s`` in the order of :meth:`CrackMeter.from_bonds` with the
    model's interfaces: the bonds, then the interface bonds (n_bonds,)."""
    if _interfaces(model) and "interface_intact" in s:
        return np.concatenate([s.intact, s["interface_intact"]])
    return s.intact


def build_meter(model: Model, table: NDArray[np.float64] | None = None) -> CrackMeter:
    """The crack meter of a model (its bonds and those of its bonded interfaces);
    ``table``: its orientation table when made elsewhere (a decomposed run)."""
    extra = [f.bonds for f in _interfaces(model)]
    return CrackMeter.from_bonds(model.cloud, model.bonds, extra, table)


class CrackLength(Observer):
    """Crack length (2-D, m) or area (3-D, m^2) from the bonds broken during the run, at
    every history record and at the end; per tracked crack (``output.crack_paths``,
    ``output.crack_tip``) at the end. Keys: docs/output.md."""

    def __init__(self, deck: dk.Deck, model: Model) -> None:
        self.deck, self.model = deck, model
        self.dim = model.dim
        # result keys: crack_length_m ... in 2-D, crack_area_m2 ... in 3-D
        what, unit = ("length", "m") if self.dim == 2 else ("area", "m2")
        self.keys = {
            "total": f"crack_{what}_{unit}",
            "history": f"crack_{what}_history_{unit}",
            "all": f"crack_{what}_all_bonds_{unit}",
            "rest": f"crack_{what}_unattributed_{unit}",
            "per_crack": f"broken_bond_{what}_{unit}",
        }
        self.meter: CrackMeter | None = None
        self._last: tuple[int, float] | None = None  # (bonds_broken, value) of the last record

    def _meter(self) -> CrackMeter:
        if self.meter is None:
            self.meter = build_meter(self.model)
        return self.meter

    def value(self, s: State) -> float:
        """Crack length (area) of ``s``: reused while no further bond broke."""
        if self._last is not None and self._last[0] == s.bonds_broken:
            return self._last[1]
        distributed = getattr(self.model, "crack_measure", None)  # every rank its bonds
        v = distributed() if distributed else self._meter().measure(all_intact(self.model, s))
        self._last = (s.bonds_broken, v)
        return v

    def on_start(self, ctx: RunContext, s: State, resumed: bool) -> None:
        ctx.records.setdefault(self.keys["history"], [])
        if not resumed:
            self.record(ctx, s)

    def on_step(self, ctx: RunContext, s: State, result: StepResult) -> None:
        if ctx.history_due(s):
            self.record(ctx, s)

    def record(self, ctx: RunContext, s: State) -> None:
        """Append the crack length (area) at this state."""
        ctx.records[self.keys["history"]].append(self.value(s))

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        m, keys = self.model, self.keys
        weights, measure = getattr(m, "crack_weights", None), getattr(m, "crack_measure", None)
        if weights is not None and measure is not None:  # a decomposed run
            mid, w = weights()
            results[keys["all"]] = measure(separating=False)
        else:
            meter = self._meter()
            intact = all_intact(m, s)
            idx, w = meter.weights(intact)
            results[keys["all"]] = meter.measure(intact, separating=False)
            mid = meter.midpoints(idx)
        results[keys["total"]] = float(w.sum())
        results[keys["history"]] = list(ctx.records.get(keys["history"], []))
        horizon = m.bonds.horizon
        o = self.deck.output
        if o.crack_paths and isinstance(results.get("crack_paths"), dict):
            from peridynamics.io.observers import CrackPaths

            paths = CrackPaths(self.deck, m).paths(ctx, s)
            lines = {n: list(p.branches) or [p.vertices] for n, p in paths.items()}
            share, rest = attribute_to_polylines(mid, w, lines, 2.0 * horizon)
            for name, v in share.items():
                if name in results["crack_paths"]:
                    results["crack_paths"][name][keys["per_crack"]] = v
            results[keys["rest"]] = rest
        ct = o.crack_tip
        if ct is not None and self.dim == 2:
            if ct.direction is None:
                ahead = np.ones(w.size, dtype=bool)
            else:
                d = np.asarray(ct.direction, dtype=float)
                d = d / np.linalg.norm(d)
                ahead = (mid - np.asarray(ct.origin, dtype=float)) @ d >= -horizon
            results["crack_tip_broken_bond_length_m"] = float(w[ahead].sum())
        return []


def broken_pairs(model: Model, s: State) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """End points (i, j) of the directed bonds broken during the run (pre-cracks
    excluded), interface bonds included; the owned families' bonds on a rank of a
    decomposed run (local indices; the whole body's view gathers them in global ids)."""
    pairs = getattr(model, "broken_pairs", None)
    if pairs is not None:  # the whole body's view of a decomposed run (global ids)
        return pairs()
    b, end = model.bonds, model.owned_bonds
    k = np.flatnonzero(b.bond_intact[:end].astype(bool) & (s.intact[:end] == 0))
    ii, jj = [b.bond_i[k]], [b.bond_j[k]]
    if _interfaces(model) and "interface_intact" in s:
        start = 0
        for f in _interfaces(model):  # over interfaces (a handful)
            now = s["interface_intact"][start : start + f.n_bonds]
            g = np.flatnonzero(f.bonds.bond_intact.astype(bool) & (now == 0))
            ii.append(f.bonds.bond_i[g])
            jj.append(f.bonds.bond_j[g])
            start += f.n_bonds
    return np.concatenate(ii).astype(np.intp), np.concatenate(jj).astype(np.intp)


def ridge_mask(
    bond_i: NDArray[np.integer], bond_j: NDArray[np.integer], damage: NDArray[np.float64]
) -> NDArray[np.bool_]:
    """Points on the ridge of a crack band, shape (n,): points owning one of the broken
    bonds (``bond_i``, ``bond_j``: their end points) whose damage is within
    ``RIDGE_TOLERANCE`` of the largest damage of the points across their broken bonds.
    Beside a straight crack these are the rows next to it (damage 0.350 at m = 2, 0.399
    at m = 3, 0.422 at m = 4 on a clean cut), not the rows farther out (0.05; 0.196 at
    m = 3), whose damage says nothing about whether a tracker sees the crack."""
    across = np.full(damage.shape[0], np.inf)
    across[bond_i] = -np.inf
    np.maximum.at(across, bond_i, damage[bond_j])
    return damage >= across - RIDGE_TOLERANCE


def crack_ridge(model: Model, s: State, damage: NDArray[np.float64]) -> NDArray[np.bool_]:
    """:func:`ridge_mask` of the bonds broken during the run (pre-cracks excluded)."""
    i, j = broken_pairs(model, s)
    return ridge_mask(i, j, damage)


def threshold_check(
    damage: NDArray[np.float64],
    ridge: NDArray[np.bool_],
    threshold: float,
    band: float = THRESHOLD_BAND,
    share: float = THRESHOLD_SHARE,
    min_points: int = THRESHOLD_MIN_POINTS,
) -> tuple[str | None, int, int, float]:
    """Whether a tracker's damage threshold misjudges the crack whose ridge is given.

    "at": at least ``share`` of the ridge points (:func:`crack_ridge`) lie within
    +-``band`` of the threshold, so whether a point counts as cracked is decided by
    round-off (a straight crack at m = 2 leaves 0.350 beside it: the default 0.35).
    "above": at least ``share`` of them lie below threshold - band: the tracker misses
    most of the crack. None otherwise, or with fewer than ``min_points`` ridge points.

    Parameters
    ----------
    damage : ndarray, shape (n,)
        Point damage.
    ridge : ndarray of bool, shape (n,)
        Ridge points of the crack band to judge.
    threshold : float
        The tracker's damage threshold.
    band, share, min_points
        The rule above.

    Returns
    -------
    kind : {"at", "above"} or None
    n : int
        Ridge points judged.
    k : int
        Of those, the ones within the band ("at") or below it ("above"; 0 for None).
    median : float
        Median damage of the ridge points (NaN if none).
    """
    d = damage[ridge]
    n = int(d.size)
    if n < min_points:
        return None, n, 0, float(np.median(d)) if n else float("nan")
    med = float(np.median(d))
    at = int(np.count_nonzero(np.abs(d - threshold) <= band))
    below = int(np.count_nonzero(d < threshold - band))
    if at >= share * n:
        return "at", n, at, med
    if below >= share * n:
        return "above", n, below, med
    return None, n, 0, med


def warn_threshold(
    ctx: RunContext,
    s: State,
    results: dict[str, Any],
    key: str,
    threshold: float,
    region: NDArray[np.bool_] | None = None,
) -> None:
    """Add a warning to ``results["warnings"]`` (and ``warnings.warn`` a
    :class:`CrackThresholdWarning`) when the damage threshold ``key`` misjudges the
    cracks grown in the run (inside ``region`` if given): :func:`threshold_check`."""
    m = ctx.model
    if m.dim < 2:
        return
    damage = ctx.damage(s)
    ridge = crack_ridge(m, s, damage)
    if region is not None:
        ridge &= region
    kind, n, k, med = threshold_check(damage, ridge, threshold)
    if kind is None:
        return
    unit = "crack_length_m" if m.dim == 2 else "crack_area_m2"  # CrackLength's key
    lower = max(0.05, round(min(threshold, med) - 0.1, 2))
    what = (
        f"sits at the damage the crack leaves: {k} of the {n} points along the crack lie "
        f"within +-{THRESHOLD_BAND} of it (median {med:.3f}), so whether a point counts "
        "as cracked is decided by round-off and the tracked crack may be missed or cut short"
        if kind == "at"
        else f"is above the damage the crack leaves: {k} of the {n} points along the "
        f"crack lie below {threshold - THRESHOLD_BAND:.2f} (median {med:.3f}), so the "
        "tracker misses that part of the crack"
    )
    msg = (
        f"{key} = {threshold:g} {what}; use a lower threshold (e.g. {lower:g}) or the "
        f"broken-bond measure results.{unit}"
    )
    results.setdefault("warnings", []).append(msg)
    warnings.warn(msg, CrackThresholdWarning, stacklevel=2)


def crack_tip_region(model: Model, spec: dk.CrackTip) -> NDArray[np.bool_] | None:
    """Points ahead of a crack tip's origin (less one horizon), or ``None`` (all)."""
    if spec.direction is None:
        return None
    d = np.asarray(spec.direction, dtype=float)
    d = d / np.linalg.norm(d)
    rel = model.cloud.x - np.asarray(spec.origin, dtype=float)
    return np.asarray(rel @ d >= -model.bonds.horizon)


def crack_length_observers(deck: dk.Deck, model: Model) -> list[Observer]:
    """The observers of this module a deck gets: :class:`CrackLength` in 2-D and 3-D when
    bonds can break and ``output.crack_length`` is on."""
    if model.dim < 2 or not getattr(deck.output, "crack_length", True):
        return []
    if not can_break_bonds(deck):
        return []
    return [CrackLength(deck, model)]
