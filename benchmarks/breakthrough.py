"""An embedded penny near a plate's face grows under Paris fatigue, breaks through and grows on as a surface crack.

The plate of the built-in `surface-crack` scene (thickness t = 1.5, half-width b = 5, length 20, remote
tension S = 1, one end clamped) with a penny of radius `--r0` in the plane y = 0, its nearest point
`--ligament` below the face z = t. `nc.grow(scene, da, steps, paris=(1e-3, m))`: the embedded front
grows until its ligament is below 0.4 of its half-height (ASME XI's proximity rule) and is then
re-characterised as a semi-elliptical surface crack of depth 2a + S centred on the face
(ngcrack.studies.growth.breakthrough), which grows on with the surface stepper.

Printed per step: the crack's kind; embedded, its ligament to the face and K_I at the point nearest
the face and at the farthest point against Sneddon's 2 S sqrt(L/pi) at its equivalent radius L (an
ellipse's: a scale only); surface, a/t, a/c, the reference's a/c at the same depth (Newman and Raju's
trajectory from the re-characterised crack, ngcrack.studies.growth.newman_raju_growth) and K_I at the
deepest point and the growth's K at the 5% surface point against Newman and Raju's there; the
cumulative cycles against the reference (Paris with Sneddon's K at the equivalent radius while
embedded; after the event the count on arriving at the surface crack plus the Newman-Raju
trajectory's); the unknowns and the CPU seconds of the step (process time).

    python benchmarks/breakthrough.py --r0 0.3 --ligament 0.15 --da 0.075 --steps 5 --front-h 0.06

No number here is a test threshold.
"""

from __future__ import annotations

import argparse
import copy
import math
import os
import time

import numpy as np

T, B = 1.5, 5.0
C_P = 1e-3


