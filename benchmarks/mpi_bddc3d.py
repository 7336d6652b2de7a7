"""The 3D distributed CG's preconditioners against the problem size: CG steps, coarse size, time, memory.

    python benchmarks/mpi_bddc3d.py [--scales 1.33,1,0.75] [--ranks 2,3] [--orders 1,2]
                                    [--kinds subdomains,bddc] [--scene penny]

For every mesh scale (the scene's maxh, crack_h and front_h times the scale), order, number
of ranks N and preconditioner, one `mpiexec -n N` run (its own processes, so that the peak
memory is that run's) assembles the distributed 3D TDNNS system of the scene (the penny:
a penny crack in a block of side 20 under tension) and runs CG on the sign-flipped
condensed system without crack constraints (`distributed.bddc.unconstrained_steps`) to
the preconditioned relative residuals 1e-6, 1e-8 and 1e-12 from zero. Printed per run:
global unknowns, subdomains (N - 1: rank 0 holds none), the preconditioner ("subdomains":
BDDC with one subdomain per rank, `distributed.subdomains`; "bddc": NGSolve's
element-wise BDDC with the coarse space of `distributed.solid.coarse_space`), its coarse
problem's size (global unknowns, and as a share of the system), the CG steps to each
tolerance, the preconditioner's setup seconds, the seconds of the CG run to 1e-12, and
the peak memory of every rank (MB, rank 0 first: it meshes and holds no elements).
`--corners averages`: the unknowns shared by three or more subdomains (from 4 ranks on)
as rigid-motion averages per subdomain edge instead of primal (`subdomains.CORNERS`).
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

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
TOLS = (1e-6, 1e-8, 1e-12)


def worker(scene_name: str, scale: float, order: int, kind: str, corners: str, out: str) -> None:
    """Under mpiexec: one system, one preconditioner, CG to TOLS; rank 0 writes its record to `out`."""
    from mpi4py import MPI

    import ngcrack as nc
    from ngcrack.distributed.bddc import subdomain_preconditioner, unconstrained_steps
    from ngcrack.distributed.solid import local_system, make_preconditioner
    from ngcrack.solid.solve import check_options

    comm = MPI.COMM_WORLD
    scene = nc.scenes.load(scene_name)
    sizes = scene.mesh_sizes()
    opts = dict(check_options({"order": order}), **{k: sizes[k] * scale for k in ("maxh", "crack_h", "front_h")})
    timings: dict[str, float] = {}
    loc = local_system(comm, scene, opts, timings)
    comm.Barrier()
    t0 = time.perf_counter()
    if kind == "subdomains":
        made = subdomain_preconditioner(loc.disc, comm, corners)
    else:
        made = make_preconditioner(loc.disc, loc.lsm, kind, comm)
    comm.Barrier()
    setup = time.perf_counter() - t0
    its = unconstrained_steps(loc.disc, kind, tols=TOLS, comm=comm, made=made, exact=False)
    memory = comm.gather(round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0, 1), root=0)
    if comm.rank == 0:
        json.dump(dict(its, setup=setup, memory=memory, timings=timings, ranks=comm.size), open(out, "w"))


def run(scene: str, scale: float, order: int, n: int, kind: str, corners: str, tmp: str) -> dict:
    out = os.path.join(tmp, "out.json")
    env = dict(os.environ, OMP_NUM_THREADS="1", PYTHONPATH=ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))
    cmd = ["mpiexec", "-n", str(n), sys.executable, os.path.abspath(__file__), "--worker", scene, str(scale),
           str(order), kind, corners, out]
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(proc.stderr[-2000:])
    return json.load(open(out))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scene", default="penny")
    p.add_argument("--scales", default="1.33,1,0.75")
    p.add_argument("--ranks", default="2,3")
    p.add_argument("--orders", default="1,2")
    p.add_argument("--kinds", default="subdomains,bddc")
    p.add_argument("--corners", default="primal", help="subdomains: unknowns shared by 3+ ranks (primal, averages)")
    p.add_argument("--worker", nargs=6, help=argparse.SUPPRESS)
    a = p.parse_args()
    if a.worker:
        scene, scale, order, kind, corners, out = a.worker
        worker(scene, float(scale), int(order), kind, corners, out)
        return
    print("| scale | order | unknowns | N | preconditioner | coarse (share) | CG to 1e-6 / 1e-8 / 1e-12 | setup s "
          "| CG s (1e-12) | MB per rank | uptime |")
    print("|---:|---:|---:|---:|---|---:|---|---:|---:|---|---|")
    for scale in (float(s) for s in a.scales.split(",")):
        for order in (int(o) for o in a.orders.split(",")):
            for n in (int(x) for x in a.ranks.split(",")):
                for kind in a.kinds.split(","):
                    load = subprocess.run(["uptime"], capture_output=True, text=True).stdout.split("average:")[-1]
                    with tempfile.TemporaryDirectory() as tmp:
                        try:
                            r = run(a.scene, scale, order, n, kind, a.corners, tmp)
                        except RuntimeError as exc:
                            print(f"| {scale:g} | {order} | - | {n} | {kind} | failed: {str(exc).strip()[-200:]} |",
                                  flush=True)
                            continue
                    name = kind + (f" ({a.corners})" if kind == "subdomains" and a.corners != "primal" else "")
                    steps = " / ".join(map(str, r["steps"]))
                    print(f"| {scale:g} | {order} | {r['unknowns']:,} | {n} | {name} | {r['coarse']:,} "
                          f"({100.0 * r['coarse'] / r['unknowns']:.2g}%) | {steps} | {r['setup']:.2f} | "
                          f"{r['seconds_each'][-1]:.2f} | {', '.join(f'{m:.0f}' for m in r['memory'])} | "
                          f"{load.strip()} |", flush=True)


if __name__ == "__main__":
    main()
