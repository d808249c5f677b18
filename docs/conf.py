"""Sphinx configuration of the noslipsim documentation.

Build: ``python -m sphinx -W -b html docs docs/_build/html`` (the ``docs`` extra
installs what it needs); ``tests/test_docs.py`` builds it the same way in a
temporary folder, so a broken page, docstring or gallery example fails the suite.
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "src"))  # the package in this tree, installed or not
sys.path.insert(0, os.path.join(HERE, "_ext"))  # local extensions (gif_scraper)

import noslipsim

project = "noslipsim"
author = "the noslipsim developers"
copyright = "the noslipsim developers"
version = release = noslipsim.__version__

extensions = [
    "myst_parser",
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "sphinx-mathjax-offline",  # MathJax shipped into _static/mathjax: formulas render without a network
    "sphinx_gallery.gen_gallery",
    "matplotlib.sphinxext.plot_directive",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "**.ipynb_checkpoints", "auto_examples/*.ipynb", "auto_examples/*.py",
                    "auto_examples/*.zip", "auto_examples/*.json", "auto_examples/*.md5"]
templates_path = ["_templates"]

# ---------------------------------------------------------------------------- Markdown pages
myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3

# ---------------------------------------------------------------------------- API reference
autosummary_generate = True
autosummary_ignore_module_all = False  # a module's __all__ says what is public
autodoc_default_options = {"member-order": "bysource"}
numpydoc_show_class_members = False  # the class template lists members itself
numpydoc_class_members_toctree = False

# ---------------------------------------------------------------------------- gallery
sphinx_gallery_conf = {
    "examples_dirs": "../examples/gallery",
    "gallery_dirs": "auto_examples",
    "filename_pattern": r"/plot_",
    "abort_on_example_error": True,
    "download_all_examples": False,
    "remove_config_comments": True,
    "show_memory": False,
    "min_reported_time": 1,
    "image_scrapers": ("matplotlib", "gif_scraper.gif_scraper"),  # by name: a function would not pickle
    "write_computation_times": False,  # that page loads a table script from a CDN
}

plot_include_source = True
plot_html_show_source_link = False
plot_html_show_formats = False
plot_formats = [("png", 100)]

# ---------------------------------------------------------------------------- HTML
html_theme = "pydata_sphinx_theme"
html_title = f"noslipsim {release}"
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
}
html_static_path = []
