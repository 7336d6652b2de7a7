"""Hydraulic fracture: several parallel cracks fed from one injection, the stress shadow between them.

n equal cracks (-1, y)-(1, y) at the spacing h (centred) in the `kgd` scene's clamped 400 m square
(E = 30 GPa, nu = 0.25), fed at the total rate Q0 = 1e-4 m^2/s at one pressure (inviscid fluid, no
perforation friction), K_Ic = 1 MPa m^(1/2), da = 0.2 m per tip and step, tips meshed at 0.1 m, the
cracks at 0.2 m (tdnns). Printed per case at the last step: each crack's half-length, its share of
the step's fluid and its tips' K_I / K_Ic, the half-lengths against the K-vertex of a single crack fed
at Q0 / n, the volume balance (sum of the cracks' volumes against Q0 t) and CPU.

    OMP_NUM_THREADS=1 python benchmarks/hydrofrac_multi.py [--steps 4] [--spacing 40 4 2 1] [--n 3]

No number here is a test threshold: the machine is shared and timings are noisy.
"""

from __future__ import annotations

import argparse
import time

Q0, K_IC = 1e-4, 1e6
MESH = dict(maxh=40.0, tip_h=0.1, crack_h=0.2)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=4)
    parser.add_argument("--spacing", type=float, nargs="+", default=[40.0, 4.0, 2.0, 1.0])
    parser.add_argument("--n", type=int, nargs="+", default=[3])
    args = parser.parse_args(argv)

    import ngcrack as nc
    from ngcrack.studies.hydrofrac.flow import k_vertex

    base = nc.scenes.load("kgd")
    e_prime = base.material.E / (1 - base.material.nu ** 2)
    print("| n | spacing h | steps | per crack: l [m], share of the last step, K_I / K_Ic of its tips | l against the "
          "K-vertex at Q0 / n | volume - Q0 t | CPU |")
    print("|---|---|---|---|---|---|---|")
    for n in args.n:
        # a single crack at Q0 / n on the same mesh: the discretization's own deviation
        cpu0 = time.process_time()
        one = nc.hydrofrac(base, rate=Q0 / n, K_Ic=K_IC, da=0.2, steps=args.steps, **MESH)
        cpu = time.process_time() - cpu0
        dev = [100 * (s["half_length"] / k_vertex(s["time"], e_prime, K_IC, Q0 / n)[0] - 1) for s in one.steps]
        print(f"| 1 (at Q0 / {n}) | - | {len(one.steps) - 1} | l = {one.steps[-1]['half_length']:.2f} | "
              f"{min(dev):+.2f}..{max(dev):+.2f}% | - | {cpu:.1f} s |", flush=True)
        for h in args.spacing:
            d = base.to_dict()
            d["crack"] = [{"points": [[-1.0, h * (i - (n - 1) / 2)], [1.0, h * (i - (n - 1) / 2)]]} for i in range(n)]
            scene = nc.Scene.from_dict(d)
            cpu0 = time.process_time()
            run = nc.hydrofrac(scene, rate=Q0, K_Ic=K_IC, da=0.2, steps=args.steps, crack=list(range(n)), **MESH)
            cpu = time.process_time() - cpu0
            last = run.steps[-1]
            cracks = []
            for f in last["fractures"]:
                k = [t["K_I"] / K_IC for t in last["tips"] if t["crack"] == f["crack"]]
                cracks.append(f"{f['half_length']:.2f}, {f['share']:+.2f}, {min(k):.2f}-{max(k):.2f}")
            dev = [100 * (f["half_length"] / k_vertex(s["time"], e_prime, K_IC, Q0 / n)[0] - 1)
                   for s in run.steps for f in s["fractures"]]
            balance = max(abs(s["volume"] - Q0 * s["time"]) / s["volume"] for s in run.steps)
            stop = "" if run.stopped.startswith("steps") else f" ({run.stopped.split(';')[0]})"
            print(f"| {n} | {h:g} | {len(run.steps) - 1}{stop} | {'; '.join(cracks)} | {min(dev):+.2f}..{max(dev):+.2f}% | "
                  f"{balance:.1e} | {cpu:.1f} s |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
