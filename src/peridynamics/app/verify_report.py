"""The reports of ``peridynamics verify``: ``verify.json`` (the data), ``verify.md`` and
``verify.html`` (a table per case and the figure its run drew)."""

from __future__ import annotations

import html
import json
from pathlib import Path
from typing import Any

from peridynamics.io.atomic import atomic_path


def _num(v: Any) -> str:
    return f"{v:.5g}" if isinstance(v, float) else str(v)


def rows(report: dict[str, Any]) -> list[list[str]]:
    """One row per check: case, quantity, measured, reference, unit, tolerance, verdict,
    time, source."""
    rows = []
    for rec in report["cases"]:
        checks = rec["checks"] or [{"quantity": rec.get("error", rec["status"]), "unit": "",
                                    "measured": "", "reference": "", "tolerance": "",
                                    "passed": False, "source": ""}]  # fmt: skip
        for k, c in enumerate(checks):
            rows.append([
                rec["case"] if k == 0 else "", c["quantity"], _num(c["measured"]),
                _num(c["reference"]), c["unit"], c["tolerance"],
                "pass" if c["passed"] else "FAIL", f"{rec['wall_s']:.1f}" if k == 0 else "",
                c["source"],
            ])  # fmt: skip
    return rows


HEAD = ["case", "quantity", "measured", "reference", "unit", "tolerance", "result",
        "time (s)", "reference from"]  # fmt: skip


def intro(report: dict[str, Any]) -> str:
    m = report["machine"]
    n = len(report["cases"])
    failed = sum(not r["passed"] for r in report["cases"])
    runs = report.get("case_wall_s")
    reused = any(r.get("reused") for r in report["cases"])
    took = f"{report['wall_s']:.0f} s"
    if reused and runs is not None:  # a resumed campaign: say what its runs took
        took += f" (resumed; the cases' runs {runs:.0f} s)"
    return (
        f"peridynamics {report['version']}, `verify --{report['tier']}`, {report['date']}, "
        f"{m['cpu']} ({m['cores']} cores), {took}: {n} cases, "
        f"{n - failed} passed, {failed} failed"
    )


def markdown(report: dict[str, Any]) -> str:
    """``verify.md``."""
    lines = ["# Verification report", "", intro(report), "",
             "| " + " | ".join(HEAD) + " |", "|" + "---|" * len(HEAD)]  # fmt: skip
    lines += ["| " + " | ".join(r) + " |" for r in rows(report)]
    for rec in report["cases"]:
        lines += ["", f"## {rec['case']}", "", rec["title"] + ".", ""]
        lines += [f"![{rec['case']}]({rec['case']}/{f})" for f in rec.get("figures", [])]
    return "\n".join(lines) + "\n"


def page(report: dict[str, Any]) -> str:
    """``verify.html`` (one self-contained page; the figures are the runs' PNG files)."""
    esc = html.escape
    head = "".join(f"<th>{esc(h)}</th>" for h in HEAD)
    body = "".join(
        "<tr>" + "".join(
            f"<td class='{'fail' if cell == 'FAIL' else ''}'>{esc(cell)}</td>" for cell in row
        ) + "</tr>"
        for row in rows(report)
    )  # fmt: skip
    figures = "".join(
        f"<h2>{esc(r['case'])}</h2><p>{esc(r['title'])}.</p>"
        + "".join(
            f"<img src='{esc(r['case'])}/{esc(f)}' style='max-width:48%'>"
            for f in r.get("figures", [])
        )  # fmt: skip
        for r in report["cases"]
    )
    style = ("body{font-family:sans-serif;margin:2em}table{border-collapse:collapse}"
             "td,th{border:1px solid #bbb;padding:3px 6px;text-align:left}"
             ".fail{background:#fbb;font-weight:bold}")  # fmt: skip
    return (
        f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>Verification report"
        f"</title><style>{style}</style></head><body><h1>Verification report</h1>"
        f"<p>{esc(intro(report))}</p><table><tr>{head}</tr>{body}</table>{figures}"
        "</body></html>\n"
    )


def write_reports(out: Path, report: dict[str, Any]) -> None:
    """Write ``verify.json``, ``verify.md`` and ``verify.html`` into ``out`` atomically."""
    for name, text in (
        ("verify.json", json.dumps(report, indent=2, default=str) + "\n"),
        ("verify.md", markdown(report)),
        ("verify.html", page(report)),
    ):
        with atomic_path(out / name) as tmp:
            tmp.write_text(text, encoding="utf-8")
