"""Plate with a circular hole (LPS, plane stress, static ADR) against Kirsch (1898).

Runs ``plate_hole.yaml`` (or a given deck), recovers the stress from the displacement
field and compares sigma_xx along the line through the hole centre perpendicular to the
load with Kirsch's solution for an infinite plate (Timoshenko & Goodier 1970, sec. 35):

    sigma_xx(r, theta = 90 deg) = sigma / 2 (2 + a^2 / r^2 + 3 a^4 / r^4).

Stress recovery (:func:`nonlocal_stress`): the nonlocal least-squares deformation
gradient over each point's family,

    F_i = (sum_j omega y_ij (x) xi_ij V_j) (sum_j omega xi_ij (x) xi_ij V_j)^-1,

strain eps = sym(F - I) and the plane-stress (or plane-strain) Hooke law with the deck's
E and nu. It is exact for an affine displacement field, also on a truncated family.

What is compared (written into ``kirsch.json``), against two references: Kirsch's
infinite plate and the *same finite plate* solved by classical (local) plane-stress
elasticity with finite elements (:func:`fe_plate_hole`), which carries the finite width
and length that Kirsch leaves out (+1.7 to +3.8 % on 1.4 a <= r <= 4 a for 16a x 16a):

* the profile error PD / reference - 1 at r/a = 1 + delta/a, 1 + 2 delta/a, 2, 3, 4;
  within a horizon of the hole edge the recovered stress is a nonlocal average (and the
  LPS surface layer is stiffer than the bulk), so the profile is compared for
  r >= a + delta only;
* the concentration factor at r = a, extrapolated from the PD profile on
  [a + delta, a + 3 delta] (two wider ranges for the spread, and the same fits of the FE
  profile for the error of the extrapolation itself) by a least-squares fit of Kirsch's
  form A + B (a/r)^2 + C (a/r)^4, against Kirsch's 3, the FE value and the finite-width
  K_tg of Howland (1930) for a long strip as fitted in Peterson's Stress Concentration
  Factors (Pilkey & Pilkey 2008, Chart 4.1): K_tn = 2 + 0.284 (1 - d/W)
  - 0.600 (1 - d/W)^2 + 1.32 (1 - d/W)^3 on the net section, K_tg = K_tn / (1 - d/W) on
  the gross stress;
* the recovered stress at the points next to the hole (r = a + dx/2), and the balance
  of the section: int sigma_xx dy over the ligament / (sigma W) (1 for a stress field in
  equilibrium with the load; the deviation is the error of the stress recovery, largest
  in the surface layers);
* with ``--baseline``, the recovered sigma_xx on the same line of the plate without the
  hole (what the PD plate edges and loaded ends alone do to the field).

Usage::

    python examples/lps/kirsch.py                       # the deck as shipped (README)
    python examples/lps/kirsch.py --spacing 1.0e-3      # a coarser, quicker run
    python examples/lps/kirsch.py --set solver.tolerance=1.0e-10 --out results/x
    python examples/lps/kirsch.py --no-run --out DIR    # re-analyse final_state.npz
    python examples/lps/kirsch.py --baseline            # also the plate without the hole

Writes ``kirsch.json`` and ``kirsch.png`` into the output folder (default
``results/lps_plate_hole``) next to the run's own files.
"""

from __future__ import annotations

import argparse
import json
import platform
import subprocess
import time
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.app.run import Simulation
from peridynamics.bonds.bonds import Bonds
from peridynamics.build.cloud import build_bonds_for, build_cloud
from peridynamics.deck import Deck, load_deck
from peridynamics.geometry.cloud import PointCloud

HERE = Path(__file__).resolve().parent
DECK = HERE / "plate_hole.yaml"
#: radii (in units of delta beyond the hole edge, or of a) where the profile is compared
PROFILE_DELTAS = (1.0, 2.0)
PROFILE_RADII = (2.0, 3.0, 4.0)


def kt_fit_ranges(a: float, delta: float) -> list[tuple[str, float]]:
    """Upper ends of the Kirsch-form fits (all start at a + delta); the first is the one
    reported as the PD concentration factor, the others show the spread."""
    return [("a+delta..a+3delta", a + 3 * delta), ("a+delta..3a", 3 * a), ("a+delta..4a", 4 * a)]


