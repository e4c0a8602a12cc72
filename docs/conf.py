"""Sphinx configuration of the documentation site (``make docs``, built with warnings as errors)."""

from __future__ import annotations

import shutil
from pathlib import Path

import rocking

ROOT = Path(__file__).resolve().parent.parent

project = "rocking"
author = "The rocking developers"
copyright = "2026, The rocking developers"  # noqa: A001 - Sphinx's name
release = version = rocking.__version__

extensions = ["myst_nb", "sphinx.ext.autodoc", "sphinx.ext.napoleon", "sphinx.ext.mathjax", "sphinx.ext.viewcode"]
# The tutorial is copied in at each build (it lives in examples/, where users find it) and run then.
(Path(__file__).parent / "site").mkdir(exist_ok=True)
shutil.copy(ROOT / "examples" / "tutorial.ipynb", Path(__file__).parent / "site" / "tutorial.ipynb")
nb_execution_mode = "force"
nb_execution_timeout = 600
nb_execution_raise_on_error = True

exclude_patterns = ["_build", "figures/*.json"]
myst_enable_extensions = ["dollarmath", "amsmath"]
myst_heading_anchors = 3
# The documents link to the repository's source files (rocking/sim/sim.c, tests/...), which are not pages.
suppress_warnings = ["myst.xref_missing"]

# The docstrings write an absolute value as |theta|, which reStructuredText reads as a substitution: each is
# defined as its own text.
rst_prolog = "\n".join(rf".. |{name}| replace:: \|{name}\|" for name in ("theta", "q[1]"))

napoleon_google_docstring = False
napoleon_numpy_docstring = True
autodoc_member_order = "bysource"
autodoc_typehints = "description"

html_theme = "furo"
html_title = f"rocking {version}"
