"""Converged plane-stress finite-element reference for the micropolar cantilever example.

The body is the rectangle 0 <= x <= L, 0 <= y <= H (m) of thickness t (m), isotropic and linear
elastic in plane stress (Young's modulus E in Pa, Poisson's ratio nu). With the default
``bc="clamped"`` the left edge x = 0 is fully clamped (u = 0) and the right edge x = L carries a
uniform shear traction F / (H t) (Pa) in y whose resultant is the end force F (N, signed,
negative downwards); the top and bottom faces are free. This is the set-up of the peridynamic
cantilever; like it, it does not reproduce the warping displacements that the elasticity
solution of Timoshenko & Goodier (1970), section 21, prescribes on its clamped section
(:func:`peridynamics.analysis.beams.timoshenko_goodier_cantilever`). With
``bc="timoshenko"`` the same model is solved with the boundary conditions of that solution
(the parabolic end shear F (H**2/4 - s**2) / (2 I) with s = y - H/2 and I = t H**3 / 12, and the
exact displacements imposed on x = 0), and reproduces it: a check of the finite-element model
and of the closed form together.

Discretisation (scikit-fem): quadratic Lagrange triangles (``ElementTriP2``, vector valued) on
a uniform grid of square cells of side H / (3 * 2**refine), each split in two triangles, then
refined ``corner_levels`` more times near the four corners (elements within two current cell
sizes of a corner are bisected, conformingly). The corners are singular points: the clamped
ones (a fixed edge meeting a free one) and the loaded ones (the uniform end shear meeting a free
face), and the maximum deflection lies at a loaded corner. On uniform grids the displacement
converges there only like h**1 to h**1.2 (1e-4 relative in max |u_y| needs about 6e4
unknowns); with the corner refinement the default mesh (about 1.1e4 unknowns, 0.1 s) is within
1e-5 of the finest mesh of the table. The system is solved directly (scipy's sparse LU through
``skfem.solve``).

Usage::

    python examples/micropolar/fem_reference.py                 # table + fem_reference.json
    python examples/micropolar/fem_reference.py --out DIR/ref.json --thickness 0.01

Prints, for uniform and corner-refined meshes, max |u_x| and max |u_y| over the body (nodal
values of the quadratic field, vertices and edge midpoints), the neutral-axis tip deflection
u_y(L, H/2), the number of unknowns and the wall time, and writes the default solution, the
table and displacement profiles along y = 0, H/2 and H into a JSON file.

Importable: ``solve_cantilever(...)`` returns a :class:`CantileverFEM` whose
``displacement(points)`` evaluates u at arbitrary points of the body. scikit-fem is imported
only inside the functions of this script (it is a test extra, not a package dependency).

References: S. P. Timoshenko and J. N. Goodier, *Theory of Elasticity*, 3rd ed. (McGraw-Hill,
1970), section 21; C. E. Augarde and A. J. Deeks, *Finite Elements in Analysis and Design* 44
(2008) 595-601 (the cantilever as a finite-element benchmark).
"""

# No ``from __future__ import annotations``: with string annotations the dataclass below needs
# the module in sys.modules, which loading this file by path (importlib) does not provide.
import argparse
import json
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

F64 = NDArray[np.float64]
BoundaryConditions = Literal["clamped", "timoshenko"]

#: Default mesh: uniform cells of side H / 12, ten corner-refinement levels. Converged to about
#: 1e-5 relative in max |u_x| and max |u_y| (see the table printed by the script).
DEFAULT_REFINE = 2
DEFAULT_CORNER_LEVELS = 10


