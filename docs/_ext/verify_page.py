"""The verification page's table from the last ``peridynamics verify --full`` report.

The report is committed as ``docs/verification/verify_full.json`` (copied from the
``--out`` folder of a run; its date, version and machine are in it). At every site build
(``builder-inited``) this writes ``docs/_generated/verify_full.inc``: the report's
summary line and its table, which ``docs/verify.md`` includes. By hand:
``python docs/_ext/verify_page.py``.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]
REPORT = ROOT / "docs" / "verification" / "verify_full.json"
OUT = ROOT / "docs" / "_generated" / "verify_full.inc"


def write() -> Path:
    """Write the include file from the committed report; its path."""
    sys.path.insert(0, str(ROOT / "src"))
    from peridynamics.app.verify_report import HEAD, intro, rows

    report = json.loads(REPORT.read_text(encoding="utf-8"))
    lines = [intro(report) + ".", "", "| " + " | ".join(HEAD) + " |", "|" + "---|" * len(HEAD)]
    lines += ["| " + " | ".join(r) + " |" for r in rows(report)]
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return OUT


def _on_init(app: Any) -> None:
    write()


def setup(app: Any) -> dict[str, Any]:
    app.connect("builder-inited", _on_init)
    return {"parallel_read_safe": True, "version": "1"}


if __name__ == "__main__":
    print(f"wrote {write()}")
