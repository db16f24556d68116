"""Command line: ``peridynamics run|check|examples|bench``.

Exit codes: 0 success; 2 invalid deck or model set-up (the key path is on stderr);
3 the run went unstable (a summary and ``last_good.vtu`` are written).
"""

from __future__ import annotations

import argparse
import json
import shutil
import sys
from pathlib import Path

import numpy as np

from peridynamics import __version__

EXIT_OK, EXIT_INVALID, EXIT_UNSTABLE = 0, 2, 3


def examples_dir() -> Path:
    """Folder holding the example decks (installed copy first, then the source tree)."""
    here = Path(__file__).resolve().parent
    for cand in (here / "_examples", here.parents[1] / "examples"):
        if cand.is_dir():
            return cand
    raise FileNotFoundError("the example decks are not installed")


def list_examples() -> dict[str, Path]:
    """Map example name -> deck path (every ``*.yaml`` under the examples folder)."""
    root = examples_dir()
    out = {}
    for p in sorted(root.rglob("*.yaml")):
        rel = p.relative_to(root)
        name = rel.parent.as_posix() if p.stem == "deck" else rel.with_suffix("").as_posix()
        out[name] = p
    for folder in sorted(d for d in root.iterdir() if d.is_dir()):
        scripts = sorted(folder.glob("*.py"))
        if scripts and not any(folder.glob("*.yaml")):  # a script example (figures, ...)
            out[folder.name] = scripts[0]
    return dict(sorted(out.items()))


def _err(msg: str) -> None:
    print(msg, file=sys.stderr)


def _load(args: argparse.Namespace):  # noqa: ANN202 - returns a Deck
    from peridynamics.io.deck import DeckError, load_deck

    try:
        return load_deck(args.deck, overrides=args.set or [])
    except DeckError as exc:
        _err(str(exc))
        return None


def cmd_check(args: argparse.Namespace) -> int:
    """Validate a deck and build its geometry and node sets, without running.

    With ``--bonds`` also build the bonds, the model and the solver: the time step is
    then checked against the stable limit as ``run`` would.
    """
    from peridynamics.runner import SetupError, Simulation, build_cloud

    deck = _load(args)
    if deck is None:
        return EXIT_INVALID
    try:
        if args.bonds:
            sim = Simulation.from_deck(deck)
            extra = f", {sim.model.bonds.n_bonds} bonds, {sim.solver.describe()}"
            n_points = sim.cloud.n_points
        else:
            n_points, extra = build_cloud(deck).n_points, ""
    except SetupError as exc:
        _err(f"invalid deck:\n  {exc}")
        return EXIT_INVALID
    print(f"{args.deck}: valid ({deck.dim}-D, {n_points} points{extra})")
    return EXIT_OK


def cmd_run(args: argparse.Namespace) -> int:
    """Run a deck."""
    from peridynamics.runner import SetupError, Simulation
    from peridynamics.solvers import SimulationUnstable

    if args.resume and args.out:
        _err("give either --out DIR (a new run) or --resume DIR (continue the run in DIR)")
        return EXIT_INVALID
    if args.checkpoint_every < 0:
        _err("--checkpoint-every must be >= 0 (0: no checkpoints)")
        return EXIT_INVALID
    if args.resume and not Path(args.resume).is_dir():
        _err(f"--resume: no run folder {args.resume!r}")
        return EXIT_INVALID
    deck = _load(args)
    if deck is None:
        return EXIT_INVALID
    out = Path(args.resume or args.out or Path("results") / deck.name)
    if out.exists() and not out.is_dir():
        _err(f"--out: {str(out)!r} exists and is not a folder")
        return EXIT_INVALID
    try:
        sim = Simulation.from_deck(deck)
        if not args.quiet:
            print(
                f"{deck.name}: {sim.cloud.n_points} points, {sim.model.bonds.n_bonds} bonds, "
                f"{sim.solver.describe()} -> {out}"
            )
        summary = sim.run(
            out, quiet=args.quiet, checkpoint_every=args.checkpoint_every, resume=bool(args.resume)
        )
    except SetupError as exc:
        _err(f"invalid deck:\n  {exc}")
        return EXIT_INVALID
    except OSError as exc:  # no checkpoint, unwritable output folder, ...
        _err(f"error: {exc}")
        return EXIT_INVALID
    except SimulationUnstable as exc:
        _err(f"error: {exc}\nwrote {out / 'last_good.vtu'} and {out / 'summary.json'}")
        return EXIT_UNSTABLE
    if not args.quiet:
        r, t = summary["results"], summary["timing"]
        print(
            f"done: {t['steps']} steps in {t['wall_s']:.2f} s "
            f"({t['bond_updates_per_s']:.3g} bond updates/s); max damage "
            f"{r['max_damage']:.3f}; wrote {out / 'summary.json'}"
        )
    return EXIT_OK


