"""Reproduce the dispersion figures of Lu & Wang (2016), Fig. 5, and PD wave dispersion (n.d.).

One command (from the repository root)::

    python examples/dispersion/make_figures.py [--out DIR] [--n-points N]

writes the PNGs listed in ``README.md`` (next to this script by default; PD wave dispersion
(n.d.), Figs 2, 3, 5, 6) and prints the key numbers computed from
:mod:`peridynamics.analysis.dispersion` next to reference values computed independently
from the papers' equations (the papers show them only as figures; full references in
docs/references.md). A last figure goes beyond the papers: the Bloch-wave dispersion of a
patch built by the engine against the closed form of PD wave dispersion (n.d.).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.optimize import brentq, minimize_scalar  # noqa: E402

try:
    import peridynamics  # noqa: F401
except ImportError:  # a source checkout that was not installed: use its src/ folder
    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "src"))

from peridynamics.analysis import dispersion as dsp  # noqa: E402
from peridynamics.bonds import build_bonds  # noqa: E402
from peridynamics.evaluation import Evaluator  # noqa: E402
from peridynamics.families.pmb import BondBasedMaterial  # noqa: E402
from peridynamics.geometry import rectangle  # noqa: E402

HERE = Path(__file__).resolve().parent

#: Lu & Wang (2016), Fig. 5 (biotite granite)
E, RHO = 20e9, 2620.0
C = math.sqrt(E / RHO)  # bar speed, 2762.9 m/s
#: PD wave dispersion (n.d.): delta = 3.015 h
M003 = 3.015
THETAS = (0.0, 30.0, 45.0)

FIGURES = (
    "seed000_fig5a.png",
    "seed000_fig5b.png",
    "seed000_fig5c.png",
    "seed000_fig5d.png",
    "seed003_fig2.png",
    "seed003_fig3.png",
    "seed003_fig5.png",
    "seed003_fig6.png",
    "bloch_vs_closed_form.png",
)

#: reference values computed from the papers' equations (used only to print the comparison)
PAPER_1D = {0.0: 1.14896, 0.2: 0.78270, 0.25: 0.64508, 0.5: 0.34481, 1.0: 0.0, 1.5: 0.11494}
PAPER_2D = {
    0.0: (0.81528, 0.39279, 0.0, 0.13093),
    30.0: (0.81906, 0.42212, 0.21088, 0.13439),
    45.0: (0.81772, 0.40065, 0.19870, 0.06742),
}
PAPER_TABLE_000 = {  # k (rad/m): exact f, m = 1, 2, 3, 4 (Hz), dx = 5 mm, dt = 1 us
    100: (43973, 43653, 42976, 41874, 40387),
    200: (87946, 85346, 80179, 72417, 63186),
    400: (175891, 153938, 121915, 89097, 68645),
}

_HIGH_BAND = {"color": "0.93", "zorder": 0}


# --------------------------------------------------------------------------- helpers
def _save(fig: plt.Figure, out_dir: Path, name: str) -> Path:
    path = out_dir / name
    fig.savefig(path, dpi=130, bbox_inches="tight")
    plt.close(fig)
    return path


def _f_hz(k: np.ndarray, dx: float, m: int, dt: float) -> np.ndarray:
    """Lu & Wang (2016), eq. 12: f = omega / (2 pi) in Hz (NaN where unstable)."""
    return dsp.fully_discrete_1d(k, dx, m, dt, E, RHO) / (2.0 * np.pi)


def _seed000_axes(ax: plt.Axes, k_max: float, title: str) -> None:
    k = np.linspace(0.0, k_max, 200)
    ax.plot(k, C * k / (2 * np.pi), "k--", lw=1.2, label="exact  $f = ck/2\\pi$")
    ax.set_xlim(0, k_max)
    ax.set_ylim(bottom=0)
    ax.set_xlabel("wavenumber $k$ (rad/m)")
    ax.set_ylabel("frequency $f = \\omega/2\\pi$ (Hz)")
    ax.ticklabel_format(axis="y", style="sci", scilimits=(0, 0))
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")


def _high_band(ax: plt.Axes) -> None:
    ax.axvspan(1.0, 2.0, **_HIGH_BAND)
    ax.text(
        1.5,
        0.97,
        "high-frequency band",
        transform=ax.get_xaxis_transform(),
        ha="center",
        va="top",
        fontsize=8,
        color="0.4",
    )


# --------------------------------------------------------- Lu & Wang (2016), Fig. 5
def seed000_fig5(out_dir: Path, n: int) -> list[Path]:
    """The four panels of Lu & Wang (2016), Fig. 5 (eq. 12), one PNG each."""
    paths = []
    us = 1e-6

    fig, ax = plt.subplots(figsize=(6, 4.2))
    dx = 0.005
    k = np.linspace(0.0, np.pi / dx, n)
    for m in (1, 2, 3, 4):
        ax.plot(k, _f_hz(k, dx, m, 1 * us), label=f"$m = {m}$ ($\\delta = {m * dx * 1e3:g}$ mm)")
    _seed000_axes(
        ax,
        np.pi / dx,
        "Seed 000, Fig. 5(a): $\\Delta x$ = 5 mm, $\\Delta t$ = 1 µs, "
        "horizon ratio $m = \\delta/\\Delta x$",
    )
    paths.append(_save(fig, out_dir, "seed000_fig5a.png"))

    fig, ax = plt.subplots(figsize=(6, 4.2))
    for dx in (0.005, 0.01, 0.015, 0.02):
        k = np.linspace(0.0, np.pi / dx, n)  # each curve up to its own pi/dx
        ax.plot(k, _f_hz(k, dx, 3, 1 * us), label=f"$\\Delta x$ = {dx * 1e3:g} mm")
    _seed000_axes(
        ax,
        np.pi / 0.005,
        "Seed 000, Fig. 5(b): $m$ = 3, $\\Delta t$ = 1 µs, grid spacing $\\Delta x$",
    )
    paths.append(_save(fig, out_dir, "seed000_fig5b.png"))

    fig, ax = plt.subplots(figsize=(6, 4.2))
    delta = 0.02
    for m in (1, 2, 3, 4):
        dx = delta / m
        k = np.linspace(0.0, np.pi / dx, n)
        ax.plot(k, _f_hz(k, dx, m, 1 * us), label=f"$m = {m}$ ($\\Delta x$ = {dx * 1e3:.3g} mm)")
    _seed000_axes(
        ax,
        np.pi / (delta / 4),
        "Seed 000, Fig. 5(c): $\\delta$ = 20 mm fixed, $\\Delta t$ = 1 µs, $\\Delta x = \\delta/m$",
    )
    paths.append(_save(fig, out_dir, "seed000_fig5c.png"))

    fig, (ax, ax2) = plt.subplots(
        2, 1, figsize=(6, 5.6), sharex=True, gridspec_kw={"height_ratios": [3, 1.3]}
    )
    dx, m = 0.005, 3
    k = np.linspace(0.0, np.pi / dx, n)
    ref = _f_hz(k, dx, m, 0.1 * us)
    styles = ("-", "--", "-.", ":")
    for dt, ls in zip((1.0, 0.5, 0.2, 0.1), styles, strict=True):
        f = _f_hz(k, dx, m, dt * us)
        ax.plot(k, f, ls, lw=1.6, label=f"$\\Delta t$ = {dt:g} µs")
        ax2.plot(k, f - ref, ls, lw=1.4)
    _seed000_axes(
        ax, np.pi / dx, "Seed 000, Fig. 5(d): $\\Delta x$ = 5 mm, $m$ = 3, time step $\\Delta t$"
    )
    ax.set_xlabel("")
    ax2.set_xlabel("wavenumber $k$ (rad/m)")
    ax2.set_ylabel("$f - f_{0.1\\,µs}$ (Hz)")
    ax2.grid(alpha=0.3)
    fig.tight_layout()
    paths.append(_save(fig, out_dir, "seed000_fig5d.png"))
    return paths


# -------------------------------------------------------- PD wave dispersion (n.d.), 1-D
def critical_point_1d() -> float:
    """N_h where the 1-D phase velocity of PD wave dispersion (n.d.) crosses the local value
    v/v0 = 1."""
    return float(
        brentq(lambda x: dsp.semi_discrete_1d([x], M003).v_over_v0[0] - 1.0, 0.05, 0.2, xtol=1e-14)
    )


def omega_max_1d() -> tuple[float, float]:
    """(N_h, omega/omega0) at the maximum of the 1-D frequency of PD wave dispersion (n.d.) in
    (0, 1)."""
    r = minimize_scalar(
        lambda x: -dsp.semi_discrete_1d([x], M003).omega_over_omega0[0],
        bounds=(0.3, 0.7),
        method="bounded",
        options={"xatol": 1e-10},
    )
    return float(r.x), float(-r.fun)


def seed003_fig2(out_dir: Path, n: int) -> Path:
    nh = np.linspace(0.0, 2.0, n)
    d = dsp.semi_discrete_1d(nh, M003)
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    _high_band(ax)
    ax.plot(nh, d.v_over_v0, "C0", lw=1.6, label="discrete PD (eq. 19), $\\delta$ = 3.015$h$")
    ax.plot(
        nh,
        dsp.continuous_1d(2 * np.pi * nh * M003),
        "C1--",
        lw=1.4,
        label="continuous PD (eqs 14-16)",
    )
    ax.axhline(1.0, color="k", lw=1.0, ls=":", label="local theory, $v = v_0$")
    zero = dsp.zero_energy_points_1d(2)
    ax.plot(
        zero,
        dsp.semi_discrete_1d(zero, M003).v_over_v0,
        "rv",
        ms=8,
        clip_on=False,
        zorder=5,
        label="zero-energy modes ($v$ = 0)",
    )
    nc = critical_point_1d()
    ax.plot([nc], [1.0], "ko", ms=6, mfc="gold", label=f"critical point $N_h$ = {nc:.5f}")
    ax.annotate(
        f"critical point\n$N_h$ = {nc:.4f}",
        (nc, 1.0),
        (0.3, 1.1),
        fontsize=8,
        arrowprops={"arrowstyle": "->", "lw": 0.8},
    )
    ax.set_xlim(0, 2)
    ax.set_ylim(0, 1.25)
    ax.set_xlabel("$N_h = \\kappa h / 2\\pi$ (wavenumber per grid spacing)")
    ax.set_ylabel("phase velocity $v / v_0$")
    ax.set_title("Seed 003, Fig. 2: 1-D phase velocity, $\\delta$ = 3.015$h$", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="center right")
    return _save(fig, out_dir, "seed003_fig2.png")


def seed003_fig3(out_dir: Path, n: int) -> Path:
    nh = np.linspace(0.0, 2.0, n)
    d = dsp.semi_discrete_1d(nh, M003)
    vg = d.group_velocity_over_v0.copy()
    # the group velocity jumps from -v_long to +v_long at integer N_h > 0: break the line
    vg[(np.abs(nh - np.round(nh)) < 1e-12) & (nh > 0)] = np.nan
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    _high_band(ax)
    ax.plot(nh, d.omega_over_omega0, "C0", lw=1.6, label="frequency $\\omega/\\omega_0$ (eq. 21)")
    ax.plot(nh, vg, "C3", lw=1.4, label="group velocity $v_g/v_0$")
    ax.axhline(0.0, color="k", lw=0.8)
    zg = dsp.zero_group_velocity_points_1d(M003, N_max=2.0)
    ax.plot(zg, np.zeros_like(zg), "ko", ms=5, mfc="w", label="$v_g$ = 0 (zero group velocity)")
    for x in zg:
        ax.axvline(x, color="0.6", lw=0.5, ls=":")
    nm, om = omega_max_1d()
    ax.plot(
        [nm], [om], "C0^", ms=7, label=f"max $\\omega/\\omega_0$ = {om:.5f} at $N_h$ = {nm:.3f}"
    )
    ax.set_xlim(0, 2)
    ax.set_xlabel("$N_h = \\kappa h / 2\\pi$")
    ax.set_ylabel("$\\omega/\\omega_0$,  $v_g/v_0$  ($\\omega_0 = v_0/h$)")
    ax.set_title(
        "Seed 003, Fig. 3: 1-D frequency and group velocity, $\\delta$ = 3.015$h$", fontsize=10
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7.5, loc="lower left", ncol=2)
    ax.set_ylim(-1.9, 1.45)
    return _save(fig, out_dir, "seed003_fig3.png")


# -------------------------------------------------------- PD wave dispersion (n.d.), 2-D
def seed003_fig5(out_dir: Path, n: int) -> Path:
    nh = np.linspace(0.0, 2.0, n)
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    _high_band(ax)
    for theta, ls in zip(THETAS, ("-", "--", "-."), strict=True):
        d = dsp.semi_discrete_2d(nh, M003, theta)
        ax.plot(nh, d.v_over_v0, ls, lw=1.5, label=f"$\\theta$ = {theta:g}°")
    long = dsp.semi_discrete_2d([0.0], M003).v_over_v0[0]
    ax.axhline(
        math.sqrt(1.5),
        color="k",
        lw=0.9,
        ls=":",
        label=f"continuum scalar operator $\\sqrt{{3/2}}$; lattice: {long:.5f}",
    )
    ax.set_xlim(0, 2)
    ax.set_ylim(0, 1.35)
    ax.set_xlabel("$N_h = \\kappa h / 2\\pi$")
    ax.set_ylabel("phase velocity $v / v_0$")
    ax.set_title(
        "Seed 003, Fig. 5: 2-D phase velocity (eq. 32), $\\delta$ = 3.015$h$, direction $\\theta$",
        fontsize=10,
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="center right")
    return _save(fig, out_dir, "seed003_fig5.png")


def oscillation_samples(n: int) -> tuple[np.ndarray, int]:
    """Directions (degrees) and N_h samples of Fig. 6: 1 degree and 2001 samples at full
    resolution, coarser when ``n`` is small (a quick run)."""
    step = 1.0 if n >= 1000 else 5.0
    return np.arange(0.0, 360.0 + step / 2, step), int(min(n, 2001))


def seed003_fig6(out_dir: Path, n: int) -> Path:
    th, samples = oscillation_samples(n)
    idx = dsp.oscillation_index_2d(M003, th, samples=samples)
    # 45-degree symmetry: I(theta) = I(90 - theta) (and period 90)
    mirror = dsp.oscillation_index_2d(M003, 90.0 - th, samples=samples)
    sym = float(np.max(np.abs(idx - mirror)))
    fig = plt.figure(figsize=(5.6, 5.6))
    ax = fig.add_subplot(projection="polar")
    t = np.radians(th)
    ax.plot(t, idx, "C0", lw=1.5)
    ax.fill(t, idx, "C0", alpha=0.15)
    rmax = float(np.max(idx)) * 1.1
    for a in range(0, 360, 45):
        ax.plot(
            [np.radians(a)] * 2, [0, rmax], color="C3" if a % 90 == 45 else "0.5", lw=0.8, ls="--"
        )
    ax.set_ylim(0, rmax)
    ax.set_thetagrids(range(0, 360, 45))
    ax.set_title(
        "Seed 003, Fig. 6: oscillation index max$|d(v/v_0)/dN_h|$, $1 \\leq N_h \\leq 2$\n"
        f"symmetric about 45° (red): max$|I(\\theta) - I(90° - \\theta)|$ = {sym:.1e}",
        fontsize=9,
    )
    return _save(fig, out_dir, "seed003_fig6.png")


# ------------------------------------------------------ beyond the paper: Bloch waves
def engine_patch(partial_volume: str, h: float = 1e-3, thickness: float = 0.01) -> tuple:
    """(model, centre point) of a 21 x 21-point plane-stress patch, delta = 3.015 h."""
    cloud = rectangle((21 * h, 21 * h), h, thickness=thickness)
    model = Evaluator(
        cloud, build_bonds(cloud, M003 * h, partial_volume), BondBasedMaterial(E, RHO)
    )
    centre = int(np.argmin(np.sum((cloud.x - cloud.x.mean(axis=0)) ** 2, axis=1)))
    return model, centre


def _diagonal_branches(model: Evaluator, point: int, kx: np.ndarray) -> np.ndarray:
    """(D_xx, D_yy) of the tensor operator along x from the bond list: at theta = 0 the
    mirror-symmetric family makes D(k) diagonal, so these are the L and T branches."""
    b = model.bonds
    sl = slice(int(b.offsets[point]), int(b.offsets[point + 1]))
    n = b.bond_xi[sl] / b.bond_length[sl, None]
    w = model.stiffness[sl] / b.bond_length[sl]
    one = 1.0 - np.cos(np.outer(kx, b.bond_xi[sl, 0]))
    return np.sqrt(np.column_stack([one @ (w * n[:, 0] ** 2), one @ (w * n[:, 1] ** 2)]) / RHO)


def bloch_comparison(n: int, h: float = 1e-3) -> dict:
    """v/v0 along theta = 0 from the engine's bond lists and from PD wave dispersion (n.d.),
    eq. 32."""
    nh = np.linspace(0.0, 2.0, n)[1:]  # v = omega/kappa: skip kappa = 0
    kappa = 2.0 * np.pi * nh / h
    kv = np.column_stack([kappa, np.zeros_like(kappa)])
    v0 = math.sqrt(E / RHO)
    none, c_none = engine_patch("none", h)
    scalar = dsp.bloch_dispersion(none, c_none, kv, mode="scalar") / kappa / v0
    closed = dsp.semi_discrete_2d(nh, M003, 0.0).v_over_v0
    trunc, c_trunc = engine_patch("truncated", h)
    tensor = dsp.bloch_dispersion(trunc, c_trunc, kv, mode="tensor") / kappa[:, None] / v0
    lt = _diagonal_branches(trunc, c_trunc, kappa) / kappa[:, None] / v0
    return {
        "N_h": nh,
        "scalar_none": scalar,
        "closed": closed,
        "max_abs_diff": float(np.max(np.abs(scalar - closed))),
        "tensor_truncated": tensor,  # ascending: (transverse, longitudinal), checked below
        "branch_check": float(np.nanmax(np.abs(tensor - lt[:, ::-1]))),
        "n_bonds": (
            int(np.diff(none.bonds.offsets)[c_none]),
            int(np.diff(trunc.bonds.offsets)[c_trunc]),
        ),
    }


def bloch_figure(out_dir: Path, n: int) -> tuple[Path, dict]:
    r = bloch_comparison(n)
    if not r["max_abs_diff"] < 1e-10:
        raise RuntimeError(f"Bloch waves and eq. 32 differ by {r['max_abs_diff']:.3e}")
    if not r["branch_check"] < 1e-10:
        raise RuntimeError("tensor branches are not (transverse, longitudinal)")
    nh = r["N_h"]
    fig, ax = plt.subplots(figsize=(6.8, 4.6))
    _high_band(ax)
    ax.plot(
        nh, r["closed"], "k-", lw=2.6, alpha=0.35, label="seed 003 eq. 32 (closed form, scalar)"
    )
    step = max(1, len(nh) // 80)
    ax.plot(
        nh[::step],
        r["scalar_none"][::step],
        "C0o",
        ms=3.5,
        mfc="none",
        label=f"engine Bloch scalar, 'none' ({r['n_bonds'][0]} bonds)",
    )
    ax.plot(
        nh, r["tensor_truncated"][:, 1], "C3", lw=1.3, label="engine Bloch tensor, 'truncated': L"
    )
    ax.plot(
        nh, r["tensor_truncated"][:, 0], "C2", lw=1.3, label="engine Bloch tensor, 'truncated': T"
    )
    for val, txt in ((math.sqrt(9 / 8), "$\\sqrt{9/8}$"), (math.sqrt(3 / 8), "$\\sqrt{3/8}$")):
        ax.axhline(val, color="0.4", lw=0.7, ls=":")
        ax.text(
            0.40,
            val + 0.015,
            f"continuum BB, long waves: {txt}",
            ha="left",
            fontsize=7,
            color="0.35",
        )
    ax.set_xlim(0, 2)
    ax.set_ylim(0, 1.4)
    ax.set_xlabel("$N_h = \\kappa h / 2\\pi$,  $\\theta$ = 0°")
    ax.set_ylabel("phase velocity $v/v_0 = \\omega / (\\kappa v_0)$")
    ax.set_title(
        "Beyond the paper: Bloch waves of a 21x21 engine patch ($\\delta$ = 3.015$h$) "
        f"vs eq. 32\nscalar Bloch = closed form: max$|\\Delta(v/v_0)|$ = {r['max_abs_diff']:.1e}"
        " (< 1e-10)",
        fontsize=9,
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7.5, loc="center right", bbox_to_anchor=(1.0, 0.47))
    return _save(fig, out_dir, "bloch_vs_closed_form.png"), r


# ------------------------------------------------------------------- the numbers
def key_numbers(n: int = 2001) -> list[tuple[str, float, float | None, float]]:
    """(label, computed, paper value or None, tolerance for 'match'): the key numbers of
    Lu & Wang (2016), section 2, and PD wave dispersion (n.d.), section 2."""
    rows: list[tuple[str, float, float | None, float]] = []
    tol5 = 6e-6  # the papers print 5 decimals
    d = dsp.semi_discrete_1d(list(PAPER_1D), M003)
    for (nh, ref), v in zip(PAPER_1D.items(), d.v_over_v0, strict=True):
        rows.append((f"seed003 1-D v/v0 at N_h = {nh:g}", float(v), ref, tol5))
    rows.append(("seed003 1-D critical point N_h (v/v0 = 1)", critical_point_1d(), 0.11892, tol5))
    nm, om = omega_max_1d()
    rows.append(("seed003 1-D max omega/omega0", om, 1.08325, tol5))
    rows.append(("seed003 1-D N_h of max omega/omega0", nm, 0.5, 1e-6))
    for z, ref in zip(
        dsp.zero_group_velocity_points_1d(M003), (0.25, 1 / 3, 0.5, 2 / 3, 0.75), strict=True
    ):
        rows.append(("seed003 1-D zero group velocity N_h", float(z), ref, 1e-9))
    rows.append(
        (
            "seed003 continuous v/v0 at N_h = 0.25",
            float(dsp.continuous_1d(2 * np.pi * 0.25 * M003)[0]),
            None,
            0.0,
        )
    )
    rows.append(
        ("seed003 2-D lattice family size", float(len(dsp.lattice_family_2d(M003))), 28.0, 0.0)
    )
    for theta, refs in PAPER_2D.items():
        d = dsp.semi_discrete_2d([0.0, 0.25, 0.5, 1.0, 1.5], M003, theta)
        rows.append(
            (f"seed003 2-D theta = {theta:g}: long-wave v/v0", float(d.v_over_v0[0]), 1.24020, tol5)
        )
        for nh, v, ref in zip((0.25, 0.5, 1.0, 1.5), d.v_over_v0[1:], refs, strict=True):
            rows.append(
                (f"seed003 2-D theta = {theta:g}: v/v0 at N_h = {nh:g}", float(v), ref, tol5)
            )
    th, samples = oscillation_samples(n)
    idx = dsp.oscillation_index_2d(M003, [0.0, 15.0, 22.5, 30.0, 45.0], samples=samples)
    for t, v in zip((0, 15, 22.5, 30, 45), idx, strict=True):
        rows.append((f"seed003 2-D oscillation index at theta = {t:g}", float(v), None, 0.0))
    k = np.array(list(PAPER_TABLE_000), dtype=float)
    for kk, refs in zip(k, PAPER_TABLE_000.values(), strict=True):
        rows.append((f"seed000 exact f (Hz) at k = {kk:g}", C * kk / (2 * np.pi), refs[0], 0.6))
        for m in (1, 2, 3, 4):
            f = float(_f_hz(np.array([kk]), 0.005, m, 1e-6)[0])
            rows.append((f"seed000 f (Hz) at k = {kk:g}, m = {m}", f, refs[m], 0.6))
    return rows


def print_numbers(rows: list[tuple[str, float, float | None, float]]) -> None:
    print(f"{'quantity':52s} {'computed':>14s} {'paper':>12s}  match")
    for label, val, ref, tol in rows:
        if ref is None:
            print(f"{label:52s} {val:14.6f} {'-':>12s}  -")
        else:
            ok = "yes" if abs(val - ref) <= tol else "NO"
            paper = f"{ref:12.0f}" if abs(ref) >= 100 else f"{ref:12.5f}"
            print(f"{label:52s} {val:14.6f} {paper}  {ok}")


# --------------------------------------------------------------------------- main
def make_figures(out_dir: Path, n_points: int = 2001) -> list[Path]:
    """Write every figure into ``out_dir`` (created if needed); return the PNG paths.

    ``n_points`` is the number of samples per curve (2001 for the paper-quality run; a
    few hundred for a quick check).
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    n = int(n_points)
    if n < 11:
        raise ValueError("n_points must be >= 11")
    paths = seed000_fig5(out_dir, n)
    paths += [
        seed003_fig2(out_dir, n),
        seed003_fig3(out_dir, n),
        seed003_fig5(out_dir, n),
        seed003_fig6(out_dir, n),
    ]
    path, _ = bloch_figure(out_dir, n)
    paths.append(path)
    assert [p.name for p in paths] == list(FIGURES)
    return paths


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=HERE, help="output folder (default: %(default)s)")
    p.add_argument("--n-points", type=int, default=2001, help="samples per curve")
    args = p.parse_args(argv)
    t0 = time.perf_counter()
    paths = make_figures(args.out, args.n_points)
    t_fig = time.perf_counter() - t0
    for path in paths:
        print(f"wrote {path}")
    print()
    print_numbers(key_numbers(args.n_points))
    r = bloch_comparison(args.n_points)
    print()
    print(f"Bloch scalar ('none') vs eq. 32, theta = 0: max |diff v/v0| = {r['max_abs_diff']:.3e}")
    print(
        f"Bloch tensor ('truncated') long-wave v/v0 (T, L) at N_h = {r['N_h'][0]:.4g}: "
        f"{r['tensor_truncated'][0, 0]:.5f}, {r['tensor_truncated'][0, 1]:.5f} "
        f"(continuum {math.sqrt(3 / 8):.5f}, {math.sqrt(9 / 8):.5f})"
    )
    print(f"figures: {t_fig:.2f} s; total {time.perf_counter() - t0:.2f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
