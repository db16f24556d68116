"""Lu & Wang (2016), Table 1 (rock-bar spalling): run the seven decks and write the comparison.

    python examples/spalling/make_table.py            # runs the 7 cases, rewrites README.md

Each case is ``peridynamics run examples/spalling/table1_case<N>.yaml``; the table puts the
paper's fracture position x_F and time t_F beside ours and checks x_F within the paper's
range +/- 2 dx and t_F within 1 %.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
try:
    import peridynamics  # noqa: F401
except ImportError:  # running from a checkout without installing
    sys.path.insert(0, str(HERE.parents[1] / "src"))

from peridynamics.app.run import Simulation  # noqa: E402
from peridynamics.deck import load_deck  # noqa: E402

#: Lu & Wang (2016), Table 1:
#: case -> (m, dx (m), p_m (MPa), t0 (ms), dt (us), x_F range (m), t_F (ms))
PAPER = {
    1: (3, 0.0010, 12, 0.12, 0.10, (0.906, 0.909), 0.4395),
    2: (5, 0.0010, 12, 0.12, 0.10, (0.901, 0.908), 0.4399),
    3: (10, 0.0010, 12, 0.12, 0.10, (0.900, 0.910), 0.4407),
    4: (3, 0.0005, 12, 0.12, 0.05, (0.905, 0.907), 0.4389),
    5: (5, 0.0005, 12, 0.12, 0.05, (0.904, 0.908), 0.4392),
    6: (3, 0.0010, 12, 0.24, 0.10, (0.811, 0.816), 0.5126),
    7: (3, 0.0010, 15, 0.12, 0.10, (0.924, 0.928), 0.4327),
}


def run_case(n: int, out: Path) -> dict:
    """Run case ``n`` into ``out`` and return its results with the checks."""
    sim = Simulation.from_deck(load_deck(HERE / f"table1_case{n}.yaml"))
    summary = sim.run(out, quiet=True)
    r = summary["results"]
    m, dx, pm, t0, dt, (lo, hi), t_f = PAPER[n]
    x = r["fracture_position_m"]
    return {
        "case": n,
        "m": m,
        "dx_m": dx,
        "p_m_MPa": pm,
        "t0_ms": t0,
        "dt_us": dt,
        "paper_x_F_m": [lo, hi],
        "paper_t_F_ms": t_f,
        "x_F_m": x,
        "t_F_ms": r["fracture_time_s"] * 1e3,
        "x_F_ok": bool(x[0] >= lo - 2 * dx - 1e-12 and x[1] <= hi + 2 * dx + 1e-12),
        "t_F_error": r["fracture_time_s"] * 1e3 / t_f - 1.0,
        "wall_s": summary["timing"]["wall_s"],
    }


def table_markdown(rows: list[dict]) -> str:
    """The README table."""
    lines = [
        "| case | m | dx (mm) | p_m (MPa) | t0 (ms) | paper x_F (m) | ours x_F (m) | "
        "paper t_F (ms) | ours t_F (ms) | t_F error | x_F within ±2dx |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['case']} | {r['m']} | {r['dx_m'] * 1e3:g} | {r['p_m_MPa']} | {r['t0_ms']} | "
            f"{r['paper_x_F_m'][0]:.3f}–{r['paper_x_F_m'][1]:.3f} | "
            f"{r['x_F_m'][0]:.4f}–{r['x_F_m'][1]:.4f} | {r['paper_t_F_ms']:.4f} | "
            f"{r['t_F_ms']:.4f} | {100 * r['t_F_error']:+.2f} % | "
            f"{'yes' if r['x_F_ok'] else 'NO'} |"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """Run all cases; print the table and write it into README.md."""
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--no-readme", action="store_true", help="print only")
    args = p.parse_args(argv)
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        rows = [run_case(n, Path(tmp) / f"case{n}") for n in PAPER]
    table = table_markdown(rows)
    print(table)
    print(f"\n7 cases in {time.perf_counter() - t0:.1f} s")
    if not args.no_readme:
        readme = HERE / "README.md"
        text = readme.read_text()
        start, end = "<!-- table1 -->", "<!-- /table1 -->"
        head, rest = text.split(start)
        _, tail = rest.split(end)
        readme.write_text(f"{head}{start}\n{table}\n{end}{tail}")
        (HERE / "table1_results.json").write_text(json.dumps(rows, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