@dataclass
class CantileverFEM:
    """Plane-stress finite-element solution of the cantilever.

    Attributes
    ----------
    length, height, thickness : float
        L, H and t (m); the body is 0 <= x <= L, 0 <= y <= H, the neutral axis y = H / 2.
    E : float
        Young's modulus (Pa).
    nu : float
        Poisson's ratio.
    force : float
        End force F (N), signed (negative downwards).
    bc : {"clamped", "timoshenko"}
        Boundary conditions (see the module docstring).
    refine, corner_levels : int
        Mesh parameters of :func:`solve_cantilever`.
    basis : skfem.CellBasis
        Vector P2 basis on the mesh.
    u : ndarray
        Degrees of freedom (m), interleaved (u_x, u_y) per node as in scikit-fem.
    seconds : float
        Wall time of meshing, assembly and solution (s).
    """

    length: float
    height: float
    thickness: float
    E: float
    nu: float
    force: float
    bc: str
    refine: int
    corner_levels: int
    basis: Any
    u: F64
    seconds: float

    @property
    def n_dofs(self) -> int:
        """Number of unknowns (two per P2 node)."""
        return int(self.u.size)

    @property
    def n_elements(self) -> int:
        """Number of triangles."""
        return int(self.basis.mesh.t.shape[1])

    @property
    def min_element_size(self) -> float:
        """Shortest edge of the mesh (m)."""
        mesh = self.basis.mesh
        p = mesh.p[:, mesh.facets]
        return float(np.min(np.hypot(p[0, 1] - p[0, 0], p[1, 1] - p[1, 0])))

    def _component(self, k: int) -> F64:
        return self.u[self.basis.split_indices()[k]]

    @property
    def max_abs_ux(self) -> float:
        """max |u_x| over the nodes (vertices and edge midpoints) of the body (m)."""
        return float(np.max(np.abs(self._component(0))))

    @property
    def max_abs_uy(self) -> float:
        """max |u_y| over the nodes (vertices and edge midpoints) of the body (m)."""
        return float(np.max(np.abs(self._component(1))))

    @property
    def tip_uy(self) -> float:
        """Deflection u_y(L, H / 2) on the neutral axis at the loaded end (m), signed."""
        return float(self.displacement([[self.length, 0.5 * self.height]])[0, 1])

    def displacement(self, points: ArrayLike) -> F64:
        """Displacement (m) at ``points``.

        Parameters
        ----------
        points : array_like, shape (n, 2)
            Coordinates (m) inside the body 0 <= x <= L, 0 <= y <= H; points within 1e-9 of
            the body's size outside it are moved onto its boundary.

        Returns
        -------
        ndarray, shape (n, 2)
            (u_x, u_y) at each point (m).

        Raises
        ------
        ValueError
            If a point lies outside the body.
        """
        pts = np.atleast_2d(np.asarray(points, dtype=float))
        if pts.ndim != 2 or pts.shape[1] != 2:
            raise ValueError(f"points must have shape (n, 2), got {pts.shape}")
        tol = 1e-9 * max(self.length, self.height)
        lo = np.array([0.0, 0.0])
        hi = np.array([self.length, self.height])
        if np.any(pts < lo - tol) or np.any(pts > hi + tol):
            raise ValueError("points must lie inside the body [0, L] x [0, H]")
        pts = np.clip(pts, lo, hi)
        values = self.basis.probes(pts.T) @ self.u
        n = pts.shape[0]
        return np.column_stack([values[:n], values[n:]])

    def summary(self) -> dict[str, float | int | str]:
        """Scalar results and mesh data as a JSON-ready dict (SI units)."""
        return {
            "bc": self.bc,
            "refine": self.refine,
            "corner_levels": self.corner_levels,
            "n_dofs": self.n_dofs,
            "n_elements": self.n_elements,
            "min_element_size_m": self.min_element_size,
            "max_abs_ux_m": self.max_abs_ux,
            "max_abs_uy_m": self.max_abs_uy,
            "tip_uy_m": self.tip_uy,
            "seconds": self.seconds,
        }


