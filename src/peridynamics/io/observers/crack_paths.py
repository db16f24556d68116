"""Cracks tracked by a damage threshold: the crack tip's branching analysis
(``output.crack_tip``) and crack paths followed from seed points
(``output.crack_paths``), with the Rayleigh speed of the model as run."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from peridynamics.analysis.crack import branching, tip_speed
from peridynamics.io.observers.base import Observer, RunContext, RunOptions
from peridynamics.io.observers.crack_threshold import crack_tip_region, warn_threshold
from peridynamics.io.options import CrackPathSpec, CrackTip
from peridynamics.solvers.base import StepResult
from peridynamics.state import State

if TYPE_CHECKING:
    from peridynamics.evaluation import Evaluator


class CrackBranching(Observer):
    """Crack-tip position and speed histories; in 2-D the branching analysis of the
    final damage field (the tip itself is recorded by :class:`History`)."""

    def __init__(self, spec: CrackTip, model: Evaluator) -> None:
        self.spec, self.model = spec, model

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        ct, cloud = self.spec, self.model.cloud
        pos = np.asarray(ctx.records["crack_tip_m"])
        speed = tip_speed(np.asarray(ctx.records["time_s"]), pos)
        results["crack_tip_position_m"] = pos.tolist()
        results["crack_tip_speed_m_per_s"] = speed.tolist()
        results["max_crack_tip_speed_m_per_s"] = float(speed.max()) if len(speed) else 0.0
        if cloud.dim == 2:
            origin = np.asarray(ct.origin, dtype=float)
            direction = np.asarray(ct.direction or [1.0, 0.0], dtype=float)
            direction = direction / np.linalg.norm(direction)
            n_br, dist = branching(
                cloud.x, ctx.damage(s), cloud.spacing, ct.damage_threshold, origin, direction
            )
            point = None if dist is None else (origin + dist * direction).tolist()
            results["crack_branches"] = n_br
            results["crack_branched"] = n_br >= 2
            results["branching_distance_m"] = dist
            results["branching_point_m"] = point
            results["branching_x_m"] = None if point is None else point[0]
        key = "output.crack_tip.damage_threshold"
        region = crack_tip_region(self.model, ct)
        warn_threshold(ctx, s, results, key, ct.damage_threshold, region)
        return []


def effective_modulus_ratio(model: Evaluator) -> float:
    """E of the model as run over the nominal E: the median over points of the strain
    energy density under a uniform uniaxial strain (1e-6 along x) over the continuum
    value (PMB; 1.0 for other families). About 1 with the surface correction, 0.84-0.86
    in 2-D without it."""
    material = model.material
    energy = getattr(material, "uniaxial_energy_density", None)
    if energy is None:
        return 1.0
    cloud, eps = model.cloud, 1e-6
    u = np.zeros_like(cloud.x)
    u[:, 0] = eps * (cloud.x[:, 0] - cloud.x[:, 0].mean())
    w = model.strain_energy_density(u, model.bonds.bond_intact)
    w_inf = energy(eps, cloud.dim, model.bonds.horizon, cloud.cross_section, cloud.plane)
    return float(np.median(w) / w_inf)


class CrackPaths(Observer):
    """Cracks followed from seed points as polylines (``output.crack_paths``): the path
    length at every history record (for the tip speed) and, at the end, the path, its
    length, initial angle, angles along it and tip speeds, flagged above the Rayleigh
    speed of the model as run (:mod:`peridynamics.analysis.crack_path`)."""

    def __init__(self, run: RunOptions, model: Evaluator) -> None:
        self.run, self.model = run, model
        self.specs = run.output.crack_paths
        self._last: tuple[int, dict[str, Any]] | None = None  # (step, paths) of the last record
        self._broken = -1  # state.bonds_broken at the last record

    def on_start(self, ctx: RunContext, s: State, resumed: bool) -> None:
        r = ctx.records
        r.setdefault("crack_path_time_s", [])
        r.setdefault("crack_path_length_m", {c.name: [] for c in self.specs})
        if not resumed:
            self.record(ctx, s)

    def on_step(self, ctx: RunContext, s: State, result: StepResult) -> None:
        if ctx.history_due(s):
            self.record(ctx, s)

    def paths(self, ctx: RunContext, s: State) -> dict[str, Any]:
        """The current path of every crack, by name (cracks with the same threshold and
        region are extracted together, so a crack never runs on into another's)."""
        from peridynamics.analysis.crack_path import extract_crack_paths

        m = self.model
        damage = ctx.damage(s)
        groups: dict[tuple[float, str | None], list[CrackPathSpec]] = {}
        for c in self.specs:
            groups.setdefault((c.damage_threshold, c.within), []).append(c)
        out: dict[str, Any] = {}
        for (thr, within), specs in groups.items():
            exclude = ctx.initial_damage() >= thr  # points notches and pre-cracks damage
            mask = None
            if within is not None:
                mask = np.zeros(m.n_points, dtype=bool)
                mask[m.cloud.node_set(within)] = True
            lengths = [c.initial_length for c in specs]
            found = extract_crack_paths(
                m.cloud.x, damage, [np.asarray(c.seed, dtype=float) for c in specs],
                m.cloud.spacing, thr, exclude=exclude, within=mask,
                reference_direction=[np.asarray(c.direction, dtype=float) for c in specs],
                initial_length=lengths[0] if len(set(lengths)) == 1 else None,
            )  # fmt: skip
            out.update({c.name: p for c, p in zip(specs, found, strict=True)})
        return out

    def record(self, ctx: RunContext, s: State) -> None:
        """Append the path lengths at this state (the paths of the last record are
        reused when no bond broke since: damage, and so the paths, are unchanged)."""
        r = ctx.records
        if self._last is not None and self._broken == s.bonds_broken:
            paths = self._last[1]
        else:
            paths = self.paths(ctx, s)
        self._broken = s.bonds_broken
        self._last = (s.step, paths)
        r["crack_path_time_s"].append(s.t)
        for name, p in paths.items():
            r["crack_path_length_m"][name].append(float(p.length))

    def finalize(self, ctx: RunContext, s: State, results: dict[str, Any]) -> list[str]:
        from peridynamics.analysis.crack_speed import rayleigh_speed, tip_speed_from_paths
        from peridynamics.families.pmb.material import fixed_poisson_ratio

        m, r = self.model, ctx.records
        mat = m.material
        nu = getattr(mat, "poisson_ratio", None)
        if nu is None:
            nu = fixed_poisson_ratio(m.dim, m.cloud.plane if m.dim == 2 else None)
        ratio = effective_modulus_ratio(m)
        plane = m.cloud.plane if m.dim == 2 and m.cloud.plane else "3d"
        # a per-point density (or modulus) array: its median, the one value the
        # Rayleigh speed of a single material takes
        rho = float(np.median(np.asarray(mat.density, dtype=float)))
        young = float(np.median(np.asarray(mat.youngs_modulus, dtype=float)))
        c_r = rayleigh_speed(ratio * young, nu, rho, plane, "exact")
        t = np.asarray(r["crack_path_time_s"])
        out: dict[str, Any] = {}
        # the last record is usually of this very state: reuse its paths
        final = self._last[1] if self._last and self._last[0] == s.step else self.paths(ctx, s)
        for name, p in final.items():
            lengths = np.asarray(r["crack_path_length_m"][name])
            static = self.run.static  # no physical time
            if len(t) >= 2 and not static:
                speed, flagged = tip_speed_from_paths(t, lengths, c_r)
            else:
                speed, flagged = np.zeros(len(t)), np.zeros(len(t), dtype=bool)
            out[name] = {
                "vertices_m": p.vertices.tolist(),
                "length_m": float(p.length),
                "initial_angle_deg": float(p.initial_angle_deg),
                "angles_deg": np.asarray(p.angles_deg).tolist(),
                "tip_m": np.asarray(p.tip).tolist(),
                "branches": len(p.branches),
                "time_s": t.tolist(),
                "length_history_m": lengths.tolist(),
                "tip_speed_m_per_s": speed.tolist(),
                "max_tip_speed_m_per_s": float(speed.max()) if len(speed) else 0.0,
                "above_rayleigh_speed": int(np.count_nonzero(flagged)),
            }
        results["crack_paths"] = out
        results["rayleigh_speed_m_per_s"] = c_r
        results["effective_modulus_ratio"] = ratio
        for k, c in enumerate(self.specs):  # over tracked cracks (a handful)
            region = None
            if c.within is not None:
                region = np.zeros(m.n_points, dtype=bool)
                region[m.cloud.node_set(c.within)] = True
            key = f"output.crack_paths[{k}].damage_threshold"
            warn_threshold(ctx, s, results, key, c.damage_threshold, region)
        return []
