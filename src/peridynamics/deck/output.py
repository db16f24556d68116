"""Deck section ``output``: the output options (:mod:`peridynamics.io.options`,
which observers read) checked against the rest of the deck: node sets, rigid bodies,
probes named before they are combined, vectors of the model's dimension."""

from __future__ import annotations

from typing import Any

from peridynamics.deck.regions import check_len, check_nonzero
from peridynamics.deck.thermal_coupling import coupling_of
from peridynamics.deck.types import Errors
from peridynamics.io.options import (
    CrackPathSpec,
    CrackTip,
    Fracture,
    Output,
    Period,
    Probe,
    Quantity,
    Slice,
    StressStrain,
    WaveComparison,
    load_source,
)

__all__ = [
    "CrackPathSpec",
    "CrackTip",
    "Fracture",
    "Output",
    "Period",
    "Probe",
    "Quantity",
    "Slice",
    "StressStrain",
    "WaveComparison",
    "crack_tracking_errors",
    "output_errors",
    "probe_errors",
]


def output_errors(deck: Any, sets: set[str]) -> Errors:
    """Checks of the output options against the deck: the probe of ``period``, probes
    combined, rigid bodies, node sets, the load of ``peak_load``, figures of the
    model's dimension, the stress-strain direction, the 1-D wave comparison."""
    errors: Errors = []
    out, dim = deck.output, deck.dim
    probe_names = {p.name for p in out.probes}
    if out.period is not None and out.period.probe not in probe_names:
        errors.append(
            (
                "output.period.probe",
                f"unknown probe {out.period.probe!r}; known: {sorted(probe_names)}",
            )
        )
    ss = out.stress_strain
    errors += _option_errors(out, dim, sets, {b.name for b in deck.rigid_bodies})
    if ss is not None:
        check_len(errors, "output.stress_strain.direction", ss.direction, dim)
        check_nonzero(errors, "output.stress_strain.direction", ss.direction)
    if out.wave_comparison is not None and dim != 1:
        errors.append(("output.wave_comparison", "the d'Alembert comparison is 1-D"))
    return errors


def probe_errors(deck: Any, sets: set[str]) -> Errors:
    """Checks of ``output.probes``: 1-D quantities, rotations of a family with point
    rotations, node sets, components of the model's dimension, unique names."""
    errors: Errors = []
    dim, probes = deck.dim, deck.output.probes
    if dim != 1:
        for n, probe in enumerate(probes):
            if probe.quantity == "section_stress":
                errors.append((f"output.probes.{n}.quantity", "section_stress is 1-D"))
    for n, probe in enumerate(probes):
        if probe.quantity in ("rotation", "moment") and not deck.material.point_rotations:
            errors.append(
                (
                    f"output.probes.{n}.quantity",
                    f"{probe.quantity} is a point rotation's: only material.model micropolar "
                    "has point rotations",
                )
            )
        stress_kind = probe.quantity in ("stress", "strain", "von_mises", "pressure",
                                         "principal_stress")  # fmt: skip
        if stress_kind and deck.material.model == "micropolar":
            errors.append(
                (
                    f"output.probes.{n}.quantity",
                    f"{probe.quantity} needs the point stress, which micropolar models do not "
                    "define (docs/stress.md); probe displacement, rotation or moment",
                )
            )
        heat = getattr(deck.solver, "type", "") in ("heat", "heat_steady")
        coupled = coupling_of(deck) is not None  # a thermo-mechanical run has both
        combined = probe.quantity in ("difference", "sum")
        allowed = coupled and probe.quantity == "temperature"
        if (probe.quantity == "temperature") != heat and not combined and not allowed:
            errors.append(
                (
                    f"output.probes.{n}.quantity",
                    "temperature needs a heat solver (solver.type heat or heat_steady) or "
                    "thermal.expansion with a mechanical solver"
                    if heat is False
                    else f"a heat solver records temperature, not {probe.quantity}",
                )
            )
        comp = {"xx": "x", "yy": "y", "zz": "z", "xy": "y", "yz": "z", "xz": "z"}
        if probe.component in comp and "xyz".index(comp[probe.component]) >= dim:
            errors.append(
                (
                    f"output.probes.{n}.component",
                    f"{probe.component} needs a {'xyz'.index(comp[probe.component]) + 1}-D "
                    f"model (this one is {dim}-D)",
                )
            )
        if probe.set not in sets and probe.quantity not in ("difference", "sum"):
            errors.append(
                (f"output.probes.{n}.set", f"unknown node set {probe.set!r}; known: {sorted(sets)}")
            )
        if probe.component in ("y", "z") and "xyz".index(probe.component) >= dim:
            errors.append(
                (
                    f"output.probes.{n}.component",
                    f"component {probe.component!r} does not exist in {dim}-D",
                )
            )
    names = [p.name for p in probes]
    dup = sorted({p for p in names if names.count(p) > 1})
    if dup:
        errors.append(("output.probes", f"probe names must be unique; repeated: {dup}"))
    return errors