def _mesh(length: float, height: float, refine: int, corner_levels: int) -> Any:
    """Uniform P2-ready triangle mesh refined towards the four corners."""
    from skfem import MeshTri

    if refine < 0 or corner_levels < 0:
        raise ValueError("refine and corner_levels must be non-negative")
    ny = 3 * 2**refine
    nx = max(1, round(length / height * ny))
    mesh = MeshTri.init_tensor(np.linspace(0.0, length, nx + 1), np.linspace(0.0, height, ny + 1))
    cell = min(length / nx, height / ny)
    corners = np.array([[0.0, 0.0, length, length], [0.0, height, 0.0, height]])
    for level in range(corner_levels):
        dist = np.min(
            np.hypot(mesh.p[0][:, None] - corners[0], mesh.p[1][:, None] - corners[1]), axis=1
        )
        near = dist <= 2.01 * cell / 2**level
        marked = np.nonzero(near[mesh.t].any(axis=0))[0]
        mesh = mesh.refined(marked)
    tol = 1e-12 * max(length, height)
    return mesh.with_boundaries(
        {
            "left": lambda x: np.abs(x[0]) < tol,
            "right": lambda x: np.abs(x[0] - length) < tol,
        }
    )


def solve_cantilever(
    length: float = 1.0,
    height: float = 0.3,
    thickness: float = 1.0,
    E: float = 200e9,
    nu: float = 0.2,
    force: float = -1000.0,
    refine: int = DEFAULT_REFINE,
    corner_levels: int = DEFAULT_CORNER_LEVELS,
    bc: BoundaryConditions = "clamped",
) -> CantileverFEM:
    """Solve the plane-stress cantilever with quadratic triangles (scikit-fem).

    Parameters
    ----------
    length, height, thickness : float
        L, H and t (m); the body is [0, L] x [0, H].
    E : float
        Young's modulus (Pa).
    nu : float
        Poisson's ratio.
    force : float
        Resultant end force F (N) in y, signed (negative downwards).
    refine : int
        Uniform level: square cells of side H / (3 * 2**refine), two triangles each.
    corner_levels : int
        Local refinement levels at the four corners (0 for a uniform mesh).
    bc : {"clamped", "timoshenko"}
        ``"clamped"``: u = 0 on x = 0 and a uniform shear traction F / (H t) on x = L.
        ``"timoshenko"``: the displacements of Timoshenko & Goodier (1970), section 21, on
        x = 0 and their parabolic end shear on x = L.

    Returns
    -------
    CantileverFEM
        The solution; ``displacement(points)`` evaluates it.
    """
    from skfem import (
        Basis,
        ElementTriP2,
        ElementVector,
        FacetBasis,
        LinearForm,
        asm,
        condense,
        solve,
    )
    from skfem.models.elasticity import linear_elasticity, plane_stress

    if bc not in ("clamped", "timoshenko"):
        raise ValueError(f"bc must be 'clamped' or 'timoshenko', got {bc!r}")
    if min(length, height, thickness, E) <= 0.0:
        raise ValueError("length, height, thickness and E must be positive")
    start = time.perf_counter()
    mesh = _mesh(length, height, refine, corner_levels)
    element = ElementVector(ElementTriP2())
    basis = Basis(mesh, element)
    lam, mu = plane_stress(E, nu)
    stiffness = thickness * asm(linear_elasticity(lam, mu), basis)

    inertia = thickness * height**3 / 12.0

    @LinearForm
    def end_traction(v: Any, w: Any) -> Any:
        if bc == "clamped":
            return force / (height * thickness) * v[1]
        s = w.x[1] - 0.5 * height
        return force * (0.25 * height**2 - s**2) / (2.0 * inertia) * v[1]

    right = FacetBasis(mesh, element, facets=mesh.boundaries["right"])
    load = thickness * asm(end_traction, right)

    clamped = basis.get_dofs("left").all()
    prescribed = np.zeros(basis.N)
    if bc == "timoshenko":
        from peridynamics.analysis.beams import timoshenko_goodier_cantilever

        ix, iy = basis.split_indices()
        locs = basis.doflocs
        args = (force, length, height, thickness, E, nu)
        prescribed[ix] = timoshenko_goodier_cantilever(
            locs[0, ix], locs[1, ix] - 0.5 * height, *args
        )[0]
        prescribed[iy] = timoshenko_goodier_cantilever(
            locs[0, iy], locs[1, iy] - 0.5 * height, *args
        )[1]
    u = solve(*condense(stiffness, load, x=prescribed, D=clamped))
    return CantileverFEM(
        length=length,
        height=height,
        thickness=thickness,
        E=E,
        nu=nu,
        force=force,
        bc=bc,
        refine=refine,
        corner_levels=corner_levels,
        basis=basis,
        u=np.asarray(u, dtype=float),
        seconds=time.perf_counter() - start,
    )


