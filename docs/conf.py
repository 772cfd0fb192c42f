"""Sphinx configuration of isorock's documentation site.

Build it (warnings are errors, as in ``.ci/run``)::

    .venv/bin/python -m sphinx -W --keep-going -b html docs docs/_build/html

The reference pages are generated from the code at every build: the command line from ``isorock``'s
argparse parser (sphinx-argparse), the configuration from ``workflow/schemas/config.schema.yaml``
(sphinx-jsonschema), the store's layout from :mod:`isorock.store.layout` and the measured timings from
:mod:`isorock.timings` (``docs/_ext/isorock_docs.py``), the Python API from the docstrings (autodoc,
numpydoc).
"""

from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))

project = "isorock"
author = "isorock developers"
copyright = "2026, isorock developers (MIT licence)"

from isorock import __version__ as release  # noqa: E402
from isorock.timings import TIMINGS  # noqa: E402

version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    # MathJax shipped in _static/mathjax (not from a CDN): the formulas render offline too
    "sphinx-mathjax-offline",
    "numpydoc",
    "sphinxarg.ext",
    "sphinx-jsonschema",
    "isorock_docs",
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = ["_build", "Thumbs.db", ".DS_Store"]
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist", "substitution"]
myst_heading_anchors = 3
# the measured timings ({{ t_main_job }} ...), from isorock.timings: the one place they are kept
myst_substitutions = {f"t_{key}": t.text for key, t in TIMINGS.items()}
# no "smart" dashes: docutils would print an option's "--" as an en-dash, which does not exist when copied
# (quotes and ellipses are left as typed too: the pages quote commands and file contents)
smartquotes = False
suppress_warnings = ["myst.header"]  # model.md's sections are numbered in their titles ("## 1. ...")

numpydoc_show_class_members = False
numpydoc_validation_checks: set[str] = set()
autodoc_typehints = "none"  # numpydoc's Parameters sections carry the types and units
autodoc_member_order = "bysource"

html_theme = "furo"
html_title = f"isorock {release}"
html_static_path = ["_static"]
# tables that fit the page: the configuration reference's nested schemas, the validation tables
html_css_files = ["isorock.css"]
html_theme_options = {"source_repository": "", "navigation_with_keys": True}
