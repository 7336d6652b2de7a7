"""Coulomb friction on a 3D crack under mpiexec against the serial 3D solve: agreement, steps, time.

    python benchmarks/mpi_friction3d.py [--cases inclined-0.4,inclined-1.5,bent-1.0] [--ranks 2,3]

Cases (order 1 TDNNS; `ngcrack.scenes.coarse3d`): `inclined-MU`, the inclined penny pressed
shut (509 tetrahedra) with friction MU; `bent-MU`, the penny across the bent beam (half the
crack open) with friction MU. Every run is its own process: N = 1 is the serial solve
(`core.sparse_friction`: a semismooth Newton method, one sparse LU per step), N > 1 runs under
`mpiexec -n N` (`distributed.solid_friction`: Newton steps by projected CG, preconditioned
by the default distributed 3D preconditioner). Printed per run: global unknowns, Newton
steps, CG steps per step (to 1e-12), the closed / sticking / slipping points, the seconds of
the crack problem (N = 1: the friction solve; N > 1: all the CG steps and the set updates)
and of the whole solve, and against the serial run: the largest difference of K_I, K_II,
K_III over the front (relative to the largest |K|), of the normal jumps and slips at the
points (relative to the largest of either), whether the sets are equal, and the Coulomb KKT
residual (`kkt["friction"]`). `uptime` before the table and after every row.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import tempfile
import time


def case(name: str) -> dict:
    """The scene of a case name `inclined-MU` or `bent-MU`."""
    from ngcrack.scenes.coarse3d import bent_penny, inclined_penny

    kind, mu = name.rsplit("-", 1)
    if kind == "inclined":
        return inclined_penny(float(mu))
    d = bent_penny()
    d["crack"][0]["friction"] = float(mu)
    return d


def worker(scene_path: str, out: str) -> None:
    """One run (serial without mpiexec, distributed under it); rank 0 writes its record to `out`."""
    import numpy as np

    import ngcrack as nc
    from ngcrack.solid.scene import SolidScene

    scene = SolidScene.from_dict(json.load(open(scene_path)))
    t0 = time.perf_counter()
    sol = nc.solve(scene)
    if sol is None:
        return
    c = sol.contact
    record = dict(K=[np.column_stack([f.K_I, f.K_II, f.K_III]).tolist() for f in sol.fronts],
                  jumps=sol.normal_jumps().tolist(), slip=c.slip.tolist(), active=c.active.tolist(),
                  stick=c.stick.tolist(), on=(c.bound > 0).tolist(), kkt=sol.kkt, iterations=c.iterations,
                  timings=sol.timings, wall=time.perf_counter() - t0, info=sol.distributed or {}, ndof=sol.ndof)
    json.dump(record, open(out, "w"))


def run(scene: dict, n: int, tmp: str) -> dict:
    """This script's worker on `scene` (mpi_solid.run: serial for n = 1, under mpiexec -n n otherwise)."""
    from mpi_solid import run as run_worker

    return run_worker(scene, n, tmp, __file__)


def compare(r: dict, s: dict) -> dict:
    """K's difference relative to the largest |K|; the jumps' and slips' relative to the largest of either, or
    absolute where every point sticks and is closed (both zero to round-off)."""
    import numpy as np

    K, Ks = np.array(r["K"]), np.array(s["K"])
    scale = max(np.max(np.abs(s["jumps"])), np.max(np.abs(s["slip"])))
    jumps = max(np.max(np.abs(np.subtract(r["jumps"], s["jumps"]))), np.max(np.abs(np.subtract(r["slip"], s["slip"]))))
    absolute = scale < 1e-15
    return dict(K=float(np.max(np.abs(K - Ks)) / np.max(np.abs(Ks))), jumps=float(jumps / (1.0 if absolute else scale)),
                absolute=absolute, same=all(r[k] == s[k] for k in ("active", "stick", "on")))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--cases", default="inclined-0.4,inclined-1.5,bent-1.0")
    p.add_argument("--ranks", default="2,3")
    p.add_argument("--worker", nargs=2, help=argparse.SUPPRESS)
    a = p.parse_args()
    if a.worker:
        worker(*a.worker)
        return
    uptime = lambda: subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()  # noqa: E731
    print("uptime:", uptime())
    print("| case | N | global dofs | Newton steps | CG per step | closed / stick / slip | K diff | jumps, slips diff "
          "| sets | friction KKT | crack problem s | total s |")
    print("|---|---:|---:|---:|---|---|---:|---:|---|---:|---:|---:|")
    for name in a.cases.split(","):
        scene = case(name)
        with tempfile.TemporaryDirectory() as tmp:
            serial = run(scene, 1, tmp)
            for n in [1] + [int(x) for x in a.ranks.split(",")]:
                if n > 2 and name.startswith("inclined"):
                    continue  # 509 tetrahedra: one worker rank's worth (solid_mesh.MIN_TETS_PER_RANK)
                r = serial if n == 1 else run(scene, n, tmp)
                c = compare(r, serial)
                t, info = r["timings"], r["info"]
                cg = ", ".join(map(str, info["cg_steps"])) if info else "sparse LU"
                steps = info["active_set_steps"] if info else r["iterations"]
                crack = t.get("contact", 0.0) if not info else t.get("cg", t["solve"])
                on, stick, active = sum(r["on"]), sum(r["stick"]), sum(r["active"])
                absolute = " (absolute)" if c["absolute"] else ""
                print(f"| {name} | {n} | {r['ndof']['global']} | {steps} | {cg} | {active} / {stick} / {on - stick} "
                      f"of {len(r['active'])} | {c['K']:.1e} | {c['jumps']:.1e}{absolute} | {'same' if c['same'] else 'DIFFERENT'} "
                      f"| {r['kkt']['friction']:.1e} | {crack:.1f} | {t['total']:.1f} |", flush=True)
                print("  uptime:", uptime(), flush=True)


if __name__ == "__main__":
    main()
