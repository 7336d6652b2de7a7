"""NGSolve's Cumulate against the mpi4py exchange (ngcrack.distributed.exchange) under mpiexec.

    python benchmarks/mpi_exchange.py [--ranks 2,3,4,5,6] [--trials 20]

A unit square (maxh 0.05) distributed by netgen over N ranks (rank 0 holds no elements:
N - 1 subdomains), H1 of order 2. Every trial splits a field known exactly on every rank
(x^2 - 2xy + 1/2, the local L2 projection: exact) over the ranks sharing each unknown and
sums it again, by NGSolve's `BaseVector.Cumulate` or by `Exchange.cumulate`; one worker
rank sleeps 20 ms before each sum, a different one each trial, so that the messages
arrive in varying order, as under load. Printed per N and method: the most neighbours
of a rank, the trials whose sum was wrong on some rank (error above 1e-12 of the field),
and how the run ended (a corrupted heap ends it with a signal). The MPI library is
printed first: the fault is that of netgen's MPI wrapper with MPICH's 4-byte request
handles (exchange.py), so with Open MPI both methods are exact.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
TRIALS = 20


def worker(method: str, trials: int, out: str) -> None:
    import time

    import netgen.meshing as nm
    import ngsolve as ngs
    import numpy as np
    from mpi4py import MPI
    from netgen.geom2d import unit_square

    from ngcrack.distributed.exchange import Exchange
    from ngcrack.distributed.subdomains import _local_projection

    comm = MPI.COMM_WORLD
    if comm.rank == 0:
        mesh = ngs.Mesh(unit_square.GenerateMesh(maxh=0.05).Distribute(comm))
    else:
        mesh = ngs.Mesh(nm.Mesh.Receive(comm))
    fes = ngs.H1(mesh, order=2)
    exact = _local_projection(fes, [ngs.x * ngs.x - 2 * ngs.x * ngs.y + 0.5])[:, 0] if fes.ndof else np.zeros(0)
    pd = fes.ParallelDofs()
    mult = np.array([1 + len(pd.Dof2Proc(d)) for d in range(fes.ndof)], dtype=float)
    ex = Exchange.of_space(fes, comm)
    wrong = 0
    for t in range(trials):
        vec = ngs.GridFunction(fes).vec.CreateVector()
        vec.FV().NumPy()[:] = exact / mult
        vec.SetParallelStatus(ngs.PARALLEL_STATUS.DISTRIBUTED)
        if comm.size > 1 and comm.rank == 1 + t % (comm.size - 1):
            time.sleep(0.02)
        if method == "ngsolve":
            vec.Cumulate()
        else:
            ex.cumulate(vec)
        bad = bool(np.max(np.abs(vec.FV().NumPy() - exact), initial=0.0) > 1e-12)
        wrong += int(comm.allreduce(int(bad), op=MPI.MAX))
        del vec
    neighbours = comm.allreduce(len(ex.shared), op=MPI.MAX)
    if comm.rank == 0:
        with open(out, "w") as f:
            json.dump({"wrong": wrong, "neighbours": neighbours, "library": MPI.Get_library_version().split("\n")[0]}, f)


def run(n: int, method: str, trials: int) -> dict:
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "out.json")
        env = dict(os.environ, OMP_NUM_THREADS="1")
        proc = subprocess.run(["mpiexec", "-n", str(n), sys.executable, __file__, "--worker", method, "--trials",
                               str(trials), "--out", out], env=env, capture_output=True, text=True, timeout=600)
        if proc.returncode == 0 and os.path.exists(out):
            with open(out) as f:
                return dict(json.load(f), ended="clean")
        text = proc.stdout + proc.stderr
        how = "corrupted heap" if "malloc" in text else f"exit {proc.returncode}"
        signal = [ln for ln in text.splitlines() if "signal" in ln]
        return {"wrong": None, "neighbours": None, "library": None,
                "ended": how + (f" ({signal[-1].split('(')[-1].rstrip(')')})" if signal else "")}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--ranks", default="2,3,4,5,6")
    ap.add_argument("--trials", type=int, default=TRIALS)
    ap.add_argument("--worker", default=None, help=argparse.SUPPRESS)
    ap.add_argument("--out", default=None, help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.worker:
        worker(a.worker, a.trials, a.out)
        return
    rows = []
    for n in (int(v) for v in a.ranks.split(",")):
        rows.append((n, run(n, "ngsolve", a.trials), run(n, "mpi4py", a.trials)))
    library = next((r["library"] for _, x, y in rows for r in (x, y) if r["library"]), "?")
    print(f"MPI: {library}; {a.trials} trials per run\n")
    print("| N | subdomains | most neighbours of a rank | NGSolve Cumulate: wrong sums | ended | mpi4py exchange: wrong "
          "sums | ended |")
    print("|---:|---:|---:|---|---|---|---|")

    def fmt(r: dict) -> str:
        return "-" if r["wrong"] is None else f"{r['wrong']} of {a.trials}"

    for n, ng, ours in rows:
        nb = ours["neighbours"] if ours["neighbours"] is not None else "-"
        print(f"| {n} | {n - 1} | {nb} | {fmt(ng)} | {ng['ended']} | {fmt(ours)} | {ours['ended']} |")


if __name__ == "__main__":
    main()
