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

import os

from ..core.errors import InputError

#: environment variables through which mpiexec (MPICH/hydra, Open MPI, Slurm's PMI) tells a
#: process the size of its world, read without importing MPI
SIZE_VARIABLES = ("PMI_SIZE", "OMPI_COMM_WORLD_SIZE", "MPI_LOCALNRANKS", "PMIX_SIZE")
#: and its rank
RANK_VARIABLES = ("PMI_RANK", "OMPI_COMM_WORLD_RANK", "MPI_LOCALRANKID", "PMIX_RANK")


class MPIUnavailable(InputError):
    """mpiexec started the process, but mpi4py or an MPI-enabled NGSolve is missing."""


def world_size() -> int:
    """The number of processes mpiexec started (1 outside mpiexec), from the environment."""
    for name in SIZE_VARIABLES:
        value = os.environ.get(name)
        if value and value.isdigit():
            return int(value)
    return 1


def world_rank() -> int:
    """This process's rank under mpiexec (0 outside mpiexec), from the environment."""
    for name in RANK_VARIABLES:
        value = os.environ.get(name)
        if value and value.isdigit():
            return int(value)
    return 0


def refuse(message: str) -> None:
    """Refuse a request that every rank finds alike with one line: InputError on rank 0, a quiet exit with the
    same status (2) on the others."""
    if world_rank() == 0:
        raise InputError(message)
    raise SystemExit(2)


def require_mpi():
    """mpi4py's COMM_WORLD, or MPIUnavailable with one line naming the `[mpi]` extra."""
    try:
        from mpi4py import MPI
    except ImportError as exc:
        raise MPIUnavailable("distributed solve: mpi4py is not installed; pip install 'ngcrack[mpi]' "
                             "(mpi4py and mpich) to run under mpiexec") from exc
    import netgen.config

    if not getattr(netgen.config, "USE_MPI", False):
        raise MPIUnavailable("distributed solve: this NGSolve was built without MPI (netgen.config.USE_MPI is "
                             "False); pip install 'ngcrack[mpi]' next to the ngsolve wheel")
    return MPI.COMM_WORLD


def active() -> bool:
    """Whether a solve should run distributed: more than one process under mpiexec."""
    return world_size() > 1


def summary_line(info: dict) -> str:
    """The one line `ngcrack solve` prints after a distributed solve: ranks, subdomains, preconditioner, steps."""
    steps = info["cg_steps"]
    cg = f"{sum(steps)} CG steps ({', '.join(map(str, steps))} per active-set step)"
    return (f"distributed over {info['ranks']} ranks ({info['subdomains']} subdomains), preconditioner "
            f"{info['preconditioner'].split(':')[0]}: {info['active_set_steps']} active-set steps, {cg}")


def solve(scene, options=None):
    """The distributed solve (ngcrack.distributed.planar.solve); the Solution on rank 0, None elsewhere."""
    from .planar import solve as _solve

    return _solve(scene, options)
