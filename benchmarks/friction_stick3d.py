"""3D Coulomb friction from slip to full stick: the inclined penny on the standard box.

The penny (a = 1) at 60 degrees to a compression p = 1 (normal (sin 60, 0, cos 60): sigma_n =
0.25, tau = 0.433 on its plane, so every face sticks for mu > tau / sigma_n = 1.73), in the
box of side 20a of the built-in `penny` (rollers on three faces, E = 1000, nu = 0.3), TDNNS
order 1 at the default sizes (front_h 0.2a). Each friction coefficient is solved in its own
process on one thread: the Newton steps of the Coulomb solve (`core.sparse_friction`, method
"schur"), CPU seconds (`time.process_time`, the whole solve and its stages), the peak resident
memory, the certificate (the friction residual of the KKT dictionary), the friction points that
stick, and the largest |K_II|, |K_III| along the front over the frictionless ones.

The shear modes are given twice: with the crack faces' friction term of the front integral as it
is (`ngcrack.solid.face_friction`: each face's traction fitted to the work of the point forces on
the jumps, the mean traction's uniform shear taken out and its K subtracted) and as it was
(columns "before": each face's point forces spread over it, integrated with the face rule alone;
the same solve, the front integral run again with `CONSISTENT = False`). "front s": the CPU
seconds of the front integral with the term before and after (after: two runs of the integral,
the solution's and the uniform shear's).
"K uniform rest" is the largest |K_II|, |K_III| (over the frictionless ones) that the front integral
gives for the remote uniform stress less its shear on the crack's plane (a smooth field with no
shear traction on the faces: 0 in the continuum), the extraction's own error that a sticking
crack's K keeps (and the frictionless K of a closed crack too).

    python benchmarks/friction_stick3d.py                      # mu = 0, 0.4, 1, 2, 5
    python benchmarks/friction_stick3d.py --mu 0 2 --box 4     # a smaller box (quick)
    python benchmarks/friction_stick3d.py --mu 0 5 --front-h 0.3 0.2 0.15   # full stick against the mesh

No number here is a test threshold: the machine is shared and timings are noisy.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys

#: the inclination of the crack's normal to the compression (degrees)
ANGLE = 60.0
#: the compression on the box's top face
LOAD = 1.0


def scene_dict(mu: float, box: float, mesh: dict | None = None) -> dict:
    """The inclined penny of the module docstring in a box of side 2 `box`."""
    from ngcrack.scenes.coarse3d import coarse_penny

    d = coarse_penny(-LOAD)
    d["name"] = "inclined-penny-60"
    d["domain"]["box"] = [[-box] * 3, [box] * 3]
    th = math.radians(ANGLE)
    d["crack"][0].update(normal=[math.sin(th), 0.0, math.cos(th)], friction=float(mu))
    if mesh is None:
        d.pop("mesh")  # the defaults (front_h 0.2a)
    else:
        d["mesh"] = mesh
    return d


def run_case(args: dict) -> dict:
    """One solve in this process."""
    import resource
    import time

    import numpy as np

    import ngcrack as nc
    from ngcrack.solid import face_friction
    from ngcrack.solid.front import front_parameters
    from ngcrack.solid.scene import SolidScene

    scene = SolidScene.from_dict(scene_dict(args["mu"], args["box"], args.get("mesh")))
    load = os.getloadavg()[0]
    t0 = time.process_time()
    sol = nc.solve(scene)
    cpu = time.process_time() - t0
    res = sol.contact
    front = sol.fronts[0]
    out = {**args, "cpu": cpu, "load": load, "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
           "timings": {k: float(v) for k, v in sol.timings.items() if isinstance(v, (int, float))},
           "K_II": float(np.max(np.abs(front.K_II))), "K_III": float(np.max(np.abs(front.K_III))),
           "K_I": float(np.max(np.abs(front.K_I))), "kkt": {k: float(v) for k, v in sol.kkt.items()},
           "steps": int(getattr(res, "iterations", 0)), "n": int(sol.system.n)}
    # the same solve's shear modes with the friction term as it was (no uniform part taken out)
    face_friction.CONSISTENT = False
    t0 = time.process_time()
    before = front_parameters(sol, points=sol.options.get("front_points"))[0]
    face_friction.CONSISTENT = True
    t1 = time.process_time()
    front_parameters(sol, points=sol.options.get("front_points"))
    out.update(front_cpu_before=t1 - t0, front_cpu=time.process_time() - t1)
    out.update(K_II_before=float(np.max(np.abs(before.K_II))), K_III_before=float(np.max(np.abs(before.K_III))))
    # the remote uniform stress (-p e_z e_z) less its shear on the crack's plane: K = 0 in the continuum
    n = np.array(scene_dict(0.0, 1.0)["crack"][0]["normal"])
    s0 = np.diag([0.0, 0.0, -LOAD])
    t = s0 @ n - (n @ s0 @ n) * n
    rest = front_parameters(face_friction.uniform_stress_solution(sol, s0 - np.outer(t, n) - np.outer(n, t)),
                            points=sol.options.get("front_points"))[0]
    out.update(K_II_rest=float(np.max(np.abs(rest.K_II))), K_III_rest=float(np.max(np.abs(rest.K_III))),
               front_h=float(sol.smesh.sizes["front_h"]))
    if hasattr(res, "stick"):
        out.update(stick=int(np.count_nonzero(res.stick)), points=len(res.stick),
                   slip_max=float(np.max(np.linalg.norm(res.slip, axis=1))),
                   rt={k: float(v) for k, v in (res.timings or {}).items()})
    return out


def in_subprocess(args: dict) -> dict:
    env = {**os.environ, "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}
    res = subprocess.run([sys.executable, __file__, "case", json.dumps(args)], capture_output=True, text=True, env=env)
    if res.returncode != 0:
        return {**args, "error": res.stderr.strip().splitlines()[-1] if res.stderr.strip() else f"exit {res.returncode}"}
    return json.loads(res.stdout.strip().splitlines()[-1])


def main() -> None:
    if len(sys.argv) > 1 and sys.argv[1] == "case":
        print(json.dumps(run_case(json.loads(sys.argv[2]))))
        return
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--mu", nargs="+", type=float, default=[0.0, 0.4, 1.0, 2.0, 5.0])
    p.add_argument("--box", type=float, default=10.0, help="half the box's side (10: the standard 20a box)")
    p.add_argument("--front-h", nargs="+", type=float, default=[None],
                   help="the mesh size at the front (default: the scene's defaults, 0.2a); several: one series each")
    p.add_argument("--out", help="append the raw results as JSON lines")
    args = p.parse_args()
    head = (f"{'h':>5s} {'mu':>5s} {'steps':>5s} {'stick':>9s} {'CPU s':>7s} {'contact':>7s} {'peak MB':>8s} "
            f"{'KKT fric':>8s} {'driving':>7s} {'K_II/0 before':>13s} {'after':>7s} {'K_III/0 before':>14s} {'after':>7s} "
            f"{'K rest':>15s} {'front s':>11s} {'max slip':>9s} {'load':>5s}")
    print(head)
    print("-" * len(head))
    for front_h in args.front_h:
        base = None
        for mu in args.mu:
            case = {"mu": mu, "box": args.box}
            if front_h is not None:
                case["mesh"] = {"front_h": front_h}
            r = in_subprocess(case)
            if "error" in r:
                print(f"{front_h or 0.2:5g} {mu:5g} error: {r['error']}", flush=True)
                continue
            base = base or (r if mu == 0 else None)
            b2, b3 = (base["K_II"], base["K_III"]) if base else (float("nan"), float("nan"))
            t = r["timings"]
            stick = f"{r.get('stick', 0)}/{r.get('points', 0)}" if "stick" in r else "-"
            print(f"{r['front_h']:5g} {mu:5g} {r['steps']:5d} {stick:>9s} {r['cpu']:7.1f} {t.get('contact', 0):7.1f} "
                  f"{r['peak_mb']:8.0f} {r['kkt'].get('friction', 0.0):8.0e} {driving_shear(mu):7.3f} "
                  f"{r['K_II_before'] / b2:13.4f} {r['K_II'] / b2:7.4f} {r['K_III_before'] / b3:14.4f} {r['K_III'] / b3:7.4f} "
                  f"{r['K_II_rest'] / b2:7.4f} {r['K_III_rest'] / b3:7.4f} {r['front_cpu_before']:5.1f} {r['front_cpu']:5.1f} "
                  f"{r.get('slip_max', 0.0):9.1e} {r['load']:5.1f}",
                  flush=True)
            if args.out:
                with open(args.out, "a") as fh:
                    fh.write(json.dumps(r) + "\n")


def driving_shear(mu: float) -> float:
    """(tau - mu sigma_n) / tau on the crack's plane, at least 0: the shear modes' share where every face slips."""
    th = math.radians(ANGLE)
    sigma_n, tau = LOAD * math.cos(th) ** 2, LOAD * math.sin(th) * math.cos(th)
    return max(0.0, (tau - mu * sigma_n) / tau)


if __name__ == "__main__":
    main()