def sneddon_cycles(L0: float, L1: float, m: float) -> float:
    """Paris's law with Sneddon's K = 2 S sqrt(r / pi) (S = 1) from radius L0 to L1 (closed form)."""
    k = (2.0 / math.sqrt(math.pi)) ** m
    if abs(m - 2.0) < 1e-12:
        return math.log(L1 / L0) / (C_P * k)
    e = 1.0 - 0.5 * m
    return (L1 ** e - L0 ** e) / (e * C_P * k)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--r0", type=float, default=0.3, help="the penny's radius (an ellipse's semi-axis across the face)")
    parser.add_argument("--c0", type=float, help="an ellipse: its semi-axis along the face (default: a penny)")
    parser.add_argument("--png", help="draw the fronts over the steps and the cycles here")
    parser.add_argument("--corrector", action="store_true", help="the surface crack's steps by Heun's predictor-corrector")
    parser.add_argument("--ligament", type=float, default=0.15, help="the ligament from the penny to the face z = t")
    parser.add_argument("--da", type=float, default=0.075)
    parser.add_argument("--steps", type=int, default=4)
    parser.add_argument("--m", type=float, default=3.0)
    parser.add_argument("--front-h", type=float, default=0.06)
    parser.add_argument("--json", help="write the run's JSON here")
    args = parser.parse_args(argv)
    print(f"{os.uname().nodename}: {os.cpu_count()} cores; load {os.getloadavg()[0]:.1f}")

    import ngcrack as nc
    from ngcrack.studies.growth.newman_raju_growth import phi_in_from_surface, surface_K_any, trajectory
    from ngcrack.studies.growth.surface3d import SURFACE_K_FRACTION, depth_and_length, is_surface_crack

    m = args.m
    d = copy.deepcopy(nc.scenes.load("surface-crack").to_dict())
    d["crack"][0] = {"shape": "disc", "center": [0.0, 0.0, T - args.ligament - args.r0], "normal": [0.0, 1.0, 0.0],
                     "radius": args.r0}
    if args.c0 is not None:
        d["crack"][0] = {"shape": "ellipse", "center": d["crack"][0]["center"], "normal": [0.0, 1.0, 0.0],
                         "semi_axes": [args.c0, args.r0], "major_axis": [1.0, 0.0, 0.0]}
    d["mesh"] = {"front_h": args.front_h, "crack_h": 2 * args.front_h}
    clock, cpu = [time.process_time()], []

    def progress(n, result):
        now = time.process_time()
        cpu.append(now - clock[0])
        clock[0] = now

    r = nc.grow(nc.Scene.from_dict(d), da=args.da, steps=args.steps, paris=(C_P, m), progress=progress,
                corrector=args.corrector)
    N = r.cycles()
    what = "penny" if args.c0 is None else f"ellipse c0 = {args.c0:g} along the face,"
    print(f"\n{what} r0 = {args.r0:g}, ligament {args.ligament:g}, da {args.da:g}, front_h {args.front_h:g}, m {m:g}"
          f"{', Heun' if args.corrector else ''}; {r.stopped}")
    for e in r.transitions:
        print(f"event at step {e['step']}: {e['what']}")
    event = r.transitions[0] if r.transitions else None
    ref = None
    if event is not None:
        a1, c1 = event["depth"], event["surface_half_length"]
        N1 = float(N[event["step"]])  # the count on arriving at the surface crack
        ref = trajectory(a1, c1, T * 0.8, T, B, C_P, m)
    print(f"{'step':>4} {'kind':>8} {'lig/a_t':>7} {'a/c':>6} {'ref a/c':>7} {'K near/A':>8} {'ref':>6} {'ratio':>6} "
          f"{'K far/C':>7} {'ref':>6} {'ratio':>6} {'cycles':>8} {'ref N':>8} {'N/ref':>6} {'ndof':>8} {'cpu s':>6}")
    L0 = r.sizes()[0]
    for k, scene in enumerate(r.scenes):
        step, crack = r.steps[k], scene.cracks[0]
        f = step["fronts"][0]
        K = np.asarray(f["K_I"])
        if not is_surface_crack(scene.domain, crack):
            p = np.asarray(f["points"])
            near, far = int(np.argmax(p[:, 2])), int(np.argmin(p[:, 2]))
            lig = T - p[:, 2].max()
            L = math.sqrt(crack.area / math.pi)
            K_ref = 2.0 / math.sqrt(math.pi) * math.sqrt(L)  # (an ellipse: a scale only)
            N_ref = sneddon_cycles(L0, L, m)
            print(f"{k:4d} {'embedded':>8} {lig:7.3f} {'':>6} {'':>7} {K[near]:8.3f} {K_ref:6.3f} {K[near] / K_ref:6.3f} "
                  f"{K[far]:7.3f} {K_ref:6.3f} {K[far] / K_ref:6.3f} {N[k]:8.4g} {N_ref:8.4g} "
                  f"{(N[k] / N_ref if N_ref else 1.0):6.3f} {step['ndof']:8d} {cpu[k]:6.1f}")
            continue
        a, c = depth_and_length(scene.domain, crack)
        K_A, K_C = float(K[len(K) // 2]), float(f["K_drive"][0])
        nr_A = float(surface_K_any(1.0, a, c, T, B, 0.5 * np.pi))
        nr_C = float(surface_K_any(1.0, a, c, T, B, phi_in_from_surface(a, c, SURFACE_K_FRACTION)))
        want = float(np.interp(a, ref["a"], ref["a"] / ref["c"])) if ref is not None else math.nan
        N_ref = (N1 + float(np.interp(a, ref["a"], ref["N"]))) if ref is not None else math.nan
        print(f"{k:4d} {'surface':>8} {a / T:7.3f} {a / c:6.3f} {want:7.3f} {K_A:8.3f} {nr_A:6.3f} {K_A / nr_A:6.3f} "
              f"{K_C:7.3f} {nr_C:6.3f} {K_C / nr_C:6.3f} {N[k]:8.4g} {N_ref:8.4g} {N[k] / N_ref:6.3f} "
              f"{step['ndof']:8d} {cpu[k]:6.1f}")
    if args.png:
        r.plot(args.png)
        print(f"wrote {args.png}")
    if args.json:
        import json

        with open(args.json, "w") as fh:
            json.dump(r.to_json_dict(), fh)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
