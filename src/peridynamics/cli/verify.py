"""``peridynamics verify``: the verification cases as one command and a report
(:mod:`peridynamics.app.verify`)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from peridynamics.app.checks import err
from peridynamics.app.exit_codes import EXIT_CASES_FAILED, EXIT_INVALID, EXIT_OK


def cmd_verify(args: argparse.Namespace) -> int:
    """Run the cases of the tier and write the reports; exit 0 when every check passed,
    4 when one failed, 2 on bad arguments."""
    from peridynamics.app.verify import run_cases
    from peridynamics.app.verify_cases import select

    tier = "full" if args.full else "quick"
    if args.jobs < 1:
        err("--jobs must be >= 1 (cases run at a time)")
        return EXIT_INVALID
    cases = select(tier, args.only)
    if not cases:
        names = ", ".join(c.name for c in select(tier))
        err(f"--only {args.only!r} matches no case of the {tier} tier; the cases: {names}")
        return EXIT_INVALID
    if args.list:
        for c in cases:
            print(f"{c.name}: {c.title} ({len(c.checks)} checks)")
        return EXIT_OK
    out = Path(args.out or Path("results") / f"verify_{tier}")
    if out.exists() and not out.is_dir():
        err(f"--out: {str(out)!r} exists and is not a folder")
        return EXIT_INVALID
    if not args.quiet:
        print(f"verify --{tier}: {len(cases)} case(s), {args.jobs} at a time -> {out}", flush=True)
    report = run_cases(tier, out, args.only, args.jobs, quiet=args.quiet)
    failed = [r["case"] for r in report["cases"] if not r["passed"]]
    if not args.quiet:
        print(
            f"{len(cases) - len(failed)} of {len(cases)} cases passed in "
            f"{report['wall_s']:.0f} s; report: {out / 'verify.html'}"
            + (f"; failed: {', '.join(failed)}" if failed else "")
        )
    return EXIT_CASES_FAILED if failed else EXIT_OK


def register(sub: Any) -> None:
    """The parser of ``verify``."""
    v = sub.add_parser(
        "verify",
        help="run the verification cases and write a report (verify.html, .md, .json)",
        description="Run the package's verification cases: shipped examples against "
        "closed-form solutions and published observations, each with its source and "
        "tolerance. Exit 0 every check passed, 4 a check failed, 2 bad arguments. A rerun "
        "with the same --out skips the cases that finished.",
    )
    tier = v.add_mutually_exclusive_group()
    tier.add_argument("--quick", action="store_true", help="the quick tier (default; minutes)")
    tier.add_argument("--full", action="store_true", help="the full tier (paper sizes; hours)")
    v.add_argument("--only", metavar="PATTERN", help="cases whose name matches (shell pattern)")
    v.add_argument("--out", metavar="DIR", help="report folder (default results/verify_<tier>)")
    v.add_argument("--jobs", type=int, default=1, metavar="N", help="cases run at a time")
    v.add_argument("--list", action="store_true", help="list the cases and exit")
    v.add_argument("--quiet", action="store_true", help="no progress lines")
    v.set_defaults(func=cmd_verify)
