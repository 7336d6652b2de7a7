"""The sum of a distributed vector over the ranks that share each unknown, by mpi4py.

NGSolve's `BaseVector.Cumulate` does this exchange itself, but not reliably with the
MPICH of the `[mpi]` extra: the NGSolve and netgen wheels reach MPI through netgen's
run-time wrapper (`NG_MPI_WRAPPER`), whose request handles are 8 bytes wide. MPICH's are
4 bytes (`MPI_Request` is an int; Open MPI's is a pointer), so the wrapper packs an
array of handles in place into MPICH's layout before each `MPI_Waitany` and
`MPI_Waitall` and does not unpack the completed ones afterwards. `Cumulate` waits for
its receives one `Waitany` at a time on the same array: from the second call on the
array it hands MPI is shuffled, one request is waited twice (after MPI freed it) and
another never. On a rank that exchanges with two or more ranks the sum comes out wrong
(the neighbour whose message arrived first is added twice, the other not at all) and
the receive left running writes into the vector's buffer after the vector is freed:
"malloc(): unaligned tcache chunk detected" a few calls later. A rank has two
neighbours from `mpiexec -n 4` on (rank 0 holds no elements, so from three subdomains);
with one neighbour a single `Waitany` is correct, hence nothing showed at -n 2 and 3.
benchmarks/mpi_exchange.py reproduces it on a unit square (wrong sums on every worker
rank at -n 4 with MPICH, none with the Open MPI wheel).

So the distributed solve never asks NGSolve to cumulate a distributed vector: `cumulate`
below exchanges the shared entries with mpi4py (whose handles are MPI's own), in the
order of NGSolve's `ParallelDofs.Proc2Dof` (the exchange order NGSolve itself relies
on: both ranks list their common unknowns in the same order). NGSolve operations that
cumulate internally (`GridFunction.Set`, a ParallelMatrix applied to a distributed
vector, NGSolve's BDDC) are avoided on such ranks or kept where `ngsolve_exchange_safe`.
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np

#: NGSolve's request handles, in bytes (netgen's NG_MPI_Request holds a uintptr_t)
WRAPPER_HANDLE_BYTES = 8


def ngsolve_exchange_safe(fes: ngs.FESpace, comm) -> bool:
    """Whether NGSolve's own exchanges (Cumulate, its BDDC) are reliable for `fes` on `comm`: netgen reaches MPI
    directly (no run-time wrapper), or the MPI's request handles are as wide as the wrapper's, or no rank exchanges
    with more than one other (collective)."""
    import netgen.config
    from mpi4py import MPI

    wrapped = "NG_MPI_WRAPPER" in str(getattr(netgen.config, "ngcore_compile_definitions", ""))
    if not wrapped or MPI._sizeof(MPI.Request) >= WRAPPER_HANDLE_BYTES:
        return True
    pd = fes.ParallelDofs()
    neighbours = len(list(pd.ExchangeProcs())) if pd is not None else 0
    return int(comm.allreduce(neighbours, op=MPI.MAX)) <= 1


#: the message tag of the exchanges (apart from NGSolve's own)
TAG = 4711


class Exchange:
    """The unknowns shared with each neighbouring rank, from NGSolve's ParallelDofs `pardofs` (a space's
    `ParallelDofs()` or a ParallelMatrix's `row_pardofs`); `cumulate` sums a vector's shared entries over the ranks."""

    def __init__(self, pardofs, comm=None):
        if comm is None:
            from mpi4py import MPI

            comm = MPI.COMM_WORLD
        self.comm = comm
        procs = sorted(int(p) for p in pardofs.ExchangeProcs()) if pardofs is not None else []
        shared = {p: np.array(list(pardofs.Proc2Dof(p)), dtype=np.int64) for p in procs}
        self.shared = {p: d for p, d in shared.items() if len(d)}

    @classmethod
    def of_space(cls, fes: ngs.FESpace, comm=None) -> Exchange:
        return cls(fes.ParallelDofs(), comm)

    def add_shared(self, values: np.ndarray) -> None:
        """values[d] += the other ranks' values at every shared unknown d (in place; a float array over the local
        unknowns; every rank with shared unknowns calls it alike)."""
        from mpi4py import MPI

        sent = {p: np.ascontiguousarray(values[d], dtype=float) for p, d in self.shared.items()}
        received = {p: np.empty(len(d)) for p, d in self.shared.items()}
        requests = [self.comm.Irecv(received[p], source=p, tag=TAG) for p in self.shared]
        requests += [self.comm.Isend(sent[p], dest=p, tag=TAG) for p in self.shared]
        MPI.Request.Waitall(requests)
        for p, d in self.shared.items():
            values[d] += received[p]

    def cumulate(self, vec: ngs.BaseVector) -> None:
        """NGSolve's `vec.Cumulate()` done here: a distributed vector summed over the ranks sharing each unknown and
        marked cumulated; any other left as it is (every rank calls it alike, as NGSolve's)."""
        if vec.GetParallelStatus() != ngs.PARALLEL_STATUS.DISTRIBUTED:
            return
        self.add_shared(vec.FV().NumPy())
        vec.SetParallelStatus(ngs.PARALLEL_STATUS.CUMULATED)