def crack_tracking_errors(deck: Any, sets: set[str]) -> Errors:
    """Checks of ``output.crack_paths`` and ``output.crack_tip``: a 2-D or 3-D model,
    vectors of its dimension, unique names, known node sets."""
    errors: Errors = []
    dim = deck.dim
    names_seen: set[str] = set()
    for n, cp in enumerate(deck.output.crack_paths):
        path = f"output.crack_paths.{n}"
        if dim == 1:
            errors.append((path, "crack paths need a 2-D or 3-D model"))
        check_len(errors, f"{path}.seed", cp.seed, dim)
        check_len(errors, f"{path}.direction", cp.direction, dim)
        check_nonzero(errors, f"{path}.direction", cp.direction)
        if cp.within is not None and cp.within not in sets:
            errors.append((f"{path}.within", f"unknown node set {cp.within!r}"))
        if cp.name in names_seen:
            errors.append((f"{path}.name", f"crack path {cp.name!r} is given twice"))
        names_seen.add(cp.name)
    tip = deck.output.crack_tip
    if tip is not None:
        check_len(errors, "output.crack_tip.origin", tip.origin, dim)
        check_len(errors, "output.crack_tip.direction", tip.direction, dim)
        check_nonzero(errors, "output.crack_tip.direction", tip.direction)
    return errors


def _option_errors(out: Output, dim: int, sets: set[str], rigid: set[str]) -> Errors:
    """Cross-checks of the output section against the rest of the deck (``sets``: node
    set names, ``rigid``: rigid body names): (key path, message) pairs."""
    errors: Errors = []
    seen: list[str] = []
    for n, p in enumerate(out.probes):
        for name in p.of or []:
            if name not in seen:
                errors.append(
                    (
                        f"output.probes.{n}.of",
                        f"{name!r} is not a probe listed before {p.name!r}; a derived "
                        f"probe combines earlier probes (listed before it: {seen})",
                    )
                )
        if p.body is not None and p.body not in rigid:
            errors.append(
                (
                    f"output.probes.{n}.body",
                    f"unknown rigid body {p.body!r}; known: {sorted(rigid)}",
                )
            )
        seen.append(p.name)
    ss = out.stress_strain
    if ss is not None and ss.body is not None and ss.body not in rigid:
        errors.append(
            ("output.stress_strain.body", f"unknown rigid body {ss.body!r}; known: {sorted(rigid)}")
        )
    if ss is not None and ss.set is not None and ss.set not in sets:
        errors.append(("output.stress_strain.set", f"unknown node set {ss.set!r}"))
    if out.load_probe is not None and out.load_probe not in seen:
        errors.append(("output.load_probe", f"unknown probe {out.load_probe!r}; known: {seen}"))
    if "peak_load" in out.frames_on and load_source(out) is None:
        errors.append(
            (
                "output.frames_on",
                "peak_load needs a load: output.load_probe (a probe name), "
                "output.stress_strain or a reaction_force probe",
            )
        )
    if out.slices and dim != 3:
        errors.append(("output.slices", "slices are planes through a 3-D model; remove them"))
    kinds = [out.plot] if isinstance(out.plot, str) else list(out.plot)
    if "stress_strain" in kinds and ss is None:
        errors.append(("output.plot", "stress_strain needs an output.stress_strain section"))
    if dim == 1 and out.png_frames:
        errors.append(("output.png_frames", "PNG frames are 2-D/3-D figures; remove it in 1-D"))
    if dim == 1 and "deformed" in kinds:
        errors.append(("output.plot", "deformed is a 2-D/3-D figure; use probes or damage"))
    return errors
