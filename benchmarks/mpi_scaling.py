"""Distributed solves against the serial one: time per stage, Krylov steps, memory per rank.

    python benchmarks/mpi_scaling.py [--scales 1,0.5] [--ranks 1,2,3] [--scene griffith] [--no-counts]

For every mesh scale (maxh, tip_h and crack_h of the scene times the scale) it runs the
serial direct solve (N = 1, its own process) and `mpiexec -n N` distributed solves, one
after the other, and prints one table row per run: global unknowns, subdomains (N - 1:
rank 0 holds none), the active-set steps and the CG steps of each (preconditioned by BDDC
per rank subdomain) to 1e-8 and to the solve's 1e-12 (one CG run: the first step below
1e-8 on its way), the CG steps with that BDDC on the same condensed system without crack
constraints to 1e-6 and 1e-8 and its coarse problem's size (a second distributed build
and a direct solve for the comparison; `--no-counts` leaves them out, "-"), the same for
NGSolve's element-wise BDDC (`--element-bddc`; "-" without), the seconds per stage (mesh
on rank 0, rank 0's serial discretization for the crack's constraint blocks, distribute,
assemble, preconditioner setup, CG, the rest of the active-set iteration, gather, rank
0's serial system and post-processing) and the peak memory of every rank over the whole
solve (MB, rank 0 first) with the largest sum over the run's processes at one time
(sampled every 0.2 s). `uptime` is printed before the table and after every row: the
seconds are those of the machine at that load.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
#: one solve's unknowns may exceed the size guard's default here (the largest case is the point)
MAX_DOF = 10**8


def options(scene, scale: float):
    from ngcrack.core.options import SolveOptions

    return SolveOptions(maxh=scene.maxh * scale, tip_h=scene.tip_h * scale, crack_h=scene.crack_h * scale,
                        max_dof=MAX_DOF)


def peak_mb() -> float:
    return round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0, 1)


def bddc_iterations(scene, o, comm, kind: str) -> dict:
    """CG steps with the preconditioner `kind` on the sign-flipped condensed system (no crack constraint) to
    1e-6 and 1e-8 (preconditioned residual), and the size of its coarse problem (global unknowns)."""
    from ngcrack.core.pipeline import ParameterLoads, Pipeline
    from ngcrack.distributed.bddc import unconstrained_steps
    from ngcrack.distributed.mesh import distribute
    from ngcrack.planar import elements
    from ngcrack.planar.materials import compliance

    serial = Pipeline().mesh(scene, o) if comm.rank == 0 else None
    cmesh = distribute(serial, scene, comm)
    loads = ParameterLoads(scene).loads
    mat = scene.material
    disc = elements.build(o.element, cmesh, compliance(mat.E, mat.nu, mat.plane), loads, order=o.order)
    return unconstrained_steps(disc, kind, comm=comm)


def worker(scene_name: str, scale: float, element_bddc: bool, counts: bool) -> None:
    """Under mpiexec: one distributed solve and the BDDC counts; rank 0 prints one JSON line."""
    from mpi4py import MPI

    from ngcrack.distributed import solve
    from ngcrack.scenes import load

    comm = MPI.COMM_WORLD
    scene = load(scene_name)
    o = options(scene, scale)
    t0 = time.perf_counter()
    sol = solve(scene, o)
    wall = time.perf_counter() - t0
    memory = comm.gather(peak_mb(), root=0)  # over the whole solve, rank 0's post-processing included
    record = None
    if sol is not None:
        record = {"global": sol.ndof["global"], "info": sol.options["distributed"], "timings": sol.timings,
                  "wall": wall, "memory": memory, "K_I": sol.tips[0].K_I if sol.tips else None}
    del sol
    none = {"steps": ["-"], "coarse": "-"}
    its = bddc_iterations(scene, o, comm, "subdomains") if counts else none
    el = bddc_iterations(scene, o, comm, "bddc") if element_bddc else none
    if record is not None:
        record.update(bddc=its["steps"], coarse=its["coarse"], element=el["steps"], element_coarse=el["coarse"])
        print(json.dumps(record), flush=True)


def serial_worker(scene_name: str, scale: float) -> None:
    """The serial solve in its own process; one JSON line."""
    from ngcrack.core.pipeline import Pipeline
    from ngcrack.scenes import load

    scene = load(scene_name)
    t0 = time.perf_counter()
    sol = Pipeline().run(scene, options(scene, scale))
    print(json.dumps({"global": sol.ndof["global"], "timings": sol.timings, "wall": time.perf_counter() - t0,
                      "memory": [peak_mb()], "K_I": sol.tips[0].K_I if sol.tips else None}), flush=True)


def _tree_rss(root: int) -> float:
    """Resident MB of process `root` and all its descendants (0 where psutil is missing or the process is gone)."""
    try:
        import psutil

        p = psutil.Process(root)
        procs = [p] + p.children(recursive=True)
        total = 0
        for q in procs:
            try:
                total += q.memory_info().rss
            except psutil.Error:
                pass
        return total / 2**20
    except Exception:  # noqa: BLE001 -- a sampler never stops the run
        return 0.0


def run(cmd: list[str], env: dict) -> tuple[subprocess.CompletedProcess, float]:
    """Run `cmd`, sampling the summed resident memory of its process tree; (result, largest sum in MB)."""
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    peak = [0.0]
    done = threading.Event()

    def sample():
        while not done.is_set():
            peak[0] = max(peak[0], _tree_rss(proc.pid))
            done.wait(0.2)

    th = threading.Thread(target=sample, daemon=True)
    th.start()
    try:
        out, err = proc.communicate()
    finally:
        done.set()
        th.join()
        if proc.poll() is None:
            proc.kill()
    return subprocess.CompletedProcess(cmd, proc.returncode, out, err), peak[0]


def uptime() -> str:
    return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()


COLUMNS = ("scale N sub global AS CG-to-1e-8 CG-to-1e-12 BDDC coarse elem. coarse mesh blocks distr assem setup CG-s "
           "AS-s gather r0-sys r0-post total K_I MB-per-rank MB-sum")


def row(scale: float, n: int, d: dict, sampled: float) -> str:
    t = d["timings"]
    mem = ", ".join(f"{m:.0f}" for m in d["memory"])
    if n == 1:
        return (f"| {scale:g} | 1 | 1 | {d['global']} | - | direct | direct | - | - | - | - | {t['mesh']:.2f} | - | - | "
                f"{t['assemble']:.2f} | {t['factorize']:.2f} | {t['solve'] + t['contact']:.2f} | - | - | - | "
                f"{t['recover'] + t.get('tips', 0.0):.2f} | {t['total']:.2f} | {d['K_I']:.10f} | {mem} | {sampled:.0f} |")
    i = d["info"]
    steps8 = "+".join("-" if s is None else str(s) for s in i.get("cg_steps_1e-8", []))
    return (f"| {scale:g} | {n} | {i['subdomains']} | {d['global']} | {i['active_set_steps']} | {steps8 or '-'} | "
            f"{'+'.join(map(str, i['cg_steps']))} | {'/'.join(map(str, d['bddc']))} | {d['coarse']} | "
            f"{'/'.join(map(str, d['element']))} | {d['element_coarse']} | {t['mesh']:.2f} | {t.get('blocks', 0.0):.2f} | "
            f"{t['distribute']:.2f} | {t['assemble']:.2f} | {t['preconditioner']:.2f} | {t['cg']:.2f} | "
            f"{t['solve'] - t['cg']:.2f} | {t['gather']:.2f} | {t['rank0_system']:.2f} | "
            f"{t['rank0_post'] + t.get('tips', 0.0):.2f} | {t['total']:.2f} | {d['K_I']:.10f} | {mem} | {sampled:.0f} |")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--scene", default="griffith")
    ap.add_argument("--scales", default="1,0.5")
    ap.add_argument("--ranks", default="1,2,3", help="1 is the serial solve")
    ap.add_argument("--element-bddc", action="store_true",
                    help="also count CG steps with NGSolve's element-wise BDDC (its coarse problem is 3/4 of the system)")
    ap.add_argument("--no-counts", action="store_true",
                    help="leave out the unconstrained CG counts (a second distributed build and a direct solve)")
    ap.add_argument("--worker", type=float, default=None, help=argparse.SUPPRESS)
    ap.add_argument("--serial-worker", type=float, default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker is not None:
        worker(args.scene, args.worker, args.element_bddc, not args.no_counts)
        return
    if args.serial_worker is not None:
        serial_worker(args.scene, args.serial_worker)
        return
    env = dict(os.environ, OMP_NUM_THREADS="1", PYTHONPATH=os.path.dirname(HERE))
    mpiexec = os.path.join(os.path.dirname(sys.executable), "mpiexec")
    print("uptime:", uptime(), flush=True)
    print("| " + " | ".join(COLUMNS.split()) + " |")
    print("|" + "---|" * len(COLUMNS.split()), flush=True)
    for scale in (float(s) for s in args.scales.split(",")):
        for n in (int(k) for k in args.ranks.split(",")):
            if n == 1:
                cmd = [sys.executable, __file__, "--scene", args.scene, "--serial-worker", str(scale)]
            else:
                cmd = [mpiexec, "-n", str(n), sys.executable, __file__, "--scene", args.scene, "--worker", str(scale)]
                cmd += (["--element-bddc"] if args.element_bddc else []) + (["--no-counts"] if args.no_counts else [])
            proc, sampled = run(cmd, env)
            lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("{")]
            if proc.returncode or not lines:
                print(f"| {scale:g} | {n} | failed (exit {proc.returncode}, sampled peak {sampled:.0f} MB): "
                      f"{proc.stderr.strip().splitlines()[-1:]} |", flush=True)
            else:
                print(row(scale, n, json.loads(lines[-1]), sampled), flush=True)
            print(f"  uptime: {uptime()}", flush=True)


if __name__ == "__main__":
    main()
