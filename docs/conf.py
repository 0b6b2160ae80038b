"""Sphinx configuration of the tendonrod documentation (``make docs``).

Markdown pages through MyST, the API reference through autodoc/autosummary from the
NumPy-style docstrings (napoleon), doctests through ``sphinx.ext.doctest`` (the
``Examples`` sections of the docstrings and the ``{doctest}`` blocks of the pages).
No intersphinx: the build machines reach the package registries only.
"""

from __future__ import annotations

import os
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, ROOT)
os.environ.setdefault("MPLBACKEND", "Agg")

import tendonrod  # noqa: E402

project = "tendonrod"
author = "the tendonrod developers"
copyright = "2026, the tendonrod developers"
release = tendonrod.__version__
version = release

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.doctest",
    "sphinx.ext.mathjax",
]

source_suffix = {".md": "markdown", ".rst": "restructuredtext"}
root_doc = "index"
exclude_patterns = ["_build", "**/.ipynb_checkpoints"]
myst_enable_extensions = ["dollarmath", "colon_fence", "deflist"]
myst_heading_anchors = 3

autosummary_generate = True
autosummary_imported_members = False
autosummary_ignore_module_all = False  # a module with __all__ lists those names
autodoc_default_options = {"members": True, "undoc-members": False, "show-inheritance": False}
autodoc_member_order = "bysource"
autodoc_typehints = "description"
napoleon_use_ivar = True
napoleon_numpy_docstring = True
napoleon_google_docstring = False
napoleon_use_rtype = False

# doctests: every block sees numpy and tendonrod, warnings of the package as in a script
doctest_global_setup = f"""
ROOT = {ROOT!r}  # the checkout: pages that read its files chdir there
import numpy as np
import tendonrod as tr
np.set_printoptions(precision=6, suppress=True)
"""

import doctest as _doctest  # noqa: E402

doctest_default_flags = (
    _doctest.ELLIPSIS | _doctest.NORMALIZE_WHITESPACE | _doctest.DONT_ACCEPT_TRUE_FOR_1
)

html_theme = "pydata_sphinx_theme"
html_title = f"tendonrod {release}"
html_theme_options = {"navigation_with_keys": False, "show_toc_level": 2}
html_static_path: list[str] = []


def _write_ufunc_pages(app):
    """autodoc does not document NumPy ufuncs: write ``api/generated/ufuncs.rst`` from
    their docstrings (NumPy's generic signature line dropped, the docstring's own
    signature line used, the NumPy-style sections converted by napoleon)."""
    import numpy as np
    from sphinx.ext.napoleon import NumpyDocstring

    from tendonrod import analytic

    out = ["", ".. currentmodule:: tendonrod.analytic", ""]
    for name in analytic.__all__:
        f = getattr(analytic, name)
        if not isinstance(f, np.ufunc):
            continue
        lines = f.__doc__.splitlines()
        own = [i for i, ln in enumerate(lines) if ln.startswith(name + "(")][-1]
        body = str(NumpyDocstring(lines[own + 1 :], app.config, app, "function", name, f))
        out += [f".. function:: {lines[own]}", ""]
        out += ["   " + ln if ln else "" for ln in body.splitlines()] + [""]
    gen = os.path.join(app.srcdir, "api", "generated")
    os.makedirs(gen, exist_ok=True)
    path = os.path.join(gen, "ufuncs.rst.inc")
    text = "\n".join(out) + "\n"
    if not os.path.exists(path) or open(path).read() != text:
        with open(path, "w") as fh:
            fh.write(text)


def setup(app):
    app.connect("builder-inited", _write_ufunc_pages)


# napoleon writes a class's Attributes as ``:ivar name:`` fields, and Sphinx links each
# field's *name* as an object reference.  Where the class sets that attribute in __init__
# (Solution.nit, .nfev) autodoc has no object of that name, and the link finds
# BatchResult.nit and SweepResult.nit instead: an ambiguous link, not a docstring error.
# Only that category (ref.python) is silenced; everything else is an error under -W.
suppress_warnings = ["ref.python"]
