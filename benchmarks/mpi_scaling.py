"""Distributed solves against the serial one: time per stage, Krylov steps, memory per rank.

    python benchmarks/mpi_scaling.py [--scales 1,0.5] [--ranks 2,3] [--scene griffith]

For every mesh scale (maxh, tip_h and crack_h of the scene times the scale) it runs the
serial direct solve in this process and `mpiexec -n N` distributed solves, and prints
one table row per run: global unknowns, subdomains (N - 1: rank 0 holds none), the
active-set steps and the CG steps of each (preconditioned by BDDC per rank subdomain, to
1e-12), the CG steps with that BDDC on the same condensed system without crack
constraints to 1e-6 and 1e-8 and its coarse problem's size, the same for NGSolve's
element-wise BDDC (`--element-bddc`; "-" without), the seconds per stage (mesh on rank 0,
distribute, assemble, preconditioner setup, CG, the rest of the active-set iteration,
gather, rank 0's post-processing) and the peak memory of every rank (MB).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))


def options(scene, scale: float):
    from ngcrack.options import SolveOptions

    return SolveOptions(maxh=scene.maxh * scale, tip_h=scene.tip_h * scale, crack_h=scene.crack_h * scale)


def bddc_iterations(scene, o, comm, kind: str) -> dict:
    """CG steps with the preconditioner `kind` on the sign-flipped condensed system (no crack constraint) to
    1e-6 and 1e-8 (preconditioned residual), and the size of its coarse problem (global unknowns)."""
    from ngcrack import elements
    from ngcrack.distributed.bddc import unconstrained_steps
    from ngcrack.distributed.mesh import distribute
    from ngcrack.materials import compliance
    from ngcrack.pipeline import ParameterLoads, Pipeline

    serial = Pipeline().mesh(scene, o) if comm.rank == 0 else None
    cmesh = distribute(serial, scene, comm)
    loads = ParameterLoads(scene).loads
    mat = scene.material
    disc = elements.build(o.element, cmesh, compliance(mat.E, mat.nu, mat.plane), loads, order=o.order)
    return unconstrained_steps(disc, kind, comm=comm)


def worker(scene_name: str, scale: float, element_bddc: bool) -> None:
    """Under mpiexec: one distributed solve and the BDDC counts; rank 0 prints one JSON line."""
    from mpi4py import MPI

    from ngcrack.distributed import solve
    from ngcrack.scenes import load

    scene = load(scene_name)
    o = options(scene, scale)
    t0 = time.perf_counter()
    sol = solve(scene, o)
    wall = time.perf_counter() - t0
    its = bddc_iterations(scene, o, MPI.COMM_WORLD, "subdomains")
    el = bddc_iterations(scene, o, MPI.COMM_WORLD, "bddc") if element_bddc else {"steps": ["-"], "coarse": "-"}
    if sol is not None:
        info = sol.options["distributed"]
        print(json.dumps({"global": sol.ndof["global"], "info": info, "timings": sol.timings, "wall": wall,
                          "bddc": its["steps"], "coarse": its["coarse"], "element": el["steps"],
                          "element_coarse": el["coarse"], "K_I": sol.tips[0].K_I if sol.tips else None}), flush=True)


def serial(scene_name: str, scale: float) -> dict:
    from ngcrack.pipeline import Pipeline
    from ngcrack.scenes import load

    scene = load(scene_name)
    t0 = time.perf_counter()
    sol = Pipeline().run(scene, options(scene, scale))
    return {"global": sol.ndof["global"], "timings": sol.timings, "wall": time.perf_counter() - t0,
            "memory": round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0, 1),
            "K_I": sol.tips[0].K_I if sol.tips else None}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--scene", default="griffith")
    ap.add_argument("--scales", default="1,0.5")
    ap.add_argument("--ranks", default="2,3")
    ap.add_argument("--element-bddc", action="store_true",
                    help="also count CG steps with NGSolve's element-wise BDDC (its coarse problem is 3/4 of the system)")
    ap.add_argument("--worker", type=float, default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker is not None:
        worker(args.scene, args.worker, args.element_bddc)
        return
    env = dict(os.environ, OMP_NUM_THREADS="1", PYTHONPATH=os.path.dirname(HERE))
    mpiexec = os.path.join(os.path.dirname(sys.executable), "mpiexec")
    print(f"{'scale':>5} {'N':>2} {'sub':>3} {'global':>7} {'AS':>3} {'CG':>12} {'BDDC':>7} {'coarse':>6} "
          f"{'elem.':>7} {'coarse':>6} {'mesh':>6} {'distr':>6} {'assem':>6} {'setup':>6} {'CG s':>6} {'AS s':>6} "
          f"{'gather':>6} {'rank0':>6} {'total':>6} {'K_I':>14}  memory MB per rank")
    for scale in (float(s) for s in args.scales.split(",")):
        r = serial(args.scene, scale)
        t = r["timings"]
        print(f"{scale:5.2f} {1:2d} {1:3d} {r['global']:7d} {'-':>3} {'direct':>12} {'-':>7} {'-':>6} {'-':>7} {'-':>6} "
              f"{t['mesh']:6.2f} {'-':>6} {t['assemble']:6.2f} {'-':>6} {t['linear'] + t['contact']:6.2f} {'-':>6} "
              f"{'-':>6} {'-':>6} {t['total']:6.2f} {r['K_I']:14.10f}  [{r['memory']}] (serial, this process)", flush=True)
        for n in (int(k) for k in args.ranks.split(",")):
            cmd = [mpiexec, "-n", str(n), sys.executable, __file__, "--scene", args.scene, "--worker", str(scale)]
            proc = subprocess.run(cmd + (["--element-bddc"] if args.element_bddc else []), env=env,
                                  capture_output=True, text=True)
            lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("{")]
            if proc.returncode or not lines:
                print(f"{scale:5.2f} {n:2d} failed: {proc.stderr.strip().splitlines()[-1:]}", flush=True)
                continue
            d = json.loads(lines[-1])
            i, t = d["info"], d["timings"]
            rank0 = t["rank0_system"] + t["rank0_post"] + t.get("tips", 0.0)
            print(f"{scale:5.2f} {n:2d} {i['subdomains']:3d} {d['global']:7d} {i['active_set_steps']:3d} "
                  f"{'+'.join(map(str, i['cg_steps'])):>12} {'/'.join(map(str, d['bddc'])):>7} {d['coarse']:>6} "
                  f"{'/'.join(map(str, d['element'])):>7} {d['element_coarse']:>6} {t['mesh']:6.2f} "
                  f"{t['distribute']:6.2f} {t['assemble']:6.2f} {t['preconditioner']:6.2f} {t['cg']:6.2f} "
                  f"{t['solve'] - t['cg']:6.2f} {t['gather']:6.2f} {rank0:6.2f} {t['total']:6.2f} {d['K_I']:14.10f}  "
                  f"{i['memory_mb']}", flush=True)


if __name__ == "__main__":
    main()
