"""Sphinx configuration of the tendonrod documentation (``make docs``).

Markdown pages through MyST, the notebooks of ``notebooks/`` through MyST-NB with their
stored outputs (never executed here: ``tools/notebooks_full.py`` makes those outputs, and
``make test`` runs every notebook through nbmake), the API reference through autodoc/autosummary from the
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
    "myst_nb",  # MyST Markdown pages and the notebooks (it loads myst_parser)
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.doctest",
    "sphinx.ext.mathjax",
]

# .rst first: autosummary writes its stubs with the first suffix
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}
root_doc = "index"
exclude_patterns = ["_build", "**/.ipynb_checkpoints"]
myst_enable_extensions = ["dollarmath", "colon_fence", "deflist"]
myst_heading_anchors = 3

# The notebooks are rendered with the outputs stored in them: executing them here would
# double CI's notebook time (nbmake runs them in `make test`), and the stored outputs are
# the full-resolution ones (tools/notebooks_full.py).  Their warnings (stderr) are shown.
nb_execution_mode = "off"
nb_output_stderr = "show"
nb_merge_streams = True

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
html_static_path = ["_static"]
html_css_files = ["gallery.css"]


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


# The gallery (gallery.md): which stored figure of each notebook is its thumbnail (1-based,
# in the order of the outputs; the first one where a notebook is missing here).
THUMBNAILS = {"02": 5, "04": 4, "05": 3, "06": 2, "07": 1, "08": 2, "09": 2, "11": 1}


def _copy_notebooks(app):
    """Sphinx reads sources below docs/ only: copy ``notebooks/*.ipynb`` to
    ``docs/notebooks/`` (generated, not committed) and write each one's thumbnail, a
    reduced copy of one of its stored PNG figures, to ``docs/notebooks/thumbs/NN.png``.
    Files are rewritten only when they change, so incremental builds stay incremental."""
    import base64
    import glob
    import io

    import nbformat
    from PIL import Image  # matplotlib's own dependency

    out = os.path.join(app.srcdir, "notebooks")
    os.makedirs(os.path.join(out, "thumbs"), exist_ok=True)
    for src in sorted(glob.glob(os.path.join(ROOT, "notebooks", "*.ipynb"))):
        name = os.path.basename(src)
        data = open(src, "rb").read()
        dst = os.path.join(out, name)
        if not os.path.exists(dst) or open(dst, "rb").read() != data:
            with open(dst, "wb") as fh:
                fh.write(data)
        nb = nbformat.reads(data.decode(), as_version=4)
        pngs = [
            o["data"]["image/png"]
            for c in nb.cells
            if c.cell_type == "code"
            for o in c.get("outputs", [])
            if "image/png" in o.get("data", {})
        ]
        thumb = os.path.join(out, "thumbs", name[:2] + ".png")
        if not pngs:
            raise RuntimeError(f"{src} has no stored figure: run tools/notebooks_full.py")
        img = Image.open(io.BytesIO(base64.b64decode(pngs[THUMBNAILS.get(name[:2], 1) - 1])))
        img.thumbnail((360, 240))  # in place, keeps the aspect ratio
        buf = io.BytesIO()
        img.save(buf, format="png", optimize=True)
        if not os.path.exists(thumb) or open(thumb, "rb").read() != buf.getvalue():
            with open(thumb, "wb") as fh:
                fh.write(buf.getvalue())


def _write_view_pages(app, exception):
    """The guide's interactive 3-D views (docs/guide/view.md embeds them): the figures of
    ``docs/images/make_view.py`` as standalone pages (plotly.js inlined, no network) in the
    HTML output's ``_static/``."""
    if exception is not None or app.builder.format != "html":
        return
    import runpy

    figures = runpy.run_path(os.path.join(app.srcdir, "images", "make_view.py"))["figures"]
    static = os.path.join(app.outdir, "_static")
    os.makedirs(static, exist_ok=True)
    import tendonrod as tr

    for name, fig in figures().items():
        tr.plot.save_html(fig, os.path.join(static, f"{name}.html"))


def setup(app):
    app.connect("builder-inited", _write_ufunc_pages)
    app.connect("builder-inited", _copy_notebooks)
    app.connect("build-finished", _write_view_pages)


# napoleon writes a class's Attributes as ``:ivar name:`` fields, and Sphinx links each
# field's *name* as an object reference.  Where the class sets that attribute in __init__
# (Solution.nit, .nfev) autodoc has no object of that name, and the link finds
# BatchResult.nit and SweepResult.nit instead: an ambiguous link, not a docstring error.
# Only that category (ref.python) is silenced; everything else is an error under -W.
suppress_warnings = ["ref.python"]
