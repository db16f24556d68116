"""Sphinx configuration of the peridynamics documentation site.

Build: ``pip install ".[docs]" && sphinx-build -W -n -b html docs docs/_build/html``.
The pages are the Markdown files of this folder (MyST), the API reference is generated
from the numpydoc docstrings, the command-line reference from the argument parser and
the gallery from ``examples/`` (``_ext/``)."""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))
sys.path.insert(0, str(HERE.parent / "src"))

from peridynamics import __version__  # noqa: E402

project = "peridynamics"
author = "the peridynamics developers"
copyright = "2026, the peridynamics developers"  # noqa: A001
release = __version__
version = __version__

extensions = [
    "myst_nb",  # MyST Markdown pages (myst-parser) and the tutorials, executed notebooks
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "numpydoc",
    "cli_help",
    "docstrings",
    "gallery",
    "import_graph",
    "verify_page",
]
templates_path = ["_templates"]
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb"}
root_doc = "index"
exclude_patterns = ["_build", "Thumbs.db", ".DS_Store", "img/site/*.md", "jupyter_execute",
                    "gallery/_*.md"]  # fmt: skip
# the tutorials (docs/tutorials/*.md, MyST notebooks) run at every build: a cell that
# raises fails the build; each notebook's time is in the build log and in
# _build/.../reports when one fails
nb_execution_mode = "force"
nb_execution_timeout = 600
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_merge_streams = True
myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3
suppress_warnings = ["myst.header"]

# targets outside this package (no intersphinx: the build works offline), private
# helpers and the views of dict methods that autodoc inherits
nitpick_ignore_regex = [
    (r"py:.*", r"(abc|ast|pydantic|warp|numpy|scipy|enum|typing|collections|yaml|matplotlib|pandas|pyvista)(\..*)?"),
    (r"py:.*", r".*\._[A-Za-z_]\w*"),
    (r"py:class", r"(a set-like object|an object) providing a view on D's .*"),
]

autosummary_generate = True
autodoc_typehints = "none"
# a package documents what it defines; re-exports are documented where they live
autodoc_default_options = {"ignore-module-all": True}
autodoc_member_order = "bysource"
numpydoc_show_class_members = False
numpydoc_validation_checks: set[str] = set()

# the PyData theme (pydata-sphinx-theme, the [docs] extra): no icon links and no
# external assets, so the site works offline; the gallery's cards: _static/gallery.css
html_theme = "pydata_sphinx_theme"
html_title = f"peridynamics {release}"
html_static_path = ["_static"]
html_js_files = ["check_images.js"]
html_css_files = ["gallery.css"]
html_theme_options = {
    "navbar_align": "left",
    "header_links_before_dropdown": 4,
    "show_toc_level": 2,
    "navigation_depth": 2,
    "show_prev_next": True,
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version", "theme-version"],
}
