"""``peridynamics bench`` (the kernel benchmark) and ``peridynamics dispersion``
(dispersion curves and grid advice)."""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from peridynamics.app.checks import err
from peridynamics.app.exit_codes import EXIT_INVALID, EXIT_OK


def cmd_bench(args: argparse.Namespace) -> int:
    """Run the kernel benchmark."""
    from peridynamics.app.bench import run_benchmarks

    try:
        dims = tuple(int(d) for d in args.dims.split(","))
    except ValueError:
        dims = ()
    if not dims or any(d not in (1, 2, 3) for d in dims):
        err(f"--dims: comma-separated dimensions from 1, 2, 3, got {args.dims!r}")
        return EXIT_INVALID
    if args.steps < 1:
        err("--steps must be >= 1")
        return EXIT_INVALID
    results = run_benchmarks(args.size, dims=dims, steps=args.steps)
    if args.json:
        print(json.dumps([r.as_dict() for r in results], indent=2))
    else:
        print(
            f"{'dim':>3} {'points':>9} {'bonds':>11} {'s/step':>9} {'bonds/s':>10} "
            f"{'numpy b/s':>10} {'speedup':>8} {'B/bond':>7} {'peak GiB':>8}"
        )
        for r in results:
            print(
                f"{r.dim:>3} {r.points:>9} {r.bonds:>11} {r.seconds_per_step:>9.4f} "
                f"{r.bonds_per_second:>10.3g} {r.numpy_bonds_per_second:>10.3g} "
                f"{r.speedup:>8.1f} {r.bytes_per_bond:>7.1f} {r.peak_rss_gib:>8.2f}"
            )
    return EXIT_OK


