"""CG steps of the 2D distributed solve with BDDC per rank subdomain, against the number of ranks and the size.

    python benchmarks/mpi_ranks.py [--ranks 2,3,4,5,6] [--scales 0.25] [--scene griffith]

For every number of ranks N and mesh scale (the scene's maxh, tip_h and crack_h times the
scale), one `mpiexec -n N` run assembles the distributed condensed TDNNS system and runs
CG with BDDC per rank subdomain (`distributed.subdomains`) on it without crack
constraints (`distributed.bddc.unconstrained_steps`) from zero to the preconditioned
relative residuals 1e-6, 1e-8 and 1e-12. Printed per run: global unknowns, subdomains
(N - 1: rank 0 holds none), the largest subdomain (free unknowns of one rank), the most
neighbours of a rank, the coarse problem's size, the CG steps to each tolerance, the
answer's relative difference to the direct solve (NGSolve's masterinverse), the
preconditioner's setup and the CG run's seconds, and the peak memory of every rank (MB,
rank 0 first). N above the machine's cores oversubscribes them: the steps are exact, the
seconds are not comparable then.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time

TOLS = (1e-6, 1e-8, 1e-12)


def worker(scene_name: str, scale: float, out: str) -> None:
    import numpy as np
    from mpi4py import MPI

    import ngcrack as nc
    from ngcrack.core.options import SolveOptions
    from ngcrack.core.pipeline import ParameterLoads, Pipeline
    from ngcrack.distributed.bddc import preconditioner, unconstrained_steps
    from ngcrack.distributed.mesh import distribute
    from ngcrack.planar import elements
    from ngcrack.planar.materials import compliance

    comm = MPI.COMM_WORLD
    scene = nc.scenes.load(scene_name)
    o = SolveOptions(maxh=scene.maxh * scale, tip_h=scene.tip_h * scale, crack_h=scene.crack_h * scale,
                     max_dof=10**8)
    serial = Pipeline().mesh(scene, o) if comm.rank == 0 else None
    cmesh = distribute(serial, scene, comm)
    mat = scene.material
    disc = elements.build("tdnns", cmesh, compliance(mat.E, mat.nu, mat.plane), ParameterLoads(scene).loads)
    comm.Barrier()
    t0 = time.perf_counter()
    made = preconditioner(disc, "subdomains", comm=comm)
    comm.Barrier()
    setup = time.perf_counter() - t0
    r = unconstrained_steps(disc, "subdomains", tols=TOLS, comm=comm, made=made)
    pre = made[0]
    local = comm.allgather(len(pre.idx))
    neighbours = comm.allreduce(len(pre.exchange.shared), op=MPI.MAX)
    peak = comm.gather(round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0), root=0)
    if comm.rank == 0:
        with open(out, "w") as f:
            json.dump(dict(r, setup=setup, largest=int(np.max(local)), neighbours=neighbours, peak=peak), f)


def run(n: int, scene: str, scale: float) -> dict:
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "out.json")
        env = dict(os.environ, OMP_NUM_THREADS="1")
        proc = subprocess.run(["mpiexec", "-n", str(n), sys.executable, __file__, "--worker", "--scene", scene,
                               "--scales", str(scale), "--out", out], env=env, capture_output=True, text=True)
        if proc.returncode != 0:
            raise RuntimeError(f"mpiexec -n {n}, scale {scale}: {proc.stderr[-1500:]}")
        with open(out) as f:
            return json.load(f)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--scene", default="griffith")
    ap.add_argument("--ranks", default="2,3,4,5,6")
    ap.add_argument("--scales", default="0.25")
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--out", default=None, help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.worker:
        worker(a.scene, float(a.scales), a.out)
        return
    print(os.popen("uptime").read().strip())
    print("\n| scale | N | unknowns | subdomains | largest subdomain | most neighbours | coarse | CG to 1e-6 / 1e-8 / "
          "1e-12 | difference to direct | setup s | CG s (all three) | peak MB per rank |")
    print("|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---|")
    for scale in (float(v) for v in a.scales.split(",")):
        for n in (int(v) for v in a.ranks.split(",")):
            r = run(n, a.scene, scale)
            steps = " / ".join(str(s) for s in r["steps"])
            print(f"| {scale:g} | {n} | {r['unknowns']} | {n - 1} | {r['largest']} | {r['neighbours']} | {r['coarse']} | "
                  f"{steps} | {r['difference']:.1e} | {r['setup']:.2f} | {r['seconds']:.2f} | "
                  f"{', '.join(str(m) for m in r['peak'])} |", flush=True)
    print(os.popen("uptime").read().strip())


if __name__ == "__main__":
    main()
