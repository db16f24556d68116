"""Command line: ``peridynamics run|check|examples|bench|dispersion|ensemble|sweep|help``.

Exit codes: 0 success; 2 invalid deck or model set-up (the key path is on stderr), a
model too large for this machine, bad arguments; 3 the run went unstable (a summary and
``last_good.vtu`` are written); 130 interrupted by Ctrl-C (a summary with status
``"interrupted"`` and, when checkpointing is on, a checkpoint to resume from).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shlex
import shutil
import sys
from pathlib import Path
from typing import Any

import numpy as np

from peridynamics import __version__
from peridynamics.io.deck_help import deck_reference, hint

EXIT_OK, EXIT_INVALID, EXIT_UNSTABLE, EXIT_INTERRUPTED = 0, 2, 3, 130
EXIT_CODES = """exit codes:
  0    success
  2    invalid deck or set-up (key.path: message on stderr), a model too large for
       this machine (see --allow-large), bad arguments
  3    run: the run went unstable (summary.json and last_good.vtu are written)
  130  run: interrupted by Ctrl-C (summary.json with status "interrupted"; with
       --checkpoint-every N also a checkpoint: peridynamics run DECK --resume DIR)"""
HELP_TOPICS = """the reference, from the installed package (the documentation site's pages):
  peridynamics help deck               every key a deck accepts, type and default
  peridynamics help deck.SECTION       one section with units, ranges and examples,
                                       e.g. deck.material, deck.solver.adr, deck.bodies
  peridynamics help output             the files of a run and summary.json"""
#: bond updates per second assumed for the wall-time estimate (README: 3.5e8 measured)
BOND_UPDATES_PER_S = 3e8
#: more bond updates than this (steps x bonds) is refused without --allow-large
MAX_BOND_UPDATES = 1e15


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


def _invalid_deck(exc: Any) -> str:
    """A set-up error (``runner.SetupError``) as a deck error prints: the key path and
    message, then the help topic of its section."""
    return f"invalid deck:\n  {exc}\n{hint([exc.path])}".rstrip()


def _load(args: argparse.Namespace):  # noqa: ANN202 - returns a Deck
    from peridynamics.io.deck import DeckError, load_deck

    try:
        return load_deck(args.deck, overrides=args.set or [])
    except DeckError as exc:
        _err(str(exc))
        return None


def available_memory() -> tuple[float, str]:
    """Bytes of memory a run may use here, and where the figure comes from: the smaller
    of MemAvailable (/proc/meminfo) and the room left under a cgroup limit; else the
    free physical pages (os.sysconf); else 8 GiB, assumed."""
    found: list[tuple[float, str]] = []
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                found.append((float(line.split()[1]) * 1024.0, "MemAvailable"))
    except (OSError, ValueError, IndexError):
        pass
    try:
        limit = Path("/sys/fs/cgroup/memory.max").read_text().strip()
        used = Path("/sys/fs/cgroup/memory.current").read_text().strip()
        if limit != "max":
            found.append((float(limit) - float(used), "the cgroup memory limit"))
    except (OSError, ValueError):
        pass
    if not found:
        try:
            pages = os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
            found.append((float(pages), "free physical memory"))
        except (ValueError, OSError, AttributeError):
            found.append((8.0 * 2**30, "assumed: the available memory could not be read"))
    return min(found)


def _human_time(seconds: float) -> str:
    for unit, size in (("years", 3.15e7), ("days", 86400.0), ("hours", 3600.0)):
        if seconds >= size:
            return f"{seconds / size:.3g} {unit}"
    return f"{seconds:.3g} s"


def _size_problem(
    deck: Any, allow_large: bool, n_points: float | None = None, share: float = 1.0
) -> str | None:
    """Why the model is too large for this machine (``None`` when it fits, when the size
    cannot be estimated yet, or with ``allow_large``). ``share``: the part of the model
    this machine holds (under MPI: its ranks / all ranks)."""
    from peridynamics.io.deck import estimate_size

    est = estimate_size(deck, n_points)
    if est is None or allow_large:
        return None
    avail, source = available_memory()
    if est.points >= 2**31 - 1:
        why = "more points than the 32-bit point index holds"
    elif est.bytes * share > avail:
        why = f"more than the {avail / 1e9:.3g} GB available ({source})"
    else:
        return None
    d = deck.discretisation
    points_only = est.BASE_BYTES + est.BYTES_PER_POINT * est.points
    key = "spacing"  # too many points, or a horizon that holds thousands of them:
    if points_only < min(avail, 0.5 * est.bytes) and est.points < 2**31 - 1:
        key = "horizon" if d.horizon is not None else "horizon_factor"
    return (
        f"discretisation.{key}: the model is too large: {est.describe()}, {why}. "
        f"spacing = {d.spacing:g} m, horizon = {d.delta:g} m: check them (a typo in an "
        "exponent?), or pass --allow-large to try anyway"
    )


def _work_problem(
    steps: float | None, bonds: float, allow_large: bool, estimated: bool
) -> str | None:
    """Why steps x bonds is beyond any sensible run (``None`` when it is not)."""
    if steps is None or allow_large:
        return None
    work = steps * bonds
    if not work > MAX_BOND_UPDATES:
        return None
    about = "about " if estimated else ""
    return (
        f"solver: {about}{steps:.3g} steps x {bonds:.3g} bonds = {work:.3g} bond updates, "
        f"about {_human_time(work / BOND_UPDATES_PER_S)} at {BOND_UPDATES_PER_S:.0e} bond "
        f"updates/s (more than {MAX_BOND_UPDATES:.0e}); check solver.end_time, "
        "solver.time_step and the material's units, or pass --allow-large to run anyway"
    )


def _built_problem(sim: Any, allow_large: bool) -> str | None:
    """Checks of a built model: a finite, non-zero time step; a sensible amount of
    work (steps x bonds)."""
    solver = sim.solver
    for attr, key in (("stable_time_step", "material.youngs_modulus"), ("dt", "solver.time_step")):
        value = getattr(solver, attr, None)
        if value is not None and not (math.isfinite(value) and value > 0):
            return (
                f"{key}: the {attr.replace('_', ' ')} is {value:.3g} s, not a finite time > 0; "
                "check material.youngs_modulus (Pa), material.density (kg/m^3) and the "
                "discretisation (m)"
            )
    from peridynamics.solvers.explicit import ExplicitSolver

    inner = getattr(solver, "second", solver)  # a hybrid: the PD model sets the cost
    steps = float(solver.total_steps()) if isinstance(inner, ExplicitSolver) else None
    return _work_problem(steps, float(sim.model.bonds.n_bonds), allow_large, False)


def _refuse(msg: str) -> int:
    _err(f"invalid deck:\n  {msg}")
    return EXIT_INVALID


def _out_of_memory(exc: MemoryError) -> int:
    _err(
        f"error: out of memory ({exc or 'MemoryError'}): the model is too large for this "
        "machine; use a coarser discretisation.spacing or a smaller horizon"
    )
    return EXIT_INVALID


def cmd_check(args: argparse.Namespace) -> int:
    """Validate a deck and build its geometry and node sets, without running.

    With ``--bonds`` also build the bonds, the model and the solver: the time step is
    then checked against the stable limit as ``run`` would. The size of the model is
    estimated first and a model that cannot fit in memory is refused (exit 2) unless
    ``--allow-large``.
    """
    from peridynamics.app.run import Simulation
    from peridynamics.build.cloud import build_cloud
    from peridynamics.build.errors import SetupError
    from peridynamics.io.deck import MeshGeometry, estimate_size, estimate_steps

    deck = _load(args)
    if deck is None:
        return EXIT_INVALID
    try:
        problem = _size_problem(deck, args.allow_large)
        if problem:
            return _refuse(problem)
        if args.bonds:
            if isinstance(deck.geometry, MeshGeometry):  # the size is known once it is read
                problem = _size_problem(deck, args.allow_large, build_cloud(deck).n_points)
                if problem:
                    return _refuse(problem)
            sim = Simulation.from_deck(deck)
            problem = _built_problem(sim, args.allow_large)
            extra = f", {sim.model.bonds.n_bonds} bonds, {sim.solver.describe()}"
            n_points = sim.cloud.n_points
        else:
            n_points, extra = build_cloud(deck).n_points, ""
            est = estimate_size(deck, n_points)
            problem = _size_problem(deck, args.allow_large, n_points)
            if problem is None and est is not None:
                problem = _work_problem(estimate_steps(deck), est.bonds, args.allow_large, True)
        if problem:
            return _refuse(problem)
    except SetupError as exc:
        _err(_invalid_deck(exc))
        return EXIT_INVALID
    except MemoryError as exc:
        return _out_of_memory(exc)
    print(f"{args.deck}: valid ({deck.dim}-D, {n_points} points{extra})")
    return EXIT_OK


def _resume_hint(args: argparse.Namespace, out: Path) -> str:
    sets = "".join(f" --set {shlex.quote(s)}" for s in args.set or [])
    return f"peridynamics run {shlex.quote(str(args.deck))} --resume {shlex.quote(str(out))}{sets}"


def cmd_run(args: argparse.Namespace) -> int:
    """Run a deck."""
    from peridynamics.app.run import RunInterrupted, Simulation
    from peridynamics.build.cloud import build_cloud
    from peridynamics.build.errors import SetupError
    from peridynamics.io.deck import MeshGeometry
    from peridynamics.solvers import SimulationUnstable

    if args.resume and args.out:
        _err("give either --out DIR (a new run) or --resume DIR (continue the run in DIR)")
        return EXIT_INVALID
    if args.checkpoint_every is not None and args.checkpoint_every < 0:
        _err("--checkpoint-every must be >= 0 (0: no checkpoints)")
        return EXIT_INVALID
    if args.resume and not Path(args.resume).is_dir():
        _err(f"--resume: no run folder {args.resume!r}")
        return EXIT_INVALID
    if getattr(args, "backend", None):
        args.set = [*(args.set or []), f"solver.backend={args.backend}"]
    deck = _load(args)
    if deck is None:
        return EXIT_INVALID
    out = Path(args.resume or args.out or Path("results") / deck.name)
    if out.exists() and not out.is_dir():
        _err(f"--out: {str(out)!r} exists and is not a folder")
        return EXIT_INVALID
    every = args.checkpoint_every if args.resume else (args.checkpoint_every or 0)
    comm = _run_comm()
    if comm is False:
        return EXIT_INVALID
    rank = 0 if comm is None else int(comm.Get_rank())
    quiet = args.quiet or rank != 0  # under mpiexec rank 0 speaks
    share = 1.0
    if comm is not None:  # the ranks on this machine hold their part of the model
        from peridynamics.parallel.launch import node_ranks

        share = node_ranks(comm) / comm.Get_size()
    try:
        problem = _size_problem(deck, args.allow_large, share=share)
        if problem is None and isinstance(deck.geometry, MeshGeometry):
            n = build_cloud(deck).n_points
            problem = _size_problem(deck, args.allow_large, n, share)
        if problem:
            return _refuse(problem) if rank == 0 else EXIT_INVALID
        sim = Simulation.from_deck(deck, comm)
        problem = _built_problem(sim, args.allow_large)
        if problem:
            return _refuse(problem)
        if not quiet:
            where = ""
            n_points, n_bonds = sim.cloud.n_points, sim.model.bonds.n_bonds
            if sim.session is not None:
                where = f" on {sim.session.comm.size} MPI ranks"
                n_points = sim.session.global_cloud.n_points
                n_bonds = sim._global_bonds()
            print(
                f"{deck.name}: {n_points} points, {n_bonds} bonds, "
                f"{sim.solver.describe()}{where} -> {out}"
            )
        elif sim.session is not None:
            sim._global_bonds()  # collective: every rank takes part
        summary = sim.run(out, quiet=quiet, checkpoint_every=every, resume=bool(args.resume))
        if rank != 0:
            return EXIT_OK
    except SetupError as exc:
        if rank == 0:
            _err(f"error: {exc}" if exc.path.startswith("--") else _invalid_deck(exc))
        return EXIT_INVALID
    except OSError as exc:  # no checkpoint, unwritable output folder, ...
        _err(f"error: {exc}")
        return EXIT_INVALID
    except MemoryError as exc:
        return _out_of_memory(exc)
    except SimulationUnstable as exc:
        if rank == 0:
            _err(f"error: {exc}\nwrote {out / 'last_good.vtu'} and {out / 'summary.json'}")
        return EXIT_UNSTABLE
    except RunInterrupted as exc:
        if rank != 0:
            return EXIT_INTERRUPTED
        _err(
            f"interrupted after step {exc.step} of {exc.total} (t = {exc.t:.6g} s); wrote "
            f'{out / "summary.json"} (status "interrupted")'
        )
        if exc.checkpoint is not None:
            _err(f"checkpoint: {exc.checkpoint}\nresume with: {_resume_hint(args, out)}")
        else:
            _err(
                "no checkpoint (checkpointing is off): run with --checkpoint-every N "
                "to be able to resume an interrupted run"
            )
        return EXIT_INTERRUPTED
    if not args.quiet:
        r, t = summary["results"], summary["timing"]
        print(
            f"done: {t['steps']} steps in {t['wall_s']:.2f} s "
            f"({t['bond_updates_per_s']:.3g} bond updates/s); max damage "
            f"{r['max_damage']:.3f}; wrote {out / 'summary.json'}"
        )
    if summary["results"].get("converged") is False:  # adr / static: reported, not an error
        r = summary["results"]
        steps = r.get("not_converged_load_steps")
        _err(
            "warning: the static solve did not converge"
            + (f" in load steps {steps}" if steps else "")
            + f": {r.get('message') or 'see summary.json'} (results.converged is false)"
        )
    return EXIT_OK


def _run_comm() -> Any:
    """The MPI communicator of ``mpiexec -n N peridynamics run`` (N > 1), ``None`` for a
    plain run, ``False`` after printing why an MPI launch cannot work. Each rank gets
    its share of the machine's cores as Numba threads (unless NUMBA_NUM_THREADS is set)."""
    from peridynamics.parallel.launch import LaunchError, mpi_comm, share_cores

    try:
        comm = mpi_comm()
    except LaunchError as exc:
        _err(f"error: {exc}")
        return False
    share_cores(comm)
    if comm is not None:  # an error on one rank must not leave the others waiting

        def abort(kind: Any, value: Any, tb: Any) -> None:
            sys.__excepthook__(kind, value, tb)
            comm.Abort(1)

        sys.excepthook = abort
    return comm


def cmd_ensemble(args: argparse.Namespace) -> int:
    """Run N Weibull realisations of a deck (seeds seed0 .. seed0 + N - 1) and report the
    spread of the peak stress and of the damaged area (``ensemble.json``); under
    ``mpiexec -n R`` the realisations are spread over the R ranks (``peridynamics.ensemble``)."""
    from peridynamics.ensemble import cmd_ensemble as run_ensemble

    return run_ensemble(args)


def cmd_sweep(args: argparse.Namespace) -> int:
    """Run a deck over a grid or a list of parameter values (``peridynamics.sweep``)."""
    from peridynamics.sweep import cmd_sweep as run_sweep

    return run_sweep(args)


def cmd_examples(args: argparse.Namespace) -> int:
    """List the examples or copy one to a folder."""
    ex = list_examples()
    if args.action == "list" or args.action is None:
        for name, path in ex.items():
            print(f"{name:40s} {path}")
        return EXIT_OK
    if not args.name:
        _err(
            "examples copy: give the NAME of an example (and a DEST folder), e.g. "
            f"peridynamics examples copy bar_wave_1d mine/; known: {', '.join(ex)}"
        )
        return EXIT_INVALID
    if args.name not in ex:
        _err(f"unknown example {args.name!r}; known: {', '.join(ex)}")
        return EXIT_INVALID
    src = ex[args.name]
    dest = Path(args.dest or ".")
    dest.mkdir(parents=True, exist_ok=True)
    # an example is its folder (decks, mesh files, scripts, README): copy all of it;
    # only a deck lying at the top of the examples tree is copied alone
    whole_folder = src.parent != examples_dir()
    target = dest / (src.parent.name if whole_folder else src.name)
    if target.exists() and not args.force:
        _err(f"{str(target)!r} exists; not overwriting your copy (use --force to replace it)")
        return EXIT_INVALID
    if whole_folder:
        shutil.copytree(src.parent, target, dirs_exist_ok=True)
        if src.stem == "deck" or src.suffix == ".py":
            print(f"copied {args.name} to {target}")
        else:  # one deck of a folder of decks
            print(
                f"copied {args.name} with its folder to {target}; the deck is {target / src.name}"
            )
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
    for name, value in (("--youngs-modulus", args.youngs_modulus), ("--density", args.density)):
        if not (math.isfinite(value) and value > 0):
            _err(f"{name} must be a finite number > 0, got {value}")
            return EXIT_INVALID
    try:
        adv = dsp.advise_1d(
            freq, args.tolerance, args.youngs_modulus, args.density, m_min=args.m_min
        )
    except ValueError as exc:
        _err(f"error: {exc}")
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


def cmd_help(args: argparse.Namespace) -> int:
    """Print a section of the deck reference or of the output page, from the installed
    package, with the keys of the schema of this version (``help deck.material``); or
    every key a deck accepts (``help deck``)."""
    from peridynamics.io.deck_help import HelpTopicError, help_text, topics

    topic = args.topic if args.section is None else f"{args.topic}.{args.section}"
    if topic == "deck":
        print(deck_reference())
        print(
            "\nEach section with its units, allowed ranges and examples: "
            "`peridynamics help deck.SECTION`\n(sections: "
            + ", ".join(t.split(".", 1)[1] for t in topics("deck"))
            + ");\nthe outputs and summary.json: `peridynamics help output`; complete decks: "
            "`peridynamics examples copy NAME DIR`."
        )
        return EXIT_OK
    try:
        text = help_text(topic)
    except HelpTopicError as exc:
        _err(str(exc))
        return EXIT_INVALID
    print(text)
    return EXIT_OK


def build_parser() -> argparse.ArgumentParser:
    """The argument parser."""
    p = argparse.ArgumentParser(
        prog="peridynamics",
        description="Peridynamic simulation of fracture and waves.",
        epilog=EXIT_CODES + "\n\n" + HELP_TOPICS,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--version", action="version", version=f"peridynamics {__version__}")
    sub = p.add_subparsers(dest="command", required=True)

    def deck_args(sp: argparse.ArgumentParser) -> None:
        sp.add_argument("deck", help="YAML deck")
        sp.add_argument(
            "--set",
            action="append",
            metavar="KEY.PATH=VALUE",
            help="override a deck value (repeatable), e.g. solver.steps=100; the keys: "
            "peridynamics help deck.SECTION",
        )

    def large_arg(sp: argparse.ArgumentParser) -> None:
        sp.add_argument(
            "--allow-large",
            action="store_true",
            help="do not refuse a model estimated to exceed the available memory, or a run "
            f"of more than {MAX_BOND_UPDATES:.0e} bond updates (steps x bonds)",
        )

    r = sub.add_parser(
        "run",
        help="run a deck",
        epilog=EXIT_CODES + "\n\nCtrl-C stops after the current step and writes the outputs "
        "and summary.json;\nwith --checkpoint-every N, resume with --resume DIR.\n\n" + HELP_TOPICS,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    deck_args(r)
    r.add_argument("--out", help="output folder (default results/<name>)")
    r.add_argument("--quiet", action="store_true", help="no progress bar or messages")
    r.add_argument(
        "--checkpoint-every",
        type=int,
        default=None,
        metavar="N",
        help="write an atomic checkpoint every N steps, and one of the final state "
        "(default 0: none; with --resume: the interval of the original run)",
    )
    r.add_argument("--resume", metavar="DIR", help="continue from the checkpoint in DIR")
    r.add_argument(
        "--backend",
        choices=["numba", "warp"],
        help="compute backend of the explicit step (sets solver.backend; warp: pip install "
        "'peridynamics[gpu]', its CUDA device when there is one, else its CPU device)",
    )
    large_arg(r)
    r.set_defaults(func=cmd_run)

    en = sub.add_parser(
        "ensemble",
        help="run N Weibull realisations of a deck",
        description="Run N Weibull realisations of a deck; under mpiexec -n R they are "
        "spread over the R ranks (realisation k on rank k % R).",
    )
    deck_args(en)
    en.add_argument("--n", type=int, default=5, help="number of realisations")
    en.add_argument("--seed0", type=int, default=0, help="first seed (then +1, +2, ...)")
    en.add_argument("--out", help="output folder (default results/<name>_ensemble)")
    en.add_argument("--quiet", action="store_true")
    large_arg(en)
    en.set_defaults(func=cmd_ensemble)

    sw = sub.add_parser(
        "sweep",
        help="run a deck over a grid or a list of parameter values (docs/sweep.md)",
        epilog="exit codes:\n  0    every case completed (or was done before)\n  2    bad "
        "arguments or an invalid case (nothing was run)\n  4    some case failed or went "
        "unstable (the others ran; see sweep.csv)\n  130  interrupted (Ctrl-C or SIGTERM): "
        "run the same command again to continue",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    deck_args(sw)
    sw.add_argument(
        "--grid",
        action="append",
        metavar="KEY.PATH=V1,V2,...",
        help="values of a deck key (repeatable: the cases are the Cartesian product), "
        "e.g. discretisation.spacing=1e-3,5e-4",
    )
    sw.add_argument(
        "--cases", metavar="FILE", help="cases from a file: YAML list of {key.path: value}, or CSV"
    )
    sw.add_argument("--jobs", type=int, default=1, metavar="N", help="cases run at a time")
    sw.add_argument("--out", metavar="DIR", help="output folder (default results/<name>_sweep)")
    sw.add_argument("--plot", metavar="COL,COL", help="sweep.csv columns drawn in sweep.png")
    sw.add_argument(
        "--checkpoint-every",
        type=int,
        metavar="N",
        help="passed to each run: an interrupted case resumes from its checkpoint",
    )
    sw.add_argument("--dry-run", action="store_true", help="validate and list the cases only")
    sw.add_argument("--quiet", action="store_true", help="no progress lines or table")
    large_arg(sw)
    sw.set_defaults(func=cmd_sweep)

    c = sub.add_parser("check", help="validate a deck without running (exit 0 valid, 2 not)")
    deck_args(c)
    c.add_argument(
        "--bonds",
        action="store_true",
        help="also build bonds, model and solver (checks the time step)",
    )
    large_arg(c)
    c.set_defaults(func=cmd_check)

    hp = sub.add_parser(
        "help",
        help="the deck reference from the installed package: help deck.material, "
        "help deck.solver.adr, help output.summary_json; help deck lists every key",
    )
    hp.add_argument(
        "topic",
        help="deck (every key), deck.SECTION[.KIND] (a section of the deck reference with "
        "its keys), output[.SECTION] (files of a run, summary.json)",
    )
    hp.add_argument("section", nargs="?", help="a deck section (the older form: help deck solver)")
    hp.set_defaults(func=cmd_help)

    e = sub.add_parser(
        "examples", help="list the examples, or copy one (its whole folder): examples copy NAME DIR"
    )
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
    return p


def _format_warning(
    message: Warning | str,
    category: type[Warning],
    filename: str,
    lineno: int,
    line: str | None = None,
) -> str:
    return f"warning: {message}\n"


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``peridynamics`` console script."""
    import warnings

    # warnings of the package read as messages, not as source lines
    warnings.formatwarning = _format_warning  # type: ignore[assignment]
    args = build_parser().parse_args(argv)
    try:
        return int(args.func(args))
    except KeyboardInterrupt:  # Ctrl-C outside a run's loop (set-up), or a second one
        _err("interrupted (Ctrl-C); nothing more was written")
        return EXIT_INTERRUPTED
    except MemoryError as exc:
        return _out_of_memory(exc)
    except BrokenPipeError:  # the reader went away (peridynamics help deck | head)
        sys.stdout = open(os.devnull, "w")  # noqa: SIM115 - no flush error at exit
        return EXIT_OK


if __name__ == "__main__":
    sys.exit(main())
