"""The layer picture of ``docs/architecture.md``, drawn from the imports of the code.

Every module of ``src/peridynamics`` is read with :mod:`ast` (nothing is imported);
each ``import``/``from ... import`` of a ``peridynamics`` module, wherever it stands
(top level, inside a function, under ``TYPE_CHECKING``: all count, as for
import-linter), becomes an edge between the *top-level subpackages* of the two modules
(``peridynamics.families.pmb.force`` -> ``families``; a top-level module such as
``state.py`` is its own node). The nodes are placed in their layer, bottom to top; an
arrow that points up a layer (an import against the layering) is drawn in red and
listed below the picture, one that stays within a layer in blue, the others in grey.

The layer order is read from the first ``layers`` contract of ``[tool.importlinter]``
in ``pyproject.toml`` when there is one (the contract the tests enforce), else it is
:data:`DEFAULT_LAYERS`. A node in no layer is drawn in the row "not in a layer".

Run at every site build (``builder-inited``), writing ``docs/_generated/layers.svg``
and ``docs/_generated/layers.inc``; or by hand: ``python docs/_ext/import_graph.py``.
Needs matplotlib only.
"""

from __future__ import annotations

import ast
import math
import sys
from collections import Counter
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = "peridynamics"
SRC = ROOT / "src" / PACKAGE
OUT = ROOT / "docs" / "_generated"

#: the target layers, top to bottom; names within a layer are siblings
DEFAULT_LAYERS: list[list[str]] = [
    ["cli", "__main__"],
    ["app"],
    ["build", "deck"],
    ["analysis", "io"],
    ["backends", "parallel"],
    ["solvers"],
    ["evaluation", "bodies"],
    ["damage"],
    ["families"],
    ["geometry", "bonds", "state", "loading", "communicator"],
    ["kernels"],
]
#: what each layer holds, for the row labels (by its first name)
LAYER_NAMES = {
    "cli": "command line",
    "app": "application",
    "build": "build (deck to objects)",
    "io": "outputs",
    "analysis": "analysis",
    "backends": "backends, MPI",
    "solvers": "solvers",
    "evaluation": "evaluation",
    "damage": "damage laws",
    "families": "model families",
    "geometry": "points, bonds, basics",
    "kernels": "kernels",
}


def read_layers(pyproject: Path = ROOT / "pyproject.toml") -> list[list[str]]:
    """The layers (top to bottom) of the first import-linter ``layers`` contract, or
    :data:`DEFAULT_LAYERS`. Entries may be ``peridynamics.x``, ``x`` or siblings joined
    by ``|`` or ``:``."""
    try:
        import tomllib
    except ImportError:  # Python < 3.11
        return DEFAULT_LAYERS
    if not pyproject.exists():
        return DEFAULT_LAYERS
    data = tomllib.loads(pyproject.read_text())
    contracts = data.get("tool", {}).get("importlinter", {}).get("contracts", [])
    for c in contracts:
        if c.get("type") == "layers" and c.get("layers"):
            prefix = "".join(f"{x}." for x in c.get("containers", [])[:1])
            rows = []
            for entry in c["layers"]:
                names = entry.replace(":", "|").split("|")
                rows.append([_short(n.strip().strip("()"), prefix) for n in names if n.strip()])
            return rows
    return DEFAULT_LAYERS


def _short(name: str, prefix: str) -> str:
    name = name.removeprefix(prefix).removeprefix(f"{PACKAGE}.")
    return name.split(".")[0]


def _node(module: str) -> str | None:
    """Top-level subpackage (or module) of a ``peridynamics.*`` module name."""
    parts = module.split(".")
    if parts[0] != PACKAGE or len(parts) < 2:
        return None  # the package root (its API re-exports) is not a layer
    return parts[1]