def cmd_dispersion(args: argparse.Namespace) -> int:
    """Dispersion curve of the semi-discrete relation (PD wave dispersion (n.d.)), or grid
    advice."""
    from peridynamics.analysis import dispersion as dsp

    if args.frequency is not None or args.pulse_duration is not None:
        return _advise(args)
    if not args.m >= 1:
        err("--m must be >= 1 (delta = m h)")
        return EXIT_INVALID
    if args.n_points < 2:
        err("--n-points must be >= 2")
        return EXIT_INVALID
    if args.dim == 1 and args.theta != 0.0:
        err("--theta is for --dim 2")
        return EXIT_INVALID
    nh = np.linspace(0.0, 2.0, args.n_points)
    curve = (
        dsp.semi_discrete_1d(nh, args.m)
        if args.dim == 1
        else dsp.semi_discrete_2d(nh, args.m, args.theta)
    )
    if args.json:
        print(json.dumps(curve.as_dict()))
    if args.plot:
        from peridynamics.io.plots import plot_histories

        label = f"{args.dim}-D, delta = {args.m:g} h" + (
            f", theta = {args.theta:g} deg" if args.dim == 2 else ""
        )
        plot_histories(
            Path(args.plot),
            curve.N_h.tolist(),
            {
                "v / v0": curve.v_over_v0.tolist(),
                "omega / omega0": curve.omega_over_omega0.tolist(),
                "group velocity / v0": curve.group_velocity_over_v0.tolist(),
            },
            f"semi-discrete dispersion (PD wave dispersion (n.d.)), {label}",
            xlabel="N_h = kappa h / (2 pi)",
            xscale=1.0,
        )
        if not args.json:
            print(f"wrote {args.plot}")
    if not args.json and not args.plot:
        for a, v, w, g in zip(
            curve.N_h[:: max(1, len(nh) // 20)],
            curve.v_over_v0[:: max(1, len(nh) // 20)],
            curve.omega_over_omega0[:: max(1, len(nh) // 20)],
            curve.group_velocity_over_v0[:: max(1, len(nh) // 20)],
            strict=True,
        ):
            print(f"N_h {a:6.3f}  v/v0 {v:8.5f}  omega/omega0 {w:8.5f}  v_g/v0 {g:9.5f}")
    return EXIT_OK


def _advise(args: argparse.Namespace) -> int:
    from peridynamics.analysis import dispersion as dsp

    if args.frequency is not None and args.pulse_duration is not None:
        err("give --frequency or --pulse-duration, not both")
        return EXIT_INVALID
    # a pulse of duration T carries most of its energy below about 2 / T
    freq = args.frequency if args.frequency is not None else 2.0 / args.pulse_duration
    for name, value in (("--youngs-modulus", args.youngs_modulus), ("--density", args.density)):
        if not (math.isfinite(value) and value > 0):
            err(f"{name} must be a finite number > 0, got {value}")
            return EXIT_INVALID
    try:
        adv = dsp.advise_1d(
            freq, args.tolerance, args.youngs_modulus, args.density, m_min=args.m_min
        )
    except ValueError as exc:
        err(f"error: {exc}")
        return EXIT_INVALID
    speed = math.sqrt(args.youngs_modulus / args.density)
    if args.json:
        print(
            json.dumps(
                {
                    "frequency_hz": adv.frequency,
                    "youngs_modulus_Pa": args.youngs_modulus,
                    "density_kg_per_m3": args.density,
                    "wave_speed_m_per_s": speed,
                    "m": adv.m,
                    "spacing_m": adv.spacing,
                    "horizon_m": adv.horizon,
                    "max_phase_error": adv.max_phase_error,
                    "table": adv.table,
                }
            )
        )
        return EXIT_OK
    print(
        f"material: E = {args.youngs_modulus:.4g} Pa, rho = {args.density:.4g} kg/m^3 "
        f"(wave speed {speed:.4g} m/s; set them with --youngs-modulus and --density)"
    )
    print(f"up to {adv.frequency:.4g} Hz with phase-speed error <= {args.tolerance:g}:")
    print(
        f"  use m = {adv.m}, dx = {adv.spacing:.4g} m, delta = {adv.horizon:.4g} m "
        f"(error {adv.max_phase_error:.3g})"
    )
    for row in adv.table:
        print(f"  m = {int(row['m']):2d}: coarsest dx = {row['spacing_m']:.4g} m")
    return EXIT_OK


def register_dispersion(sub: Any) -> None:
    """The parser of ``dispersion``."""
    d = sub.add_parser(
        "dispersion", help="dispersion curves (PD wave dispersion (n.d.)) and grid advice"
    )
    d.add_argument("--dim", type=int, choices=[1, 2], default=1)
    d.add_argument("--m", type=float, default=3.015, help="delta / h (default 3.015)")
    d.add_argument("--theta", type=float, default=0.0, help="direction in degrees (2-D)")
    d.add_argument("--n-points", type=int, default=401, help="samples of N_h in [0, 2]")
    d.add_argument("--json", action="store_true", help="print the curve as JSON")
    d.add_argument("--plot", metavar="FILE.png", help="draw the curve")
    d.add_argument("--frequency", type=float, help="advice: highest frequency in the load (Hz)")
    d.add_argument(
        "--pulse-duration",
        type=float,
        help="advice: shortest pulse duration (s); frequency = 2 / duration",
    )
    d.add_argument("--tolerance", type=float, default=0.01, help="advice: phase-speed error")
    d.add_argument(
        "--youngs-modulus",
        type=float,
        default=20e9,
        help="advice: E (Pa; default 20e9, a rock; printed with the advice)",
    )
    d.add_argument(
        "--density",
        type=float,
        default=2620.0,
        help="advice: rho (kg/m^3; default 2620, a rock; printed with the advice)",
    )
    d.add_argument("--m-min", type=int, default=3, help="advice: smallest m to recommend")
    d.set_defaults(func=cmd_dispersion)


def register_bench(sub: Any) -> None:
    """The parser of ``bench``."""
    b = sub.add_parser("bench", help="benchmark the explicit PMB step (Numba vs NumPy)")
    b.add_argument("--json", action="store_true", help="print a JSON list of cases")
    b.add_argument(
        "--size",
        choices=["quick", "default", "full", "huge"],
        default="default",
        help="default: 1-D 1e6, 2-D 1000^2, 3-D 60^3 points; full: 3-D 100^3; huge: 1-D 8e6, "
        "2-D 2000^2, 3-D 200^3 (8 million points, about 14 GiB; no NumPy baseline)",
    )
    b.add_argument("--dims", default="1,2,3", help="comma-separated dimensions")
    b.add_argument("--steps", type=int, default=20)
    b.set_defaults(func=cmd_bench)
