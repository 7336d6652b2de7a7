"""The distributed 3D solve against the serial one: agreement, CG steps, time per stage, memory per rank.

    python benchmarks/mpi_solid.py [--cases bent,penny,penny-closed] [--ranks 2,3] [--scale 1]

Cases (order 1 TDNNS, coarse meshes): `bent`, the penny across a clamped beam bent by a
shear load (tests/test_mpi_solid.py: half the crack closes); `penny` and `penny-closed`,
the coarse penny of tests/test_solid.py under tension (every face open) and compression
(every face closed). Every run is its own process: N = 1 is the serial 3D solve
(`solid.solve.solve_solid`, sparse direct active set), N > 1 runs under `mpiexec -n N`
(condense: there the serial condensation rank 0 does for the post-processing).
Printed per run: global unknowns, active-set steps, CG steps per step (to 1e-12; in
brackets to 1e-8 on the way), the preconditioner, seconds per stage (setup: the
preconditioner's; CG: within solve), peak memory per rank, and against the serial run: the
largest difference of K_I, K_II, K_III over the front (relative to the largest |K|), of
the normal jumps at the constraint points (relative to the largest), whether the active
sets are equal, and the KKT residuals. `--scale` multiplies the mesh sizes (maxh, crack_h,
front_h) of every case. The memory: every rank's peak over the whole solve (rank 0's
post-processing included) and the largest sum over the run's processes at one time
(sampled every 0.2 s); `uptime` before the table and after every row.
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

def case(name: str, scale: float = 1.0) -> dict:
    """The scene of a case name: ngcrack.scenes.coarse3d's (the 3D tests' scenes), its mesh sizes times `scale`."""
    from ngcrack.scenes.coarse3d import bent_penny, coarse_penny

    if name == "bent":
        d = bent_penny()
    elif name == "penny-closed":
        d = dict(coarse_penny(load=-1.0), name="penny-closed")
    else:
        d = coarse_penny()
    d["mesh"] = {k: v * scale for k, v in d["mesh"].items()}
    return d


def worker(scene_path: str, out: str) -> None:
    """One run (serial without mpiexec, distributed under it); rank 0 writes its record to `out`."""
    import numpy as np

    import ngcrack as nc
    from ngcrack.solid.scene import SolidScene

    scene = SolidScene.from_dict(json.load(open(scene_path)))
    t0 = time.perf_counter()
    sol = nc.solve(scene)
    peak = round(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0, 1)  # over the whole solve
    memory = [peak]
    if "OMPI_COMM_WORLD_SIZE" in os.environ or "PMI_SIZE" in os.environ:
        from mpi4py import MPI

        memory = MPI.COMM_WORLD.gather(peak, root=0)
    if sol is None:
        return
    wall = time.perf_counter() - t0
    info = sol.distributed or {}
    record = dict(
        K=[np.column_stack([f.K_I, f.K_II, f.K_III]).tolist() for f in sol.fronts],
        jumps=sol.normal_jumps().tolist(), active=sol.contact.active.tolist(), kkt=sol.kkt,
        timings=sol.timings, wall=wall, info=info, ndof=sol.ndof, memory=memory)
    json.dump(record, open(out, "w"))


def run(scene: dict, n: int, tmp: str, script: str = __file__) -> dict:
    """`script --worker` on `scene` (serial for n = 1, under mpiexec -n n otherwise), its record."""
    path, out = os.path.join(tmp, "scene.json"), os.path.join(tmp, f"out{n}.json")
    json.dump(scene, open(path, "w"))
    env = dict(os.environ, OMP_NUM_THREADS="1", PYTHONPATH=ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))
    cmd = [sys.executable, os.path.abspath(script), "--worker", path, out]
    if n > 1:
        cmd = ["mpiexec", "-n", str(n)] + cmd
    from mpi_scaling import run as run_sampled

    proc, sampled = run_sampled(cmd, env)
    if proc.returncode != 0:
        raise RuntimeError(proc.stderr[-2000:])
    return dict(json.load(open(out)), sampled=sampled)


def compare(r: dict, s: dict) -> dict:
    import numpy as np

    K, Ks = np.array(r["K"]), np.array(s["K"])
    w, ws = np.array(r["jumps"]), np.array(s["jumps"])
    return dict(K=float(np.max(np.abs(K - Ks)) / np.max(np.abs(Ks))),
                profile=float(np.max(np.abs(w - ws)) / max(np.max(np.abs(ws)), 1e-300)),
                same_active=r["active"] == s["active"], active=int(sum(r["active"])), points=len(r["active"]),
                kkt=max(r["kkt"].values()))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--cases", default="bent,penny,penny-closed")
    p.add_argument("--ranks", default="2,3", help="N > 1 under mpiexec; 1 (the serial run) always runs first")
    p.add_argument("--scale", type=float, default=1.0, help="the cases' mesh sizes times this")
    p.add_argument("--worker", nargs=2, help=argparse.SUPPRESS)
    a = p.parse_args()
    if a.worker:
        worker(*a.worker)
        return
    print("uptime:", subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())
    print("| case | N | global dofs | AS: CG per step | preconditioner | K diff | profile diff | active (same) | KKT "
          "| mesh | distribute | assemble | setup | CG | solve | gather | condense | fronts | total | MB per rank | MB sum |")
    print("|---|---:|---:|---|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|")
    for name in a.cases.split(","):
        scene = case(name, a.scale)
        with tempfile.TemporaryDirectory() as tmp:
            serial = run(scene, 1, tmp)
            for n in [1] + [int(x) for x in a.ranks.split(",") if int(x) > 1]:
                r = serial if n == 1 else run(scene, n, tmp)
                c = compare(r, serial)
                t = r["timings"]
                info = r["info"]
                steps = f"{info['active_set_steps']}: {', '.join(map(str, info['cg_steps']))}" if info else "sparse LU"
                if info.get("cg_steps_1e-8"):  # to 1e-8 on the way to 1e-12
                    steps += f" (to 1e-8: {', '.join(map(str, info['cg_steps_1e-8']))})"
                pre = info.get("preconditioner", "direct (serial)").split(",")[0]
                stages = ["mesh", "distribute", "assemble", "preconditioner", "cg", "solve", "gather", "condense", "fronts",
                          "total"]
                if n == 1:
                    t = dict(t, solve=t.get("contact", 0.0) + t.get("linear", 0.0))
                cells = [f"{t[k]:.2f}" if k in t else "-" for k in stages]
                print(f"| {name} | {n} | {r['ndof']['global']} | {steps} | {pre} | {c['K']:.1e} | {c['profile']:.1e} | "
                      f"{c['active']}/{c['points']} ({'same' if c['same_active'] else 'DIFFERENT'}) | {c['kkt']:.1e} | "
                      + " | ".join(cells) + f" | {', '.join(f'{m:.0f}' for m in r['memory'])} | {r['sampled']:.0f} |",
                      flush=True)
                print("  uptime:", subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip(), flush=True)


if __name__ == "__main__":
    main()
