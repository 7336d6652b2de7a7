"""One crack problem over many processes with MPI, on NGSolve's own parallel machinery.

Under `mpiexec -n N` (N > 1) `ngcrack solve` and `nc.solve` run `distributed.solve`:

- mesh: made on rank 0 by the serial pipeline, distributed by netgen (`Distribute` /
  `Receive`). NGSolve's distributed meshes leave rank 0 without elements: the N - 1
  other ranks hold one subdomain each, rank 0 takes part in every reduction;
- system: every rank builds the element's spaces and forms on its subdomain (the crack
  edges found again on each rank) and assembles the statically condensed facet system
  in parallel (NGSolve ParallelMatrix);
- linear solves: conjugate gradients preconditioned by BDDC with one subdomain per rank
  (`subdomains.py`; the choices and why: `bddc.py`), the crack problem's held values
  constraints of its local solves;
- crack problem: a primal-dual active-set iteration on the distributed crack unknowns,
  each step one constrained linear solve (active constraint values held at zero by a
  projection), the multipliers from the residual, the KKT residuals and the change of
  the active set reduced over the ranks; with Coulomb friction the stick and slip sets
  too, and the slip threshold mu lam_n by a fixed point (`friction.py`);
- gather: the condensed unknowns go to rank 0, which recovers the element-local
  unknowns and runs the serial post-processing (profiles, KKT residuals with the
  definitions of `constraints.py`, the tips' K_I, K_II, G): one Solution on rank 0,
  written once.

A 3D scene (ngcrack.solid, tdnns) goes the same way through `distributed.solid`: the mesh
curved on every rank with the scene's geometry, the crack faces' active set by projected
CG with a 3D BDDC coarse space, the fronts' K on rank 0 from the gathered answer.

N = 1 (no mpiexec) is the serial direct path, unchanged. mpi4py and an MPI library are
the `[mpi]` extra.
"""

from __future__ import annotations

from ..core.solution import summary_line  # noqa: F401  (re-exported)
from .world import (  # noqa: F401  (re-exported: the package's face)
    RANK_VARIABLES,
    SIZE_VARIABLES,
    MPIUnavailable,
    active,
    refuse,
    require_mpi,
    world_rank,
    world_size,
)


def solve(scene, options=None):
    """The distributed solve of a scene of either dimension (ngcrack.distributed.planar.solve,
    ngcrack.distributed.solid.solve_scene); the Solution on rank 0, None elsewhere."""
    if scene.dimension == 3:
        from .solid import solve_scene

        return solve_scene(scene, options)
    from .planar import solve as _solve

    if options is not None and options.preconditioner is not None:
        refuse(f"preconditioner = {options.preconditioner!r}: a 2D distributed solve preconditions with BDDC per rank "
               "subdomain (the 3D one takes a choice)")
    return _solve(scene, options)