def cmd_ensemble(args: argparse.Namespace) -> int:
    """Run N Weibull realisations of a deck (seeds seed0 .. seed0 + N - 1) and report the
    spread of the peak stress and of the damaged area (``ensemble.json``)."""
    import json

    import numpy as np

    from peridynamics.io.deck import DeckError, load_deck
    from peridynamics.runner import SetupError, Simulation
    from peridynamics.solvers import SimulationUnstable

    if args.n < 1:
        _err("--n must be >= 1")
        return EXIT_INVALID
    deck = _load(args)
    if deck is None:
        return EXIT_INVALID
    if deck.damage.weibull is None:
        _err("ensemble: the deck has no damage.weibull section (nothing to vary)")
        return EXIT_INVALID
    out = Path(args.out or Path("results") / f"{deck.name}_ensemble")
    runs = []
    for k in range(args.n):
        seed = args.seed0 + k
        try:
            member = load_deck(args.deck, [*(args.set or []), f"damage.weibull.seed={seed}"])
            sim = Simulation.from_deck(member)
            summary = sim.run(out / f"seed_{seed}", quiet=True)
        except (DeckError, SetupError) as exc:
            _err(f"invalid deck:\n  {exc}")
            return EXIT_INVALID
        except SimulationUnstable as exc:
            _err(f"error (seed {seed}): {exc}")
            return EXIT_UNSTABLE
        r = summary["results"]
        runs.append(
            {
                "seed": seed,
                "peak_stress_Pa": r.get("peak_stress_Pa"),
                "damaged_area_fraction": r["damaged_area_fraction"],
                "wall_s": summary["timing"]["wall_s"],
            }
        )
        if not args.quiet:
            print(
                f"seed {seed}: peak stress {r.get('peak_stress_Pa')}, damaged area "
                f"{r['damaged_area_fraction']:.4f}"
            )

    def spread(key: str) -> dict[str, float] | None:
        vals = np.array([r[key] for r in runs if r[key] is not None], dtype=float)
        if vals.size == 0:
            return None
        return {
            "mean": float(vals.mean()),
            "std": float(vals.std(ddof=1)) if vals.size > 1 else 0.0,
            "min": float(vals.min()),
            "max": float(vals.max()),
            "cv": float(vals.std(ddof=1) / vals.mean()) if vals.size > 1 and vals.mean() else 0.0,
        }

    report = {
        "deck": str(args.deck),
        "n": args.n,
        "seeds": [r["seed"] for r in runs],
        "peak_stress_Pa": spread("peak_stress_Pa"),
        "damaged_area_fraction": spread("damaged_area_fraction"),
        "runs": runs,
    }
    out.mkdir(parents=True, exist_ok=True)
    (out / "ensemble.json").write_text(json.dumps(report, indent=2))
    if not args.quiet:
        print(f"wrote {out / 'ensemble.json'}")
    return EXIT_OK


def cmd_examples(args: argparse.Namespace) -> int:
    """List the examples or copy one to a folder."""
    ex = list_examples()
    if args.action == "list" or args.action is None:
        for name, path in ex.items():
            print(f"{name:40s} {path}")
        return EXIT_OK
    if not args.name or args.name not in ex:
        _err(f"unknown example {args.name!r}; known: {', '.join(ex)}")
        return EXIT_INVALID
    src = ex[args.name]
    dest = Path(args.dest or ".")
    dest.mkdir(parents=True, exist_ok=True)
    whole_folder = src.stem == "deck" or src.suffix == ".py"
    target = dest / (src.parent.name if whole_folder else src.name)
    if target.exists() and not args.force:
        _err(f"{str(target)!r} exists; not overwriting your copy (use --force to replace it)")
        return EXIT_INVALID
    if whole_folder:  # a folder example: copy the whole folder
        shutil.copytree(src.parent, target, dirs_exist_ok=True)
    else:
        shutil.copy2(src, target)
    print(f"copied {args.name} to {target}")
    return EXIT_OK


def cmd_bench(args: argparse.Namespace) -> int:
    """Run the kernel benchmark."""
    from peridynamics.bench import run_benchmarks

    try:
        dims = tuple(int(d) for d in args.dims.split(","))
    except ValueError:
        dims = ()
    if not dims or any(d not in (1, 2, 3) for d in dims):
        _err(f"--dims: comma-separated dimensions from 1, 2, 3, got {args.dims!r}")
        return EXIT_INVALID
    if args.steps < 1:
        _err("--steps must be >= 1")
        return EXIT_INVALID
    results = run_benchmarks(args.size, dims=dims, steps=args.steps)
    if args.json:
        print(json.dumps([r.as_dict() for r in results], indent=2))
    else:
        print(
            f"{'dim':>3} {'points':>9} {'bonds':>11} {'s/step':>9} {'bonds/s':>10} "
            f"{'numpy b/s':>10} {'speedup':>8} {'B/bond':>7}"
        )
        for r in results:
            print(
                f"{r.dim:>3} {r.points:>9} {r.bonds:>11} {r.seconds_per_step:>9.4f} "
                f"{r.bonds_per_second:>10.3g} {r.numpy_bonds_per_second:>10.3g} "
                f"{r.speedup:>8.1f} {r.bytes_per_bond:>7.1f}"
            )
    return EXIT_OK


