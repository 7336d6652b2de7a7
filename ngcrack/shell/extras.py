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
that says what to install (the command line prints it). `lazy_exports(...)` gives a
subpackage the module `__getattr__` and `__dir__` that import its public names on first use,
so importing the package loads none of its optional parts.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys

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


def lazy_exports(package: str, exports: dict[str, str], names: list[str]):
    """The `__getattr__` and `__dir__` of `package` (PEP 562): each name of `exports` (name -> the module
    that defines it, relative to `package`) is imported on first use and kept in the package; `names`: its
    `__all__`."""

    def __getattr__(name: str):
        """A public name, imported from its module on first use."""
        where = exports.get(name)
        if where is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(where, package), name)
        vars(sys.modules[package])[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted(set(vars(sys.modules[package])) | set(names))

    return __getattr__, __dir__
