"""ngcrack: cracked elastic bodies with unilateral (Signorini) crack contact on NGSolve.

    import ngcrack as nc
    scene = nc.scenes.load("paper-2")            # or nc.Scene.from_toml("my.toml")
    sol = nc.solve(scene, element="bdm", maxh=0.05)
    sol.u, sol.sigma, sol.crack_profiles(), sol.kkt, sol.timings, sol.ndof
    table = nc.sweep(scene, elements=["bdm", "peers"], maxh=[0.2, 0.1, 0.05])  # a DataFrame
    nc.explore("inclined-crack")                 # ipywidgets: sliders and a live figure (JupyterLab)

Locking-free hybridized mixed elements (PEERS, BDM) after Belhachmi et al.,
"Locking-free finite elements for unilateral crack problems in elasticity".

`import ngcrack` loads only this file: every public name below is imported from its
module on first use (PEP 562), so a script or the command line pays for what it uses
(NGSolve and scipy for a solve; pandas for a sweep; ipywidgets for the explorer).
"""

from __future__ import annotations

import importlib
import sys
import types
from typing import TYPE_CHECKING

__version__ = "0.1.0"

#: public name -> the module that defines it
_EXPORTS = {
    "references": ".references", "scenes": ".scenes",
    "ContactSolverError": ".constraints",
    "ELEMENTS": ".elements", "Loads": ".elements",
    "InputError": ".errors",
    "Explorer": ".explorer", "Study": ".explorer", "explore": ".explorer", "explore_growth": ".explorer",
    "GrowthResult": ".growth", "grow": ".growth",
    "HydrofracResult": ".hydrofrac", "hydrofrac": ".hydrofrac",
    "CRACK_MODELS": ".options", "SolveOptions": ".options",
    "Pipeline": ".pipeline",
    "BoundaryCondition": ".scene", "Crack": ".scene", "Hole": ".scene", "Material": ".scene", "PointCondition": ".scene", "Scene": ".scene",
    "SceneError": ".scene",
    "LinearSolverError": ".schur",
    "CoarseMeshWarning": ".sizing",
    "Solution": ".solution",
    "SolveError": ".solve", "solve": ".solve",
    "SweepError": ".sweeps", "fitted_rates": ".sweeps", "sweep": ".sweeps",
    "crack_volume": ".volume", "solve_volume": ".volume",
}

__all__ = [
    "BoundaryCondition", "CRACK_MODELS", "Crack", "ELEMENTS", "Explorer", "GrowthResult", "Hole", "Loads", "Material",
    "Pipeline", "PointCondition",
    "Scene", "SceneError", "Solution", "SolveError", "SolveOptions", "Study", "explore", "explore_growth", "fitted_rates",
    "grow", "references", "scenes", "solve", "sweep", "crack_volume", "solve_volume", "HydrofracResult", "hydrofrac",
    # the errors and warnings a script may catch
    "CoarseMeshWarning", "ContactSolverError", "InputError", "LinearSolverError", "SweepError",
]


#: the public names that are modules themselves
_MODULES = ("references", "scenes")


def __getattr__(name: str):
    """A public name or a submodule (``nc.vtk``, ``nc.tips``), imported on first use."""
    where = _EXPORTS.get(name)
    if where is not None:
        module = importlib.import_module(where, __name__)
        value = module if name in _MODULES else getattr(module, name)
    else:
        try:
            value = importlib.import_module("." + name, __name__)
        except ModuleNotFoundError as exc:
            if exc.name != f"{__name__}.{name}":
                raise
            raise AttributeError(f"module {__name__!r} has no attribute {name!r}") from None
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


class _Package(types.ModuleType):
    """The package's module type. Importing a submodule that shares its name with a public
    function (``ngcrack.solve``, ``ngcrack.hydrofrac``) binds the submodule as an attribute
    of the package (Python's import system does), which would hide the function; that
    binding is skipped, so the name stays the function's (resolved on first use, as with
    eager imports) and the submodule stays in sys.modules."""

    def __setattr__(self, name, value):
        if isinstance(value, types.ModuleType) and name in _EXPORTS and name not in _MODULES:
            return
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package

if TYPE_CHECKING:  # what type checkers and editors see: the names above, eagerly
    from . import references, scenes
    from .constraints import ContactSolverError
    from .elements import ELEMENTS, Loads
    from .errors import InputError
    from .explorer import Explorer, Study, explore, explore_growth
    from .growth import GrowthResult, grow
    from .hydrofrac import HydrofracResult, hydrofrac
    from .options import CRACK_MODELS, SolveOptions
    from .pipeline import Pipeline
    from .scene import BoundaryCondition, Crack, Hole, Material, PointCondition, Scene, SceneError
    from .schur import LinearSolverError
    from .sizing import CoarseMeshWarning
    from .solution import Solution
    from .solve import SolveError, solve
    from .sweeps import SweepError, fitted_rates, sweep
    from .volume import crack_volume, solve_volume
