"""Sphinx configuration: the user guide (MyST markdown), the gallery of the bundled models
and worked examples (sphinx-gallery, executed at build time) and the API reference
(autosummary + numpydoc). Build: ``python -m sphinx -W --keep-going -b html docs
docs/_build/html``."""
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")                      # the gallery draws without a display

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))              # the checkout's mechdyn, not an installed copy

import mechdyn  # noqa: E402

# The compiled kernels compile once per cache folder: here, in the build's log, rather
# than in the output of the first gallery example (without numba the gallery runs on scipy).
try:
    import mechdyn.kernels.loop  # noqa: E402,F401
except ImportError:
    pass

project = "mechdyn"
author = "the mechdyn developers"
copyright = "2026, the mechdyn developers"
release = version = mechdyn.__version__

extensions = [
    "myst_parser",
    "sphinx_gallery.gen_gallery",
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "gallery/**/*.ipynb", "gallery/**/*.py",
                    "gallery/**/*.zip", "gallery/**/*.md5", "gallery/**/*.json"]

# MyST: headings get anchors down to level 3, so pages can link to a section.
myst_heading_anchors = 3

# API reference: autosummary writes docs/api/ (generated, not committed); numpydoc
# renders the docstrings.
autosummary_generate = True
autodoc_default_options = {"members": True}
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False

# The gallery: examples/ holds two sub-galleries (models/, worked/); every plot_*.py runs
# at build time, and an example that raises fails the build.
sphinx_gallery_conf = {
    "examples_dirs": ["../examples"],
    "gallery_dirs": ["gallery"],
    "filename_pattern": r"/plot_",
    "ignore_pattern": r"__init__\.py",
    "abort_on_example_error": True,
    "within_subsection_order": "FileNameSortKey",
    "download_all_examples": False,
    "remove_config_comments": True,
    "matplotlib_animations": False,
    "image_scrapers": ("matplotlib",),
    "reset_modules": ("matplotlib",),
    "show_memory": False,
}

html_theme = "pydata_sphinx_theme"
html_title = "mechdyn"
html_theme_options = {
    "navbar_align": "left",
    "show_toc_level": 2,
    "secondary_sidebar_items": ["page-toc"],
    "footer_start": ["copyright"],
    "footer_end": [],
}
html_static_path = []
