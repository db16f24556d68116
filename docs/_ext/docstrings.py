"""Docstring hooks of the documentation site: norms written ``|xi|`` escaped, members
that other packages define left out, short cross-references resolved by module."""

from __future__ import annotations

import re
from typing import Any

_PIPES = re.compile(r"(?<![\\|])\|(?=[^\s|])([^|\n`]*?[^\s\\|])\|(?![|_])")


def escape_norms(app: Any, what: str, name: str, obj: Any, options: Any, lines: list[str]) -> None:
    """Docstrings write norms as ``|xi|``, which reStructuredText reads as a
    substitution: escape the bars (tables in docstrings start a line with ``|`` or
    ``+`` and are left alone)."""
    for k, line in enumerate(lines):
        row = line.strip()
        if row.startswith(("+-", "+=")) or (row.startswith("| ") and row.endswith(" |")):
            continue  # a table
        lines[k] = _PIPES.sub(r"\\|\1\\|", line)


def skip_foreign(app: Any, what: str, name: str, obj: Any, skip: bool, options: Any) -> Any:
    """Leave out members that other packages define (``cKDTree`` imported at module
    level, for instance)."""
    module = getattr(obj, "__module__", None)
    if isinstance(module, str) and not module.startswith("peridynamics") and what == "module":
        return True
    return None


def resolve_short(app: Any, env: Any, node: Any, contnode: Any) -> Any:
    """Docstrings name the package's objects briefly (``:class:`Evaluator```,
    ``:meth:`ExplicitSolver.step```). Resolve such a name to the object of the same
    module when there is one, else to the only documented object whose full name ends
    with it; leave it unresolved (a warning, an error with ``-W``) when it is
    ambiguous."""
    if node.get("refdomain") != "py":
        return None
    from sphinx.util.nodes import make_refnode

    target = node["reftarget"].lstrip(".~")
    domain = env.get_domain("py")
    ends = [n for n in domain.objects if n == target or n.endswith("." + target)]
    module = node.get("py:module") or ""
    local = [n for n in ends if module and n.startswith(module + ".")]
    picks = local if len(local) == 1 else ends
    if len(picks) > 1:  # one object re-exported by its packages: take the defining one
        deepest = max(picks, key=lambda n: n.count("."))
        owner = deepest[: -len(target) - 1]
        if all(owner.startswith(n[: -len(target) - 1] + ".") for n in picks if n != deepest):
            picks = [deepest]
    if len(picks) != 1:
        return None
    obj = domain.objects[picks[0]]
    return make_refnode(app.builder, node["refdoc"], obj.docname, obj.node_id, contnode, picks[0])


def setup(app: Any) -> dict[str, Any]:
    app.connect("autodoc-process-docstring", escape_norms, priority=100)
    app.connect("autodoc-skip-member", skip_foreign)
    app.connect("missing-reference", resolve_short)
    return {"parallel_read_safe": True, "version": "1"}