def cmd_dispersion(args: argparse.Namespace) -> int:
    """Dispersion curve of the semi-discrete relation (PD wave dispersion (n.d.)), or grid
    advice."""
    from peridynamics.analysis import dispersion as dsp

    if args.frequency is not None or args.pulse_duration is not None:
        return _advise(args)
    if not args.m >= 1:
        _err("--m must be >= 1 (delta = m h)")
        return EXIT_INVALID
    if args.n_points < 2:
        _err("--n-points must be >= 2")
        return EXIT_INVALID
    if args.dim == 1 and args.theta != 0.0:
        _err("--theta is for --dim 2")
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
        _err("give --frequency or --pulse-duration, not both")
        return EXIT_INVALID
    # a pulse of duration T carries most of its energy below about 2 / T
    freq = args.frequency if args.frequency is not None else 2.0 / args.pulse_duration
    try:
        adv = dsp.advise_1d(
            freq, args.tolerance, args.youngs_modulus, args.density, m_min=args.m_min
        )
    except ValueError as exc:
        _err(f"error: {exc}")
        return EXIT_INVALID
    if args.json:
        print(
            json.dumps(
                {
                    "frequency_hz": adv.frequency,
                    "m": adv.m,
                    "spacing_m": adv.spacing,
                    "horizon_m": adv.horizon,
                    "max_phase_error": adv.max_phase_error,
                    "table": adv.table,
                }
            )
        )
        return EXIT_OK
    print(f"up to {adv.frequency:.4g} Hz with phase-speed error <= {args.tolerance:g}:")
    print(
        f"  use m = {adv.m}, dx = {adv.spacing:.4g} m, delta = {adv.horizon:.4g} m "
        f"(error {adv.max_phase_error:.3g})"
    )
    for row in adv.table:
        print(f"  m = {int(row['m']):2d}: coarsest dx = {row['spacing_m']:.4g} m")
    return EXIT_OK


def build_parser() -> argparse.ArgumentParser:
    """The argument parser."""
    p = argparse.ArgumentParser(
        prog="peridynamics", description="Peridynamic simulation of fracture and waves."
    )
    p.add_argument("--version", action="version", version=f"peridynamics {__version__}")
    sub = p.add_subparsers(dest="command", required=True)

    def deck_args(sp: argparse.ArgumentParser) -> None:
        sp.add_argument("deck", help="YAML deck")
        sp.add_argument(
            "--set",
            action="append",
            metavar="KEY.PATH=VALUE",
            help="override a deck value (repeatable), e.g. solver.steps=100",
        )

    r = sub.add_parser("run", help="run a deck")
    deck_args(r)
    r.add_argument("--out", help="output folder (default results/<name>)")
    r.add_argument("--quiet", action="store_true", help="no progress bar or messages")
    r.add_argument(
        "--checkpoint-every",
        type=int,
        default=0,
        metavar="N",
        help="write an atomic checkpoint every N steps",
    )
    r.add_argument("--resume", metavar="DIR", help="continue from the checkpoint in DIR")
    r.set_defaults(func=cmd_run)

    en = sub.add_parser("ensemble", help="run N Weibull realisations of a deck")
    deck_args(en)
    en.add_argument("--n", type=int, default=5, help="number of realisations")
    en.add_argument("--seed0", type=int, default=0, help="first seed (then +1, +2, ...)")
    en.add_argument("--out", help="output folder (default results/<name>_ensemble)")
    en.add_argument("--quiet", action="store_true")
    en.set_defaults(func=cmd_ensemble)

    c = sub.add_parser("check", help="validate a deck without running (exit 0 valid, 2 not)")
    deck_args(c)
    c.add_argument(
        "--bonds",
        action="store_true",
        help="also build bonds, model and solver (checks the time step)",
    )
    c.set_defaults(func=cmd_check)

    e = sub.add_parser("examples", help="list the examples, or copy one: examples copy NAME DIR")
    e.add_argument("action", nargs="?", choices=["list", "copy"], default="list")
    e.add_argument("name", nargs="?")
    e.add_argument("dest", nargs="?")
    e.add_argument("--force", action="store_true", help="replace an existing copy")
    e.set_defaults(func=cmd_examples)

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
    d.add_argument("--youngs-modulus", type=float, default=20e9, help="advice: E (Pa)")
    d.add_argument("--density", type=float, default=2620.0, help="advice: rho (kg/m^3)")
    d.add_argument("--m-min", type=int, default=3, help="advice: smallest m to recommend")
    d.set_defaults(func=cmd_dispersion)

    b = sub.add_parser("bench", help="benchmark the explicit PMB step (Numba vs NumPy)")
    b.add_argument("--json", action="store_true", help="print a JSON list of cases")
    b.add_argument("--size", choices=["quick", "default", "full"], default="default")
    b.add_argument("--dims", default="1,2,3", help="comma-separated dimensions")
    b.add_argument("--steps", type=int, default=20)
    b.set_defaults(func=cmd_bench)
    return p


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``peridynamics`` console script."""
    args = build_parser().parse_args(argv)
    return int(args.func(args))


if __name__ == "__main__":
    sys.exit(main())
