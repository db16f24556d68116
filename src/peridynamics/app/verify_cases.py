"""The verification cases of ``peridynamics verify``: a shipped example deck at a stated
size, and the quantities measured from its run against references that do not come
from this code (closed-form solutions, published observations), each with its source
and a tolerance.

A case is data: the example, the overrides of each tier, and its checks
(:class:`~peridynamics.app.verify_base.Check`,
:class:`~peridynamics.app.verify_base.Case`). A check reads the run's
``summary.json`` mapping (with ``"folder"``, the run's folder, for a check that reads
the final fields) and returns the measured value; the reference is a number computed
from the deck's own parameters (so an override that changes E also changes the
reference), never a number an earlier run of this code printed.

The cases live by domain: waves (:mod:`~peridynamics.app.verify_waves`), static
elasticity (:mod:`~peridynamics.app.verify_elastic`), dynamic fracture and fatigue
(:mod:`~peridynamics.app.verify_fracture`), the micropolar static solver
(:mod:`~peridynamics.app.verify_micropolar`) and the Brazilian disc's convergence
studies (:mod:`~peridynamics.app.verify_brazilian`, cases of several runs);
:data:`CASES` lists them in report order.
"""

from __future__ import annotations

from peridynamics.app import verify_base
from peridynamics.app.verify_base import Case, Check, Summary
from peridynamics.app.verify_brazilian import (
    BRAZILIAN_DELTA_CONVERGENCE,
    BRAZILIAN_M_CONVERGENCE,
)
from peridynamics.app.verify_elastic import (
    PLATE_TENSION_ADR,
    PLATE_TENSION_EXPLICIT,
    PMB_BOX_MODULI,
    THERMAL_EXPANSION_BAR,
    lps_case,
)
from peridynamics.app.verify_fracture import (
    BEND_WORK_OF_FRACTURE,
    CRACK_BRANCHING,
    FATIGUE_SN_BAR,
    KALTHOFF_WINKLER,
)
from peridynamics.app.verify_micropolar import (
    MICROPOLAR_CANTILEVER,
    MICROPOLAR_DCB,
    MICROPOLAR_L_PANEL,
    MICROPOLAR_L_PANEL_PAPER,
)
from peridynamics.app.verify_waves import BAR_NEAREST_EQUALS_FDM, BAR_WAVE_1D

__all__ = ["CASES", "Case", "Check", "Summary", "select"]

#: every case, in report order
CASES: tuple[verify_base.Case, ...] = (
    BAR_WAVE_1D,
    BAR_NEAREST_EQUALS_FDM,
    PMB_BOX_MODULI,
    lps_case(0.1, (30, 20, 20)),
    lps_case(0.25, (30, 20, 20)),
    lps_case(0.35, (30, 20, 20)),
    PLATE_TENSION_EXPLICIT,
    PLATE_TENSION_ADR,
    CRACK_BRANCHING,
    THERMAL_EXPANSION_BAR,
    FATIGUE_SN_BAR,
    KALTHOFF_WINKLER,
    MICROPOLAR_CANTILEVER,
    MICROPOLAR_DCB,
    MICROPOLAR_L_PANEL,
    MICROPOLAR_L_PANEL_PAPER,
    BEND_WORK_OF_FRACTURE,
    BRAZILIAN_M_CONVERGENCE,
    BRAZILIAN_DELTA_CONVERGENCE,
)


def select(tier: str, pattern: str | None = None) -> list[Case]:
    """The cases of ``tier`` whose name matches the shell pattern ``pattern``."""
    from fnmatch import fnmatch

    return [
        c for c in CASES
        if c.overrides(tier) is not None and (pattern is None or fnmatch(c.name, pattern))
    ]  # fmt: skip
