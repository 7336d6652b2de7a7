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
    "references": ".studies.references", "scenes": ".scenes",
    "ContactSolverError": ".core.constraints",
    "ELEMENTS": ".planar.elements", "Loads": ".planar.elements",
    "InputError": ".core.errors",
    "Explorer": ".shell.explorer", "Study": ".shell.explorer", "explore": ".shell.explorer", "explore_growth": ".shell.explorer",
    "GrowthResult": ".studies.growth", "grow": ".studies.growth",
    "HydrofracResult": ".studies.hydrofrac", "hydrofrac": ".studies.hydrofrac",
    "CRACK_MODELS": ".core.options", "SolveOptions": ".core.options",
    "Pipeline": ".core.pipeline",
    "BoundaryCondition": ".planar.scene", "Crack": ".planar.scene", "Hole": ".planar.scene", "Material": ".planar.scene",
    "PointCondition": ".planar.scene", "Scene": ".planar.scene",
    "SceneError": ".planar.scene",
    "LinearSolverError": ".core.schur",
    "CoarseMeshWarning": ".planar.sizing",
    "Front": ".core.solution", "Solution": ".core.solution",
    "SolveError": ".core.solve", "solve": ".core.solve",
    "SweepError": ".studies.sweeps", "fitted_rates": ".studies.sweeps", "sweep": ".studies.sweeps",
    "crack_volume": ".studies.volume", "solve_volume": ".studies.volume",
}

__all__ = [
    "BoundaryCondition", "CRACK_MODELS", "Crack", "ELEMENTS", "Explorer", "GrowthResult", "Hole", "Loads", "Material",
    "Pipeline", "PointCondition",
    "Front", "Scene", "SceneError", "Solution", "SolveError", "SolveOptions", "Study", "explore", "explore_growth", "fitted_rates",
    "grow", "references", "scenes", "solve", "sweep", "crack_volume", "solve_volume", "HydrofracResult", "hydrofrac",
    # the errors and warnings a script may catch
    "CoarseMeshWarning", "ContactSolverError", "InputError", "LinearSolverError", "SweepError",
]


#: the public names that are modules themselves
_MODULES = ("references", "scenes")

#: the package's folders: the dimension-free core, the planar (2D) and solid (3D) bodies, distributed
#: solves, the studies and loops over solves, and the user's shell (command line, explorer, files)
FOLDERS = ("core", "planar", "solid", "distributed", "studies", "shell", "scenes")

#: the modules a script reaches as ``nc.<name>`` (``nc.tips``, ``nc.hp``, ``nc.vtk``) -> where they live
_SUBMODULES = {name: f"{folder}.{name}" for folder, names in {
    "core": ("constraints", "contact", "friction", "hybrid", "options", "pipeline", "schur", "solution", "stages"),
    "planar": ("elements", "estimate", "geometry", "hp", "materials", "plots", "post", "sizing", "tips", "tstress", "vtk"),
    "studies": ("adapt", "growth", "hydrofrac", "paper", "stability", "sweeps", "volume"),
    "shell": ("cli", "explorer", "files", "interrupts"),
}.items() for name in names}


def __getattr__(name: str):
    """A public name or a submodule (``nc.vtk``, ``nc.tips``), imported on first use."""
    where = _EXPORTS.get(name)
    if where is not None:
        module = importlib.import_module(where, __name__)
        value = module if name in _MODULES else getattr(module, name)
    else:
        try:
            value = importlib.import_module("." + _SUBMODULES.get(name, name), __name__)
        except ModuleNotFoundError as exc:
            if exc.name != f"{__name__}.{_SUBMODULES.get(name, name)}":
                raise
            raise AttributeError(f"module {__name__!r} has no attribute {name!r}") from None
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


class _Package(types.ModuleType):
    """The package's module type. Importing a submodule that shares its name with a public
    function (``ngcrack.core.solve``, ``ngcrack.studies.hydrofrac``) binds the submodule as an attribute
    of the package (Python's import system does), which would hide the function; that
    binding is skipped, so the name stays the function's (resolved on first use, as with
    eager imports) and the submodule stays in sys.modules."""

    def __setattr__(self, name, value):
        if isinstance(value, types.ModuleType) and name in _EXPORTS and name not in _MODULES:
            return
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package

if TYPE_CHECKING:  # what type checkers and editors see: the names above, eagerly
    from . import scenes
    from .core.constraints import ContactSolverError
    from .core.errors import InputError
    from .core.options import CRACK_MODELS, SolveOptions
    from .core.pipeline import Pipeline
    from .core.schur import LinearSolverError
    from .core.solution import Front, Solution
    from .core.solve import SolveError, solve
    from .planar.elements import ELEMENTS, Loads
    from .planar.scene import BoundaryCondition, Crack, Hole, Material, PointCondition, Scene, SceneError
    from .planar.sizing import CoarseMeshWarning
    from .shell.explorer import Explorer, Study, explore, explore_growth
    from .studies import references
    from .studies.growth import GrowthResult, grow
    from .studies.hydrofrac import HydrofracResult, hydrofrac
    from .studies.sweeps import SweepError, fitted_rates, sweep
    from .studies.volume import crack_volume, solve_volume
