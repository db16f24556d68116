"""The documentation site: it builds with warnings as errors and nitpicky
cross-references; no internal link is broken and no image is missing; the pages render
in headless Chromium with every image loaded. Skipped without the ``[docs]`` extra
(Sphinx) and, for the browser part, without Debian's ``chromium``.

The site is built (or read from ``PERIDYNAMICS_SITE``) by the ``docs`` tier
(``pytest -m docs``, run by ``.ci/run``); the default selection keeps the cheap smoke
test ``test_site_sources_are_linked`` (no Sphinx: the pages' toctree, links and images).

Screenshots: ``PERIDYNAMICS_SITE_SCREENSHOTS=docs/img/site pytest tests/unit/test_docs_site.py``
writes the landing page, a user-guide page, the deck reference and a gallery entry.
``PERIDYNAMICS_SITE=docs/_build/html`` tests a site already built by the README's
command instead of building one."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlparse

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
SHOTS = {
    "landing.png": "index.html",
    "user_guide.png": "solvers.html",
    "deck_reference.png": "deck.html",
    "gallery_entry.png": "gallery/rock_compression.html",
    "gallery.png": "gallery/index.html",
}


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The site built as the README's development section builds it; or, where
    ``PERIDYNAMICS_SITE`` names a folder, the site that command already built there
    (``.ci/run`` builds it once, with warnings as errors, before the tests)."""
    built = os.environ.get("PERIDYNAMICS_SITE")
    if built:
        assert (Path(built) / "index.html").is_file(), f"PERIDYNAMICS_SITE={built}: no site"
        return Path(built).resolve()
    pytest.importorskip("sphinx", reason="Sphinx not installed (pip install '.[docs]')")
    pytest.importorskip("myst_parser", reason="myst-parser not installed (pip install '.[docs]')")
    out = tmp_path_factory.mktemp("site")
    cmd = [sys.executable, "-m", "sphinx", "-W", "-n", "--keep-going", "-q", "-b", "html",
           str(ROOT / "docs"), str(out / "html"), "-d", str(out / "doctrees")]  # fmt: skip
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-4000:]
    return out / "html"


def _toctree_entries(text: str) -> set[str]:
    """The documents a page's MyST ``{toctree}`` blocks list."""
    blocks = re.findall(r"```\{toctree\}\n(.*?)```", text, flags=re.S)
    return {
        line.strip()
        for block in blocks
        for line in block.splitlines()
        if line.strip() and not line.strip().startswith(":")
    }


def _source(target: str) -> Path:
    """The source of a page or image a page of ``docs/`` names: the file itself, or
    for a gallery page what the gallery extension makes it from (an example folder,
    ``examples/`` for the index, the README for the verification page)."""
    if target.startswith("gallery/"):
        name = Path(target).with_suffix("").name
        if name == "verification":  # made from the README's measured results
            return ROOT / "README.md"
        return ROOT / "examples" / ("" if name == "index" else name)
    return DOCS / target


def test_site_sources_are_linked() -> None:
    """The default selection's smoke test of the site, without Sphinx: every page of
    ``docs/`` is in the index's toctree, and every page a toctree, link or image of a
    page names exists (a gallery page: its example folder)."""
    listed = _toctree_entries((DOCS / "index.md").read_text())
    pages = {p.stem for p in DOCS.glob("*.md")} - {"index"}
    assert pages <= listed, f"pages in no toctree: {sorted(pages - listed)}"
    missing = [f"index.md toctree: {e}" for e in listed if not _source(e + ".md").exists()]
    for page in DOCS.glob("*.md"):
        text = page.read_text()
        images = re.findall(r"!\[[^\]]*\]\(([^)\s]+)\)", text)
        links = re.findall(r"(?<!!)\[[^\]]*\]\(([^)#\s:]+)(?:#[^)]*)?\)", text)
        made = [t for t in images if t.startswith("_generated/")]  # drawn at build time
        missing += [
            f"{page.name}: {t}" for t in images + links if t not in made and not _source(t).exists()
        ]
    generator = DOCS / "_ext" / "import_graph.py"
    assert generator.exists(), "docs/_ext/import_graph.py draws docs/_generated/ at build time"
    assert not missing, "\n".join(missing)


