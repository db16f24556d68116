"""The warning raised when a threshold-based crack tracker (``output.crack_tip``,
``output.crack_paths``) has its threshold at the damage the crack leaves (a straight
crack at m = 2 leaves phi = 0.350 beside it)."""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.io.observers.base import RunContext
from peridynamics.io.observers.crack_bonds import broken_pairs
from peridynamics.io.options import CrackTip
from peridynamics.state import State

if TYPE_CHECKING:
    from peridynamics.evaluation import Evaluator

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


def crack_ridge(
    model: Evaluator, s: State, damage: NDArray[np.float64], session: Any = None
) -> NDArray[np.bool_]:
    """:func:`ridge_mask` of the bonds broken during the run (pre-cracks excluded;
    ``session``: of a decomposed run, see :func:`broken_pairs`)."""
    i, j = broken_pairs(model, s, session)
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
    ridge = crack_ridge(m, s, damage, ctx.session)
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
    advice = (
        f"use a lower threshold (e.g. {lower:g}) or the broken-bond measure results.{unit}"
        if lower < threshold
        else f"a lower threshold would count damage that is no crack; use the broken-bond "
        f"measure results.{unit} (or a finer discretisation)"
    )
    msg = f"{key} = {threshold:g} {what}; {advice}"
    results.setdefault("warnings", []).append(msg)
    warnings.warn(msg, CrackThresholdWarning, stacklevel=2)


def crack_tip_region(model: Evaluator, spec: CrackTip) -> NDArray[np.bool_] | None:
    """Points ahead of a crack tip's origin (less one horizon), or ``None`` (all)."""
    if spec.direction is None:
        return None
    d = np.asarray(spec.direction, dtype=float)
    d = d / np.linalg.norm(d)
    rel = model.cloud.x - np.asarray(spec.origin, dtype=float)
    return np.asarray(rel @ d >= -model.bonds.horizon)
