"""Markdown tables for docs/performance.md from the JSON files of the benchmarks here.

    python benchmarks/performance_tables.py --ceiling C.json [C2.json ...] \
        --lammps L.json [...] --bytes B.json

``C.json`` from ``bond_ceiling.py --json``, ``L.json`` from ``lammps_peri.py --json``,
``B.json`` from ``bond_bytes.py --json``. Rates are directed bond updates per second,
"best / median" over the rounds of one run.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

ROWS = [
    ("pkg_step", "package: PMB step (`peridynamics bench`)"),
    ("pkg_force", "package: force kernel alone"),
    ("mix", "(a) mix, vectorised (unsigned indices)"),
    ("mix_signed", "(a) mix, vectorised, signed indices"),
    ("mix_scalar", "(a) mix, scalar"),
    ("mixflag", "(a') mix + intact flag + max stretch (package loop)"),
    ("nogather", "(b) no gathers (unit-stride loads)"),
    ("alu", "(b') arithmetic only (no per-bond loads)"),
    ("mix32", "(c) mix float32, vectorised"),
    ("mix32_scalar", "(c) mix float32, scalar"),
]


def _e(v: float) -> str:
    m, x = f"{v:.2e}".split("e")
    return f"{m}e{int(x)}"


def _case(c: dict) -> str:
    if c["dim"] == 1:
        return f"1-D {c['n_side']:,} points"
    return f"{c['dim']}-D {c['n_side']}{'²' if c['dim'] == 2 else '³'}"


def _short(path: str) -> str:
    return path.replace("dict['state'].", "state.").replace("dict['solver'].", "solver.")


def ceiling_tables(files: list[Path]) -> str:
    out = []
    for f in files:
        d = json.loads(f.read_text())
        cases = [c for c in d["cases"] if "results" in c]
        m = d["meta"]
        out.append(
            f"\n`{f.name}`: {m['date']}, CPU {m['cpu']}, {m['numba_threads']} Numba threads, "
            f"commit {m['commit']}; other load (cores, mean / max over the kept windows): "
            + ", ".join(
                f"{_case(c)} {c['other_load_mean_cores']} / {c['other_load_max_cores']}"
                for c in cases
            )
            + "\n"
        )
        head = "| kernel | " + " | ".join(
            f"{_case(c)} ({c['directed_bonds']:,} bonds) best / median" for c in cases
        )
        out.append(head + " |")
        out.append("|---" * (len(cases) + 1) + "|")
        for key, label in ROWS:
            cells = []
            for c in cases:
                r = c["results"].get(key)
                cells.append(f"{_e(r['rate_best'])} / {_e(r['rate_median'])}" if r else "—")
            out.append(f"| {label} | " + " | ".join(cells) + " |")
        for a in ("pkg_step", "pkg_force"):
            cells = []
            for c in cases:
                k = f"{a} / {c['ceiling_kernel']}"
                r = c["ratios"][k]
                cells.append(f"{r['best']:.2f} / {r['median']:.2f}")
            label = "ratio package step / ceiling" if a == "pkg_step" else "ratio force / ceiling"
            out.append(f"| **{label}** | " + " | ".join(cells) + " |")
    return "\n".join(out)


def lammps_tables(files: list[Path]) -> str:
    out = []
    for f in files:
        d = json.loads(f.read_text())
        m = d["meta"]
        out.append(
            f"\n`{f.name}`: {m['date']}, CPU {m['cpu']}, LAMMPS {m['lammps']['version']} "
            f"({m['lammps']['mpi']}); package {m['numba_threads']} Numba threads\n"
        )
        out.append(
            "| case | directed bonds | package step best / median | LAMMPS launch | "
            "LAMMPS best / median | package / LAMMPS best / median | other load mean / max |"
        )
        out.append("|---|---|---|---|---|---|---|")
        for c in d["cases"]:
            p = c["package"]
            for cfg, r in c["lammps"].items():
                q = c["ratios"][f"package / LAMMPS {cfg}"]
                name = {"mpi": "MPI rank(s)", "omp": "OpenMP threads, 1 rank"}[cfg[:3]]
                out.append(
                    f"| {_case(c)} | {c['directed_bonds']:,} | {_e(p['rate_best'])} / "
                    f"{_e(p['rate_median'])} | {cfg[3:]} {name} | {_e(r['rate_best'])} / "
                    f"{_e(r['rate_median'])} | **{q['best']:.2f} / {q['median']:.2f}** | "
                    f"{c['other_load_mean_cores']} / {c['other_load_max_cores']} |"
                )
    return "\n".join(out)


def bytes_table(files: list[Path]) -> str:
    out = []
    for f in files:
        cases = json.loads(f.read_text())
        names = []
        for c in cases:
            for k in c["reachable_arrays"]:
                short = _short(k)
                if short not in names:
                    names.append(short)
        out.append(f"\n`{f.name}`\n")
        out.append("| per-bond array | dtype | " + " | ".join(_case(c) for c in cases) + " |")
        out.append("|---|---" + "|---" * len(cases) + "|")
        for n in names:
            row, dtype = [], ""
            for c in cases:
                v = next((v for k, v in c["reachable_arrays"].items() if _short(k) == n), None)
                row.append(f"{v['bytes_per_bond']:g}" if v else "—")
                dtype = dtype or (v["dtype"] if v else "")
            out.append(f"| `{n}` | {dtype} | " + " | ".join(row) + " |")
        out.append(
            "| **`peridynamics bench` bytes/bond** | | "
            + " | ".join(f"**{c['bench_bytes_per_bond']:g}**" for c in cases)
            + " |"
        )
        out.append(
            "| **all per-bond arrays reachable** | | "
            + " | ".join(f"**{c['reachable_bytes_per_bond']:g}**" for c in cases)
            + " |"
        )
        out.append(
            "| per-point arrays, per bond | | "
            + " | ".join(f"{c['per_point_arrays_bytes_per_bond']:.1f}" for c in cases)
            + " |"
        )
        out.append(
            "| peak RSS per bond (set-up included) | | "
            + " | ".join(f"{c['peak_rss_bytes_per_bond']:.0f}" for c in cases)
            + " |"
        )
    return "\n".join(out)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--ceiling", nargs="*", type=Path, default=[])
    p.add_argument("--lammps", nargs="*", type=Path, default=[])
    p.add_argument("--bytes", nargs="*", type=Path, default=[])
    a = p.parse_args()
    if a.ceiling:
        print(ceiling_tables(a.ceiling))
    if a.lammps:
        print(lammps_tables(a.lammps))
    if a.bytes:
        print(bytes_table(a.bytes))


if __name__ == "__main__":
    main()
