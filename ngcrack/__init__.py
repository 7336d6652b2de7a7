"""ngcrack: cracked elastic bodies with unilateral (Signorini) crack contact on NGSolve.

    import ngcrack as nc
    scene = nc.scenes.load("paper-2")            # or nc.Scene.from_toml("my.toml")
    sol = nc.solve(scene, element="bdm", maxh=0.05)
    sol.u, sol.sigma, sol.crack_profiles(), sol.kkt, sol.timings, sol.ndof
    table = nc.sweep(scene, elements=["bdm", "peers"], maxh=[0.2, 0.1, 0.05])  # a DataFrame
    nc.explore("inclined-crack")                 # ipywidgets: sliders and a live figure (JupyterLab)

Locking-free hybridized mixed elements (PEERS, BDM) after Belhachmi et al.,
"Locking-free finite elements for unilateral crack problems in elasticity".
"""

from . import references, scenes
from .constraints import ContactSolverError
from .elements import ELEMENTS, Loads
from .errors import InputError
from .explorer import Explorer, Study, explore, explore_growth
from .growth import GrowthResult, grow
from .hydrofrac import HydrofracResult, hydrofrac
from .options import CRACK_MODELS, SolveOptions
from .pipeline import Pipeline
from .scene import BoundaryCondition, Crack, Material, PointCondition, Scene, SceneError
from .schur import LinearSolverError
from .sizing import CoarseMeshWarning
from .solution import Solution
from .solve import SolveError, solve
from .sweeps import SweepError, fitted_rates, sweep
from .volume import crack_volume, solve_volume

__version__ = "0.1.0"

__all__ = [
    "BoundaryCondition", "CRACK_MODELS", "Crack", "ELEMENTS", "Explorer", "GrowthResult", "Loads", "Material",
    "Pipeline", "PointCondition",
    "Scene", "SceneError", "Solution", "SolveError", "SolveOptions", "Study", "explore", "explore_growth", "fitted_rates",
    "grow", "hydrofrac", "HydrofracResult", "references", "scenes", "solve", "sweep", "crack_volume", "solve_volume",
    # the errors and warnings a script may catch
    "CoarseMeshWarning", "ContactSolverError", "InputError", "LinearSolverError", "SweepError",
]
