"""Hydraulic fracture: the CPU time of 50 KGD steps, and the answer at t = 10 s against KGD.

The built-in scene `kgd` (GEOS's parameters: Q0 = 1e-4 m^2/s, E = 30 GPa, nu = 0.25,
K_Ic = 1 MPa sqrt(m); a 2 m crack in a clamped 400 m square, tips meshed at 0.05 m, the
crack at crack_h) grows by da = 0.1 m per tip and step, tdnns. Printed: the CPU time
(time.process_time of this process, OMP_NUM_THREADS=1 recommended) and the wall time of
the run, the unknowns of the first and last step, the solves per step, and the
half-length, pressure and opening at the injection point at t = 10 s (linear
interpolation between the steps around it) against KGD's closed form (l = 4.335 m,
p = 0.2710 MPa, w0 = 146.8 micrometres), and the largest deviation over the steps.

    OMP_NUM_THREADS=1 python benchmarks/hydrofrac.py               # 50 steps, crack_h 0.1 (the scene's)
    OMP_NUM_THREADS=1 python benchmarks/hydrofrac.py --crack-h 0.2

No number here is a test threshold: the machine is shared and timings are noisy.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

Q0, K_IC = 1e-4, 1e6


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=50)
    parser.add_argument("--crack-h", dest="crack_h", type=float, default=None)
    args = parser.parse_args(argv)

    import ngcrack as nc

    scene = nc.scenes.load("kgd")
    e_prime = scene.material.E / (1 - scene.material.nu ** 2)
    options = {} if args.crack_h is None else {"crack_h": args.crack_h}
    cpu0, wall0 = time.process_time(), time.perf_counter()
    res = nc.hydrofrac(scene, rate=Q0, K_Ic=K_IC, da=0.1, steps=args.steps, **options)
    cpu, wall = time.process_time() - cpu0, time.perf_counter() - wall0
    steps = res.steps
    t = np.array([s["time"] for s in steps])
    cols = {k: np.array([s[k] for s in steps]) for k in ("half_length", "pressure", "opening_at_injection")}
    l_kgd = 0.4302 * (e_prime * Q0 * t / K_IC) ** (2 / 3)
    p_kgd = K_IC / np.sqrt(math.pi * l_kgd)
    w_kgd = 4 * p_kgd * l_kgd / e_prime
    dev = {k: float(np.max(np.abs(cols[k] / ref - 1))) for k, ref in
           (("half_length", l_kgd), ("pressure", p_kgd), ("opening_at_injection", w_kgd))}
    print(f"scene kgd, tdnns, da 0.1 m, crack_h {args.crack_h or scene.crack_h} m: {len(steps) - 1} steps, "
          f"stopped: {res.stopped}")
    print(f"{'steps':>5} {'CPU s':>8} {'wall s':>8} {'CPU s/step':>10} {'ndof first':>10} {'ndof last':>9} "
          f"{'solves/step':>11}")
    print(f"{len(steps) - 1:>5} {cpu:>8.1f} {wall:>8.1f} {cpu / len(steps):>10.2f} {steps[0]['ndof']:>10} "
          f"{steps[-1]['ndof']:>9} {np.mean([s['solves'] for s in steps]):>11.1f}")
    if t[0] <= 10.0 <= t[-1]:
        at = {k: float(np.interp(10.0, t, v)) for k, v in cols.items()}
        print(f"at t = 10 s: l = {at['half_length']:.4f} m (KGD 4.335), p = {at['pressure'] / 1e6:.4f} MPa "
              f"(KGD 0.2710), w0 = {at['opening_at_injection'] * 1e6:.1f} um (KGD 146.8)")
    print("largest deviation from KGD over the steps: " + ", ".join(f"{k} {100 * v:.2f}%" for k, v in dev.items()))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
