"""Sphinx configuration of the documentation site (``make docs``, built with warnings as errors)."""

from __future__ import annotations

import os
import shutil
import sys
from pathlib import Path

import rocking

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(Path(__file__).parent))
# The notebooks' kernels import the rocking of this tree, as this file does, whatever is installed.
os.environ["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))
# Without ipywidgets (not a docs dependency) tqdm.auto warns at import, with the path of the build machine's
# install, and falls back to its text bar: advice for a user's own Jupyter, noise on the site's pages.
os.environ["PYTHONWARNINGS"] = ",".join(filter(None, [os.environ.get("PYTHONWARNINGS"), "ignore:IProgress not found"]))

import cli_reference  # noqa: E402 - lives beside this file

project = "rocking"
author = "The rocking developers"
copyright = "2026, The rocking developers"  # noqa: A001 - Sphinx's name
release = version = rocking.__version__

extensions = [
    "myst_nb",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
]
# docs/site/ holds what each build makes (not in git): the tutorial, copied in from examples/ (where users find
# it) and run then; the command-line reference, written from the parser; the API's pages (autosummary).
SITE = Path(__file__).parent / "site"
SITE.mkdir(exist_ok=True)
shutil.copy(ROOT / "examples" / "tutorial.ipynb", SITE / "tutorial.ipynb")
cli_reference.write(SITE / "cli.md")
autosummary_generate = True
# A class's page: its docstring, a table of its methods, then each documented (not __init__ twice).
templates_path = ["_templates"]
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
# Each class's page (autosummary) documents its methods and attributes, not only their names.
autodoc_default_options = {"members": True}

# Quotes and ellipses typeset, dashes not: a flag typed in prose (--stops) stays two hyphens.
smartquotes_action = "qe"

html_theme = "furo"
html_static_path = ["_static"]
html_css_files = ["site.css"]
html_title = f"rocking {version}"
