"""Hydraulic fracture with a viscous fluid: KGD against its M- and K-vertices, and water in GEOS's KGD.

The built-in scene `kgd` (Q0 = 1e-4 m^2/s, E = 30 GPa, nu = 0.25; a 2 m crack in a clamped
400 m square, tips meshed at 0.05 m, the crack at 0.1 m; tdnns) grows by da = 0.1 m per tip
and step with a viscous fluid. Cases (K_m: Adachi-Detournay's K' / (E'^3 mu' Q0)^(1/4)):

    M      mu = 1e-3 Pa s, K_Ic = 7.8e4 Pa sqrt(m)   K_m = 0.099  (viscosity-dominated)
    K      mu = 1e-7 Pa s, K_Ic = 1e6 Pa sqrt(m)     K_m = 12.7   (toughness-dominated)
    water  mu = 1e-3 Pa s, K_Ic = 1e6 Pa sqrt(m)     K_m = 1.27   (GEOS's KGD with water: both matter)
    carter as M, with Carter's leak-off C_L = 1e-4 m/s^(1/2)  (leak-off-dominated: efficiency 2-4%)

Printed per case: the CPU time (time.process_time, OMP_NUM_THREADS=1 recommended) and its
share per step, and at a few steps the half-length l, the opening w0 and pressure p at the
injection point against the vertex solutions (M: l = 0.6152 (E' Q0^3 t^4 / mu')^(1/6),
w0 = 1.1265 (mu' Q0^3 t^2 / E')^(1/6); K: l = 0.4302 (E' Q0 t / K_Ic)^(2/3), p = K_Ic / sqrt(pi l),
w0 = 4 p l / E'; Carter's storage-free asymptote l = Q0 t^(1/2) / (2 pi C_L)); for water, l, w0 and p
at t = 10 s beside both vertices.

    OMP_NUM_THREADS=1 python benchmarks/hydrofrac_viscous.py [--steps 30] [--case M K water]

No number here is a test threshold: the machine is shared and timings are noisy.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

Q0 = 1e-4
CASES = {"M": (1e-3, 7.8e4, 0.0), "K": (1e-7, 1e6, 0.0), "water": (1e-3, 1e6, 0.0), "carter": (1e-3, 7.8e4, 1e-4)}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=30)
    parser.add_argument("--case", nargs="+", choices=sorted(CASES), default=list(CASES))
    args = parser.parse_args(argv)

    import ngcrack as nc
    from ngcrack.studies.hydrofrac.flow import k_vertex, m_vertex

    scene = nc.scenes.load("kgd")
    e_prime = scene.material.E / (1 - scene.material.nu ** 2)
    for case in args.case:
        mu, K_Ic, C_L = CASES[case]
        cpu0 = time.process_time()
        run = nc.hydrofrac(scene, rate=Q0, K_Ic=K_Ic, da=0.1, steps=args.steps, viscosity=mu, leakoff=C_L)
        cpu = time.process_time() - cpu0
        steps = run.steps
        print(f"\n{case}: K_m = {run.K_m:.4g}, {len(steps) - 1} steps ({run.stopped}); CPU {cpu:.1f} s, "
              f"{cpu / len(steps):.2f} s per step; unknowns {steps[0]['ndof']} to {steps[-1]['ndof']}")
        print("step  t [s]    l [m]   w0 [um]  p [MPa] | M: l, w0 | K: l, p, w0")
        for s in steps[:: max(1, len(steps) // 6)] + [steps[-1]]:
            lm, wm = m_vertex(s["time"], e_prime, mu, Q0)
            lk, pk, wk = k_vertex(s["time"], e_prime, K_Ic, Q0)
            l, w, p = s["half_length"], s["opening_at_injection"], s["pressure"]
            print(f"{s['step']:4d} {s['time']:8.4g} {l:7.3f} {w * 1e6:8.2f} {p / 1e6:8.4f} | {100 * (l / lm - 1):+6.2f}% "
                  f"{100 * (w / wm - 1):+6.2f}% | {100 * (l / lk - 1):+6.2f}% {100 * (p / pk - 1):+6.2f}% "
                  f"{100 * (w / wk - 1):+6.2f}%")
        if C_L > 0:
            print("step  t [s]    l [m]   efficiency | Carter: l")
            for s in steps[:: max(1, len(steps) // 6)] + [steps[-1]]:
                lc = Q0 * s["time"] ** 0.5 / (2 * math.pi * C_L)
                print(f"{s['step']:4d} {s['time']:8.4g} {s['half_length']:7.3f} {s['efficiency']:10.4f} | "
                      f"{100 * (s['half_length'] / lc - 1):+6.2f}%")
            continue
        t = np.array([s["time"] for s in steps])
        if t[0] <= 10.0 <= t[-1]:
            at = {k: float(np.interp(10.0, t, [s[k] for s in steps]))
                  for k in ("half_length", "opening_at_injection", "pressure")}
            lm, wm = m_vertex(10.0, e_prime, mu, Q0)
            lk, pk, wk = k_vertex(10.0, e_prime, K_Ic, Q0)
            print(f"at t = 10 s: l = {at['half_length']:.3f} m, w0 = {at['opening_at_injection'] * 1e6:.1f} um, "
                  f"p = {at['pressure'] / 1e6:.4f} MPa (M-vertex: l = {lm:.3f} m, w0 = {wm * 1e6:.1f} um; "
                  f"K-vertex: l = {lk:.3f} m, w0 = {wk * 1e6:.1f} um, p = {pk / 1e6:.4f} MPa)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