def _module_name(path: Path) -> str:
    rel = path.relative_to(SRC.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _imported(tree: ast.AST, module: str, is_package: bool) -> list[str]:
    """Every module name an AST imports (relative imports resolved)."""
    out: list[str] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = module.split(".")
                base = base[: len(base) - node.level + (1 if is_package else 0)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            out.append(target)
            out += [f"{target}.{a.name}" for a in node.names]  # from pkg import module
    return out


def import_edges(src: Path = SRC) -> tuple[Counter[tuple[str, str]], set[str]]:
    """(edges (importer node, imported node) -> import statements, every node)."""
    edges: Counter[tuple[str, str]] = Counter()
    nodes: set[str] = set()
    for path in sorted(src.rglob("*.py")):
        module = _module_name(path)
        here = _node(module)
        if here is None:
            continue
        nodes.add(here)
        tree = ast.parse(path.read_text(), str(path))
        targets = {_node(t) for t in _imported(tree, module, path.name == "__init__.py")}
        for there in targets:
            if there is None or there == here:
                continue
            if (src / there).exists() or (src / f"{there}.py").exists():
                edges[(here, there)] += 1
    return edges, nodes


def _rows(layers: list[list[str]], nodes: set[str]) -> list[tuple[str, list[str]]]:
    """(label, nodes) per row, bottom to top, with the unplaced ones on top."""
    placed = {n for row in layers for n in row}
    rows = []
    for row in reversed(layers):
        present = [n for n in row if n in nodes]
        if present:
            rows.append((LAYER_NAMES.get(row[0], " / ".join(row)), present))
    rest = sorted(nodes - placed)
    if rest:
        rows.append(("not in a layer", rest))
    return rows


def draw(svg: Path, layers: list[list[str]] | None = None) -> list[str]:
    """Write the picture to ``svg``; return the imports against the layering as
    ``"a -> b (k imports)"`` lines."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import FancyArrowPatch, FancyBboxPatch

    matplotlib.rcParams["svg.hashsalt"] = PACKAGE  # the same file for the same graph
    layers = layers or read_layers()
    edges, nodes = import_edges()
    rows = _rows(layers, nodes)
    level = {n: k for k, (_, ns) in enumerate(rows) for n in ns}
    width = 2.2 * max(len(ns) for _, ns in rows)  # 1.8 per box and a gap
    pos = {}
    for k, (_, ns) in enumerate(rows):
        for m, n in enumerate(ns):
            pos[n] = ((m + 0.5) * width / len(ns), 1.6 * k)
    fig, ax = plt.subplots(figsize=(0.75 * width + 2.4, 1.05 * len(rows) + 0.6))
    against = []
    for (a, b), count in sorted(edges.items()):
        (x0, y0), (x1, y1) = pos[a], pos[b]
        unplaced = "not in a layer" in (rows[level[a]][0], rows[level[b]][0])
        up = level[b] > level[a] and not unplaced
        colour = "#c0392b" if up else ("#2e86c1" if level[a] == level[b] else "#8c8c8c")
        colour = "#e59866" if unplaced else colour
        if up:
            against.append(f"{a} -> {b} ({count} import{'s' * (count > 1)})")
        ax.add_patch(
            FancyArrowPatch(
                (x0, y0), (x1, y1), arrowstyle="-|>", mutation_scale=9,
                connectionstyle=f"arc3,rad={0.25 if level[a] == level[b] else 0.08}",
                lw=0.5 + 0.6 * math.log1p(count), color=colour, alpha=0.75,
                shrinkA=14, shrinkB=14, zorder=1 + up,
            )
        )  # fmt: skip
    for n, (x, y) in pos.items():
        box = FancyBboxPatch((x - 0.9, y - 0.28), 1.8, 0.56, boxstyle="round,pad=0.02")
        box.set(facecolor="#fdfefe", edgecolor="#1b2631", linewidth=1.0, zorder=3)
        ax.add_patch(box)
        ax.text(x, y, n, ha="center", va="center", fontsize=9, family="monospace", zorder=4)
    for k, (label, _) in enumerate(rows):
        ax.text(-0.3, 1.6 * k, label, ha="right", va="center", fontsize=9, style="italic")
    ax.set_xlim(-3.2, width + 0.2)
    ax.set_ylim(-0.7, 1.6 * (len(rows) - 1) + 1.2)
    ax.axis("off")
    fig.tight_layout()
    svg.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(svg, format="svg", metadata={"Date": None})
    if "--png" in sys.argv:  # a quick look by hand
        fig.savefig(svg.with_suffix(".png"), dpi=80)
    plt.close(fig)
    return against


def write(out: Path = OUT) -> list[str]:
    """``layers.svg`` and ``layers.inc`` (the picture and what it found) into ``out``."""
    layers = read_layers()
    against = draw(out / "layers.svg", layers)
    edges, nodes = import_edges()
    source = (
        "the first `layers` contract of `[tool.importlinter]` in `pyproject.toml`"
        if layers is not DEFAULT_LAYERS
        else "`DEFAULT_LAYERS` of `docs/_ext/import_graph.py` (no import-linter contract yet)"
    )
    lines = [
        f"{len(nodes)} packages, {len(edges)} package-to-package dependencies, "
        f"{sum(edges.values())} import statements; layer order from {source}.",
        "",
    ]
    if against:
        lines += ["Imports against the layering (red arrows):", ""]
        lines += [f"- `{a}`" for a in against]
    else:
        lines += ["No import points up a layer."]
    (out / "layers.inc").write_text("\n".join(lines) + "\n")
    return against


def _on_init(app: Any) -> None:
    write()


def setup(app: Any) -> dict[str, Any]:
    app.connect("builder-inited", _on_init)
    return {"parallel_read_safe": True, "version": "1"}


if __name__ == "__main__":
    found = write()
    print(f"wrote {OUT / 'layers.svg'}; {len(found)} imports against the layering")
    print("\n".join(found))
    sys.exit(0)
