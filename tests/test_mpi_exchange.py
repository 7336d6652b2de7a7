"""The exchange of shared unknowns by mpi4py (distributed/exchange.py) under mpiexec.

A field known exactly on every rank (the local L2 projection of a polynomial the space
holds, the rigid modes' construction in subdomains.py), split over the ranks that share
each unknown and summed again by `Exchange.cumulate`, must come back to round-off: this
checks the sums and that both ranks of a shared unknown list it in the same place. At
-n 3 (default suite) and at -n 4 (slow; three subdomains, ranks with two neighbours, where
NGSolve's own Cumulate fails with MPICH).
"""

from __future__ import annotations

import json
import textwrap

import pytest
from test_mpi import _run, pytestmark  # noqa: F401  (the mpi4py skip)

SCRIPT = textwrap.dedent('''
    import json, sys
    import numpy as np
    import ngsolve as ngs
    import netgen.meshing as nm
    from mpi4py import MPI
    from netgen.geom2d import unit_square
    from ngcrack.distributed.exchange import Exchange, ngsolve_exchange_safe
    from ngcrack.distributed.subdomains import _local_projection
    comm = MPI.COMM_WORLD
    if comm.rank == 0:
        mesh = ngs.Mesh(unit_square.GenerateMesh(maxh=0.08).Distribute(comm))
    else:
        mesh = ngs.Mesh(nm.Mesh.Receive(comm))
    out = {}
    for name, fes, field in [("h1", ngs.H1(mesh, order=3), ngs.x * ngs.x - 2 * ngs.x * ngs.y + 0.5),
                             ("hcurl", ngs.HCurl(mesh, order=2, type1=True), ngs.CF((-ngs.y, ngs.x + ngs.y)))]:
        exact = _local_projection(fes, [field])[:, 0] if fes.ndof else np.zeros(0)
        pd = fes.ParallelDofs()
        mult = np.array([1 + len(pd.Dof2Proc(d)) for d in range(fes.ndof)], dtype=float)
        vec = ngs.GridFunction(fes).vec.CreateVector()
        vec.FV().NumPy()[:] = exact / mult
        vec.SetParallelStatus(ngs.PARALLEL_STATUS.DISTRIBUTED)
        ex = Exchange.of_space(fes, comm)
        ex.cumulate(vec)
        err = float(np.max(np.abs(vec.FV().NumPy() - exact), initial=0.0))
        scale = float(np.max(np.abs(exact), initial=0.0))
        out[name] = dict(error=comm.allreduce(err, op=MPI.MAX), scale=comm.allreduce(scale, op=MPI.MAX),
                         status=str(vec.GetParallelStatus()), neighbours=comm.allreduce(len(ex.shared), op=MPI.MAX),
                         shared=comm.allreduce(sum(len(d) for d in ex.shared.values())),
                         safe=ngsolve_exchange_safe(fes, comm))
    if comm.rank == 0:
        json.dump(out, open(sys.argv[1], "w"))
''')


def _exchange(tmp_path, n: int) -> dict:
    script, out = tmp_path / "exchange.py", tmp_path / "exchange.json"
    script.write_text(SCRIPT)
    proc = _run([str(script), str(out)], n=n)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(out.read_text())


def _check(r: dict, neighbours: int) -> None:
    for name in ("h1", "hcurl"):
        assert r[name]["error"] <= 1e-12 * r[name]["scale"]
        assert r[name]["shared"] > 0 and r[name]["neighbours"] == neighbours
        assert r[name]["status"].endswith("CUMULATED")


def test_exchange_three_ranks(tmp_path):
    _check(_exchange(tmp_path, 3), neighbours=1)  # two subdomains (rank 0 holds no elements)


@pytest.mark.slow
def test_exchange_four_ranks(tmp_path):
    r = _exchange(tmp_path, 4)
    _check(r, neighbours=2)