def convergence_table(
    meshes: list[tuple[int, int]],
    reference: dict[str, Any] | None = None,
    **kwargs: Any,
) -> list[dict[str, Any]]:
    """Solve on each (refine, corner_levels) of ``meshes``; one summary dict per mesh.

    ``kwargs`` go to :func:`solve_cantilever`. Each row gets the relative errors
    ``rel_error_max_abs_ux``, ``rel_error_max_abs_uy`` and ``rel_error_tip_uy`` against
    ``reference`` (a summary dict; by default the row of the last mesh of the list).
    """
    rows: list[dict[str, Any]] = [
        solve_cantilever(refine=r, corner_levels=k, **kwargs).summary() for r, k in meshes
    ]
    ref = rows[-1] if reference is None else reference
    for row in rows:
        for key in ("max_abs_ux", "max_abs_uy", "tip_uy"):
            row[f"rel_error_{key}"] = float(row[f"{key}_m"]) / float(ref[f"{key}_m"]) - 1.0
    return rows


def _print_table(title: str, rows: list[dict[str, float | int | str]]) -> None:
    print(title)
    print(
        f"{'refine':>6} {'corner':>6} {'dofs':>7} {'h_min (m)':>10} {'max|ux| (m)':>13}"
        f" {'max|uy| (m)':>13} {'tip uy (m)':>14} {'err|ux|':>8} {'err|uy|':>8} {'err tip':>8}"
        f" {'time (s)':>8}"
    )
    for r in rows:
        print(
            f"{r['refine']:>6} {r['corner_levels']:>6} {r['n_dofs']:>7}"
            f" {r['min_element_size_m']:>10.2e} {r['max_abs_ux_m']:>13.6e}"
            f" {r['max_abs_uy_m']:>13.6e} {r['tip_uy_m']:>14.6e}"
            f" {r['rel_error_max_abs_ux']:>8.1e} {r['rel_error_max_abs_uy']:>8.1e}"
            f" {r['rel_error_tip_uy']:>8.1e} {r['seconds']:>8.2f}"
        )


