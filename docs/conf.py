"""Sphinx configuration of the musclesim documentation (``sphinx-build -W docs docs/_build``)."""
import sys
from pathlib import Path

import musclesim

sys.path.insert(0, str(Path(__file__).parent / "_ext"))

project = "musclesim"
author = "the musclesim developers"
copyright = "2026, the musclesim developers"
release = version = musclesim.__version__

extensions = [
    "myst_parser",
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
    "musclesim_docs",
]
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
exclude_patterns = ["_build", "examples"]  # examples: included by the pages that show them
nitpicky = False

autodoc_default_options = {"members": True, "undoc-members": False}
autodoc_member_order = "bysource"
numpydoc_show_class_members = False
numpydoc_validation_checks = set()

html_theme = "furo"
html_title = f"musclesim {release}"
html_static_path = []
