"""The optional parts of the install: which extra brings which package.

`pip install ngcrack` brings what a solve needs; the rest comes with an extra
(pyproject.toml's optional dependencies, named in the README):

    tables     pandas, tqdm       nc.sweep, ngcrack sweep and paper, solve(adapt=)'s history, growth tables
    dask       + dask.distributed ngcrack sweep --dask ADDRESS
    explorer   ipywidgets         nc.explore, nc.explore_growth
    vtk        meshio             --vtk (the crack faces' ParaView file)
    cholespy   cholespy           linear_solver = "cholespy"
    notebooks  jupyterlab, jupytext and the above

`require(package, what)` refuses early (before any work) where a package is missing;
`missing_extra(exc)` turns the ModuleNotFoundError of such a package into the one line
that says what to install (the command line prints it).
"""

from __future__ import annotations

import importlib.util

#: top-level package -> the extra that installs it
EXTRAS = {
    "pandas": "tables", "tqdm": "tables",
    "dask": "dask", "distributed": "dask",
    "ipywidgets": "explorer", "webgui_jupyter_widgets": "explorer", "anywidget": "explorer",
    "meshio": "vtk",
    "cholespy": "cholespy",
    "jupytext": "notebooks", "jupyterlab": "notebooks",
}


def missing_extra(exc: BaseException) -> str | None:
    """For a missing optional package, "... : pip install 'ngcrack[EXTRA]'"; else None."""
    if not isinstance(exc, ModuleNotFoundError) or not exc.name:
        return None
    package = exc.name.split(".")[0]
    extra = EXTRAS.get(package)
    if extra is None:
        return None
    return f"this needs the package {package!r}, an optional part of ngcrack: pip install 'ngcrack[{extra}]'"


def require(package: str, what: str) -> None:
    """Raise ModuleNotFoundError (named, so the command line names its extra) if `package`,
    which `what` needs, is not installed: before any work, not after a solve."""
    if importlib.util.find_spec(package) is None:
        raise ModuleNotFoundError(f"{what} needs the package {package!r}: pip install 'ngcrack[{EXTRAS[package]}]'",
                                  name=package)
