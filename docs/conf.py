"""Sphinx configuration of the ngcrack documentation site.

Build (from the repository root, after ``pip install -e '.[docs]'``)::

    sphinx-build -W -b html docs docs/_build/html

The tutorials are the notebooks of ``notebooks/`` (jupytext py:percent sources), converted
into ``docs/notebooks/*.ipynb`` (git-ignored) at the start of every build and executed by
myst-nb. With
``NGCRACK_QUICK=1`` in the environment they run on their small meshes (the tests build
the site that way); without it on the meshes their conclusions are written for.
``NGCRACK_DOCS_EXECUTE=NAME,NAME`` executes only the notebooks named (the quick test
build executes one).
Executed notebooks are cached per mode in ``docs/_build/.jupyter_cache-{quick,full}``.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(DOCS / "_ext"))

import ngcrack  # noqa: E402  (the checkout first on the path)

# -- the notebooks: ../notebooks/NN-topic.py -> docs/notebooks/ (git-ignored) ----------
NOTEBOOK_SOURCES = ROOT / "notebooks"
NOTEBOOK_PAGES = DOCS / "notebooks"


def _copy_notebooks() -> None:
    """Convert notebooks/NN-*.py (jupytext py:percent, no metadata) into docs/notebooks/NN-*.ipynb
    with a python3 kernelspec, rewriting only what changed (so that Sphinx re-reads only the
    notebooks that changed) and dropping the pages of removed notebooks."""
    import jupytext

    NOTEBOOK_PAGES.mkdir(exist_ok=True)
    wanted = {p.with_suffix(".ipynb").name: p for p in sorted(NOTEBOOK_SOURCES.glob("[0-9][0-9]-*.py"))}
    for old in NOTEBOOK_PAGES.glob("*.ipynb"):
        if old.name not in wanted:
            old.unlink()
    for name, src in wanted.items():
        nb = jupytext.read(src, fmt="py:percent")
        nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
        nb.metadata["language_info"] = {"name": "python", "pygments_lexer": "ipython3"}
        text = jupytext.writes(nb, fmt="ipynb")
        dst = NOTEBOOK_PAGES / name
        if not dst.exists() or dst.read_text(encoding="utf-8") != text:
            dst.write_text(text, encoding="utf-8")


_copy_notebooks()

# -- the API pages: one per module of the package, found by walking it ------------------
API_PAGES = DOCS / "api" / "generated"


def _module_pages() -> None:
    """Write docs/api/generated/<module>.rst for every module of ngcrack and an index with
    each module's first docstring line, so that a new or renamed module needs no edit here.

    (autosummary's recursive mode takes ``ngcrack.core.solve`` for the function ``nc.solve``,
    which the package's namespace binds over the module of the same name.)
    """
    import importlib
    import pkgutil

    API_PAGES.mkdir(parents=True, exist_ok=True)
    names = ["ngcrack"] + sorted(m.name for m in pkgutil.walk_packages(ngcrack.__path__, "ngcrack."))
    pages = {}
    rows = []
    for name in names:
        module = importlib.import_module(name)
        summary = (module.__doc__ or "").strip().split("\n\n")[0].replace("\n", " ")
        pages[name + ".rst"] = (f"{name}\n{'=' * len(name)}\n\n.. automodule:: {name}\n"
                                "   :members:\n   :ignore-module-all:\n   :show-inheritance:\n")
        rows.append(f"   * - :mod:`{name}`\n     - {summary or '-'}")
    pages["index.rst"] = ("Modules\n=======\n\nEvery module of the package, generated from its docstrings.\n\n"
                          ".. list-table::\n   :widths: 30 70\n\n" + "\n".join(rows) + "\n\n"
                          ".. toctree::\n   :hidden:\n\n" + "".join(f"   {n}\n" for n in names))
    for old in API_PAGES.glob("*.rst"):
        if old.name not in pages:
            old.unlink()
    for file, text in pages.items():
        path = API_PAGES / file
        if not path.exists() or path.read_text(encoding="utf-8") != text:
            path.write_text(text, encoding="utf-8")


_module_pages()

QUICK = os.environ.get("NGCRACK_QUICK") == "1"
#: NGCRACK_DOCS_EXECUTE="05-contact-teaching,10-adaptivity" executes only those notebooks
#: (the others are rendered without outputs); unset or "all": every notebook
EXECUTE = os.environ.get("NGCRACK_DOCS_EXECUTE", "all").strip()
_STEMS = [p.stem for p in sorted(NOTEBOOK_SOURCES.glob("[0-9][0-9]-*.py"))]
EXECUTED = _STEMS if EXECUTE in ("", "all") else [name.strip() for name in EXECUTE.split(",") if name.strip()]
if set(EXECUTED) - set(_STEMS):
    raise ValueError(f"NGCRACK_DOCS_EXECUTE = {EXECUTE!r}: unknown notebooks {sorted(set(EXECUTED) - set(_STEMS))}; "
                     f"allowed: 'all' or names among {', '.join(_STEMS)}")

# -- project -------------------------------------------------------------------------
project = "ngcrack"
author = "the ngcrack authors"
copyright = "2026, the ngcrack authors"
release = version = ngcrack.__version__

extensions = [
    "myst_nb",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "plain_docstrings",  # docs/_ext: plain-text docstrings as reST; numpydoc sections via napoleon
    "public_names",  # docs/_ext: ngcrack.Scene and other re-exported names link to their definitions
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
]

exclude_patterns = ["_build", "_static", "**/.ipynb_checkpoints", "Thumbs.db", ".DS_Store"]
templates_path = ["_templates"]
# `x` in a docstring is code, as in the package's docstrings (docs/_ext/plain_docstrings.py
# writes it as ``x`` for autodoc; this covers hand-written reST)
default_role = "literal"

# -- cross references: every internal reference must resolve ---------------------------
nitpicky = True
# types of other packages (ngsolve, numpy, pandas, ...) are not documented here
#: other packages whose names appear in annotations (module prefixes and bare class names)
_EXTERNAL_MODULES = ("ngs|ngsolve|netgen|np|numpy|pd|pandas|scipy|sp|cvxpy|shapely|matplotlib|plt|ipywidgets|"
                     "dask|distributed|meshio|tomllib|tomli|pathlib|os|concurrent|collections|typing|"
                     "dataclasses|enum|threading|multiprocessing")
_EXTERNAL_NAMES = ("Path|Callable|Iterable|Iterator|Sequence|Mapping|Any|Literal|Optional|Union|"
                   "ndarray|DataFrame|Series|CoefficientFunction|GridFunction|Mesh|FESpace|"
                   "BilinearForm|LinearForm|BaseMatrix|BaseVector|Figure|Axes|NDArray|ArrayLike|"
                   "TextIO|IO|Self|TypeAlias|Future|Executor|Generator|Hashable")
_BUILTIN_TYPES = ("int|float|str|bool|bytes|dict|list|tuple|set|frozenset|object|type|None|"
                  "optional|callable|array|array_like|array-like|iterable|sequence|mapping")
nitpick_ignore_regex = [
    (r"py:.*", rf"({_EXTERNAL_MODULES})(\..*)?"),
    (r"py:.*", rf"({_EXTERNAL_NAMES})"),
    (r"py:class", rf"({_BUILTIN_TYPES})"),
]

# -- API reference: pages written by _module_pages; autosummary for the top-level table --
autosummary_generate = False
autosummary_imported_members = False
autodoc_default_options = {"members": True, "undoc-members": False, "show-inheritance": True}
autodoc_typehints = "description"
autodoc_typehints_description_target = "documented"
autodoc_member_order = "bysource"
autodoc_mock_imports: list[str] = []
napoleon_numpy_docstring = True
napoleon_google_docstring = False
napoleon_use_rtype = False

# -- MyST and the notebooks ------------------------------------------------------------
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
nb_execution_mode = "cache"
nb_execution_excludepatterns = [f"notebooks/{stem}.ipynb" for stem in _STEMS if stem not in EXECUTED]
nb_execution_cache_path = str(DOCS / "_build" / (".jupyter_cache-" + ("quick" if QUICK else "full")))
nb_execution_in_temp = True
nb_execution_timeout = 900
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_kernel_rgx_aliases = {".*": "python3"}
nb_merge_streams = True

# -- math: MathJax 3 served with the site (renders offline) ---------------------------------
# docs/_static/mathjax holds MathJax 3.2.2's es5/tex-chtml.js and its woff-v2 fonts, from the
# npm package (`npm pack mathjax@3.2.2`; Apache-2.0, LICENSE beside them); the fonts load
# from output/chtml/fonts/woff-v2 beside the script, so no page asks a CDN for anything.
mathjax_path = "mathjax/tex-chtml.js"
# The explorer's widgets need a running kernel: a page shows the cell without the widget
# (myst-nb would otherwise load require.js and the widget manager from a CDN).
nb_ipywidgets_js: dict = {}

# -- HTML ------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"ngcrack {release}"
html_static_path = ["_static"]
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "secondary_sidebar_items": ["page-toc"],
    "footer_start": ["copyright"],
    "footer_end": ["build-mode", "sphinx-version"],
}
html_context = {"default_mode": "light", "ngcrack_quick": QUICK,
                "ngcrack_not_executed": [stem for stem in _STEMS if stem not in EXECUTED]}
html_show_sourcelink = False
