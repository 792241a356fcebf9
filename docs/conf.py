"""Sphinx configuration of navcli's documentation (Sphinx with MyST Markdown; contributing.md says why).

Built with warnings as errors by the README's test command (tests/test_docs.py), or by hand:
``python -m sphinx -W --keep-going -b html docs docs/_build/html``.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))
# The reference is read from the sources: a class mypyc compiles natively keeps no docstring
# (KnownObstacle, Avoidance ...), so the compiled build would document them empty.
os.environ["NAVCLI_PURE"] = "1"

import navcli  # noqa: E402

project = "navcli"
author = "The navcli developers"
copyright = "the navcli developers, MIT licence"
version = release = navcli.__version__

# napoleon: the docstrings' Google-style sections (Args, Returns, Raises, Attributes) as Sphinx fields
extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.napoleon", "navcli_reference"]
source_suffix = {".md": "markdown"}
myst_enable_extensions = ["dollarmath", "deflist"]
myst_heading_anchors = 3
exclude_patterns = ["_build", "_ext", "results/report"]
smartquotes = False  # --live stays --live, not an en dash

autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_inherit_docstrings = (
    False  # a Gymnasium method without its own docstring is not documented in Gymnasium's words
)
autodoc_default_options = {"undoc-members": False}
napoleon_google_docstring = True
napoleon_numpy_docstring = False
napoleon_attr_annotations = True  # an Attributes entry's type is its field's annotation (declared once)

html_theme = "alabaster"
html_title = f"navcli {release}"
html_static_path: list[str] = []
