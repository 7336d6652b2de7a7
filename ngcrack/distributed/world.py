"""The world of a distributed solve: how many processes mpiexec started, which one this is, and MPI itself.

Read from the environment without importing MPI (`world_size`, `world_rank`, `active`), so that a
serial run pays nothing; `require_mpi` imports mpi4py and checks NGSolve's MPI build; `refuse`
reports a request every rank finds alike once, on rank 0; `run_on_ranks` runs a solve's checks and
work so that one rank's failure stops them all; `same_exit` ends every rank of a command with rank
0's exit status.
"""

from __future__ import annotations

import os
import sys

from ..core.errors import InputError

#: environment variables through which mpiexec (MPICH/hydra, Open MPI, Slurm's PMI) tells a
#: process the size of its world, read without importing MPI
SIZE_VARIABLES = ("PMI_SIZE", "OMPI_COMM_WORLD_SIZE", "MPI_LOCALNRANKS", "PMIX_SIZE")
#: the tag of the message by which rank 0 tells the other ranks how a command ended
EXIT_TAG = 7301
#: and its rank
RANK_VARIABLES = ("PMI_RANK", "OMPI_COMM_WORLD_RANK", "MPI_LOCALRANKID", "PMIX_RANK")


class MPIUnavailable(InputError):
    """mpiexec started the process, but mpi4py or an MPI-enabled NGSolve is missing."""


def _from_environment(names: tuple[str, ...], default: int) -> int:
    """The first of `names` set to a whole number in the environment, else `default`."""
    for name in names:
        value = os.environ.get(name)
        if value and value.isdigit():
            return int(value)
    return default


def world_size() -> int:
    """The number of processes mpiexec started (1 outside mpiexec), from the environment."""
    return _from_environment(SIZE_VARIABLES, 1)


def world_rank() -> int:
    """This process's rank under mpiexec (0 outside mpiexec), from the environment."""
    return _from_environment(RANK_VARIABLES, 0)


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
    """Whether a solve should run distributed: the crack problem's strategy for this communicator is
    the projected Krylov one (`core.crack_problem.choose_strategy`: more than one process under mpiexec)."""
    from ..core.crack_problem import choose_strategy

    return choose_strategy(0, world_size()) == "krylov"


def same_exit(code: int) -> int:
    """The exit status of a command under mpiexec, the same on every rank: rank 0's.

    Rank 0 sends its status to the others (a point-to-point message, which no collective
    can match); a rank that finished its part without error waits for it, so that it
    neither ends before rank 0 has written the outputs nor with another status (mpiexec
    reports the job as failed when one rank ends 0 and another 130). A rank that failed
    keeps its own status: mpiexec then ends the job. Outside mpiexec, or in a command that
    never started MPI, `code` as it is.
    """
    if world_size() <= 1 or "mpi4py.MPI" not in sys.modules:
        return code
    from mpi4py import MPI

    comm = MPI.COMM_WORLD
    if comm.rank == 0:
        for other in range(1, comm.size):
            comm.send(code, dest=other, tag=EXIT_TAG)
        return code
    return int(comm.recv(source=0, tag=EXIT_TAG)) if code == 0 else code


def fail(comm, exc: BaseException) -> None:
    """One line on stderr and the whole communicator stopped: no rank waits for a dead one."""
    sys.stderr.write(f"ngcrack: distributed solve failed on rank {comm.rank}: {type(exc).__name__}: {exc}\n")
    sys.stderr.flush()
    comm.Abort(1)


def run_on_ranks(comm, check, work, alike: tuple[type[BaseException], ...] = ()):
    """`check()` then `work()` on every rank of `comm`, `work`'s answer returned.

    The checks run alike on every rank before any communication, so a ValueError there is
    found by all: rank 0 raises it, the others leave quietly with the same status (2). An
    error of a type in `alike` during the work is found alike on every rank too (an agreed
    refusal) and is reported the same way; any other failure of one rank stops the whole
    communicator (`fail`) instead of leaving the others waiting for it.
    """
    try:
        check()
    except ValueError:
        if comm.rank == 0:
            raise
        raise SystemExit(2) from None
    try:
        return work()
    except alike:
        if comm.rank == 0:
            raise
        raise SystemExit(2) from None
    except Exception as exc:  # noqa: BLE001 -- any failure of one rank stops all of them
        fail(comm, exc)
        raise
