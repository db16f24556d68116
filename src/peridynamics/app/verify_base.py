"""The data of a verification case of ``peridynamics verify``
(:mod:`peridynamics.app.verify_cases`): :class:`~peridynamics.app.verify_base.Check`
(one measured quantity against its reference) and
:class:`~peridynamics.app.verify_base.Case` (an example deck at a tier's size and its
checks), and the readers of a run's ``summary.json`` mapping the case modules share.

A check reads the run's ``summary.json`` mapping (with ``"folder"``, the run's folder,
for a check that reads the final fields) and returns the measured value; the reference
is a number computed from the deck's own parameters (so an override that changes E also
changes the reference), never a number an earlier run of this code printed.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

Summary = dict[str, Any]

__all__ = ["Case", "Check", "Summary", "material", "probe"]


@dataclass(frozen=True)
class Check:
    """One measured quantity against its reference.

    Attributes
    ----------
    quantity : str
        What is measured (a sentence fragment, with the unit in ``unit``).
    unit : str
        Unit of the measured and reference values (SI).
    measure : callable
        ``measure(summary) -> float``: the value from the run.
    reference : callable
        ``reference(inputs) -> float``: the reference from the deck's parameters
        (``summary["inputs"]``, the validated deck as data).
    source : str
        Where the reference comes from (an author-year citation listed in
        ``docs/references.md``, or the closed form it is).
    rel : float
        Relative tolerance (``|measured - reference| <= rel |reference| + abs``).
    abs : float
        Absolute tolerance, in ``unit``.
    at_most : bool
        An upper bound: passes when ``measured <= reference (1 + rel)`` (a crack speed
        below the Rayleigh speed, ...).
    """

    quantity: str
    unit: str
    measure: Callable[[Summary], float]
    reference: Callable[[Summary], float]
    source: str
    rel: float = 0.0
    abs: float = 0.0
    at_most: bool = False

    def judge(self, measured: float, reference: float) -> bool:
        """Whether ``measured`` is within the tolerance of ``reference``."""
        if not (math.isfinite(measured) and math.isfinite(reference)):
            return False
        if self.at_most:
            return measured <= reference * (1.0 + self.rel) + self.abs
        return abs(measured - reference) <= self.rel * abs(reference) + self.abs


@dataclass(frozen=True)
class Case:
    """A shipped example run at a tier's size, and its checks.

    Attributes
    ----------
    name : str
        The case's name (``--only`` matches it).
    title : str
        One line on what is verified.
    deck : str
        The example deck, as ``peridynamics examples`` names it (``bar_wave_1d``,
        ``plate_tension_2d/adr``).
    quick : tuple of str or None
        ``--set`` overrides of the quick tier (``None``: not in the quick tier).
    full : tuple of str
        Overrides of the full tier (the shipped deck: ``()``).
    checks : tuple of Check
        What is compared.
    companion : tuple of str or None
        Overrides added to the tier's for a second run of the same deck (into
        ``<case>/companion/``), whose summary the checks read as ``summary["companion"]``:
        a case whose reference is another scheme's run of the same problem (the 1-D
        finite-difference scheme against peridynamics with delta = dx). ``None``: one run.
    series : tuple of tuple of str
        Further runs of the same deck, each with these overrides added to the tier's
        (into ``<case>/series_<k>/``), whose summaries the checks read as
        ``summary["series"]`` (in order, after the case's own run): the refinements of a
        convergence study. ``()``: none.
    """

    name: str
    title: str
    deck: str
    quick: tuple[str, ...] | None
    full: tuple[str, ...] = ()
    checks: tuple[Check, ...] = field(default_factory=tuple)
    companion: tuple[str, ...] | None = None
    series: tuple[tuple[str, ...], ...] = ()

    def overrides(self, tier: str) -> tuple[str, ...] | None:
        """The overrides of ``tier`` (``"quick"`` or ``"full"``), ``None`` when the case
        is not in it."""
        return self.quick if tier == "quick" else self.full


def probe(summary: Summary, name: str) -> dict[str, Any]:
    """The record of the probe ``name`` of a run (``results.probes``)."""
    return dict(summary["results"]["probes"][name])


def material(inputs: Summary) -> tuple[float, float]:
    """(Young's modulus (Pa), density (kg/m^3)) of the deck's material."""
    m = inputs["material"]
    return float(m["youngs_modulus"]), float(m["density"])
