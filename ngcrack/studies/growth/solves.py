"""The growth loop's solves: one Pipeline for the whole path, the options of every solve, the cost by part.

Growth solves the same body again and again with a longer path. Two of its defaults differ
from a plain solve's, for cost, and are set here unless the caller gives them:

- `path_grading` (checks.GROWTH_PATH_GRADING): the grown path is meshed coarser with the
  distance from the crack ends (`ngcrack.planar.path_sizes`);
- `friction_method` "newton" where a crack has friction: the semismooth Newton method on
  the Coulomb law reaches the same contact, stick and slip sets as the fixed point of
  Tresca problems (the same answer: K equal to the last digit on the teaching scene's grown
  paths) with about half the crack problem's work. A Newton solve that does not converge
  is solved again with "fixed-point" (`Solver.fallback`), the plain solve's method.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from ngcrack.core.constraints import ContactSolverError
from ngcrack.core.options import SolveOptions
from ngcrack.core.pipeline import Pipeline

from .checks import GROWTH_PATH_GRADING

#: the parts of a solve's cost recorded per step (table columns PART_s), from the solve's timings
COST_PARTS = {"mesh": ("mesh",), "assembly": ("assemble",), "linear": ("factorize", "solve", "recover"),
              "crack": ("schur", "qp"), "post": ("tips", "estimate")}


def growth_solve_options(scene, solve_options: dict) -> dict:
    """The options of every solve of the run: `path_grading` GROWTH_PATH_GRADING and, where a crack
    has friction, `friction_method` "newton", unless given."""
    out = {"path_grading": GROWTH_PATH_GRADING, **solve_options}
    if any(c.friction > 0 for c in scene.cracks):
        out.setdefault("friction_method", "newton")
    return out


@dataclass
class Solver:
    """The loop's solves: one Pipeline for the whole path and the solve options, checked once.

    Every step (and every PLS trial) is a new geometry, so the pipeline meshes and
    assembles it afresh; what it keeps is the contact set handed on as a warm start.
    `fallback`: the options a solve is made again with where the crack problem's solver
    fails (growth's own choice of the Newton friction method only).
    """

    options: SolveOptions
    pipeline: Pipeline = field(default_factory=Pipeline)
    #: seconds spent so far in each part of the solves (COST_PARTS), summed over every solve
    spent: dict = field(default_factory=lambda: dict.fromkeys(COST_PARTS, 0.0))
    fallback: SolveOptions | None = None

    @classmethod
    def of(cls, scene, solve_options: dict) -> Solver:
        """The run's Solver for `scene`: growth's defaults (growth_solve_options) and their fallback."""
        options = SolveOptions.of(**growth_solve_options(scene, solve_options))
        chosen = "friction_method" not in solve_options and options.friction_method == "newton"
        return cls(options, fallback=options.replace(friction_method="fixed-point") if chosen else None)

    def since(self, before: dict) -> dict:
        """The seconds of each part spent since the snapshot `before` (a copy of `spent`)."""
        return {k: self.spent[k] - before[k] for k in COST_PARTS}


def solve_step(scene, previous, solver: Solver):
    """One solve of the loop, warm-started from the previous one: the only place the loop solves."""
    try:
        sol = solver.pipeline.run(scene, solver.options, warm_start=previous)
    except ContactSolverError:
        if solver.fallback is None:
            raise
        sol = solver.pipeline.run(scene, solver.fallback, warm_start=previous)
    for part, keys in COST_PARTS.items():
        solver.spent[part] += sum(float(sol.timings.get(k, 0.0)) for k in keys)
    return sol


def on_rank_zero() -> bool:
    """Whether this process runs a growth: rank 0 under mpiexec, or no mpiexec. The growth's solves are serial (one
    Pipeline), so growth is not distributed; read from the environment, no MPI started."""
    from ngcrack.distributed import world_rank

    return world_rank() == 0
