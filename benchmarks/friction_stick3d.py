"""3D Coulomb friction from slip to full stick: the inclined penny on the standard box.

The penny (a = 1) at 60 degrees to a compression p = 1 (normal (sin 60, 0, cos 60): sigma_n =
0.25, tau = 0.433 on its plane, so every face sticks for mu > tau / sigma_n = 1.73), in the
box of side 20a of the built-in `penny` (rollers on three faces, E = 1000, nu = 0.3), TDNNS
order 1 at the default sizes (front_h 0.2a). Each friction coefficient is solved in its own
process on one thread: the Newton steps of the Coulomb solve (`core.sparse_friction`, method
"schur"), CPU seconds (`time.process_time`, the whole solve and its stages), the peak resident
memory, the certificate (the friction residual of the KKT dictionary), the friction points that
stick, and the largest |K_II|, |K_III| along the front over the frictionless ones.

    python benchmarks/friction_stick3d.py                      # mu = 0, 0.4, 1, 2, 5
    python benchmarks/friction_stick3d.py --mu 0 2 --box 4     # a smaller box (quick)

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


def scene_dict(mu: float, box: float, mesh: dict | None = None) -> dict:
    """The inclined penny of the module docstring in a box of side 2 `box`."""
    from ngcrack.scenes.coarse3d import coarse_penny

    d = coarse_penny(-1.0)
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
    p.add_argument("--out", help="append the raw results as JSON lines")
    args = p.parse_args()
    head = (f"{'mu':>5s} {'steps':>5s} {'stick':>9s} {'CPU s':>7s} {'linear':>7s} {'contact':>7s} {'peak MB':>8s} "
            f"{'KKT friction':>12s} {'K_II/K_II0':>11s} {'K_III/K_III0':>12s} {'max slip':>9s} {'load':>5s}")
    print(head)
    print("-" * len(head))
    base = None
    for mu in args.mu:
        r = in_subprocess({"mu": mu, "box": args.box})
        if "error" in r:
            print(f"{mu:5g} error: {r['error']}", flush=True)
            continue
        base = base or (r if mu == 0 else None)
        k2 = r["K_II"] / base["K_II"] if base else float("nan")
        k3 = r["K_III"] / base["K_III"] if base else float("nan")
        t = r["timings"]
        stick = f"{r.get('stick', 0)}/{r.get('points', 0)}" if "stick" in r else "-"
        print(f"{mu:5g} {r['steps']:5d} {stick:>9s} {r['cpu']:7.1f} {t.get('linear', 0):7.1f} {t.get('contact', 0):7.1f} "
              f"{r['peak_mb']:8.0f} {r['kkt'].get('friction', 0.0):12.1e} {k2:11.2e} {k3:12.2e} "
              f"{r.get('slip_max', 0.0):9.1e} {r['load']:5.1f}", flush=True)
        if args.out:
            with open(args.out, "a") as fh:
                fh.write(json.dumps(r) + "\n")


if __name__ == "__main__":
    main()
