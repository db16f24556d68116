"""The gallery: one page per folder of ``examples/``, generated when the site is built,
and an index of cards (a thumbnail and the title of each example; the landing page shows
a selection of them, ``gallery/_landing.md``).

Each page holds the example's README (its text, the measured numbers against the
paper's, and its figures, which the example's own scripts made from a documented run),
every figure of the folder, the command that runs each deck or script, and the decks
themselves. Links of a README to the example's files become file names (the site does
not carry the files); figures are copied beside the generated page.
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
OUT = Path(__file__).resolve().parents[1] / "gallery"

_LINK = re.compile(r"(?<!!)\[([^\]]+)\]\(([^)\s]+)\)")
_IMAGE = re.compile(r"!\[([^\]]*)\]\(([^)\s]+)\)")


def _title(folder: Path) -> tuple[str, str]:
    """(title, README text without its first heading) of an example folder."""
    readme = folder / "README.md"
    name = folder.name.replace("_", " ")
    if not readme.exists():
        return name.capitalize(), ""
    text = readme.read_text()
    m = re.search(r"^# (.+)$", text, flags=re.M)
    if m is None:
        return name.capitalize(), text
    return m.group(1).strip(), text[: m.start()] + text[m.end() :]


def _rewrite(text: str, folder: Path) -> str:
    """README links to local files -> file names; images -> the copied figures;
    headings one level down (the page has its own title)."""

    def image(m: re.Match[str]) -> str:
        target = m.group(2)
        if target.startswith(("http://", "https://")):
            return m.group(0)
        src = (folder / target).resolve()
        if not src.exists():
            return f"*(figure {target} not in the repository)*"
        return f"![{m.group(1)}](_img/{folder.name}/{src.name})"

    def link(m: re.Match[str]) -> str:
        label, target = m.group(1), m.group(2)
        if target.startswith(("http://", "https://", "#")):
            return m.group(0)
        path, _, fragment = target.partition("#")
        doc = (folder / path).resolve()
        docs = ROOT / "docs"
        if doc.suffix == ".md" and doc.parent == docs and doc.exists():  # a site page
            return f"[{label}](../{doc.name}{'#' + fragment if fragment else ''})"
        return f"{label} (`{target}`)" if label.strip("`") != target else f"`{target}`"

    text = _IMAGE.sub(image, text)
    text = _LINK.sub(link, text)
    return re.sub(r"^(#+) ", lambda m: "#" + m.group(1) + " ", text, flags=re.M)


def _page(folder: Path) -> str:
    title, body = _title(folder)
    decks = sorted(folder.glob("*.yaml"))
    scripts = sorted(p for p in folder.glob("*.py") if not p.name.startswith("_"))
    figures = sorted(folder.glob("*.png"))
    rel = f"examples/{folder.name}"
    lines = [f"# {title}", ""]
    lines += [f"Folder `{rel}/` of the repository.", ""]
    if body.strip():
        lines += [_rewrite(body, folder).strip(), ""]
    shown = set(re.findall(r"_img/[^/]+/([^)\s]+)", "\n".join(lines)))
    rest = [f for f in figures if f.name not in shown]
    if rest:
        lines += ["## Figures", ""]
        lines += [f"![{f.stem}](_img/{folder.name}/{f.name})" for f in rest]
        lines += [""]
    lines += ["## Run it", "", "```bash"]
    lines += [f"peridynamics run {rel}/{d.name} --out results/{d.stem}" for d in decks]
    lines += [f"python {rel}/{s.name}" for s in scripts]
    lines += ["```", ""]
    for d in decks:
        lines += [f"### `{d.name}`", "", f"```{{literalinclude}} ../../{rel}/{d.name}"]
        lines += [":language: yaml", "```", ""]
    return "\n".join(lines)


#: the examples the landing page shows, in this order (each must have a figure)
LANDING = ("crack_branching_2d", "kalthoff_winkler", "rock_compression", "micropolar",
           "bodies", "spalling", "waves", "geometry")  # fmt: skip


def _thumbnail(folder: Path) -> Path | None:
    """The figure that stands for an example: the first one its README shows, else the
    first PNG of the folder by name; ``None`` without a figure."""
    readme = folder / "README.md"
    if readme.exists():
        for target in _IMAGE.findall(readme.read_text()):
            path = (folder / target[1]).resolve()
            if path.suffix == ".png" and path.parent == folder.resolve() and path.exists():
                return path
    figures = sorted(folder.glob("*.png"))
    return figures[0] if figures else None


def _cards(names: list[str], prefix: str) -> list[str]:
    """A grid of cards (MyST containers styled by ``_static/gallery.css``): each the
    example's thumbnail linking to its page, and its title; ``prefix`` is the path from
    the page that shows the grid to ``gallery/``."""
    lines = ["::::{container} pd-grid", ""]
    for name in names:
        folder = EXAMPLES / name
        title = _title(folder)[0].replace("[", "(").replace("]", ")")
        thumb = _thumbnail(folder)
        lines += [":::{container} pd-card", ""]
        if thumb is not None:
            lines += [f"```{{image}} {prefix}_img/{name}/{thumb.name}", f":alt: {title}",
                      f":target: {prefix}{name}.html", "```", ""]  # fmt: skip
        lines += [f"[{title}]({prefix}{name}.md)", "", ":::", ""]
    return lines + ["::::", ""]


def build_gallery() -> list[str]:
    """Write ``docs/gallery/*.md`` (and copy the figures); return the page names."""
    if OUT.exists():
        shutil.rmtree(OUT)
    (OUT / "_img").mkdir(parents=True)
    names = []
    for folder in sorted(p for p in EXAMPLES.iterdir() if p.is_dir()):
        if not any(folder.glob("*.yaml")) and not (folder / "README.md").exists():
            continue
        img = OUT / "_img" / folder.name
        img.mkdir()
        for f in folder.glob("*.png"):
            shutil.copy2(f, img / f.name)
        (OUT / f"{folder.name}.md").write_text(_page(folder))
        names.append(folder.name)
    index = ["# Gallery", "", "Every shipped example: its figures, its decks, the command",
             "that runs it and the numbers it measured against the paper's.", ""]  # fmt: skip
    index += _cards(names, "")
    index += ["```{toctree}", ":maxdepth: 1", ":hidden:", ""] + names + ["```", ""]
    (OUT / "index.md").write_text("\n".join(index))
    shown = [n for n in LANDING if n in names and _thumbnail(EXAMPLES / n) is not None]
    (OUT / "_landing.md").write_text("\n".join(_cards(shown, "gallery/")))
    return names


def build_verification() -> None:
    """``docs/gallery/verification.md``: the README's measured results (verification
    tables against analytic solutions, papers and peers), links made site links."""
    text = (ROOT / "README.md").read_text()
    start, end = text.index("## Measured"), text.index("## Development")
    body = text[start:end].replace("## Measured", "# Verification and measured results", 1)
    body = re.sub(r"\]\(docs/([\w.]+\.md)", r"](../\1", body)
    body = re.sub(r"\]\(examples/(\w+)/README\.md\)", r"](\1.md)", body)
    body = re.sub(r"\]\(docs/(img/[^)]+)\)", r"](../\1)", body)
    (OUT / "verification.md").write_text(
        body + "\n\n(From the README of the repository, the section *Measured*.)\n"
    )


def _on_init(app: Any) -> None:
    build_gallery()
    build_verification()


def setup(app: Any) -> dict[str, Any]:
    app.connect("builder-inited", _on_init)
    return {"parallel_read_safe": True, "version": "1"}