class _Refs(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.links: list[str] = []
        self.images: list[str] = []
        self.ids: set[str] = set()

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        a = dict(attrs)
        if a.get("id"):
            self.ids.add(str(a["id"]))
        if tag == "a" and a.get("href"):
            self.links.append(str(a["href"]))
        if tag == "img" and a.get("src"):
            self.images.append(str(a["src"]))


def _parse(page: Path) -> _Refs:
    p = _Refs()
    p.feed(page.read_text(errors="replace"))
    return p


@pytest.mark.docs
def test_site_pages(site: Path) -> None:
    pages = list(site.rglob("*.html"))
    assert len(pages) > 100
    for name in ("index.html", "getting_started.html", "deck.html", "output.html",
                 "cli.html", "api.html", "references.html", "gallery/index.html"):  # fmt: skip
        assert (site / name).exists(), name
    cli = (site / "cli.html").read_text()
    assert "--backend" in cli and "--checkpoint-every" in cli  # from the parser


@pytest.mark.docs
def test_gallery_and_landing_page_show_a_card_per_example(site: Path) -> None:
    """The gallery's index: one card per example page, a thumbnail on each whose example
    has a figure; the landing page: the selection of ``docs/_ext/gallery.py``'s
    ``LANDING``, each card with its thumbnail."""
    examples = [p for p in (ROOT / "examples").iterdir() if p.is_dir()]
    pages = {p.stem for p in (site / "gallery").glob("*.html")} - {"index", "verification"}
    index = (site / "gallery" / "index.html").read_text()
    assert index.count('class="pd-card') == len(pages) >= 15
    with_figures = [p for p in examples if p.name in pages and any(p.glob("*.png"))]
    cards = index.split('class="pd-card')[1:]
    assert sum("<img" in c for c in cards) == len(with_figures)
    landing = (site / "index.html").read_text().split('class="pd-card')[1:]
    assert len(landing) >= 6 and all("<img" in c for c in landing)


@pytest.mark.docs
def test_no_broken_link_or_missing_image(site: Path) -> None:
    parsed = {p: _parse(p) for p in site.rglob("*.html")}
    broken: list[str] = []
    for page, refs in parsed.items():
        for href in refs.links:
            url = urlparse(href)
            if url.scheme or href.startswith("mailto:"):
                continue  # external: not checked offline
            target = (page.parent / unquote(url.path)).resolve() if url.path else page
            if not target.exists():
                broken.append(f"{page.relative_to(site)} -> {href}")
            elif url.fragment and target.suffix == ".html":
                ids = parsed[target].ids if target in parsed else _parse(target).ids
                if url.fragment not in ids:
                    broken.append(f"{page.relative_to(site)} -> {href} (no anchor)")
        for src in refs.images:
            if urlparse(src).scheme:
                continue
            if not (page.parent / unquote(src)).resolve().exists():
                broken.append(f"{page.relative_to(site)} image {src}")
    assert not broken, "\n".join(broken[:40])


@pytest.mark.docs
def test_help_topics_point_to_anchors_of_the_site(site: Path) -> None:
    """``peridynamics help deck.X`` ends with the section's address on the site."""
    from peridynamics.deck.help import section, topics

    for page in ("deck", "output"):
        ids = _parse(site / f"{page}.html").ids
        for topic in topics(page):
            address = section(topic)[1]
            assert address.split("#")[1] in ids, (topic, address)
    assert section("deck.solver.adr")[1].split("#")[1] in _parse(site / "deck.html").ids


#: headless Chromium on a machine without a network (no background connections)
_CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                   "--no-first-run", "--disable-background-networking",
                   "--disable-component-update", "--disable-sync"]  # fmt: skip


@pytest.mark.docs
@pytest.mark.skipif(CHROMIUM is None, reason="chromium not installed (apt install chromium)")
def test_pages_render_in_chromium_with_every_image(site: Path, tmp_path: Path) -> None:
    gallery = sorted((site / "gallery").glob("*.html"))
    pages = [
        "index.html",
        "deck.html",
        "solvers.html",
        "models.html",
        "theory_bond_based.html",
        "api.html",
    ]
    pages += [str(p.relative_to(site)) for p in gallery]
    images = 0
    for name in pages:
        dom = subprocess.run(
            [str(CHROMIUM), *_CHROMIUM_FLAGS, f"--user-data-dir={tmp_path / 'profile'}",
             "--virtual-time-budget=5000", "--dump-dom", (site / name).as_uri()],
            capture_output=True, text=True, timeout=120,
        ).stdout  # fmt: skip
        assert "</body>" in dom and "bd-article" in dom, name  # the PyData theme's article
        got = re.search(r'data-images="(\d+)" data-broken-images="(\d+)"', dom)
        assert got is not None, f"{name}: the image check did not run"
        assert got.group(2) == "0", f"{name}: {got.group(2)} images did not load"
        images += int(got.group(1))
    assert images > 30  # the gallery's figures
    shots = Path(os.environ.get("PERIDYNAMICS_SITE_SCREENSHOTS", tmp_path))
    shots.mkdir(parents=True, exist_ok=True)
    for png, page in SHOTS.items():
        subprocess.run(
            [str(CHROMIUM), *_CHROMIUM_FLAGS, f"--user-data-dir={tmp_path / 'profile'}",
             "--hide-scrollbars",
             "--window-size=1280,1000", f"--screenshot={shots / png}", (site / page).as_uri()],
            capture_output=True, timeout=120, check=True,
        )  # fmt: skip
        assert (shots / png).stat().st_size > 10_000, png