# ----------------------------------------------------------------------- stress recovery
def nonlocal_stress(
    x: NDArray[np.float64],
    u: NDArray[np.float64],
    bonds: Bonds,
    youngs_modulus: float,
    poisson_ratio: float,
    plane: str = "stress",
    intact: NDArray[Any] | None = None,
    omega: NDArray[np.float64] | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Stress and strain of a 2-D displacement field from the nonlocal deformation
    gradient over each point's family (vectorised over bonds and points).

    F_i - I = (sum_j w eta_ij (x) xi_ij) K_i^-1, K_i = sum_j w xi_ij (x) xi_ij, with
    w = omega * V_j (the bond's partial volume) over the intact bonds, eta = u_j - u_i;
    eps = sym(F - I), sigma by Hooke's law.

    Parameters
    ----------
    x, u : (n, 2) reference positions and displacements (m).
    bonds : the directed bond list (``peridynamics.build.cloud.build_bonds_for``).
    youngs_modulus, poisson_ratio : E (Pa) and nu of the Hooke law.
    plane : "stress" (sigma_zz = 0) or "strain" (eps_zz = 0).
    intact : (n_bonds,) optional mask of intact bonds (``final_state.npz["intact"]``).
    omega : (n_bonds,) optional influence function (default 1).

    Returns
    -------
    sigma, eps : (n, 2, 2) stress (Pa) and strain tensors.
    """
    n, d = x.shape
    if d != 2:
        raise ValueError(f"nonlocal_stress is written for 2-D clouds, got dim = {d}")
    bi = bonds.bond_i.astype(np.intp)
    bj = bonds.bond_j.astype(np.intp)
    xi = x[bj] - x[bi]
    eta = u[bj] - u[bi]
    w = bonds.bond_volume * bonds.bond_intact
    if intact is not None:
        w = w * np.asarray(intact, dtype=np.float64)
    if omega is not None:
        w = w * omega
    shape_k = np.empty((n, d, d))
    grad_n = np.empty((n, d, d))
    for a in range(d):
        for b in range(d):
            shape_k[:, a, b] = np.bincount(bi, weights=w * xi[:, a] * xi[:, b], minlength=n)
            grad_n[:, a, b] = np.bincount(bi, weights=w * eta[:, a] * xi[:, b], minlength=n)
    # H = N K^-1  <=>  K H^T = N^T  (K symmetric)
    grad = np.swapaxes(np.linalg.solve(shape_k, np.swapaxes(grad_n, 1, 2)), 1, 2)
    eps = 0.5 * (grad + np.swapaxes(grad, 1, 2))
    E, nu = youngs_modulus, poisson_ratio
    mu = E / (2.0 * (1.0 + nu))
    lam = E * nu / (1.0 - nu**2) if plane == "stress" else E * nu / ((1 + nu) * (1 - 2 * nu))
    tr = eps[:, 0, 0] + eps[:, 1, 1]
    sigma = 2.0 * mu * eps + lam * tr[:, None, None] * np.eye(d)
    return sigma, eps


# ----------------------------------------------------------------------- references
def kirsch_sigma_xx(
    x: NDArray[np.float64], y: NDArray[np.float64], a: float, sigma: float
) -> NDArray[np.float64]:
    """Kirsch (1898): sigma_xx at (x, y) (relative to the hole centre) in an infinite
    plate with a hole of radius a under remote sigma_xx = sigma (Timoshenko & Goodier
    1970, eqs 61)."""
    r = np.hypot(x, y)
    c2, s2 = (x**2 - y**2) / r**2, 2.0 * x * y / r**2  # cos 2theta, sin 2theta
    q2, q4 = (a / r) ** 2, (a / r) ** 4
    s_rr = 0.5 * sigma * (1 - q2) + 0.5 * sigma * (1 - 4 * q2 + 3 * q4) * c2
    s_tt = 0.5 * sigma * (1 + q2) - 0.5 * sigma * (1 + 3 * q4) * c2
    s_rt = -0.5 * sigma * (1 + 2 * q2 - 3 * q4) * s2
    cos2 = x**2 / r**2
    sin2 = y**2 / r**2
    return s_rr * cos2 + s_tt * sin2 - s_rt * s2


def kirsch_profile(r: NDArray[np.float64] | float, a: float) -> Any:
    """sigma_xx(r, theta = 90 deg) / sigma = (2 + a^2/r^2 + 3 a^4/r^4) / 2."""
    q = (a / np.asarray(r)) ** 2
    return 0.5 * (2.0 + q + 3.0 * q**2)


def peterson_kt(d_over_w: float) -> dict[str, float]:
    """Finite-width concentration factor of a central hole in a strip under tension
    (Howland 1930; fit of Pilkey & Pilkey 2008, Chart 4.1): net and gross section."""
    s = 1.0 - d_over_w
    kt_net = 2.0 + 0.284 * s - 0.600 * s**2 + 1.32 * s**3
    return {"net": kt_net, "gross": kt_net / s}


def kirsch_form_fit(
    r: NDArray[np.float64], s: NDArray[np.float64], a: float
) -> NDArray[np.float64]:
    """Least-squares (A, B, C) of s(r) = A + B (a/r)^2 + C (a/r)^4."""
    q = (a / r) ** 2
    coef, *_ = np.linalg.lstsq(np.column_stack([np.ones_like(q), q, q**2]), s, rcond=None)
    return np.asarray(coef)


# ------------------------------------------------ finite-plate reference (local elasticity)
def _q4_gradients(
    xe: NDArray[np.float64], xi: float, eta: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Bilinear quadrilaterals with corners ``xe`` (ne, 4, 2), counter-clockwise: strain-
    displacement matrices B (ne, 3, 8) at the natural point (xi, eta) and det J (ne,)."""
    dn = 0.25 * np.array(
        [
            [-(1 - eta), 1 - eta, 1 + eta, -(1 + eta)],
            [-(1 - xi), -(1 + xi), 1 + xi, 1 - xi],
        ]
    )
    jac = np.einsum("ak,ekb->eab", dn, xe)
    det = jac[:, 0, 0] * jac[:, 1, 1] - jac[:, 0, 1] * jac[:, 1, 0]
    inv = np.empty_like(jac)
    inv[:, 0, 0], inv[:, 1, 1] = jac[:, 1, 1], jac[:, 0, 0]
    inv[:, 0, 1], inv[:, 1, 0] = -jac[:, 0, 1], -jac[:, 1, 0]
    dndx = np.einsum("eab,bk->eak", inv / det[:, None, None], dn)
    b = np.zeros((xe.shape[0], 3, 8))
    b[:, 0, 0::2] = dndx[:, 0]
    b[:, 1, 1::2] = dndx[:, 1]
    b[:, 2, 0::2] = dndx[:, 1]
    b[:, 2, 1::2] = dndx[:, 0]
    return b, det


def fe_plate_hole(
    a: float,
    half_width: float,
    half_length: float,
    poisson_ratio: float = 0.3,
    n: int = 160,
) -> dict[str, NDArray[np.float64]]:
    """sigma_xx / sigma on the line theta = 90 deg of the *finite* plate, by classical
    (local) plane-stress elasticity: the reference that includes the finite width and
    length, which Kirsch's infinite plate leaves out.

    A quarter of the plate (|x| <= half_length along the load, |y| <= half_width, hole
    of radius a at the centre) with symmetry conditions on x = 0 and y = 0 and a uniform
    traction on x = half_length; a mapped mesh of n x n bilinear quadrilaterals (2 x 2
    Gauss points) from the hole to the outer edges, graded towards the hole (ratio
    1 + 3/n); a sparse direct solve. sigma_xx at the nodes of the line x = 0 is the mean
    of the values of the two elements that share the node. Measured (16a x 16a): the
    profile for r >= 1.4 a changes by < 1e-4 between n = 120 and n = 360, the value at
    r = a by 0.16 % (see :func:`fe_reference`, which extrapolates it); with half-width
    and half-length 100 a the profile for r >= 1.4 a is Kirsch's within 0.04 %.

    Returns ``r`` (distance from the centre along x = 0, from a) and ``sigma_xx``.
    """
    import scipy.sparse as sp
    from scipy.sparse.linalg import spsolve

    theta = np.linspace(0.0, 0.5 * np.pi, n + 1)
    g = 1.0 + 3.0 / n
    s = (g ** np.arange(n + 1) - 1.0) / (g**n - 1.0)
    c, sn = np.cos(theta), np.sin(theta)
    with np.errstate(divide="ignore"):
        t = np.minimum(
            np.where(c > 1e-12, half_length / c, np.inf),
            np.where(sn > 1e-12, half_width / sn, np.inf),
        )
    ray = np.column_stack([c, sn])
    pts = a * ray[None] * (1.0 - s[:, None, None]) + (t[:, None] * ray)[None] * s[:, None, None]
    x = pts.reshape(-1, 2)
    nj = n + 1
    ii, jj = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    n0 = (ii * nj + jj).ravel()
    conn = np.column_stack([n0, n0 + nj, n0 + nj + 1, n0 + 1])
    nu = poisson_ratio
    dmat = np.array([[1.0, nu, 0.0], [nu, 1.0, 0.0], [0.0, 0.0, 0.5 * (1 - nu)]]) / (1 - nu**2)
    xe = x[conn]
    ke = np.zeros((conn.shape[0], 8, 8))
    gp = 1.0 / np.sqrt(3.0)
    for xi, eta in ((-gp, -gp), (gp, -gp), (gp, gp), (-gp, gp)):
        b, det = _q4_gradients(xe, xi, eta)
        ke += np.einsum("eia,ij,ejb->eab", b, dmat, b) * det[:, None, None]
    dofs = np.stack([2 * conn, 2 * conn + 1], axis=-1).reshape(-1, 8)
    ndof = 2 * x.shape[0]
    k = sp.coo_matrix(
        (ke.ravel(), (np.repeat(dofs, 8, axis=1).ravel(), np.tile(dofs, (1, 8)).ravel())),
        shape=(ndof, ndof),
    ).tocsr()
    f = np.zeros(ndof)
    edge = n * nj + np.flatnonzero(np.abs(pts[n, :, 0] - half_length) < 1e-9 * half_length)
    edge = edge[np.argsort(x[edge, 1])]
    half_seg = 0.5 * np.diff(x[edge, 1])
    np.add.at(f, 2 * edge[:-1], half_seg)
    np.add.at(f, 2 * edge[1:], half_seg)
    held = np.concatenate(
        [
            2 * np.flatnonzero(np.abs(x[:, 0]) < 1e-9 * a),
            2 * np.flatnonzero(np.abs(x[:, 1]) < 1e-9 * a) + 1,
        ]
    )
    free = np.setdiff1d(np.arange(ndof), held)
    u = np.zeros(ndof)
    u[free] = spsolve(k[free][:, free].tocsc(), f[free])
    last = np.flatnonzero(jj.ravel() == n - 1)  # the elements along theta = 90 deg
    acc, cnt = np.zeros(n + 1), np.zeros(n + 1)
    for xi, shift in ((1.0, 1), (-1.0, 0)):  # corners 3 (i + 1) and 4 (i), eta = +1
        b, _ = _q4_gradients(xe[last], xi, 1.0)
        sig = np.einsum("ij,ejb,eb->ei", dmat, b, u[dofs[last]])
        np.add.at(acc, ii.ravel()[last] + shift, sig[:, 0])
        np.add.at(cnt, ii.ravel()[last] + shift, 1.0)
    return {"r": pts[:, n, 1].copy(), "sigma_xx": acc / cnt}


def fe_reference(
    a: float, half_width: float, half_length: float, poisson_ratio: float, n: int = 160
) -> dict[str, Any]:
    """:func:`fe_plate_hole` at n and n/2; the concentration at r = a extrapolated to
    zero element size (error ~ 1/n, measured: n = 120, 240, 360 give 3.1434, 3.1396,
    3.1383 for the 16a x 16a plate, which extrapolate to 3.1358 and 3.1357)."""
    t0 = time.perf_counter()
    fine = fe_plate_hole(a, half_width, half_length, poisson_ratio, n)
    coarse = fe_plate_hole(a, half_width, half_length, poisson_ratio, n // 2)
    kt = 2.0 * fine["sigma_xx"][0] - coarse["sigma_xx"][0]
    return {
        "r": fine["r"],
        "sigma_xx": fine["sigma_xx"],
        "kt": float(kt),
        "kt_mesh": float(fine["sigma_xx"][0]),
        "elements": n * n,
        "seconds": time.perf_counter() - t0,
    }


# ----------------------------------------------------------------------- the deck
def deck_facts(deck: Deck) -> dict[str, Any]:
    """Hole centre and radius, plate size, remote traction, E, nu of a plate_hole deck."""
    g = deck.geometry
    holes = [h.circle for h in getattr(g, "holes", []) if h.circle is not None]
    if len(holes) != 1:
        raise ValueError("the deck needs exactly one circular hole (geometry.holes)")
    tractions = [bc for bc in deck.boundary_conditions if bc.type == "traction"]
    sigma = max(abs(float(bc.value[0])) for bc in tractions)
    m = deck.material
    return {
        "centre": np.asarray(holes[0].center, dtype=float),
        "a": float(holes[0].radius),
        "size": np.asarray(g.size, dtype=float),
        "origin": np.asarray(g.origin, dtype=float),
        "sigma": sigma,
        "E": float(m.youngs_modulus),
        "nu": float(getattr(m, "poisson_ratio", 1.0 / 3.0)),
        "plane": getattr(g, "plane", "stress"),
    }


def run_deck(deck: Deck, out: Path) -> dict[str, Any]:
    """Run the deck into ``out`` (the same as ``python -m peridynamics run``); returns the
    summary, with ``run_wall_s`` (set-up + solve + output, this process) added to it and
    to ``out/run_wall_s.txt``."""
    t0 = time.perf_counter()
    sim = Simulation.from_deck(deck)
    summary = sim.run(out, quiet=True)
    summary["run_wall_s"] = time.perf_counter() - t0
    (out / "run_wall_s.txt").write_text(f"{summary['run_wall_s']:.3f}\n")
    return summary


def run_facts(out: Path) -> dict[str, Any]:
    """ADR iterations, convergence and times of the run in ``out`` (its summary.json)."""
    summary = json.loads((out / "summary.json").read_text())
    r, t = summary["results"], summary["timing"]
    wall = out / "run_wall_s.txt"
    return {
        "iterations": r.get("iterations"),
        "converged": r.get("converged"),
        "residual": r.get("residual"),
        "tolerance": r.get("tolerance"),
        "solve_wall_s": t["wall_s"],
        "setup_s": t["setup_s"],
        "run_wall_s": float(wall.read_text()) if wall.exists() else None,
    }


# ----------------------------------------------------------------------- analysis
def recovered_sigma_xx(
    deck: Deck, out: Path, facts: dict[str, Any]
) -> tuple[tuple[PointCloud, Bonds], NDArray[np.float64], float]:
    """((cloud, bonds), sigma_xx / sigma at every point, recovery time) of the run of
    ``deck`` in ``out``, with the E, nu, idealisation and sigma of ``facts``."""
    cloud = build_cloud(deck)
    bonds = build_bonds_for(deck, cloud)
    state = np.load(out / "final_state.npz")
    t0 = time.perf_counter()
    sigma_t, _ = nonlocal_stress(
        cloud.x, state["u"], bonds, facts["E"], facts["nu"], facts["plane"], state["intact"]
    )
    return (cloud, bonds), sigma_t[:, 0, 0] / facts["sigma"], time.perf_counter() - t0


def line_profile(
    rel: NDArray[np.float64], values: NDArray[np.float64], dx: float
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.intp]]:
    """Values on the line theta = 90 deg: the column(s) of points nearest x = x_c (at
    x_c +- dx/2 when the centre lies between two columns), the points at the same |y|
    (left/right of the centre, above/below) averaged: by symmetry this is the value on
    the line x = x_c at r = |y| up to O(dx^2).

    Returns r = |y - y_c| (sorted), the mean, the rms spread about it and the indices of
    the column."""
    col = np.flatnonzero(np.abs(rel[:, 0]) <= np.abs(rel[:, 0]).min() + 1e-6 * dx)
    r_line = np.abs(rel[col, 1])  # distance along the line x = x_c
    key = np.round(r_line / (1e-3 * dx)).astype(np.int64)
    _, inv = np.unique(key, return_inverse=True)
    cnt = np.bincount(inv)
    r_p = np.bincount(inv, weights=r_line) / cnt
    v_p = np.bincount(inv, weights=values[col]) / cnt
    spread = np.sqrt(np.bincount(inv, weights=(values[col] - v_p[inv]) ** 2) / cnt)
    return r_p, v_p, spread, col


def analyse(deck: Deck, out: Path, baseline: tuple[Deck, Path] | None = None) -> dict[str, Any]:
    """Stress profile from ``out/final_state.npz`` against Kirsch; the measured numbers.
    With ``baseline`` (the deck of the same plate without the hole and the folder of its
    run), the recovered sigma_xx of the plain plate on the same line is reported too."""
    f = deck_facts(deck)
    (cloud, bonds), sxx, recover_s = recovered_sigma_xx(deck, out, f)
    a, s0, dx, delta = f["a"], f["sigma"], cloud.spacing, bonds.horizon
    rel = cloud.x - f["centre"]
    r_p, s_p, spread, col = line_profile(rel, sxx, dx)
    k_p = line_profile(rel, kirsch_sigma_xx(rel[:, 0], rel[:, 1], a, 1.0), dx)[1]
    err_p = (s_p - k_p) / k_p
    lo, hi = f["origin"], f["origin"] + f["size"]
    half = np.minimum(f["centre"] - lo, hi - f["centre"])
    if np.any(np.abs(f["centre"] - 0.5 * (lo + hi)) > 1e-6 * dx):
        raise ValueError("the finite-plate reference needs the hole at the plate centre")
    fe = fe_reference(a, half[1], half[0], f["nu"])
    fe_p = np.interp(r_p, fe["r"], fe["sigma_xx"])
    base = None
    if baseline is not None:
        (c0, _), sxx0, _ = recovered_sigma_xx(*baseline, f)
        r0, b0, _, _ = line_profile(c0.x - f["centre"], sxx0, dx)
        base = (r0, b0)

    targets = [a + m * delta for m in PROFILE_DELTAS] + [m * a for m in PROFILE_RADII]
    labels = [f"a+{m:g}delta" for m in PROFILE_DELTAS] + [f"{m:g}a" for m in PROFILE_RADII]
    profile = []
    for rt, lab in sorted(zip(targets, labels, strict=True)):
        if rt > r_p.max() or rt < a + delta - 1e-9 * dx:  # compared for r >= a + delta
            continue
        e = float(np.interp(rt, r_p, err_p))
        ke = float(kirsch_profile(rt, a))
        pd = ke * (1.0 + e)
        fe_r = float(np.interp(rt, fe["r"], fe["sigma_xx"]))
        profile.append(
            {
                "at": lab,
                "r_over_a": rt / a,
                "kirsch": ke,
                "finite_plate_fe": fe_r,
                "pd": pd,
                "relative_error": e,
                "relative_error_vs_fe": pd / fe_r - 1.0,
            }
        )
        if base is not None:
            profile[-1]["pd_no_hole"] = float(np.interp(rt, *base))

    # concentration: Kirsch-form fit on [a + delta, r_max], evaluated at r = a
    # (the same fit of the finite-plate FE profile at the same radii: the error of the
    # extrapolation itself)
    fits = {}
    for name, r_max in kt_fit_ranges(a, delta):
        sel = (r_p >= a + delta - 1e-9 * dx) & (r_p <= r_max + 1e-9 * dx)
        coef = kirsch_form_fit(r_p[sel], s_p[sel], a)
        q = (a / r_p[sel]) ** 2
        resid = coef[0] + coef[1] * q + coef[2] * q**2 - s_p[sel]
        fits[name] = {
            "points": int(sel.sum()),
            "A_B_C": coef.tolist(),
            "kt_extrapolated": float(coef.sum()),
            "fit_rms": float(np.sqrt(np.mean(resid**2))),
            "fe_same_fit": float(kirsch_form_fit(r_p[sel], fe_p[sel], a).sum()),
        }
    d_over_w = 2.0 * a / f["size"][1]
    kt = peterson_kt(d_over_w)
    kt_pd = fits["a+delta..a+3delta"]["kt_extrapolated"]

    # equilibrium of the section x = x_c: int sigma_xx dy over the ligament / (sigma W)
    x_col = rel[col, 0]
    one_col = col[np.abs(x_col - x_col.min()) < 1e-6 * dx]
    balance = float(sxx[one_col].sum() * dx / f["size"][1])
    # largest recovered sigma_xx anywhere, and where
    i_max = int(np.argmax(sxx))

    return {
        "deck": deck.name,
        "n_points": cloud.n_points,
        "n_bonds": bonds.n_bonds,
        "spacing_m": dx,
        "horizon_m": delta,
        "horizon_factor": delta / dx,
        "partial_volume": bonds.partial_volume,
        "surface_correction": deck.discretisation.surface_correction,
        "hole_radius_m": a,
        "a_over_dx": a / dx,
        "delta_over_a": delta / a,
        "plate_m": f["size"].tolist(),
        "d_over_W": d_over_w,
        "sigma_Pa": s0,
        "youngs_modulus_Pa": f["E"],
        "poisson_ratio": f["nu"],
        "profile": profile,
        "kt_kirsch": 3.0,
        "kt_finite_width_gross": kt["gross"],
        "kt_finite_width_net": kt["net"],
        "kt_pd_extrapolated": kt_pd,
        "kt_fits": fits,
        "kt_pd_vs_kirsch": kt_pd / 3.0 - 1.0,
        "kt_pd_vs_finite_width": kt_pd / kt["gross"] - 1.0,
        "kt_finite_plate_fe": fe["kt"],
        "kt_pd_vs_fe": kt_pd / fe["kt"] - 1.0,
        "fe": {
            **{k: fe[k] for k in ("kt", "kt_mesh", "elements", "seconds")},
            "r_over_a": (fe["r"] / a).tolist(),
            "sigma_xx": fe["sigma_xx"].tolist(),
        },
        "pd_at_hole_edge": {
            "r_over_a": float(r_p[0] / a),
            "sigma_xx_over_sigma": float(s_p[0]),
            "kirsch_there": float(k_p[0]),
            "fe_there": float(fe_p[0]),
        },
        "pd_max_sigma_xx_over_sigma": float(sxx[i_max]),
        "pd_max_at_over_a": (rel[i_max] / a).tolist(),
        "section_balance": balance,
        "symmetry_spread_max": float(spread.max()),
        "stress_recovery_s": recover_s,
        "line": {
            "r_over_a": (r_p / a).tolist(),
            "pd": s_p.tolist(),
            "kirsch": k_p.tolist(),
            "finite_plate_fe": fe_p.tolist(),
            "pd_no_hole": None if base is None else np.interp(r_p, *base).tolist(),
        },
        "_field": (cloud.x, sxx, rel),
    }


def plot(res: dict[str, Any], path: Path) -> None:
    """kirsch.png: the profile against Kirsch and the finite-plate FE (left), the
    relative differences (middle), the sigma_xx map near the hole (right)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    a, delta = res["hole_radius_m"], res["horizon_m"]
    ln = res["line"]
    r = np.asarray(ln["r_over_a"])
    fig, (ax, ex, bx) = plt.subplots(
        1, 3, figsize=(17.0, 5.2), gridspec_kw={"width_ratios": [1.15, 1.0, 1.0]}
    )
    rr = np.linspace(1.0, r.max(), 400)
    ax.plot(rr, kirsch_profile(rr, 1.0), "k-", lw=1.5, label="Kirsch (infinite plate)")
    fe = res["fe"]
    fe_label = f"the same finite plate, local elasticity (FE): {res['kt_finite_plate_fe']:.3f}"
    ax.plot(fe["r_over_a"], fe["sigma_xx"], "-", color="C1", lw=1.2, label=fe_label)
    ax.plot(r, ln["pd"], "o", ms=3.5, color="C0", label="LPS + ADR, nonlocal F")
    if ln["pd_no_hole"] is not None:
        ax.plot(r, ln["pd_no_hole"], ".", ms=3, color="0.5", label="the same plate without hole")
    coef = np.asarray(res["kt_fits"]["a+delta..a+3delta"]["A_B_C"])
    rf = np.linspace(1.0, 1.0 + 3 * delta / a, 100)
    kt_pd, kt_w = res["kt_pd_extrapolated"], res["kt_finite_width_gross"]
    fit_label = f"Kirsch-form fit on [a+δ, a+3δ]: {kt_pd:.3f} at r = a"
    ax.plot(rf, coef[0] + coef[1] / rf**2 + coef[2] / rf**4, "--", color="C3", label=fit_label)
    kt_label = f"finite-width K_t (Howland; Peterson) {kt_w:.3f}"
    ax.axhline(kt_w, color="C2", lw=0.8, ls=":", label=kt_label)
    ax.axvspan(1.0, 1.0 + delta / a, color="0.85", label="within δ of the hole edge")
    ax.set_xlabel("r / a  (θ = 90°, line through the centre, normal to the load)")
    ax.set_ylabel("σ_xx / σ")
    ax.set_xlim(1.0, r.max())
    ax.set_ylim(0.8, 3.2)
    ax.legend(fontsize=8)
    ax.set_title(
        f"plate {res['plate_m'][0] / a:g}a × {res['plate_m'][1] / a:g}a, "
        f"a = {res['a_over_dx']:g} Δx, δ = {res['horizon_factor']:.3f} Δx, "
        f"ν = {res['poisson_ratio']:g}",
        fontsize=9,
    )
    pd = np.asarray(ln["pd"])
    ex.axhline(0.0, color="k", lw=0.6)
    ex.plot(
        r,
        100 * (pd / np.asarray(ln["kirsch"]) - 1),
        "o-",
        ms=3,
        lw=0.8,
        color="k",
        label="PD / Kirsch − 1",
    )
    ex.plot(
        r,
        100 * (pd / np.asarray(ln["finite_plate_fe"]) - 1),
        "s-",
        ms=3,
        lw=0.8,
        color="C1",
        label="PD / finite plate (FE) − 1",
    )
    ex.plot(
        r,
        100 * (np.asarray(ln["finite_plate_fe"]) / np.asarray(ln["kirsch"]) - 1),
        "--",
        color="C2",
        lw=1.0,
        label="finite plate / Kirsch − 1",
    )
    ex.axvspan(1.0, 1.0 + delta / a, color="0.85")
    ex.axvline(1.0 + 2 * delta / a, color="0.5", lw=0.6, ls=":")
    ex.set_xlim(1.0, r.max())
    ex.set_ylim(-8.0, 6.0)
    ex.set_xlabel("r / a")
    ex.set_ylabel("difference (%)")
    ex.legend(fontsize=8)
    ex.set_title("dotted line: r = a + 2δ", fontsize=9)
    x, sxx, rel = res["_field"]
    near = np.all(np.abs(rel) <= 3 * a, axis=1)
    size = 3000.0 / max(int(near.sum()), 1) ** 0.5  # about the same picture at any spacing
    sc = bx.scatter(
        rel[near, 0] / a,
        rel[near, 1] / a,
        c=sxx[near],
        s=size,
        marker="s",
        cmap="viridis",
        vmin=0.0,
        vmax=3.0,
        linewidths=0,
    )
    fig.colorbar(sc, ax=bx, label="σ_xx / σ (LPS, nonlocal F)")
    t = np.linspace(0, 2 * np.pi, 200)
    bx.plot(np.cos(t), np.sin(t), "w-", lw=0.6)
    bx.set_aspect("equal")
    bx.set_xlabel("x / a")
    bx.set_ylabel("y / a")
    bx.set_title("σ_xx near the hole (load along x)", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def machine() -> str:
    """CPU model and count (lscpu), for the record."""
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, timeout=10).stdout
        info = dict(line.split(":", 1) for line in out.splitlines() if ":" in line)
        return f"{info.get('Model name', '?').strip()}, {info.get('CPU(s)', '?').strip()} CPUs"
    except (OSError, subprocess.SubprocessError):
        return platform.processor() or platform.machine()


def main(argv: list[str] | None = None) -> dict[str, Any]:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--deck", default=str(DECK))
    p.add_argument("--out", default=None, help="output folder (default results/<name>)")
    p.add_argument("--spacing", type=float, default=None, help="discretisation.spacing (m)")
    p.add_argument("--set", action="append", default=[], metavar="KEY.PATH=VALUE")
    p.add_argument("--no-run", action="store_true", help="analyse an existing final_state.npz")
    p.add_argument(
        "--baseline",
        action="store_true",
        help="also run the plate without the hole (into OUT/no_hole) and report its "
        "recovered sigma_xx on the same line",
    )
    args = p.parse_args(argv)
    overrides = list(args.set)
    if args.spacing is not None:
        overrides.append(f"discretisation.spacing={args.spacing!r}")
    deck = load_deck(args.deck, overrides)
    out = Path(args.out or f"results/{deck.name}")
    out.mkdir(parents=True, exist_ok=True)
    if not args.no_run:
        run_deck(deck, out)
    run = run_facts(out)
    baseline = None
    if args.baseline:
        plain = load_deck(args.deck, [*overrides, "geometry.holes=[]"])
        baseline = (plain, out / "no_hole")
        if not args.no_run:
            run_deck(plain, baseline[1])
        run["no_hole"] = run_facts(baseline[1])
    res = analyse(deck, out, baseline)
    res["run"] = run
    res["overrides"] = overrides
    res["machine"] = machine()
    plot(res, out / "kirsch.png")
    res.pop("_field")
    (out / "kirsch.json").write_text(json.dumps(res, indent=2) + "\n")
    print_report(res, out)
    return res


def print_report(res: dict[str, Any], out: Path) -> None:
    print(
        f"{res['n_points']} points, {res['n_bonds']} bonds, a = {res['a_over_dx']:g} dx, "
        f"delta = {res['delta_over_a']:.3f} a, d/W = {res['d_over_W']:.4f}"
    )
    if res["run"]:
        r = res["run"]
        whole = "" if r["run_wall_s"] is None else f", whole run {r['run_wall_s']:.1f} s"
        print(
            f"ADR: {r['iterations']} iterations, converged {r['converged']}, residual "
            f"{r['residual']:.2e}; solve {r['solve_wall_s']:.1f} s{whole}"
        )
    for row in res["profile"]:
        plain = f", no hole {row['pd_no_hole']:.4f}" if "pd_no_hole" in row else ""
        print(
            f"  r = {row['r_over_a']:.3f} a ({row['at']}): PD {row['pd']:.4f}, Kirsch "
            f"{row['kirsch']:.4f} (error {100 * row['relative_error']:+.2f} %), finite "
            f"plate {row['finite_plate_fe']:.4f} (error "
            f"{100 * row['relative_error_vs_fe']:+.2f} %){plain}"
        )
    spread = ", ".join(f"{k}: {v['kt_extrapolated']:.4f}" for k, v in res["kt_fits"].items())
    print(
        f"K_t: PD extrapolated {res['kt_pd_extrapolated']:.4f} "
        f"({100 * res['kt_pd_vs_kirsch']:+.2f} % vs Kirsch 3, "
        f"{100 * res['kt_pd_vs_finite_width']:+.2f} % vs finite-width "
        f"{res['kt_finite_width_gross']:.4f}); fits {spread}"
    )
    print(
        f"finite plate (FE): K_t {res['kt_finite_plate_fe']:.4f}; PD vs FE "
        f"{100 * res['kt_pd_vs_fe']:+.2f} %; the same fit of the FE profile gives "
        f"{res['kt_fits']['a+delta..a+3delta']['fe_same_fit']:.4f}"
    )
    e = res["pd_at_hole_edge"]
    print(
        f"next to the hole (r = {e['r_over_a']:.3f} a): PD {e['sigma_xx_over_sigma']:.4f}, "
        f"Kirsch {e['kirsch_there']:.4f}; section balance {res['section_balance']:.4f}"
    )
    print(f"wrote {out / 'kirsch.json'} and {out / 'kirsch.png'}")


if __name__ == "__main__":
    main()