def main(argv: list[str] | None = None) -> dict[str, Any]:
    """Run the convergence study, print it and write the JSON reference."""
    from peridynamics.analysis.beams import (
        euler_bernoulli_tip_deflection,
        timoshenko_beam_tip_deflection,
        timoshenko_goodier_cantilever,
        timoshenko_goodier_tip_deflection,
    )

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("fem_reference.json"))
    parser.add_argument("--length", type=float, default=1.0, help="L (m)")
    parser.add_argument("--height", type=float, default=0.3, help="H (m)")
    parser.add_argument("--thickness", type=float, default=1.0, help="t (m)")
    parser.add_argument("--E", type=float, default=200e9, help="Young's modulus (Pa)")
    parser.add_argument("--nu", type=float, default=0.2, help="Poisson's ratio")
    parser.add_argument("--force", type=float, default=-1000.0, help="end force (N), signed")
    parser.add_argument("--refine", type=int, default=DEFAULT_REFINE)
    parser.add_argument("--corner-levels", type=int, default=DEFAULT_CORNER_LEVELS)
    parser.add_argument("--max-refine", type=int, default=4, help="finest level of the table")
    args = parser.parse_args(argv)

    params = {
        "length": args.length,
        "height": args.height,
        "thickness": args.thickness,
        "E": args.E,
        "nu": args.nu,
        "force": args.force,
    }
    beam = (args.force, args.length, args.height, args.thickness, args.E)
    closed_form = {
        "timoshenko_goodier_tip_uy_m": timoshenko_goodier_tip_deflection(*beam, args.nu),
        "timoshenko_beam_tip_uy_m": timoshenko_beam_tip_deflection(*beam, args.nu),
        "euler_bernoulli_tip_uy_m": euler_bernoulli_tip_deflection(*beam),
    }
    levels = range(args.max_refine + 1)
    graded = convergence_table([(r, args.corner_levels) for r in levels], **params)
    uniform = convergence_table([(r, 0) for r in levels], reference=graded[-1], **params)
    title = "relative errors against the finest corner-refined mesh"
    _print_table(f"Uniform meshes ({title}):", uniform)
    _print_table(f"Corner-refined meshes, {args.corner_levels} levels ({title}):", graded)

    default = solve_cantilever(refine=args.refine, corner_levels=args.corner_levels, **params)
    ref = graded[-1]
    errors = {
        f"rel_error_{key[:-2]}": getattr(default, key[:-2]) / float(ref[key]) - 1.0
        for key in ("max_abs_ux_m", "max_abs_uy_m", "tip_uy_m")
    }

    exact = solve_cantilever(
        refine=args.refine, corner_levels=args.corner_levels, bc="timoshenko", **params
    )
    x = np.linspace(0.0, args.length, 41)
    profiles: dict[str, Any] = {"x_m": x.tolist()}
    for name, y in (("bottom", 0.0), ("neutral_axis", 0.5 * args.height), ("top", args.height)):
        u = default.displacement(np.column_stack([x, np.full_like(x, y)]))
        profiles[name] = {"y_m": y, "ux_m": u[:, 0].tolist(), "uy_m": u[:, 1].tolist()}
    gx, gy = np.meshgrid(x, np.linspace(0.0, args.height, 13))
    pts = np.column_stack([gx.ravel(), gy.ravel()])
    tg = np.column_stack(
        timoshenko_goodier_cantilever(pts[:, 0], pts[:, 1] - 0.5 * args.height, *beam, args.nu)
    )
    check = float(np.max(np.abs(exact.displacement(pts) - tg)) / np.max(np.abs(tg)))

    print(
        f"Default mesh (refine={args.refine}, corner_levels={args.corner_levels}):"
        f" max|ux| = {default.max_abs_ux:.6e} m, max|uy| = {default.max_abs_uy:.6e} m,"
        f" tip uy = {default.tip_uy:.6e} m, {default.n_dofs} dofs, {default.seconds:.2f} s;"
        " rel. error vs finest corner-refined mesh: "
        + ", ".join(f"{k[10:]} {v:.1e}" for k, v in errors.items())
    )
    tg_tip = closed_form["timoshenko_goodier_tip_uy_m"]
    print(
        "Closed forms, tip u_y (m): Timoshenko-Goodier"
        f" {tg_tip:.4e}, Timoshenko beam {closed_form['timoshenko_beam_tip_uy_m']:.4e},"
        f" Euler-Bernoulli {closed_form['euler_bernoulli_tip_uy_m']:.4e};"
        f" FE (clamped) / Timoshenko-Goodier tip - 1: tip u_y {default.tip_uy / tg_tip - 1:+.2%},"
        f" max|u_y| {default.max_abs_uy / abs(tg_tip) - 1:+.2%}"
    )
    print(f"FE with Timoshenko-Goodier conditions: max|u - u_TG| / max|u_TG| = {check:.1e}")

    result = {
        "description": "Plane-stress FE (P2 triangles, scikit-fem) of the clamped cantilever",
        "parameters": params,
        "default": default.summary() | errors,
        "closed_form": closed_form,
        "timoshenko_goodier_check_rel_error": check,
        "uniform": uniform,
        "corner_refined": graded,
        "profiles": profiles,
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(result, indent=2) + "\n")
    print(f"wrote {args.out}")
    return result


if __name__ == "__main__":
    main()
